// Helpers of the tests of scripts/: running a script under /usr/bin/python3
// and a small track CSV as `tensormass run` writes them.
#ifndef TENSORMASS_SCRIPT_TEST_SUPPORT_HPP
#define TENSORMASS_SCRIPT_TEST_SUPPORT_HPP

#include <cstdio>
#include <string>

#include "support/test_support.hpp"

namespace script_test {

/// Runs scripts/NAME with `arguments` under /usr/bin/python3 (stdout and stderr together).
inline test_support::Result run_script(const std::string& name, const std::string& arguments) {
  return test_support::python(test_support::source_path("scripts/" + name) + " " + arguments);
}

/// A track of 5 rows: centroid (1, 2, 0) + t * (0, -dy, 0) at t = 0 .. 0.4.
inline std::string track(double dy) {
  std::string text = "time,x,y,z,ux,uy,uz\n";
  char line[200];
  for (int k = 0; k < 5; ++k) {
    const double t = 0.1 * k;
    std::snprintf(line, sizeof line, "%.17g,1,%.17g,0,0,%.17g,0\n", t, 2 - dy * t, -dy * t);
    text += line;
  }
  return text;
}

}  // namespace script_test

#endif
