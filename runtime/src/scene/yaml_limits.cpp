#include "scene/yaml_limits.hpp"

#include <algorithm>

#include "tensormass/common/errors.hpp"

namespace tensormass::scene_yaml {

std::size_t yaml_node_limit(std::size_t document_bytes) {
  return std::max(kMinYamlNodeLimit, kYamlNodesPerByte * document_bytes);
}

namespace {

/// Counts the nodes of a tree, aliases expanded, and stops at the first bound passed.
class LimitWalk {
 public:
  LimitWalk(const std::string& name, std::size_t node_limit) : name_(name), node_limit_(node_limit) {}

  void visit(const YAML::Node& node, int depth) {
    if (++visited_ > node_limit_)
      fail(node, "the document holds more than " + std::to_string(node_limit_) +
                     " values once its aliases are expanded (an alias bomb?); a scene lists its values plainly");
    if (!node.IsMap() && !node.IsSequence()) return;
    if (depth >= kMaxYamlDepth)
      fail(node, "maps and lists nest deeper than " + std::to_string(kMaxYamlDepth) + " levels");
    if (node.IsSequence()) {
      for (const YAML::Node& item : node) visit(item, depth + 1);
      return;
    }
    for (const auto& entry : node) {
      visit(entry.first, depth + 1);
      visit(entry.second, depth + 1);
    }
  }

 private:
  [[noreturn]] void fail(const YAML::Node& node, const std::string& message) const {
    const YAML::Mark mark = node.Mark();
    const bool located = !mark.is_null() && mark.line >= 0;
    throw InputError(name_ + (located ? ":" + std::to_string(mark.line + 1) : std::string()) + ": " + message);
  }

  const std::string& name_;
  std::size_t node_limit_;
  std::size_t visited_ = 0;
};

}  // namespace

void check_yaml_limits(const YAML::Node& root, const std::string& name, std::size_t document_bytes) {
  LimitWalk(name, yaml_node_limit(document_bytes)).visit(root, 0);
}

}  // namespace tensormass::scene_yaml
