/// \file atomic_file.hpp
/// Writes a file under a temporary name in the same directory, then renames
/// it over the target: a reader never sees a partial file, and a failure
/// leaves no file behind.
#ifndef TENSORMASS_IO_ATOMIC_FILE_HPP
#define TENSORMASS_IO_ATOMIC_FILE_HPP

#include <functional>
#include <ostream>
#include <string>

namespace tensormass::io {

/// Calls `write` with a binary stream on "path.tmp-PID", checks the stream,
/// then renames onto `path`. On any error the temporary file is removed and
/// the exception names the path: InputError when the temporary cannot be created (a
/// missing or read-only directory), OutputError when a write, the flush,
/// the fsync or the rename fails (disk full, I/O error). An error `write`
/// throws passes through. `durable`: the data and the rename are
/// forced to disk (fsync) so that a power cut leaves the old or the new
/// file whole (checkpoints); frames skip it for speed.
void write_atomically(const std::string& path, const std::function<void(std::ostream&)>& write, bool durable = false);

}  // namespace tensormass::io

#endif
