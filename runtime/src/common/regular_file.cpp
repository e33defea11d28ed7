#include "common/regular_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

#include "tensormass/common/errors.hpp"

namespace tensormass::detail {

namespace {

/// "a directory", "a FIFO (named pipe)", ...: what a non-regular file is.
std::string describe_file_type(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

[[noreturn]] void fail_not_regular(const std::string& path, std::string_view kind, mode_t mode) {
  throw InputError(path + ": is " + describe_file_type(mode) + ", not a " + std::string(kind) +
                   " file (only regular files are read)");
}

/// Closes the descriptor on scope exit.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(Descriptor&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

/// Opens `path` read-only without blocking (a FIFO with no writer would block
/// a plain open) and refuses anything but a regular file; `info` receives its status.
Descriptor open_regular(const std::string& path, std::string_view kind, struct stat& info) {
  Descriptor file(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (file.get() < 0) {
    const int open_error = errno;
    // A socket cannot be opened at all (ENXIO): say what it is.
    if (struct stat linked{}; ::stat(path.c_str(), &linked) == 0 && !S_ISREG(linked.st_mode))
      fail_not_regular(path, kind, linked.st_mode);
    throw InputError(path + ": cannot open " + std::string(kind) + " file (" + std::strerror(open_error) + ")");
  }
  if (::fstat(file.get(), &info) != 0)
    throw InputError(path + ": cannot read the status of the " + std::string(kind) + " file (" + std::strerror(errno) +
                     ")");
  if (!S_ISREG(info.st_mode)) fail_not_regular(path, kind, info.st_mode);
  return file;
}

[[noreturn]] void fail_too_large(const std::string& path, std::string_view kind, std::size_t max_bytes) {
  throw InputError(path + ": the " + std::string(kind) + " file is larger than " + std::to_string(max_bytes) +
                   " bytes, the most this program reads");
}

}  // namespace

std::string read_regular_file(const std::string& path, std::string_view kind, std::size_t max_bytes) {
  struct stat info {};
  const Descriptor file = open_regular(path, kind, info);
  const auto declared = static_cast<unsigned long long>(info.st_size > 0 ? info.st_size : 0);
  if (declared > max_bytes) fail_too_large(path, kind, max_bytes);
  // Sized from the file's length, then read to its end: a file that grows
  // while read is still bounded by max_bytes.
  std::string data(static_cast<std::size_t>(declared), '\0');
  std::size_t used = 0;
  for (;;) {
    if (used == data.size()) {
      if (used >= max_bytes) {
        char probe = 0;
        const ssize_t more = ::read(file.get(), &probe, 1);
        if (more > 0) fail_too_large(path, kind, max_bytes);
        if (more < 0 && errno == EINTR) continue;
        if (more < 0) throw InputError(path + ": read error (" + std::string(std::strerror(errno)) + ")");
        break;
      }
      data.resize(used + std::min<std::size_t>(max_bytes - used, std::max<std::size_t>(used, 65536)));
    }
    const ssize_t got = ::read(file.get(), data.data() + used, data.size() - used);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw InputError(path + ": read error (" + std::string(std::strerror(errno)) + ")");
    if (got == 0) break;
    used += static_cast<std::size_t>(got);
  }
  data.resize(used);
  return data;
}

void check_regular_file(const std::string& path, std::string_view kind) {
  struct stat info {};
  open_regular(path, kind, info);
}

}  // namespace tensormass::detail
