/// \file input_cursor.hpp
/// Internal (not installed): reading input files held in memory (read by
/// read_regular_file, common/regular_file.hpp). InputCursor walks the bytes
/// (text tokens with line numbers, binary values with byte offsets) and
/// throws InputError "FILE:LINE: what" or "FILE: byte N: what".
#ifndef TENSORMASS_COMMON_INPUT_CURSOR_HPP
#define TENSORMASS_COMMON_INPUT_CURSOR_HPP

#include <bit>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <utility>

namespace tensormass::detail {

/// `text` in single quotes for messages, at most 40 characters, non-printable ones as '?'.
std::string quoted(std::string_view text);

/// Where something was read: a line (text) or a byte offset (binary).
struct Location {
  long value = 0;
  bool byte = false;
};

/// "FILE:LINE" or "FILE: byte N".
std::string format_location(const std::string& file, Location where);

/// The whole content of a file and a read position.
/// Text is read as whitespace-separated tokens; each newline passed counts a
/// line. Once `set_binary(true)` is called, errors name byte offsets instead.
class InputCursor {
 public:
  InputCursor(std::string path, std::string data) : path_(std::move(path)), data_(std::move(data)) {}

  const std::string& path() const { return path_; }
  std::string_view data() const { return data_; }
  /// Frees the text once everything was read from it (a reader's last step
  /// then runs without it); nothing may be read after.
  void release() {
    std::string().swap(data_);
    pos_ = 0;
  }
  std::size_t position() const { return pos_; }
  std::size_t remaining() const { return data_.size() - pos_; }
  long line() const { return line_; }
  bool binary() const { return binary_; }
  void set_binary(bool binary) { binary_ = binary; }
  Location location() const { return binary_ ? Location{static_cast<long>(pos_), true} : Location{line_, false}; }
  /// Where the next item starts: skips whitespace first in text mode (so the
  /// line is the item's own), nothing in binary mode.
  Location here() {
    if (!binary_) at_end();
    return location();
  }
  /// The line number of byte `offset` (counted from the start of the file).
  long line_at(std::size_t offset) const;

  /// Skips whitespace; true when nothing but whitespace is left.
  bool at_end();
  /// The next token; throws "unexpected end of file, expected WHAT" at the end.
  std::string_view token(std::string_view what);
  /// The next token without consuming it ("" at the end).
  std::string_view peek_token();
  /// The rest of the current line (trimmed), consuming its newline.
  std::string_view rest_of_line();
  /// Consumes spaces up to and including the end of the current line.
  void skip_line_end();
  /// Consumes the next token and throws unless it equals `keyword`.
  void expect(std::string_view keyword);
  /// Moves past the next occurrence of `marker` (not consumed when absent: throws).
  void skip_past(std::string_view marker, std::string_view what);

  long integer(std::string_view what);
  double real(std::string_view what);
  /// A count in [0, limit]: refuses counts that cannot fit in the bytes left
  /// (min_bytes_each per item) before anything is allocated for them.
  long count(std::string_view what, std::size_t min_bytes_each);
  /// Checks a count read elsewhere (binary) the same way; `where` is where it was read.
  long checked_count(unsigned long long n, std::string_view what, std::size_t min_bytes_each, Location where) const;

  /// `n` raw bytes; throws when fewer are left.
  std::span<const unsigned char> bytes(std::size_t n, std::string_view what);
  /// A binary value of type T stored little- or big-endian.
  template <class T>
  T value(std::string_view what, std::endian order = std::endian::little) {
    const auto raw = bytes(sizeof(T), what);
    unsigned char buffer[sizeof(T)];
    std::memcpy(buffer, raw.data(), sizeof(T));
    if (order != std::endian::native)
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(buffer[i], buffer[sizeof(T) - 1 - i]);
    T result;
    std::memcpy(&result, buffer, sizeof(T));
    return result;
  }

  /// Throws InputError "FILE:LINE: message" (or "FILE: byte N: message").
  [[noreturn]] void fail(const std::string& message) const;
  [[noreturn]] void fail_at(Location where, const std::string& message) const;

 private:
  std::string path_;
  std::string data_;
  std::size_t pos_ = 0;
  long line_ = 1;
  bool binary_ = false;
};

/// Parses a whole token as a number; false on garbage or overflow.
bool parse_integer(std::string_view text, long& value);
bool parse_real(std::string_view text, double& value);

}  // namespace tensormass::detail

#endif
