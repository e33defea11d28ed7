// StreamedFile: rows appended as a run goes, `.partial` until finished, and
// a resumed run's file cut back to a checkpoint's mark or refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/streamed_file.hpp"

namespace {

using tensormass::InputError;
using tensormass::io::StreamedFile;
using tensormass::io::StreamMark;
using test_support::read_file;
using test_support::TempDir;

/// A file with a header and `rows` rows "row k\n", marked after `marked` of them.
StreamMark write_rows(const std::string& path, int rows, int marked) {
  StreamedFile file(path, "header\n");
  StreamMark mark;
  for (int k = 0; k < rows; ++k) {
    if (k == marked) mark = file.mark();
    file.append("row " + std::to_string(k) + "\n");
  }
  if (marked >= rows) mark = file.mark();
  return mark;
}

TEST(StreamedFile, IsPartialUntilFinished) {
  const TempDir dir;
  StreamedFile file(dir.file("out.csv"), "a,b\n");
  file.append("1,2\n");
  EXPECT_EQ(dir.files(), std::vector<std::string>{"out.csv.partial"});
  file.finish();
  EXPECT_EQ(dir.files(), std::vector<std::string>{"out.csv"});
  EXPECT_EQ(read_file(dir.file("out.csv")), "a,b\n1,2\n");
}

TEST(StreamedFile, ManyRowsPassTheBuffer) {
  const TempDir dir;
  std::string expected = "h\n";
  StreamedFile file(dir.file("big.csv"), "h\n");
  for (int k = 0; k < 20000; ++k) {
    const std::string row = std::to_string(k) + ",0.123456789\n";
    file.append(row);
    expected += row;
  }
  const StreamMark mark = file.mark();
  EXPECT_EQ(mark.rows, 20000u);
  EXPECT_EQ(mark.bytes, expected.size());
  EXPECT_EQ(read_file(dir.file("big.csv.partial")), expected);  // mark() wrote every buffered row
  file.finish();
  EXPECT_EQ(read_file(dir.file("big.csv")), expected);
}

TEST(StreamedFile, MarkCountsRowsAndBytes) {
  const TempDir dir;
  StreamedFile file(dir.file("m.csv"), "hh\n");
  EXPECT_EQ(file.mark().rows, 0u);
  EXPECT_EQ(file.mark().bytes, 3u);
  file.append("x\n");
  const StreamMark one = file.mark();
  EXPECT_EQ(one.rows, 1u);
  EXPECT_EQ(one.bytes, 5u);
  file.append("y\n");
  EXPECT_NE(file.mark().checksum, one.checksum);
}

TEST(StreamedFile, ResumeCutsBackToTheMarkAndContinues) {
  const TempDir dir;
  const std::string path = dir.file("t.csv");
  const StreamMark mark = write_rows(path, 5, 2);  // a killed run: rows 2..4 come after its checkpoint
  StreamedFile resumed = StreamedFile::resume(path, mark);
  EXPECT_EQ(read_file(path + ".partial"), "header\nrow 0\nrow 1\n");
  resumed.append("again\n");
  EXPECT_EQ(resumed.mark().rows, 3u);
  resumed.finish();
  EXPECT_EQ(read_file(path), "header\nrow 0\nrow 1\nagain\n");
}

TEST(StreamedFile, ResumeTakesAFinishedFile) {
  const TempDir dir;
  const std::string path = dir.file("t.csv");
  StreamMark mark;
  {
    StreamedFile file(path, "header\n");
    file.append("row 0\n");
    mark = file.mark();
    file.append("row 1\n");
    file.finish();
  }
  StreamedFile resumed = StreamedFile::resume(path, mark);
  EXPECT_EQ(dir.files(), std::vector<std::string>{"t.csv.partial"});
  resumed.finish();
  EXPECT_EQ(read_file(path), "header\nrow 0\n");
}

TEST(StreamedFile, ResumeRefusesAFileThatIsNotTheMarkedOne) {
  const TempDir dir;
  const std::string path = dir.file("t.csv");
  const StreamMark mark = write_rows(path, 3, 3);
  auto refusal = [&](const StreamMark& m) -> std::string {
    try {
      StreamedFile::resume(path, m);
    } catch (const InputError& e) {
      return e.what();
    }
    return "resumed";
  };
  StreamMark longer = mark;
  longer.bytes += 1;
  EXPECT_NE(refusal(longer).find("fewer bytes"), std::string::npos) << refusal(longer);
  dir.write("t.csv.partial", "header\nrow 0\nrow X\nrow 2\n");  // same length, edited
  EXPECT_NE(refusal(mark).find("not the file the checkpoint was written with"), std::string::npos);
  std::filesystem::remove(path + ".partial");
  const std::string missing = refusal(mark);
  EXPECT_NE(missing.find(path + ".partial is missing"), std::string::npos) << missing;
  EXPECT_NE(missing.find("remove the checkpoint"), std::string::npos) << missing;
}

TEST(StreamedFile, AFileThatCannotBeCreatedIsAnInputError) {
  const TempDir dir;
  EXPECT_THROW(StreamedFile(dir.file("no/such/dir/t.csv"), "h\n"), InputError);
}

TEST(StreamedFile, DestroyedUnfinishedLeavesThePartialFile) {
  const TempDir dir;
  { StreamedFile(dir.file("t.csv"), "h\n").append("1\n"); }
  EXPECT_EQ(dir.files(), std::vector<std::string>{"t.csv.partial"});
  EXPECT_EQ(read_file(dir.file("t.csv.partial")), "h\n1\n");
}

}  // namespace
