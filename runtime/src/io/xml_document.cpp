// The XML reader under the .vtu reader (io/xml_document.hpp): a tokenizer
// for elements, attributes and content ranges, and base64 decoding.
#include "io/xml_document.hpp"

#include <cctype>

namespace tensormass::detail {

namespace {

std::string decode_entities(std::string_view text) {
  std::string result;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '&') {
      result += text[i];
      continue;
    }
    const std::size_t end = text.find(';', i);
    const std::string_view entity = end == std::string_view::npos ? std::string_view() : text.substr(i, end - i + 1);
    if (entity == "&lt;") result += '<';
    else if (entity == "&gt;") result += '>';
    else if (entity == "&amp;") result += '&';
    else if (entity == "&quot;") result += '"';
    else if (entity == "&apos;") result += '\'';
    else {
      result += '&';
      continue;
    }
    i = end;
  }
  return result;
}

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

}  // namespace

std::string XmlElement::attribute(std::string_view key, std::string fallback) const {
  for (const auto& [k, v] : attributes)
    if (k == key) return v;
  return fallback;
}

XmlDocument::XmlDocument(const InputCursor& in) : in_(in), text_(in.data()) { parse(); }

std::vector<const XmlElement*> XmlDocument::children(const XmlElement* parent, std::string_view name) const {
  std::vector<const XmlElement*> result;
  for (const int index : parent ? parent->children : top_level_)
    if (elements[static_cast<std::size_t>(index)].name == name)
      result.push_back(&elements[static_cast<std::size_t>(index)]);
  return result;
}

const XmlElement* XmlDocument::child(const XmlElement* parent, std::string_view name) const {
  const auto found = children(parent, name);
  return found.empty() ? nullptr : found.front();
}

void XmlDocument::fail(std::size_t offset, const std::string& message) const {
  in_.fail_at({in_.line_at(offset), false}, message);
}

std::size_t XmlDocument::skip_to(std::size_t from, std::string_view marker, std::string_view what) const {
  const std::size_t found = text_.find(marker, from);
  if (found == std::string_view::npos) fail(from, "unterminated " + std::string(what));
  return found + marker.size();
}

long XmlDocument::line_of(std::size_t offset) {
  for (; counted_to_ < offset; ++counted_to_)
    if (text_[counted_to_] == '\n') ++counted_line_;
  return counted_line_;
}

void XmlDocument::parse() {
  std::vector<int> open;
  std::size_t pos = 0;
  while (appended_begin == std::string::npos) {
    const std::size_t lt = text_.find('<', pos);
    if (lt == std::string_view::npos) break;
    const std::string_view rest = text_.substr(lt);
    if (rest.starts_with("<!--")) pos = skip_to(lt, "-->", "comment");
    else if (rest.starts_with("<?")) pos = skip_to(lt, "?>", "processing instruction");
    else if (rest.starts_with("<!")) pos = skip_to(lt, ">", "declaration");
    else if (rest.starts_with("</")) pos = end_tag(lt, open);
    else pos = start_tag(lt, open);
  }
  if (appended_begin == std::string::npos && !open.empty())
    fail(text_.size(), "unexpected end of file (truncated file?) inside <" +
                           elements[static_cast<std::size_t>(open.back())].name + ">");
  if (elements.empty()) fail(0, "not an XML VTK file (no elements)");
}

std::size_t XmlDocument::start_tag(std::size_t lt, std::vector<int>& open) {
  XmlElement element;
  element.begin = lt;
  element.line = line_of(lt);
  element.parent = open.empty() ? -1 : open.back();
  std::size_t i = lt + 1;
  auto is_name_char = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '-' || c == '.';
  };
  auto skip_space = [&] {
    while (i < text_.size() && std::isspace(static_cast<unsigned char>(text_[i]))) ++i;
  };
  while (i < text_.size() && is_name_char(text_[i])) element.name += text_[i++];
  if (element.name.empty()) fail(lt, "malformed XML tag");
  for (;;) {
    skip_space();
    if (i >= text_.size()) fail(lt, "unterminated tag <" + element.name + ">");
    if (text_[i] == '>' || text_.substr(i).starts_with("/>")) break;
    std::string key;
    while (i < text_.size() && is_name_char(text_[i])) key += text_[i++];
    skip_space();
    if (key.empty() || i >= text_.size() || text_[i] != '=') fail(i, "malformed attribute in <" + element.name + ">");
    ++i;
    skip_space();
    if (i >= text_.size() || (text_[i] != '"' && text_[i] != '\''))
      fail(i, "attribute " + key + " of <" + element.name + "> is not quoted");
    const char quote = text_[i++];
    const std::size_t end = text_.find(quote, i);
    if (end == std::string_view::npos) fail(i, "unterminated attribute " + key);
    element.attributes.emplace_back(key, decode_entities(text_.substr(i, end - i)));
    i = end + 1;
  }
  const bool self_closing = text_[i] == '/';
  i += self_closing ? 2 : 1;
  element.content_begin = element.content_end = i;
  const int index = static_cast<int>(elements.size());
  (element.parent < 0 ? top_level_ : elements[static_cast<std::size_t>(element.parent)].children).push_back(index);
  elements.push_back(std::move(element));
  if (elements.back().name == "AppendedData" && !self_closing) {
    appended_encoding = elements.back().attribute("encoding", "raw");
    const std::size_t underscore = text_.find('_', i);
    if (underscore == std::string_view::npos) fail(i, "<AppendedData> without the '_' that starts the data");
    appended_begin = underscore + 1;
  } else if (!self_closing) {
    open.push_back(static_cast<int>(elements.size()) - 1);
  }
  return i;
}

std::size_t XmlDocument::end_tag(std::size_t lt, std::vector<int>& open) {
  const std::size_t gt = text_.find('>', lt);
  if (gt == std::string_view::npos) fail(lt, "unterminated end tag");
  std::string_view name = text_.substr(lt + 2, gt - lt - 2);
  while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.remove_suffix(1);
  if (open.empty() || elements[static_cast<std::size_t>(open.back())].name != name)
    fail(lt, "unexpected </" + std::string(name.substr(0, 40)) + ">" +
                 (open.empty() ? std::string()
                               : " (open: <" + elements[static_cast<std::size_t>(open.back())].name + ">)"));
  elements[static_cast<std::size_t>(open.back())].content_end = lt;
  open.pop_back();
  return gt + 1;
}

bool base64_decode(std::string_view text, std::vector<unsigned char>& out) {
  out.clear();
  out.reserve(text.size() / 4 * 3 + 3);
  unsigned int buffer = 0;
  int bits = 0;
  for (char c : text) {
    if (c == '=') break;
    const int v = base64_value(c);
    if (v < 0) return false;
    buffer = (buffer << 6) | static_cast<unsigned int>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((buffer >> bits) & 0xffu));
    }
  }
  return true;
}

std::size_t base64_length(std::size_t bytes) { return (bytes + 2) / 3 * 4; }

}  // namespace tensormass::detail
