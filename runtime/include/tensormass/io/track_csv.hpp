/// \file track_csv.hpp
/// The track file of a group (scene key `output.track`, simulation/track.hpp):
/// `track_<group>.csv`, header `time,x,y,z,ux,uy,uz`, then one row per
/// recorded state, every number with 17 significant digits (round trip
/// exact). A run writes it row by row (io/streamed_file.hpp).
#ifndef TENSORMASS_IO_TRACK_CSV_HPP
#define TENSORMASS_IO_TRACK_CSV_HPP

#include <array>
#include <string>

namespace tensormass {

/// One recorded state of a track.
struct TrackRow {
  double time = 0;                       ///< seconds, or the load factor of a static solve
  std::array<double, 3> position{};      ///< current centroid
  std::array<double, 3> displacement{};  ///< from the first row
};

/// "track_<group>.csv" with every character of the group name other than a
/// letter, a digit, '.', '-' or '_' replaced by '_'.
std::string track_file_name(const std::string& group);

/// The header line, with its line end.
std::string track_csv_header();

/// One row's line, with its line end.
std::string track_csv_row(const TrackRow& row);

}  // namespace tensormass

#endif
