#include "tensormass/io/track_csv.hpp"

#include <cstdio>

namespace tensormass {

std::string track_file_name(const std::string& group) {
  std::string name = group;
  for (char& c : name) {
    const bool plain =
        (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '_';
    if (!plain) c = '_';
  }
  return "track_" + name + ".csv";
}

std::string track_csv_header() { return "time,x,y,z,ux,uy,uz\n"; }

std::string track_csv_row(const TrackRow& r) {
  char line[256];
  const int n = std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", r.time, r.position[0],
                              r.position[1], r.position[2], r.displacement[0], r.displacement[1], r.displacement[2]);
  return std::string(line, static_cast<std::size_t>(n));
}

}  // namespace tensormass
