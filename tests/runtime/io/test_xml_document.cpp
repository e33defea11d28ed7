// The XML reader under the .vtu reader (io/xml_document.hpp), on text held
// in an InputCursor: elements, attributes (both quotes, entities), content
// ranges, nested children and line numbers; <AppendedData> ending the
// parse; the messages, with their lines, for malformed XML; and base64
// decoding (padding, bad characters, text cut short).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/input_cursor.hpp"
#include "io/xml_document.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::detail {
namespace {

std::string content(const InputCursor& in, const XmlElement& e) {
  return std::string(in.data().substr(e.content_begin, e.content_end - e.content_begin));
}

/// Parses `text` as doc.xml; expects an InputError whose message is `message`.
void expect_error(const std::string& text, const std::string& message) {
  const InputCursor in("doc.xml", text);
  try {
    const XmlDocument document(in);
    ADD_FAILURE() << "no error for: " << text;
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), message) << text;
  }
}

TEST(XmlDocument, ReadsElementsAttributesAndContent) {
  const InputCursor in("doc.xml",
                       "<?xml version=\"1.0\"?>\n"
                       "<!-- a <comment> -->\n"
                       "<VTKFile type=\"UnstructuredGrid\" note='a &lt;b&gt; &amp; &quot;c&quot; &apos;d&apos; &x;'>\n"
                       "  <Piece NumberOfPoints = \"3\">1 2\n3</Piece>\n"
                       "  <Empty/>\n"
                       "</VTKFile>\n");
  const XmlDocument document(in);
  ASSERT_EQ(document.elements.size(), 3u);
  const XmlElement& root = document.elements[0];
  EXPECT_EQ(root.name, "VTKFile");
  EXPECT_EQ(root.line, 3);
  EXPECT_EQ(root.parent, -1);
  EXPECT_EQ(root.attribute("type"), "UnstructuredGrid");
  EXPECT_EQ(root.attribute("note"), "a <b> & \"c\" 'd' &x;");
  EXPECT_EQ(root.attribute("missing"), "");
  EXPECT_EQ(root.attribute("missing", "fallback"), "fallback");
  EXPECT_EQ(root.children, (std::vector<int>{1, 2}));

  const XmlElement& piece = document.elements[1];
  EXPECT_EQ(piece.name, "Piece");
  EXPECT_EQ(piece.line, 4);
  EXPECT_EQ(piece.parent, 0);
  EXPECT_EQ(piece.attribute("NumberOfPoints"), "3");
  EXPECT_EQ(content(in, piece), "1 2\n3");
  EXPECT_EQ(in.data()[piece.begin], '<');

  const XmlElement& empty = document.elements[2];
  EXPECT_EQ(empty.line, 6);
  EXPECT_TRUE(empty.attributes.empty());
  EXPECT_EQ(empty.content_begin, empty.content_end);
  EXPECT_EQ(document.appended_begin, std::string::npos);
}

TEST(XmlDocument, ChildrenAreTheParentsOwnInFileOrder) {
  const InputCursor in("doc.xml", "<A>\n<B id='1'><B id='inner'/></B>\n<C/>\n<B id='2'/>\n</A>\n<A/>");
  const XmlDocument document(in);
  ASSERT_EQ(document.children(nullptr, "A").size(), 2u);
  const XmlElement* a = document.child(nullptr, "A");
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a, &document.elements[0]);
  const std::vector<const XmlElement*> bs = document.children(a, "B");
  ASSERT_EQ(bs.size(), 2u);
  EXPECT_EQ(bs[0]->attribute("id"), "1");
  EXPECT_EQ(bs[1]->attribute("id"), "2");
  EXPECT_EQ(bs[1]->line, 4);
  ASSERT_EQ(document.children(bs[0], "B").size(), 1u);
  EXPECT_EQ(document.child(bs[0], "B")->attribute("id"), "inner");
  EXPECT_EQ(document.child(bs[0], "B")->parent, 1);
  EXPECT_EQ(document.child(a, "C")->line, 3);
  EXPECT_EQ(document.child(a, "D"), nullptr);
  EXPECT_EQ(document.child(nullptr, "B"), nullptr);
}

TEST(XmlDocument, StopsAtAppendedData) {
  const std::string text = "<VTKFile>\n<AppendedData encoding=\"base64\">\n  _<</not xml>\n";
  const InputCursor in("doc.xml", text);
  const XmlDocument document(in);
  ASSERT_EQ(document.elements.size(), 2u);
  EXPECT_EQ(document.elements[1].name, "AppendedData");
  EXPECT_EQ(document.appended_encoding, "base64");
  EXPECT_EQ(document.appended_begin, text.find('_') + 1);

  const InputCursor raw("doc.xml", "<VTKFile><AppendedData>_\x01\x02");
  EXPECT_EQ(XmlDocument(raw).appended_encoding, "raw");
}

TEST(XmlDocument, MalformedXmlIsRefusedWithItsLine) {
  expect_error("<A>\n<B>\n", "doc.xml:3: unexpected end of file (truncated file?) inside <B>");
  expect_error("<A>\n<B x='1'", "doc.xml:2: unterminated tag <B>");
  expect_error("<A>\n<B x='1>", "doc.xml:2: unterminated attribute x");
  expect_error("<A>\n<B x=1>", "doc.xml:2: attribute x of <B> is not quoted");
  expect_error("<A>\n\n<B x>", "doc.xml:3: malformed attribute in <B>");
  expect_error("<A>\n< B>", "doc.xml:2: malformed XML tag");
  expect_error("<A>\n<B>\n</A>", "doc.xml:3: unexpected </A> (open: <B>)");
  expect_error("<A/>\n</A>", "doc.xml:2: unexpected </A>");
  expect_error("<A>\n</A", "doc.xml:2: unterminated end tag");
  expect_error("<A>\n<!-- never closed", "doc.xml:2: unterminated comment");
  expect_error("<?xml version='1.0'", "doc.xml:1: unterminated processing instruction");
  expect_error("\n<!DOCTYPE", "doc.xml:2: unterminated declaration");
  expect_error("<A>\n<AppendedData>\nno underscore", "doc.xml:2: <AppendedData> without the '_' that starts the data");
  expect_error("just text\n", "doc.xml:1: not an XML VTK file (no elements)");
}

std::string decoded(std::string_view text) {
  std::vector<unsigned char> bytes;
  EXPECT_TRUE(base64_decode(text, bytes)) << text;
  return std::string(bytes.begin(), bytes.end());
}

TEST(Base64, DecodesWithAndWithoutPadding) {
  EXPECT_EQ(decoded(""), "");
  EXPECT_EQ(decoded("QUJD"), "ABC");
  EXPECT_EQ(decoded("QUI="), "AB");
  EXPECT_EQ(decoded("QQ=="), "A");
  EXPECT_EQ(decoded("QUJDRA=="), "ABCD");
  EXPECT_EQ(decoded("QQ==QUJD"), "A");  // decoding stops at the padding
  EXPECT_EQ(decoded("AAD/+/8="), std::string("\x00\x00\xff\xfb\xff", 5));
}

TEST(Base64, BadCharactersAreRefused) {
  std::vector<unsigned char> bytes;
  EXPECT_FALSE(base64_decode("QU*D", bytes));
  EXPECT_FALSE(base64_decode("QU JD", bytes));  // whitespace is removed by the caller
  EXPECT_FALSE(base64_decode("QUJD\n", bytes));
  EXPECT_FALSE(base64_decode("QUJ-", bytes));
}

// Text cut short decodes to the bytes its characters hold, fewer than the
// declared size: the .vtu reader compares lengths with base64_length.
TEST(Base64, TruncatedTextDecodesToFewerBytes) {
  EXPECT_EQ(decoded("QUJ"), "AB");
  EXPECT_EQ(decoded("QU"), "A");
  EXPECT_EQ(decoded("Q"), "");
  EXPECT_EQ(base64_length(0), 0u);
  EXPECT_EQ(base64_length(1), 4u);
  EXPECT_EQ(base64_length(3), 4u);
  EXPECT_EQ(base64_length(4), 8u);
  EXPECT_EQ(base64_length(8), 12u);
  EXPECT_LT(std::string("QUJ").size(), base64_length(3));
}

}  // namespace
}  // namespace tensormass::detail
