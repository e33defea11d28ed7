// XXH3-64 checksums (common/checksum.hpp): xxHash's published value of the
// empty input, a piecewise checksum equal to the one-shot one, and every
// flipped bit of a buffer changing it.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "common/checksum.hpp"

namespace tensormass::detail {
namespace {

TEST(Checksum, EmptyInputHasXxh3sPublishedValue) {
  EXPECT_EQ(checksum("", 0), 0x2D06800538D394C2ull);
  EXPECT_EQ(Checksum().value(), 0x2D06800538D394C2ull);
}

TEST(Checksum, PiecesGiveTheChecksumOfTheWhole) {
  std::string bytes;
  for (int i = 0; i < 5000; ++i) bytes.push_back(static_cast<char>(i * 131 % 251));
  Checksum pieces;
  for (std::size_t at = 0, size = 1; at < bytes.size(); at += size, size = size * 3 % 97 + 1)
    pieces.update(bytes.data() + at, std::min(size, bytes.size() - at));
  EXPECT_EQ(pieces.value(), checksum(bytes.data(), bytes.size()));
}

TEST(Checksum, EveryFlippedBitChangesIt) {
  std::string bytes(300, 'x');
  const std::uint64_t whole = checksum(bytes.data(), bytes.size());
  for (std::size_t at = 0; at < bytes.size(); ++at)
    for (int bit = 0; bit < 8; ++bit) {
      std::string flipped = bytes;
      flipped[at] = static_cast<char>(flipped[at] ^ (1 << bit));
      ASSERT_NE(checksum(flipped.data(), flipped.size()), whole) << "byte " << at << " bit " << bit;
    }
}

}  // namespace
}  // namespace tensormass::detail
