#include "tensormass/io/output_directory.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <regex>

#include "tensormass/common/errors.hpp"

namespace tensormass::io {

namespace {

namespace fs = std::filesystem;

/// The process id written in a held lock file, or "unknown".
std::string holder(int fd) {
  char text[32] = {};
  const ssize_t got = ::pread(fd, text, sizeof text - 1, 0);
  std::string pid = got > 0 ? std::string(text, static_cast<std::size_t>(got)) : std::string();
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  return pid.empty() ? "unknown" : pid;
}

/// Removes `directory`'s "NAME.tmp-PID" files: the lock is held, so no live
/// run is writing them.
int remove_temporaries(const std::string& directory) {
  static const std::regex temporary(".+\\.tmp-[0-9]+");
  int removed = 0;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory, error)) {
    if (!entry.is_regular_file(error) || !std::regex_match(entry.path().filename().string(), temporary)) continue;
    if (fs::remove(entry.path(), error)) ++removed;
  }
  return removed;
}

}  // namespace

OutputDirectoryLock::OutputDirectoryLock(const std::string& directory) : directory_(directory) {
  std::error_code error;
  fs::create_directories(directory, error);
  if (error) throw InputError("cannot create output directory " + directory + ": " + error.message());
  const std::string path = (fs::path(directory) / kOutputLockFile).string();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd_ < 0) throw InputError("cannot write into output directory " + directory + ": " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const std::string pid = holder(fd_);
    ::close(fd_);
    fd_ = -1;
    throw InputError("output directory " + directory + " is in use by another run (process " + pid +
                     "); wait for it to end, or give another output.directory");
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, pid.data(), pid.size(), 0) != static_cast<ssize_t>(pid.size())) {
    const std::string reason = std::strerror(errno);
    release();
    throw InputError("cannot write into output directory " + directory + ": " + reason);
  }
  removed_ = remove_temporaries(directory);
}

OutputDirectoryLock::~OutputDirectoryLock() { release(); }

void OutputDirectoryLock::release() {
  if (fd_ < 0) return;
  ::flock(fd_, LOCK_UN);
  ::close(fd_);
  fd_ = -1;
}

}  // namespace tensormass::io
