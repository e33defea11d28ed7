// write_atomically: the target appears complete or not at all.
#include <gtest/gtest.h>

#include <stdexcept>

#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/atomic_file.hpp"

namespace {

using tensormass::io::write_atomically;
using test_support::read_file;
using test_support::TempDir;

TEST(AtomicFile, WritesTheContentAndLeavesNoTemporary) {
  const TempDir dir;
  write_atomically(dir.file("out.txt"), [](std::ostream& out) { out << "hello\n" << 42; });
  EXPECT_EQ(read_file(dir.file("out.txt")), "hello\n42");
  EXPECT_EQ(dir.files(), std::vector<std::string>{"out.txt"});
}

TEST(AtomicFile, ReplacesAnExistingFile) {
  const TempDir dir;
  dir.write("out.txt", "old content that is longer");
  write_atomically(dir.file("out.txt"), [](std::ostream& out) { out << "new"; });
  EXPECT_EQ(read_file(dir.file("out.txt")), "new");
  EXPECT_EQ(dir.files(), std::vector<std::string>{"out.txt"});
}

TEST(AtomicFile, MissingDirectoryThrowsNamingThePath) {
  const TempDir dir;
  const std::string path = dir.file("missing/out.txt");
  try {
    write_atomically(path, [](std::ostream& out) { out << "x"; });
    FAIL() << "no error";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos) << error.what();
  }
  EXPECT_TRUE(dir.files().empty());
}

TEST(AtomicFile, ThrowingWriterLeavesNoFileAndKeepsItsErrorType) {
  const TempDir dir;
  EXPECT_THROW(write_atomically(dir.file("out.txt"),
                                [](std::ostream& out) {
                                  out << "partial";
                                  throw tensormass::InputError("bad element");
                                }),
               tensormass::InputError);
  EXPECT_TRUE(dir.files().empty());
}

TEST(AtomicFile, FailedWriteKeepsTheOldFile) {
  const TempDir dir;
  dir.write("out.txt", "old");
  EXPECT_THROW(write_atomically(dir.file("out.txt"),
                                [](std::ostream& out) {
                                  out << "partial";
                                  out.setstate(std::ios::badbit);  // as a full disk would
                                }),
               std::runtime_error);
  EXPECT_EQ(read_file(dir.file("out.txt")), "old");
  EXPECT_EQ(dir.files(), std::vector<std::string>{"out.txt"});
}

TEST(AtomicFile, TargetThatIsADirectoryFailsCleanly) {
  const TempDir dir;
  std::filesystem::create_directory(dir.file("target"));
  std::filesystem::create_directory(dir.file("target/inside"));  // a non-empty directory cannot be replaced
  EXPECT_THROW(write_atomically(dir.file("target"), [](std::ostream& out) { out << "x"; }), std::runtime_error);
  EXPECT_EQ(dir.files(), std::vector<std::string>{"target"});
}

}  // namespace
