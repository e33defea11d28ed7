// A run's track and record files, new or resumed (run_streams.hpp).
#include "simulation/run_streams.hpp"

#include <filesystem>

#include "simulation/summary_json.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/track_csv.hpp"

namespace tensormass::detail {
namespace {

namespace fs = std::filesystem;

std::string records_path(const std::string& directory) {
  return (fs::path(directory) / kAdaptivityRecordsFile).string();
}

/// A new run replaces the directory's results: the unfinished track and
/// record files an earlier killed run left go, those of groups this run
/// does not track too.
void remove_stale_streams(const std::string& directory) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(directory, error)) {
    const std::string name = entry.path().filename().string();
    const bool track = name.starts_with("track_") && name.ends_with(".csv.partial");
    if (track || name == std::string(kAdaptivityRecordsFile) + ".partial") fs::remove(entry.path(), error);
  }
}

}  // namespace

RunStreams::RunStreams(const std::string& directory, const std::vector<GroupTrack>& tracks, bool adaptive,
                       const Checkpoint* checkpoint, const std::string& checkpoint_path) {
  std::vector<std::string> paths;
  for (const GroupTrack& track : tracks)
    paths.push_back((fs::path(directory) / track_file_name(track.name())).string());
  if (checkpoint) {  // every file checked before any is cut back
    if (checkpoint->tracks.size() != tracks.size())
      throw InputError("checkpoint " + checkpoint_path + " holds " + std::to_string(checkpoint->tracks.size()) +
                       " tracks, the scene asks for " + std::to_string(tracks.size()));
    for (std::size_t t = 0; t < tracks.size(); ++t)
      io::StreamedFile::check_resumable(paths[t], checkpoint->tracks[t].file);
    if (adaptive) io::StreamedFile::check_resumable(records_path(directory), checkpoint->adaptivity_records);
  } else {
    remove_stale_streams(directory);
  }
  for (std::size_t t = 0; t < tracks.size(); ++t)
    tracks_.push_back(checkpoint ? io::StreamedFile::resume(paths[t], checkpoint->tracks[t].file)
                                 : io::StreamedFile(paths[t], track_csv_header()));
  if (adaptive)
    records_.emplace(checkpoint ? io::StreamedFile::resume(records_path(directory), checkpoint->adaptivity_records)
                                : io::StreamedFile(records_path(directory), ""));
}

void RunStreams::append_record(const AdaptivityRecord& record) {
  if (records_) records_->append(adaptivity_record_line(record));
}

std::vector<io::StreamMark> RunStreams::track_marks() {
  std::vector<io::StreamMark> marks;
  for (io::StreamedFile& file : tracks_) marks.push_back(file.mark());
  return marks;
}

io::StreamMark RunStreams::record_mark() { return records_ ? records_->mark() : io::StreamMark{}; }

void RunStreams::finish(const std::vector<GroupTrack>& tracks, RunReport& report) {
  for (std::size_t t = 0; t < tracks_.size(); ++t) {
    tracks_[t].finish();
    const std::string name = track_file_name(tracks[t].name());
    report.files.push_back(name);
    report.tracks.push_back({tracks[t].name(), name});
  }
  if (!records_) return;
  records_->finish();
  report.files.push_back(kAdaptivityRecordsFile);
}

}  // namespace tensormass::detail
