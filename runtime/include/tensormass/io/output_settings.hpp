/// \file output_settings.hpp
/// What a run writes, as plain data: the output directory, the frame
/// interval and the tracked groups.
#ifndef TENSORMASS_IO_OUTPUT_SETTINGS_HPP
#define TENSORMASS_IO_OUTPUT_SETTINGS_HPP

#include <string>
#include <vector>

namespace tensormass {

struct OutputSettings {
  std::string directory = "out";  ///< resolved relative to the scene file (absolute paths kept)
  int every = 0;                  ///< 0 = final state only
  /// Groups (with cells) whose centroid is written to track_<group>.csv every step (track.hpp).
  std::vector<std::string> track;
  std::vector<int> track_lines;  ///< 1-based line of each `track` entry (0: from --set), for messages
  /// Write checkpoint.bin (the full state, checkpoint.hpp) every this many steps; 0 = never.
  int checkpoint_every = 0;
};

}  // namespace tensormass

#endif
