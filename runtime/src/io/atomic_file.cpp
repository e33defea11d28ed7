#include "tensormass/io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "tensormass/common/errors.hpp"

namespace tensormass::io {
namespace {

std::string temporary_name(const std::string& path) { return path + ".tmp-" + std::to_string(::getpid()); }

std::string system_reason() { return errno ? std::string(": ") + std::strerror(errno) : std::string(); }

/// fsync of a file or directory; false on failure.
bool sync_path(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), flags);
  if (fd < 0) return false;
  const bool synced = ::fsync(fd) == 0;
  ::close(fd);
  return synced;
}

std::string directory_of(const std::string& path) {
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? std::string(".") : slash == 0 ? std::string("/") : path.substr(0, slash);
}

}  // namespace

void write_atomically(const std::string& path, const std::function<void(std::ostream&)>& write, bool durable) {
  const std::string temporary = temporary_name(path);
  errno = 0;
  std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
  // A path that cannot be created is a bad argument; a write that fails after it, an output failure.
  if (!stream) throw InputError("cannot write " + path + system_reason());
  try {
    write(stream);
    stream.flush();
    if (!stream) throw OutputError("cannot write " + path + ": write failed (disk full?)");
    stream.close();
    if (!stream) throw OutputError("cannot write " + path + ": closing failed");
  } catch (...) {
    stream.close();
    std::remove(temporary.c_str());
    throw;  // keeps the writer's own error type (InputError stays InputError)
  }
  errno = 0;
  if (durable && !sync_path(temporary, O_RDONLY)) {
    const std::string reason = system_reason();
    std::remove(temporary.c_str());
    throw OutputError("cannot write " + path + ": fsync failed" + reason);
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = system_reason();
    std::remove(temporary.c_str());
    throw OutputError("cannot write " + path + reason);
  }
  if (durable) sync_path(directory_of(path), O_RDONLY | O_DIRECTORY);  // the rename itself
}

}  // namespace tensormass::io
