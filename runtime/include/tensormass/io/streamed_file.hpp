/// \file streamed_file.hpp
/// A text file written row by row as a run goes (track CSVs, the adaptive
/// model's records), so that a run of any length holds none of its rows in
/// memory. It is `<path>.partial` until finish() renames it to `<path>`: a
/// reader never takes an unfinished file for a finished one. A checkpoint
/// keeps the file's mark (rows, bytes and their XXH3-64); a resumed run
/// cuts the file back to it, refusing a file that is not the one marked.
#ifndef TENSORMASS_IO_STREAMED_FILE_HPP
#define TENSORMASS_IO_STREAMED_FILE_HPP

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace tensormass::io {

/// Where a streamed file stood when it was last forced to disk.
struct StreamMark {
  std::uint64_t rows = 0;      ///< rows appended after the header
  std::uint64_t bytes = 0;     ///< header and rows
  std::uint64_t checksum = 0;  ///< XXH3-64 of those bytes
};

class StreamedFile {
 public:
  /// A new `<path>.partial` starting with `header` (one left by an earlier
  /// run is replaced). InputError when it cannot be created.
  StreamedFile(std::string path, std::string_view header);
  /// The file of a resumed run: `<path>.partial`, or `<path>` when the
  /// marked run had finished, cut back to `mark` and reopened as
  /// `<path>.partial`. InputError naming the file, which is left as it
  /// was, when it is missing, shorter than the mark, or its first
  /// mark.bytes bytes are not the ones the mark was taken of; OutputError
  /// when it cannot be renamed or cut back.
  static StreamedFile resume(std::string path, const StreamMark& mark);
  /// Throws as resume() would, changing nothing: a run checks every file
  /// before it cuts any back.
  static void check_resumable(const std::string& path, const StreamMark& mark);

  StreamedFile(StreamedFile&&) noexcept;
  StreamedFile& operator=(StreamedFile&&) noexcept;
  /// Closes the file without renaming it (an unfinished run leaves `<path>.partial`).
  ~StreamedFile();

  /// Appends one row (its text with the line end); buffered.
  void append(std::string_view row);
  /// Writes the buffered rows and forces the file to disk; OutputError on failure.
  StreamMark mark();
  /// Writes the buffered rows, forces them to disk and renames the file to
  /// `<path>`; OutputError on failure. Nothing may be appended after it.
  void finish();

  const std::string& path() const;

 private:
  struct State;
  explicit StreamedFile(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

}  // namespace tensormass::io

#endif
