#include "tensormass/io/track_csv.hpp"

#include <cstdio>
#include <ostream>

#include "tensormass/io/atomic_file.hpp"

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

void write_track_csv(const std::string& path, std::span<const TrackRow> rows) {
  io::write_atomically(path, [&](std::ostream& out) {
    out << "time,x,y,z,ux,uy,uz\n";
    char line[256];
    for (const TrackRow& r : rows) {
      std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", r.time, r.position[0],
                    r.position[1], r.position[2], r.displacement[0], r.displacement[1], r.displacement[2]);
      out << line;
    }
  });
}

}  // namespace tensormass
