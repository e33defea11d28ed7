/// \file yaml_reader.hpp
/// Private helpers of the scene reader: paths into a YAML tree
/// ("materials[0].young"), where a value came from (file and line, or a
/// --set override), typed access that throws InputError with that place,
/// the unknown-key check and the application of --set overrides.
#ifndef TENSORMASS_SCENE_YAML_READER_HPP
#define TENSORMASS_SCENE_YAML_READER_HPP

#include <yaml-cpp/yaml.h>

#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace tensormass::scene_yaml {

/// A path from the root of the tree: map keys and list indices.
class Path {
 public:
  Path child(std::string_view key) const;
  Path item(int index) const;
  /// "materials[0].young": for messages.
  std::string text() const;
  /// "materials[].young": list indices dropped, to look up the key table.
  std::string pattern() const;
  bool starts_with(const Path& prefix) const;

 private:
  struct Segment {
    std::string key;
    int index = -1;  ///< >= 0 for a list item
  };
  std::vector<Segment> segments_;
};

/// Known keys of every map of the schema, by path pattern ("" is the root).
using KeyTable = std::map<std::string, std::vector<std::string>>;

/// The scene file and the overrides applied to its tree: says where a value
/// came from ("scene.yaml:7" or "--set solver.dt").
class Source {
 public:
  explicit Source(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }
  /// Records that `path` was replaced by the override typed as `typed` (the part before '=').
  void add_override(const Path& path, const std::string& typed);
  /// "scene.yaml:7", "--set solver.dt" or "scene.yaml" when no line is known.
  std::string where(const Path& path, const YAML::Node& node) const;
  /// 1-based line of `node` in the file; 0 when it came from an override or has no mark.
  int line(const Path& path, const YAML::Node& node) const;

 private:
  const std::string* override_of(const Path& path) const;
  const std::string* override_below(const Path& path) const;
  std::string file_;
  std::vector<std::pair<Path, std::string>> overrides_;
};

/// Reads a YAML file; throws InputError (missing file, syntax error with its line, empty file).
YAML::Node read_yaml_file(const std::string& file);
/// The same for a scene given as text; `name` stands for the file in messages.
YAML::Node read_yaml_text(const std::string& text, const std::string& name);

/// A node of the tree with its path and source, and typed reads that throw
/// InputError "where: path: message".
class Value {
 public:
  Value(const Source& source, YAML::Node node, Path path) : Value(source, node, std::move(path), node) {}
  /// `place` locates the value in messages: the key of a map entry, the node itself for list items.
  Value(const Source& source, YAML::Node node, Path path, YAML::Node place)
      : source_(&source), node_(std::move(node)), place_(std::move(place)), path_(std::move(path)) {}

  /// Present and not null (an empty value counts as absent).
  bool present() const;
  bool is_map() const { return present() && node_.IsMap(); }
  bool is_list() const { return present() && node_.IsSequence(); }
  bool is_scalar() const { return present() && node_.IsScalar(); }

  /// The child `key` of this map (possibly absent); fails when this is not a map.
  Value child(std::string_view key) const;
  /// Like child, but fails when the key is missing or has no value; `reason`
  /// is appended to the message ("for solver type implicit").
  Value required(std::string_view key, std::string_view reason = {}) const;
  /// The items of this list; fails when this is not a list.
  std::vector<Value> items() const;
  /// Key and value of every entry of this map (the key's Value points at the key).
  std::vector<std::pair<Value, Value>> entries() const;
  void expect_map() const;

  double number() const;       ///< a finite number
  int integer() const;         ///< an int (1e3 is accepted as 1000)
  std::string text() const;    ///< a non-empty scalar string
  std::string scalar() const;  ///< the raw scalar ("" when absent)

  int line() const { return source_->line(path_, place_); }
  const Path& path() const { return path_; }
  /// "'abc'", "a list", "a map" or "nothing": for "expected ..., got ..." messages.
  std::string describe() const;
  /// "scene.yaml:7: materials[0].fibres": the prefix of `fail`'s messages, for
  /// errors found later (a fibre file, a formula).
  std::string location() const;

  /// Throws InputError "where: path: message".
  [[noreturn]] void fail(const std::string& message) const;
  /// Throws InputError "where: message" (the message names the key itself).
  [[noreturn]] void fail_here(const std::string& message) const;

 private:
  const Source* source_;
  YAML::Node node_;
  YAML::Node place_;
  Path path_;
};

/// Fails on any map key that `table` does not list for that map's pattern,
/// and on duplicate keys.
void check_keys(const Value& value, const KeyTable& table);

/// Applies one "a.b=value" override (value in YAML syntax) to `root`,
/// creating missing maps of the schema; records it in `source`.
void apply_override(YAML::Node& root, const std::string& text, const KeyTable& table, Source& source);

/// "a, b, c".
std::string join(const std::vector<std::string>& names);

}  // namespace tensormass::scene_yaml

#endif
