// One run per output directory (io/output_directory.hpp): a second lock of a
// held directory is refused naming it and the holder's process id, a
// released one can be taken again, taking it removes the temporaries of
// dead runs and nothing else, and a path that cannot be a directory is
// refused.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/output_directory.hpp"

namespace tensormass::io {
namespace {

namespace fs = std::filesystem;
using test_support::expect_contains;
using test_support::TempDir;

TEST(OutputDirectoryLock, CreatesTheDirectoryAndRefusesASecondHolder) {
  TempDir dir;
  const std::string out = dir.file("out/nested");
  OutputDirectoryLock first(out);
  EXPECT_TRUE(fs::is_directory(out));
  EXPECT_EQ(test_support::read_file(fs::path(out) / kOutputLockFile), std::to_string(::getpid()) + "\n");
  try {
    OutputDirectoryLock second(out);
    ADD_FAILURE() << "two locks on one directory";
  } catch (const InputError& e) {
    expect_contains(e.what(),
                    {"output directory " + out, "in use by another run", "process " + std::to_string(::getpid())});
  }
  first.release();
  EXPECT_NO_THROW(OutputDirectoryLock again(out));
}

TEST(OutputDirectoryLock, RemovesTheTemporariesOfDeadRunsOnly) {
  TempDir dir;
  fs::create_directory(dir.path() / "out");
  for (const char* name :
       {"frame_000002.vtu.tmp-4242", "checkpoint.bin.tmp-17", "frame_000001.vtu", "notes.tmp", "series.pvd.tmp-x1"})
    std::ofstream(dir.path() / "out" / name) << "x";
  const OutputDirectoryLock lock(dir.file("out"));
  EXPECT_EQ(lock.removed_temporaries(), 2);
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "frame_000002.vtu.tmp-4242"));
  EXPECT_FALSE(fs::exists(dir.path() / "out" / "checkpoint.bin.tmp-17"));
  for (const char* kept : {"frame_000001.vtu", "notes.tmp", "series.pvd.tmp-x1"})
    EXPECT_TRUE(fs::exists(dir.path() / "out" / kept)) << kept;
}

TEST(OutputDirectoryLock, AFileInPlaceOfTheDirectoryIsRefused) {
  TempDir dir;
  std::ofstream(dir.path() / "out") << "a file";
  try {
    OutputDirectoryLock lock(dir.file("out"));
    ADD_FAILURE() << "locked a file";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"output directory " + dir.file("out")});
  }
}

}  // namespace
}  // namespace tensormass::io
