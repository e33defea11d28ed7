// Row-by-row text files with a durable mark for checkpoints (streamed_file.hpp).
#include "tensormass/io/streamed_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "common/checksum.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::io {
namespace {

constexpr std::size_t kBufferBytes = 64 * 1024;

std::string partial_name(const std::string& path) { return path + ".partial"; }

std::string system_reason() { return errno ? std::string(": ") + std::strerror(errno) : std::string(); }

bool is_regular_file(const std::string& path) {
  struct stat info {};
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

}  // namespace

struct StreamedFile::State {
  std::string path;
  int fd = -1;
  std::string buffer;
  StreamMark written;  // rows and bytes given so far (buffered ones included)
  detail::Checksum checksum;
  bool finished = false;

  ~State() {
    if (fd < 0) return;
    try {
      write_buffer();  // an unfinished file keeps every row given (a script that stops stepping)
    } catch (const OutputError&) {
    }
    ::close(fd);
  }
  void write_buffer() {
    std::size_t done = 0;
    while (done < buffer.size()) {
      errno = 0;
      const ssize_t n = ::write(fd, buffer.data() + done, buffer.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) throw OutputError("cannot write " + partial_name(path) + system_reason());
      done += static_cast<std::size_t>(n);
    }
    buffer.clear();
  }
  void sync() {
    write_buffer();
    errno = 0;
    if (::fsync(fd) != 0) throw OutputError("cannot write " + partial_name(path) + ": fsync failed" + system_reason());
  }
  void add(std::string_view text) {
    checksum.update(text.data(), text.size());
    written.bytes += text.size();
    buffer.append(text);
    if (buffer.size() >= kBufferBytes) write_buffer();
  }
};

StreamedFile::StreamedFile(std::unique_ptr<State> state) : state_(std::move(state)) {}

StreamedFile::StreamedFile(std::string path, std::string_view header) : state_(std::make_unique<State>()) {
  state_->path = std::move(path);
  const std::string partial = partial_name(state_->path);
  errno = 0;
  state_->fd = ::open(partial.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (state_->fd < 0) throw InputError("cannot write " + partial + system_reason());
  state_->add(header);
}

namespace {

/// The file a resumed run continues: `<path>.partial`, or `<path>` of a finished run.
std::string marked_source(const std::string& path) {
  return is_regular_file(path + ".partial") || !is_regular_file(path) ? path + ".partial" : path;
}

/// Feeds the first mark.bytes bytes of the open file `fd` (named `source`)
/// to `checksum`; InputError when the file is shorter or they differ from the mark's.
void read_marked_bytes(int fd, const std::string& source, const StreamMark& mark, detail::Checksum& checksum) {
  const auto refuse = [&](const std::string& why) {
    throw InputError(source + " " + why +
                     "; the checkpoint's rows cannot be kept (remove the checkpoint to start afresh)");
  };
  struct stat info {};
  if (::fstat(fd, &info) != 0 || static_cast<std::uint64_t>(info.st_size) < mark.bytes)
    refuse("holds fewer bytes than the " + std::to_string(mark.bytes) + " the checkpoint recorded");
  std::vector<char> chunk(kBufferBytes);
  for (std::uint64_t left = mark.bytes; left > 0;) {
    errno = 0;
    const ssize_t n = ::read(fd, chunk.data(), std::min<std::uint64_t>(left, chunk.size()));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) refuse("cannot be read" + system_reason());
    checksum.update(chunk.data(), static_cast<std::size_t>(n));
    left -= static_cast<std::uint64_t>(n);
  }
  if (checksum.value() != mark.checksum) refuse("is not the file the checkpoint was written with");
}

/// The marked source opened with `flags`; InputError when it is missing.
int open_source(const std::string& path, const std::string& source, int flags) {
  if (!is_regular_file(source))
    throw InputError(path + ".partial is missing (and so is " + path +
                     "); the checkpoint's rows cannot be kept (remove the checkpoint to start afresh)");
  errno = 0;
  const int fd = ::open(source.c_str(), flags | O_CLOEXEC);
  if (fd < 0) throw InputError("cannot open " + source + system_reason());
  return fd;
}

}  // namespace

void StreamedFile::check_resumable(const std::string& path, const StreamMark& mark) {
  const std::string source = marked_source(path);
  const int fd = open_source(path, source, O_RDONLY);
  detail::Checksum checksum;
  try {
    read_marked_bytes(fd, source, mark, checksum);
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
}

StreamedFile StreamedFile::resume(std::string path, const StreamMark& mark) {
  auto state = std::make_unique<State>();
  state->path = std::move(path);
  const std::string partial = partial_name(state->path);
  const std::string source = marked_source(state->path);
  state->fd = open_source(state->path, source, O_RDWR);
  read_marked_bytes(state->fd, source, mark, state->checksum);  // checked before anything changes
  errno = 0;
  if (source != partial && std::rename(source.c_str(), partial.c_str()) != 0)
    throw OutputError("cannot rename " + source + " to " + partial + system_reason());
  if (::ftruncate(state->fd, static_cast<off_t>(mark.bytes)) != 0 ||
      ::lseek(state->fd, static_cast<off_t>(mark.bytes), SEEK_SET) < 0)
    throw OutputError("cannot cut " + partial + " back to the checkpoint's rows" + system_reason());
  state->written = mark;
  return StreamedFile(std::move(state));
}

StreamedFile::StreamedFile(StreamedFile&&) noexcept = default;
StreamedFile& StreamedFile::operator=(StreamedFile&&) noexcept = default;
StreamedFile::~StreamedFile() = default;

void StreamedFile::append(std::string_view row) {
  state_->add(row);
  ++state_->written.rows;
}

StreamMark StreamedFile::mark() {
  state_->sync();
  StreamMark mark = state_->written;
  mark.checksum = state_->checksum.value();
  return mark;
}

void StreamedFile::finish() {
  if (state_->finished) return;
  state_->sync();
  ::close(state_->fd);
  state_->fd = -1;
  const std::string partial = partial_name(state_->path);
  errno = 0;
  if (std::rename(partial.c_str(), state_->path.c_str()) != 0)
    throw OutputError("cannot rename " + partial + " to " + state_->path + system_reason());
  state_->finished = true;
}

const std::string& StreamedFile::path() const { return state_->path; }

}  // namespace tensormass::io
