// The in-memory input reader (common/input_cursor.hpp): tokens with their
// line numbers, counts checked against the bytes left, binary values in
// either byte order, and errors naming "FILE:LINE" or "FILE: byte N".
#include <gtest/gtest.h>

#include <climits>
#include <cstdint>
#include <string>

#include "common/input_cursor.hpp"
#include "support/input_error.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::detail {
namespace {

using test_support::input_error;

TEST(InputCursor, TokensCarryTheLineTheyStartOn) {
  InputCursor in("mesh.msh", "alpha beta\n\n  gamma\t\r\ndelta");
  EXPECT_EQ(in.token("first"), "alpha");
  EXPECT_EQ(in.line(), 1);
  EXPECT_EQ(in.token("second"), "beta");
  EXPECT_EQ(in.here().value, 3);  // skips the blank line before gamma
  EXPECT_FALSE(in.here().byte);
  EXPECT_EQ(in.token("third"), "gamma");
  EXPECT_EQ(in.token("fourth"), "delta");
  EXPECT_EQ(in.line(), 4);
  EXPECT_TRUE(in.at_end());
  EXPECT_EQ(in.remaining(), 0u);
}

TEST(InputCursor, TokenAtTheEndNamesFileLineAndWhatWasExpected) {
  InputCursor in("mesh.msh", "3\n\n");
  in.token("count");
  EXPECT_EQ(input_error([&] { in.token("the node count"); }),
            "mesh.msh:3: unexpected end of file (truncated file?), expected the node count");
}

TEST(InputCursor, PeekTokenLeavesTheTokenToRead) {
  InputCursor in("f", "  one two");
  EXPECT_EQ(in.peek_token(), "one");
  EXPECT_EQ(in.peek_token(), "one");
  EXPECT_EQ(in.token("x"), "one");
  EXPECT_EQ(in.token("x"), "two");
  EXPECT_EQ(in.peek_token(), "");
}

TEST(InputCursor, ExpectRefusesAnotherKeywordQuotingIt) {
  InputCursor in("mesh.msh", "$Nodes\n$Elements");
  in.expect("$Nodes");
  EXPECT_EQ(input_error([&] { in.expect("$EndNodes"); }), "mesh.msh:2: expected $EndNodes, found '$Elements'");
}

TEST(InputCursor, RestOfLineIsTrimmedAndCountsItsNewline) {
  InputCursor in("f", "key   some words here  \r\nnext\nlast  ");
  in.token("key");
  EXPECT_EQ(in.rest_of_line(), "some words here");
  EXPECT_EQ(in.line(), 2);
  EXPECT_EQ(in.rest_of_line(), "next");
  EXPECT_EQ(in.rest_of_line(), "last");  // no newline at the end: the line stays 3
  EXPECT_EQ(in.line(), 3);
  EXPECT_EQ(in.remaining(), 0u);
}

TEST(InputCursor, SkipLineEndStopsAtAnythingButSpaces) {
  InputCursor in("f", "a \t\r\nb  c\n");
  in.token("a");
  in.skip_line_end();
  EXPECT_EQ(in.line(), 2);
  EXPECT_EQ(in.position(), 5u);
  in.token("b");
  in.skip_line_end();  // "c" is on the same line: not skipped
  EXPECT_EQ(in.line(), 2);
  EXPECT_EQ(in.token("c"), "c");
}

TEST(InputCursor, SkipPastCountsTheLinesItPassesAndNamesAMissingMarker) {
  InputCursor in("mesh.msh", "$Comment\nx\ny\n$EndComment 7");
  in.skip_past("$EndComment", "$EndComment");
  EXPECT_EQ(in.line(), 4);
  EXPECT_EQ(in.integer("value"), 7);
  InputCursor missing("mesh.msh", "a\nb\n");
  EXPECT_EQ(input_error([&] { missing.skip_past("$EndNodes", "the end of the nodes"); }),
            "mesh.msh:1: missing the end of the nodes (end of file reached)");
  EXPECT_EQ(missing.position(), 0u);
}

TEST(InputCursor, IntegersAcceptAPlusSignAndRefuseGarbageOrOverflow) {
  InputCursor in("f", "42 +7 -3 12x 99999999999999999999 1.0");
  EXPECT_EQ(in.integer("a"), 42);
  EXPECT_EQ(in.integer("b"), 7);
  EXPECT_EQ(in.integer("c"), -3);
  EXPECT_EQ(input_error([&] { in.integer("node id"); }), "f:1: expected an integer (node id), found '12x'");
  EXPECT_EQ(input_error([&] { in.integer("tag"); }), "f:1: expected an integer (tag), found '99999999999999999999'");
  EXPECT_EQ(input_error([&] { in.integer("tag"); }), "f:1: expected an integer (tag), found '1.0'");
}

TEST(InputCursor, RealsReadEveryNotationAndRefuseGarbage) {
  InputCursor in("f", "1.5 -2e-3 +4 1E3 0x1p3 \n1,5");
  EXPECT_EQ(in.real("a"), 1.5);
  EXPECT_EQ(in.real("b"), -2e-3);
  EXPECT_EQ(in.real("c"), 4.0);
  EXPECT_EQ(in.real("d"), 1000.0);
  EXPECT_EQ(input_error([&] { in.real("e"); }), "f:1: expected a number (e), found '0x1p3'");
  EXPECT_EQ(input_error([&] { in.real("y coordinate"); }), "f:2: expected a number (y coordinate), found '1,5'");
}

TEST(InputCursor, CountsAreCheckedAgainstTheBytesLeftBeforeAnyAllocation) {
  InputCursor fits("f", "3\n1 2 3");
  EXPECT_EQ(fits.count("values", 2), 3);  // 6 bytes left hold 3 of 2 bytes each
  InputCursor too_many("f", "10\n1 2");
  EXPECT_EQ(input_error([&] { too_many.count("nodes", 2); }),
            "f:1: the file declares 10 nodes but only 4 bytes are left (truncated file or bad count)");
  InputCursor unchecked("f", "1000000");
  EXPECT_EQ(unchecked.count("items", 0), 1000000);  // no bytes asked for each: only the limit applies
}

TEST(InputCursor, ACountErrorNamesTheLineOfTheCount) {
  InputCursor negative("f", "\n\n  -3\n");
  EXPECT_EQ(input_error([&] { negative.count("elements", 1); }), "f:3: negative elements -3");
  InputCursor huge("f", "\n2147483648");
  EXPECT_EQ(input_error([&] { huge.count("nodes", 0); }),
            "f:2: 2147483648 nodes is more than this program supports (2147483647)");
  InputCursor at_limit("f", std::to_string(INT_MAX));
  EXPECT_EQ(at_limit.count("nodes", 0), INT_MAX);
}

TEST(InputCursor, CheckedCountNamesTheByteWhereABinaryCountWasRead) {
  const InputCursor in("data.vtu", std::string(8, '\0'));
  EXPECT_EQ(in.checked_count(4, "points", 2, Location{3, true}), 4);
  EXPECT_EQ(input_error([&] {
              in.checked_count(5, "points", 2, Location{3, true});
            }),
            "data.vtu: byte 3: the file declares 5 points but only 8 bytes are left (truncated file or bad count)");
  EXPECT_EQ(input_error([&] {
              in.checked_count(1ull << 40, "cells", 0, Location{0, true});
            }),
            "data.vtu: byte 0: 1099511627776 cells is more than this program supports (2147483647)");
}

TEST(InputCursor, BinaryValuesReadInEitherByteOrder) {
  const std::string data("\x01\x02\x03\x04\x00\x00\x00\x00\x00\x00\xf0\x3f", 12);
  InputCursor in("f.bin", data);
  in.set_binary(true);
  EXPECT_EQ(in.value<std::uint16_t>("a"), 0x0201);
  EXPECT_EQ(in.value<std::uint16_t>("b", std::endian::big), 0x0304);
  EXPECT_EQ(in.value<double>("c"), 1.0);
  EXPECT_EQ(in.position(), 12u);
  InputCursor big("f.bin", std::string("\x3f\xf0\0\0\0\0\0\0\x12\x34\x56\x78", 12));
  EXPECT_EQ(big.value<double>("d", std::endian::big), 1.0);
  EXPECT_EQ(big.value<std::int32_t>("e", std::endian::big), 0x12345678);
}

TEST(InputCursor, BinaryErrorsNameTheByteOffset) {
  InputCursor in("f.bin", std::string("\x01\x02\x03\x04\x05\x06", 6));
  in.set_binary(true);
  in.bytes(4, "header");
  EXPECT_EQ(in.here().value, 4);
  EXPECT_TRUE(in.here().byte);
  EXPECT_EQ(input_error([&] { in.value<std::uint32_t>("the point count"); }),
            "f.bin: byte 4: unexpected end of file reading the point count (truncated file? 4 bytes needed, 2 left)");
  EXPECT_EQ(in.position(), 4u);  // nothing consumed by the failed read
  EXPECT_EQ(input_error([&] { in.fail("bad block"); }), "f.bin: byte 4: bad block");
}

TEST(InputCursor, BinaryModeDoesNotSkipWhitespace) {
  InputCursor in("f", std::string("  \n\x07", 4));
  in.set_binary(true);
  EXPECT_EQ(in.here().value, 0);
  EXPECT_EQ(in.value<std::uint8_t>("first"), ' ');
}

TEST(InputCursor, LineAtCountsNewlinesBeforeAnOffset) {
  const InputCursor in("f", "a\nb\n\nc");
  EXPECT_EQ(in.line_at(0), 1);
  EXPECT_EQ(in.line_at(2), 2);
  EXPECT_EQ(in.line_at(5), 4);
  EXPECT_EQ(in.line_at(1000), 4);  // past the end: the last line
}

TEST(InputCursor, FailAtNamesTheGivenLocation) {
  const InputCursor in("scene.yaml", "x");
  EXPECT_EQ(input_error([&] { in.fail_at(Location{12, false}, "bad key"); }), "scene.yaml:12: bad key");
}

TEST(InputCursor, ReleaseFreesTheText) {
  InputCursor in("f", "some text");
  in.token("x");
  in.release();
  EXPECT_TRUE(in.data().empty());
  EXPECT_EQ(in.position(), 0u);
  EXPECT_EQ(in.remaining(), 0u);
}

TEST(Quoted, QuotesAtMostFortyCharactersShowingNonPrintableOnesAsQuestionMarks) {
  EXPECT_EQ(detail::quoted("abc"), "'abc'");
  EXPECT_EQ(detail::quoted(""), "''");
  EXPECT_EQ(detail::quoted(std::string("a\tb\x01\xff", 5)), "'a?b\?\?'");
  EXPECT_EQ(detail::quoted(std::string(40, 'x')), "'" + std::string(40, 'x') + "'");
  EXPECT_EQ(detail::quoted(std::string(41, 'x')), "'" + std::string(40, 'x') + "...'");
}

TEST(FormatLocation, NamesALineOrAByte) {
  EXPECT_EQ(format_location("a.msh", Location{7, false}), "a.msh:7");
  EXPECT_EQ(format_location("a.vtu", Location{1024, true}), "a.vtu: byte 1024");
}

TEST(ParseNumber, TakesWholeTokensOnly) {
  long integer = 0;
  EXPECT_TRUE(parse_integer("+12", integer));
  EXPECT_EQ(integer, 12);
  for (const char* bad : {"", "+", "-", "+-5", "++5", "1 ", " 1", "1e3", "0x10", "9223372036854775808"})
    EXPECT_FALSE(parse_integer(bad, integer)) << "'" << bad << "'";
  EXPECT_TRUE(parse_integer("-9223372036854775808", integer));
  EXPECT_EQ(integer, LONG_MIN);
  double real = 0;
  EXPECT_TRUE(parse_real("+.5", real));
  EXPECT_EQ(real, 0.5);
  EXPECT_TRUE(parse_real("-1e-300", real));
  EXPECT_EQ(real, -1e-300);
  for (const char* bad : {"", "+", ".", "+-5", "+-.5", "1.0x", "1e", "e3", "1e999"})
    EXPECT_FALSE(parse_real(bad, real)) << "'" << bad << "'";
}

}  // namespace
}  // namespace tensormass::detail
