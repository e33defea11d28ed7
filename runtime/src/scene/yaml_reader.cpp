#include "scene/yaml_reader.hpp"

#include <yaml-cpp/depthguard.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>

#include "common/regular_file.hpp"
#include "scene/yaml_limits.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::scene_yaml {

// --- Path ------------------------------------------------------------------

Path Path::child(std::string_view key) const {
  Path out = *this;
  out.segments_.push_back({std::string(key), -1});
  return out;
}

Path Path::item(int index) const {
  Path out = *this;
  out.segments_.push_back({{}, index});
  return out;
}

std::string Path::text() const {
  std::string out;
  for (const Segment& s : segments_) {
    if (s.index >= 0) {
      out += "[" + std::to_string(s.index) + "]";
    } else {
      if (!out.empty()) out += ".";
      out += s.key;
    }
  }
  return out;
}

std::string Path::pattern() const {
  std::string out;
  for (const Segment& s : segments_) {
    if (s.index >= 0) {
      out += "[]";
    } else {
      if (!out.empty()) out += ".";
      out += s.key;
    }
  }
  return out;
}

bool Path::starts_with(const Path& prefix) const {
  if (prefix.segments_.size() > segments_.size()) return false;
  for (std::size_t i = 0; i < prefix.segments_.size(); ++i)
    if (segments_[i].key != prefix.segments_[i].key || segments_[i].index != prefix.segments_[i].index) return false;
  return true;
}

// --- Source ----------------------------------------------------------------

void Source::add_override(const Path& path, const std::string& typed) { overrides_.emplace_back(path, typed); }

const std::string* Source::override_of(const Path& path) const {
  for (auto it = overrides_.rbegin(); it != overrides_.rend(); ++it)
    if (path.starts_with(it->first)) return &it->second;
  return nullptr;
}

const std::string* Source::override_below(const Path& path) const {
  for (auto it = overrides_.rbegin(); it != overrides_.rend(); ++it)
    if (it->first.starts_with(path)) return &it->second;
  return nullptr;
}

namespace {
int file_line(const YAML::Node& node) {
  if (!node.IsDefined()) return 0;
  const YAML::Mark mark = node.Mark();
  return mark.is_null() || mark.line < 0 ? 0 : mark.line + 1;
}
}  // namespace

int Source::line(const Path& path, const YAML::Node& node) const {
  if (override_of(path)) return 0;
  return file_line(node);
}

std::string Source::where(const Path& path, const YAML::Node& node) const {
  if (const std::string* typed = override_of(path)) return "--set " + *typed;
  if (const int l = file_line(node); l > 0) return file_ + ":" + std::to_string(l);
  if (const std::string* typed = override_below(path)) return "--set " + *typed;
  return file_;
}

// --- Reading a file --------------------------------------------------------

namespace {

/// "name:LINE" of a parser's mark (1-based), or "name" without one. A mark
/// at the end of the stream is on the text's last line, not past it.
std::string located(const std::string& name, const YAML::Mark& mark, const std::string& text) {
  if (mark.is_null() || mark.line < 0) return name;
  const long lines = std::count(text.begin(), text.end(), '\n') + (text.empty() || text.back() == '\n' ? 0 : 1);
  return name + ":" + std::to_string(std::min<long>(mark.line + 1, std::max(lines, 1L)));
}

/// Parses `text`; `name` labels messages. The document is refused when it
/// passes the bounds of yaml_limits.hpp.
YAML::Node parse_yaml(const std::string& text, const std::string& name) {
  if (text.size() > kMaxYamlBytes)
    throw InputError(name + ": the scene is " + std::to_string(text.size()) + " bytes, more than the " +
                     std::to_string(kMaxYamlBytes) + " a scene may have");
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::DeepRecursion& e) {  // yaml-cpp's own guard, far deeper than kMaxYamlDepth
    throw InputError(located(name, e.mark, text) + ": maps and lists nest deeper than " +
                     std::to_string(kMaxYamlDepth) + " levels");
  } catch (const YAML::Exception& e) {
    throw InputError(located(name, e.mark, text) + ": YAML syntax error: " + e.msg);
  }
  if (!root.IsDefined() || root.IsNull())
    throw InputError(name + ":1: the scene is empty (expected keys mesh, materials, solver, ...)");
  check_yaml_limits(root, name, text.size());
  return root;
}

}  // namespace

YAML::Node read_yaml_file(const std::string& file) {
  return parse_yaml(detail::read_regular_file(file, "scene", kMaxYamlBytes), file);
}

YAML::Node read_yaml_text(const std::string& text, const std::string& name) { return parse_yaml(text, name); }

// --- Value -----------------------------------------------------------------

bool Value::present() const { return node_.IsDefined() && !node_.IsNull(); }

std::string Value::describe() const {
  if (!present()) return "nothing";
  if (node_.IsSequence()) return "a list";
  if (node_.IsMap()) return "a map";
  return "'" + node_.Scalar() + "'";
}

std::string Value::location() const {
  const std::string name = path_.text();
  return source_->where(path_, place_) + (name.empty() ? "" : ": " + name);
}

void Value::fail(const std::string& message) const {
  const std::string name = path_.text();
  throw InputError(source_->where(path_, place_) + ": " + (name.empty() ? "" : name + ": ") + message);
}

void Value::fail_here(const std::string& message) const {
  throw InputError(source_->where(path_, place_) + ": " + message);
}

void Value::expect_map() const {
  if (!is_map()) fail("expected a map of keys, got " + describe());
}

Value Value::child(std::string_view key) const {
  expect_map();
  for (auto it = node_.begin(); it != node_.end(); ++it)
    if (it->first.IsScalar() && it->first.Scalar() == key)
      return Value(*source_, it->second, path_.child(key), it->first);
  const YAML::Node& map = node_;
  return Value(*source_, map[std::string(key)], path_.child(key));  // absent: an invalid node
}

Value Value::required(std::string_view key, std::string_view reason) const {
  const Value value = child(key);
  const std::string suffix = reason.empty() ? std::string() : " " + std::string(reason);
  if (!value.node_.IsDefined()) fail_here("missing required key '" + value.path_.text() + "'" + suffix);
  if (!value.present()) value.fail("missing value" + suffix);
  return value;
}

std::vector<Value> Value::items() const {
  if (!is_list()) fail("expected a list, got " + describe());
  std::vector<Value> out;
  int index = 0;
  for (const YAML::Node& item : node_) out.emplace_back(*source_, item, path_.item(index++));
  return out;
}

std::vector<std::pair<Value, Value>> Value::entries() const {
  expect_map();
  std::vector<std::pair<Value, Value>> out;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (!it->first.IsScalar()) Value(*source_, it->first, path_).fail("map keys must be plain names");
    const Path path = path_.child(it->first.Scalar());
    out.emplace_back(Value(*source_, it->first, path), Value(*source_, it->second, path, it->first));
  }
  return out;
}

std::string Value::scalar() const { return is_scalar() ? node_.Scalar() : std::string(); }

std::string Value::text() const {
  if (!is_scalar()) fail("expected a string, got " + describe());
  if (node_.Scalar().empty()) fail("must not be empty");
  return node_.Scalar();
}

namespace {
enum class Parsed { ok, not_a_number, out_of_range };

Parsed parse_double(std::string_view s, double& value) {
  if (s.size() > 1 && s.front() == '+' && s[1] != '-') s.remove_prefix(1);  // "+-5" is no number
  if (s.empty()) return Parsed::not_a_number;
  const auto [end, error] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (end != s.data() + s.size()) return Parsed::not_a_number;
  if (error == std::errc::result_out_of_range) return Parsed::out_of_range;
  return error == std::errc() ? Parsed::ok : Parsed::not_a_number;
}

/// YAML's spellings of infinity and NaN (.inf, -.Inf, .NAN, ...).
bool is_yaml_non_finite(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s == ".inf" || s == "+.inf" || s == "-.inf" || s == ".nan";
}
}  // namespace

double Value::number() const {
  if (!is_scalar()) fail("expected a number, got " + describe());
  double value = 0;
  const Parsed parsed = parse_double(node_.Scalar(), value);
  if (parsed == Parsed::not_a_number && !is_yaml_non_finite(node_.Scalar()))
    fail("expected a number, got " + describe());
  if (parsed != Parsed::ok || !std::isfinite(value)) fail("expected a finite number, got " + describe());
  return value;
}

int Value::integer() const {
  if (!is_scalar()) fail("expected an integer, got " + describe());
  double value = 0;
  const bool ok = parse_double(node_.Scalar(), value) == Parsed::ok && std::isfinite(value);
  if (!ok || value != std::floor(value)) fail("expected an integer, got " + describe());
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())
    fail("integer out of range, got " + describe());
  return static_cast<int>(value);
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& name : names) out += (out.empty() ? "" : ", ") + name;
  return out;
}

}  // namespace tensormass::scene_yaml
