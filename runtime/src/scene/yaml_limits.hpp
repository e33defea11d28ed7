/// \file yaml_limits.hpp
/// Private to the scene reader: the bounds a YAML document must keep before
/// the scene is read from it. yaml-cpp shares an aliased node instead of
/// copying it, but every walk over the tree visits it once per alias, so a
/// kilobyte of nested aliases stands for 10^9 nodes; the tree is therefore
/// walked once, as the readers walk it, and refused once it grows past the
/// node limit or nests past the depth limit.
#ifndef TENSORMASS_SCENE_YAML_LIMITS_HPP
#define TENSORMASS_SCENE_YAML_LIMITS_HPP

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <string>

namespace tensormass::scene_yaml {

/// The largest scene file read, in bytes.
inline constexpr std::size_t kMaxYamlBytes = 16u << 20;
/// The deepest nesting of maps and lists (the scene schema uses five levels).
inline constexpr int kMaxYamlDepth = 64;
/// The fewest nodes, aliases expanded, any document may hold.
inline constexpr std::size_t kMinYamlNodeLimit = 300000;
/// Nodes allowed per byte of the document beyond kMinYamlNodeLimit.
inline constexpr std::size_t kYamlNodesPerByte = 20;

/// The most nodes, aliases expanded, a document of `document_bytes` may hold.
std::size_t yaml_node_limit(std::size_t document_bytes);

/// Walks `root` with every alias expanded where it is used; throws InputError
/// "NAME:LINE: ..." at the node that passes yaml_node_limit(document_bytes)
/// or kMaxYamlDepth. `name` stands for the document in messages.
void check_yaml_limits(const YAML::Node& root, const std::string& name, std::size_t document_bytes);

}  // namespace tensormass::scene_yaml

#endif
