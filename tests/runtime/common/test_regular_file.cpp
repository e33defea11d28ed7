// Reading input files whole (common/regular_file.hpp): the exact bytes of a
// regular file, followed links, a size limit checked before and while
// reading, and FIFOs, devices, directories and sockets refused by path.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <string>

#include "common/regular_file.hpp"
#include "support/input_error.hpp"
#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::detail {
namespace {

namespace fs = std::filesystem;
using test_support::TempDir;

using test_support::input_error;

TEST(RegularFile, ReadsEveryByteOfTheFile) {
  const TempDir dir;
  std::string bytes;
  for (int i = 0; i < 200000; ++i) bytes.push_back(static_cast<char>(i * 7 % 256));  // NULs included
  const std::string path = dir.write("mesh.bin", bytes);
  EXPECT_EQ(read_regular_file(path, "mesh"), bytes);
  EXPECT_EQ(read_regular_file(dir.write("empty.msh", ""), "mesh"), "");
}

TEST(RegularFile, AMissingFileIsNamedWithTheReason) {
  const TempDir dir;
  const std::string path = dir.file("absent.msh");
  EXPECT_EQ(input_error([&] { read_regular_file(path, "mesh"); }),
            path + ": cannot open mesh file (No such file or directory)");
  EXPECT_EQ(input_error([&] { check_regular_file(path, "surface"); }),
            path + ": cannot open surface file (No such file or directory)");
}

TEST(RegularFile, ADirectoryIsRefused) {
  const TempDir dir;
  const std::string path = dir.path().string();
  EXPECT_EQ(input_error([&] { read_regular_file(path, "scene"); }),
            path + ": is a directory, not a scene file (only regular files are read)");
}

TEST(RegularFile, AFifoWithoutWriterIsRefusedWithoutBlocking) {
  const TempDir dir;
  const std::string path = dir.file("pipe");
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0) << std::strerror(errno);
  EXPECT_EQ(input_error([&] { read_regular_file(path, "mesh"); }),
            path + ": is a FIFO (named pipe), not a mesh file (only regular files are read)");
  EXPECT_EQ(input_error([&] { check_regular_file(path, "mesh"); }),
            path + ": is a FIFO (named pipe), not a mesh file (only regular files are read)");
}

TEST(RegularFile, ACharacterDeviceIsRefused) {
  EXPECT_EQ(input_error([] { read_regular_file("/dev/zero", "mesh"); }),
            "/dev/zero: is a character device, not a mesh file (only regular files are read)");
}

TEST(RegularFile, ASocketIsRefusedAsASocket) {
  const TempDir dir;
  const std::string path = dir.file("s");
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  ASSERT_LT(path.size(), sizeof address.sun_path);
  std::strcpy(address.sun_path, path.c_str());
  ASSERT_EQ(::bind(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0) << std::strerror(errno);
  EXPECT_EQ(input_error([&] { read_regular_file(path, "mesh"); }),
            path + ": is a socket, not a mesh file (only regular files are read)");
  ::close(fd);
}

TEST(RegularFile, LinksAreFollowedToWhatTheyName) {
  const TempDir dir;
  const std::string target = dir.write("real.msh", "content");
  fs::create_symlink(target, dir.file("link.msh"));
  EXPECT_EQ(read_regular_file(dir.file("link.msh"), "mesh"), "content");
  fs::create_symlink(dir.path(), dir.file("link_to_dir"));
  EXPECT_EQ(input_error([&] { read_regular_file(dir.file("link_to_dir"), "mesh"); }),
            dir.file("link_to_dir") + ": is a directory, not a mesh file (only regular files are read)");
  fs::create_symlink(dir.file("nowhere"), dir.file("dangling"));
  EXPECT_EQ(input_error([&] { read_regular_file(dir.file("dangling"), "mesh"); }),
            dir.file("dangling") + ": cannot open mesh file (No such file or directory)");
}

TEST(RegularFile, AFileOfExactlyTheLimitIsReadAndOneByteMoreIsRefused) {
  const TempDir dir;
  const std::string path = dir.write("scene.yaml", std::string(100, 'a'));
  EXPECT_EQ(read_regular_file(path, "scene", 100), std::string(100, 'a'));
  EXPECT_EQ(input_error([&] { read_regular_file(path, "scene", 99); }),
            path + ": the scene file is larger than 99 bytes, the most this program reads");
  EXPECT_EQ(read_regular_file(dir.write("empty.yaml", ""), "scene", 0), "");
}

// /proc files declare a size of 0 but have content: the read grows past the
// declared size, and the limit still holds while reading.
TEST(RegularFile, AFileLongerThanItsDeclaredSizeIsReadToItsEndWithinTheLimit) {
  ASSERT_EQ(fs::file_size("/proc/self/status"), 0u);
  const std::string status = read_regular_file("/proc/self/status", "status");
  EXPECT_EQ(status.rfind("Name:", 0), 0u) << status.substr(0, 80);
  EXPECT_EQ(status.back(), '\n');
  EXPECT_EQ(input_error([] { read_regular_file("/proc/self/status", "status", 16); }),
            "/proc/self/status: the status file is larger than 16 bytes, the most this program reads");
}

TEST(RegularFile, CheckRegularFileAcceptsARegularFileWithoutReadingIt) {
  const TempDir dir;
  const std::string path = dir.write("big.msh", std::string(1000, 'x'));
  EXPECT_NO_THROW(check_regular_file(path, "mesh"));
  EXPECT_EQ(input_error([&] { check_regular_file(dir.path().string(), "mesh"); }),
            dir.path().string() + ": is a directory, not a mesh file (only regular files are read)");
}

}  // namespace
}  // namespace tensormass::detail
