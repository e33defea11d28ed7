// Helpers of the scene tests: a small valid scene, text replacement and
// capture of InputError messages (the temporary directory is test_support's).
#ifndef TENSORMASS_SCENE_TEST_SUPPORT_HPP
#define TENSORMASS_SCENE_TEST_SUPPORT_HPP

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/scene/scene.hpp"

namespace scene_test {

using test_support::TempDir;

/// The message of the InputError that load_scene throws (a test failure when none).
inline std::string load_error(const std::string& path, const std::vector<std::string>& overrides = {}) {
  try {
    tensormass::load_scene(path, overrides);
  } catch (const tensormass::InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << path;
  return {};
}

/// A small valid static scene; line numbers matter to the tests.
inline const std::string kBaseScene =
    "mesh: beam.msh\n"                                                           // 1
    "materials:\n"                                                               // 2
    "  - {region: all, law: stvk, young: 1.0e6, poisson: 0.3, density: 1000}\n"  // 3
    "fixed: [clamp]\n"                                                           // 4
    "solver:\n"                                                                  // 5
    "  type: static\n"                                                           // 6
    "  load_steps: 10\n";                                                        // 7

/// `text` with the first occurrence of `from` replaced by `to`.
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

}  // namespace scene_test

#endif
