/// \file regular_file.hpp
/// Internal (not installed): input files are regular files. A FIFO would
/// block the reader, a device (/dev/zero) never ends and a directory has no
/// bytes, so each is refused with an InputError naming the path; links are
/// followed first. The check runs on the opened descriptor (fstat), which is
/// the file actually read, and the open never blocks (O_NONBLOCK).
#ifndef TENSORMASS_COMMON_REGULAR_FILE_HPP
#define TENSORMASS_COMMON_REGULAR_FILE_HPP

#include <cstddef>
#include <limits>
#include <string>
#include <string_view>

namespace tensormass::detail {

/// The whole content of the regular file `path`; `kind` names the file in
/// messages ("mesh", "scene"). Throws InputError for a missing or unreadable
/// path, anything but a regular file, a read error, or a file of more than
/// `max_bytes` bytes (checked before the read and while reading).
std::string read_regular_file(const std::string& path, std::string_view kind,
                              std::size_t max_bytes = std::numeric_limits<std::size_t>::max());

/// Checks that `path` is a regular file that can be opened, without reading
/// it: for files another library opens by name (Gmsh). Throws as read_regular_file.
void check_regular_file(const std::string& path, std::string_view kind);

}  // namespace tensormass::detail

#endif
