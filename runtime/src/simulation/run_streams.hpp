// Rank 0's streamed outputs of a run: one file per track (track_<group>.csv)
// and the adaptive model's records (adaptivity.jsonl), written row by row
// (io/streamed_file.hpp) and marked in checkpoints. Internal header.
#ifndef TENSORMASS_SIMULATION_RUN_STREAMS_HPP
#define TENSORMASS_SIMULATION_RUN_STREAMS_HPP

#include <optional>
#include <string>
#include <vector>

#include "tensormass/adaptivity/adaptivity.hpp"
#include "tensormass/io/streamed_file.hpp"
#include "tensormass/simulation/checkpoint.hpp"
#include "tensormass/simulation/simulation.hpp"
#include "tensormass/simulation/track.hpp"

namespace tensormass::detail {

class RunStreams {
 public:
  /// The files of `tracks` (and of the records when `adaptive`) in
  /// `directory`: new ones, the `.partial` files an earlier run left there
  /// removed, or with `checkpoint` (read from `checkpoint_path`) the
  /// resumed run's, every one checked against its mark before any is cut
  /// back to it. InputError naming the file when one does not match.
  RunStreams(const std::string& directory, const std::vector<GroupTrack>& tracks, bool adaptive,
             const Checkpoint* checkpoint, const std::string& checkpoint_path);

  /// Appends a row to track `t`'s file (tracks' order).
  void append_track_row(std::size_t t, const TrackRow& row) { tracks_[t].append(track_csv_row(row)); }
  /// Appends an evaluation's line to the record file (when adaptive).
  void append_record(const AdaptivityRecord& record);
  /// Writes every buffered row to disk and gives each track's mark, then the records'.
  std::vector<io::StreamMark> track_marks();
  io::StreamMark record_mark();
  /// Finishes every file (renamed from `.partial`) and lists them in the report.
  void finish(const std::vector<GroupTrack>& tracks, RunReport& report);

 private:
  std::vector<io::StreamedFile> tracks_;
  std::optional<io::StreamedFile> records_;
};

}  // namespace tensormass::detail

#endif
