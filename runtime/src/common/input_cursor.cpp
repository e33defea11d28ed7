#include "common/input_cursor.hpp"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>

#include "tensormass/common/errors.hpp"

namespace tensormass::detail {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

}  // namespace

std::string quoted(std::string_view text) {
  std::string shown(text.substr(0, 40));
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return "'" + shown + (text.size() > 40 ? "...'" : "'");
}

std::string format_location(const std::string& file, Location where) {
  if (where.byte) return file + ": byte " + std::to_string(where.value);
  return file + ":" + std::to_string(where.value);
}

// ---------------------------------------------------------------- cursor

bool InputCursor::at_end() {
  while (pos_ < data_.size() && is_space(data_[pos_])) {
    if (data_[pos_] == '\n') ++line_;
    ++pos_;
  }
  return pos_ >= data_.size();
}

std::string_view InputCursor::token(std::string_view what) {
  if (at_end()) fail("unexpected end of file (truncated file?), expected " + std::string(what));
  const std::size_t begin = pos_;
  while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
  return std::string_view(data_).substr(begin, pos_ - begin);
}

std::string_view InputCursor::peek_token() {
  if (at_end()) return {};
  std::size_t end = pos_;
  while (end < data_.size() && !is_space(data_[end])) ++end;
  return std::string_view(data_).substr(pos_, end - pos_);
}

std::string_view InputCursor::rest_of_line() {
  const std::size_t begin = pos_;
  std::size_t end = data_.find('\n', pos_);
  if (end == std::string::npos) end = data_.size();
  pos_ = end < data_.size() ? end + 1 : end;
  if (end < data_.size()) ++line_;
  std::string_view text = std::string_view(data_).substr(begin, end - begin);
  while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
  return text;
}

void InputCursor::skip_line_end() {
  while (pos_ < data_.size() && (data_[pos_] == ' ' || data_[pos_] == '\t' || data_[pos_] == '\r')) ++pos_;
  if (pos_ < data_.size() && data_[pos_] == '\n') {
    ++pos_;
    ++line_;
  }
}

void InputCursor::expect(std::string_view keyword) {
  const std::string_view found = token(keyword);
  if (found != keyword) fail("expected " + std::string(keyword) + ", found " + quoted(found));
}

void InputCursor::skip_past(std::string_view marker, std::string_view what) {
  const std::size_t found = data_.find(marker, pos_);
  if (found == std::string::npos) fail("missing " + std::string(what) + " (end of file reached)");
  line_ += static_cast<long>(std::count(data_.begin() + static_cast<std::ptrdiff_t>(pos_),
                                        data_.begin() + static_cast<std::ptrdiff_t>(found), '\n'));
  pos_ = found + marker.size();
}

long InputCursor::integer(std::string_view what) {
  const std::string_view text = token(what);
  long value = 0;
  if (!parse_integer(text, value)) fail("expected an integer (" + std::string(what) + "), found " + quoted(text));
  return value;
}

double InputCursor::real(std::string_view what) {
  const std::string_view text = token(what);
  double value = 0;
  if (!parse_real(text, value)) fail("expected a number (" + std::string(what) + "), found " + quoted(text));
  return value;
}

long InputCursor::count(std::string_view what, std::size_t min_bytes_each) {
  const Location where = here();
  const long n = integer(what);
  if (n < 0) fail_at(where, "negative " + std::string(what) + " " + std::to_string(n));
  return checked_count(static_cast<unsigned long long>(n), what, min_bytes_each, where);
}

long InputCursor::checked_count(unsigned long long n, std::string_view what, std::size_t min_bytes_each,
                                Location where) const {
  if (n > static_cast<unsigned long long>(INT_MAX))
    fail_at(where, std::to_string(n) + " " + std::string(what) + " is more than this program supports (" +
                       std::to_string(INT_MAX) + ")");
  if (min_bytes_each > 0 && n > remaining() / min_bytes_each)
    fail_at(where, "the file declares " + std::to_string(n) + " " + std::string(what) + " but only " +
                       std::to_string(remaining()) + " bytes are left (truncated file or bad count)");
  return static_cast<long>(n);
}

std::span<const unsigned char> InputCursor::bytes(std::size_t n, std::string_view what) {
  if (n > remaining())
    fail("unexpected end of file reading " + std::string(what) + " (truncated file? " + std::to_string(n) +
         " bytes needed, " + std::to_string(remaining()) + " left)");
  const auto* begin = reinterpret_cast<const unsigned char*>(data_.data()) + pos_;
  pos_ += n;
  return {begin, n};
}

long InputCursor::line_at(std::size_t offset) const {
  offset = std::min(offset, data_.size());
  return 1 + static_cast<long>(std::count(data_.begin(), data_.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
}

void InputCursor::fail(const std::string& message) const { fail_at(location(), message); }

void InputCursor::fail_at(Location where, const std::string& message) const {
  throw InputError(format_location(path_, where) + ": " + message);
}

bool parse_integer(std::string_view text, long& value) {
  if (text.size() > 1 && text.front() == '+' && text[1] != '-') text.remove_prefix(1);  // "+-5" is no number
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size() && !text.empty();
}

bool parse_real(std::string_view text, double& value) {
  if (text.size() > 1 && text.front() == '+' && text[1] != '-') text.remove_prefix(1);  // "+-5" is no number
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size() && !text.empty();
}

}  // namespace tensormass::detail
