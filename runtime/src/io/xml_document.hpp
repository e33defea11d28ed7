/// \file xml_document.hpp
/// Internal (not installed): the small XML reader under the .vtu reader and
/// the base64 decoding of its data. XmlDocument tokenizes a file held in an
/// InputCursor into elements (names, attributes with entities decoded,
/// content ranges, lines, parent and children) and stops at
/// <AppendedData>, whose content is binary. Nothing else of XML is read:
/// comments, processing instructions and declarations are skipped, entities
/// are decoded in attribute values only.
#ifndef TENSORMASS_IO_XML_DOCUMENT_HPP
#define TENSORMASS_IO_XML_DOCUMENT_HPP

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "common/input_cursor.hpp"

namespace tensormass::detail {

/// One element of an XmlDocument.
struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;  ///< in file order, values with entities decoded
  std::size_t begin = 0;                                        ///< offset of '<'
  std::size_t content_begin = 0;                                ///< offset after the start tag's '>'
  std::size_t content_end = 0;  ///< offset of the end tag's '<' (content_begin when self-closing)
  long line = 1;                ///< line of '<'
  int parent = -1;              ///< index into XmlDocument::elements; -1 at the top level
  std::vector<int> children;    ///< indices into XmlDocument::elements, in file order

  /// Takes an attribute name; returns the value of the first attribute of
  /// that name, `fallback` when there is none.
  std::string attribute(std::string_view key, std::string fallback = {}) const;
};

/// A flat list of elements parsed up to <AppendedData> (whose content is binary).
class XmlDocument {
 public:
  /// Takes the cursor holding the file (only its data and path are used;
  /// it must outlive the document) and parses the whole text. Throws
  /// InputError "FILE:LINE: what" for a malformed or unterminated tag,
  /// attribute, comment, processing instruction or declaration, an end tag
  /// that closes no open element, an element left open at the end of the
  /// file, <AppendedData> without its '_', or a file with no element.
  explicit XmlDocument(const InputCursor& in);

  std::vector<XmlElement> elements;                ///< in file order; elements.front() is the first top-level one
  std::size_t appended_begin = std::string::npos;  ///< first byte after '_'
  std::string appended_encoding = "raw";           ///< <AppendedData encoding="...">, raw when not given

  /// Takes a parent (nullptr: the top level) and a name; returns the
  /// parent's own children of that name, in file order. Only the parent's
  /// children are looked at, so reading a file stays linear.
  std::vector<const XmlElement*> children(const XmlElement* parent, std::string_view name) const;
  /// Takes a parent (nullptr: the top level) and a name; returns the first
  /// of children(parent, name), nullptr when there is none.
  const XmlElement* child(const XmlElement* parent, std::string_view name) const;

 private:
  [[noreturn]] void fail(std::size_t offset, const std::string& message) const;
  void parse();
  std::size_t start_tag(std::size_t lt, std::vector<int>& open);
  std::size_t end_tag(std::size_t lt, std::vector<int>& open);
  std::size_t skip_to(std::size_t from, std::string_view marker, std::string_view what) const;
  /// Line of `offset`, counted on from the previous call (offsets only grow).
  long line_of(std::size_t offset);

  const InputCursor& in_;
  std::string_view text_;
  std::vector<int> top_level_;
  std::size_t counted_to_ = 0;
  long counted_line_ = 1;
};

/// Takes base64 text without whitespace; decodes it into `out` (cleared
/// first), stopping at the first '='. Returns false on a character outside
/// the base64 alphabet (`out` then holds what came before it). Text cut
/// short decodes to the whole bytes its characters hold: the caller checks
/// the length against base64_length.
bool base64_decode(std::string_view text, std::vector<unsigned char>& out);

/// Takes a byte count; returns the length of its base64 encoding, padding
/// included (4 characters per 3 bytes, rounded up).
std::size_t base64_length(std::size_t bytes);

}  // namespace tensormass::detail

#endif
