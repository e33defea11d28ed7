// The key-level passes over a scene tree: rejecting unknown and duplicate
// keys, and applying --set overrides before validation.
#include <algorithm>
#include <set>

#include "scene/yaml_limits.hpp"
#include "scene/yaml_reader.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::scene_yaml {

namespace {

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

/// "solver.dt=0.01" split into its key path and its YAML value.
struct Assignment {
  std::string typed;                  ///< "solver.dt", as typed
  std::vector<std::string> segments;  ///< {"solver", "dt"}
  YAML::Node value;
};

[[noreturn]] void fail_override(const std::string& typed, const std::string& message) {
  throw InputError("--set " + typed + ": " + message);
}

std::vector<std::string> split_path(const std::string& typed) {
  std::vector<std::string> segments;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = typed.find('.', start);
    segments.push_back(trim(typed.substr(start, dot == std::string::npos ? std::string::npos : dot - start)));
    if (segments.back().empty()) fail_override(typed, "malformed key path (empty name between dots)");
    if (dot == std::string::npos) return segments;
    start = dot + 1;
  }
}

Assignment parse_assignment(const std::string& text) {
  const std::size_t equal = text.find('=');
  if (equal == std::string::npos)
    fail_override(text, "malformed override: expected key=value (for example solver.dt=0.005)");
  Assignment out;
  out.typed = trim(text.substr(0, equal));
  if (out.typed.empty()) fail_override(text, "malformed override: no key before '='");
  out.segments = split_path(out.typed);
  const std::string value = text.substr(equal + 1);
  try {
    out.value = YAML::Load(value);
  } catch (const YAML::Exception& e) {
    fail_override(out.typed, "cannot read the value '" + value + "' as YAML: " + e.msg);
  }
  check_yaml_limits(out.value, "--set " + out.typed, value.size());
  return out;
}

int list_index(const Assignment& a, const Path& path, const std::string& segment, std::size_t size) {
  const bool digits = !segment.empty() && segment.size() < 9 &&
                      std::all_of(segment.begin(), segment.end(), [](char c) { return c >= '0' && c <= '9'; });
  const int index = digits ? std::stoi(segment) : -1;
  if (index < 0 || static_cast<std::size_t>(index) >= size)
    fail_override(a.typed, "'" + path.text() + "' is a list of " + std::to_string(size) +
                               " items: expected an index from 0, got '" + segment + "'");
  return index;
}

void check_known_key(const Assignment& a, const Path& path, const std::string& key, const KeyTable& table) {
  const auto known = table.find(path.pattern());
  if (known == table.end()) fail_override(a.typed, "'" + path.text() + "' takes a value, not keys");
  if (!contains(known->second, key))
    fail_override(a.typed, "unknown key '" + path.child(key).text() + "' (known: " + join(known->second) + ")");
}

/// The map `key` of `map`, created when absent or empty (only maps of the schema are created).
YAML::Node enter_map_key(YAML::Node& map, const std::string& key, const Assignment& a, const Path& path,
                         const KeyTable& table) {
  YAML::Node next = map[key];
  if (next.IsDefined() && !next.IsNull()) return next;
  if (table.find(path.pattern()) == table.end())
    fail_override(a.typed, "'" + path.text() + "' is not in the scene: set it whole (--set " + path.text() + "=...)");
  map[key] = YAML::Node(YAML::NodeType::Map);
  return map[key];
}

}  // namespace

void check_keys(const Value& value, const KeyTable& table) {
  if (value.is_list()) {
    for (const Value& item : value.items()) check_keys(item, table);
    return;
  }
  if (!value.is_map()) return;
  const auto known = table.find(value.path().pattern());
  if (known == table.end()) return;  // a map where a value belongs: the typed read reports it
  std::set<std::string> seen;
  for (const auto& [key, child] : value.entries()) {
    const std::string name = key.scalar();
    if (!contains(known->second, name))
      key.fail_here("unknown key '" + key.path().text() + "' (known: " + join(known->second) + ")");
    if (!seen.insert(name).second) key.fail_here("duplicate key '" + key.path().text() + "'");
    check_keys(child, table);
  }
}

void apply_override(YAML::Node& root, const std::string& text, const KeyTable& table, Source& source) {
  const Assignment a = parse_assignment(text);
  YAML::Node current = root;  // shares root's node: edits land in the tree
  Path path;
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    const std::string& segment = a.segments[i];
    const bool last = i + 1 == a.segments.size();
    if (current.IsSequence()) {
      const int index = list_index(a, path, segment, current.size());
      path = path.item(index);
      if (last) current[index] = a.value;
      else current.reset(current[index]);
    } else if (current.IsMap()) {
      check_known_key(a, path, segment, table);
      path = path.child(segment);
      if (last) current[segment] = a.value;
      else current.reset(enter_map_key(current, segment, a, path, table));
    } else {
      fail_override(a.typed, "'" + path.text() + "' is a single value, not a map or a list");
    }
  }
  source.add_override(path, a.typed);
}

}  // namespace tensormass::scene_yaml
