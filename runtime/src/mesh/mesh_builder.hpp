/// \file mesh_builder.hpp
/// Internal (not installed): MeshBuilder assembles a Mesh from
/// format-independent raw nodes and elements (file ids, our node order, group
/// keys); the mesh readers of io/ and the generators of meshing/ use it.
#ifndef TENSORMASS_MESH_BUILDER_HPP
#define TENSORMASS_MESH_BUILDER_HPP

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "common/input_cursor.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace tensormass::detail {

/// An element kind the builder knows: a point, a line (2 or 3 nodes) or a
/// registry reference element.
struct Shape {
  std::string name;
  int dim = 0;
  int nodes = 0;
  int order = 1;
  const tm_element_info* element = nullptr;  ///< null for point and lines
};

/// "point", "line2", "line3" or a registry element name; nullptr otherwise.
const Shape* find_shape(std::string_view name);
/// The shape of a registry element.
const Shape* shape_of(const tm_element_info* element);

/// How a group key is turned into a group: its name and dimension
/// (dim < 0: the highest dimension of its elements).
struct GroupInfo {
  std::string name;
  int dim = -1;
};

/// Collects raw nodes and elements, then builds a Mesh:
///   - the mesh dimension is the highest element dimension (2 or 3); the
///     elements of that dimension are the cells, sorted into blocks in
///     registry order (file order inside a block);
///   - elements of dimension dim-1 are the facets of their groups; a
///     group's nodes are the nodes of its elements of any dimension;
///   - elements repeated with the same shape and nodes are merged (MSH 2.2
///     writes an element once per physical group);
///   - nodes used by no cell are dropped; the others are renumbered
///     0..n-1 in file order (node_source_ids keeps the file ids);
///   - groups sharing a name are merged (dimension: the highest).
class MeshBuilder {
 public:
  /// `element_word` names elements in messages ("element" or "cell").
  MeshBuilder(std::string source, std::string element_word);

  /// Reserves room for `count` nodes (counts already checked by the reader).
  void reserve_nodes(std::size_t count);
  /// Reserves room for `count` more elements' own entries (counts already
  /// checked by the reader): a million-element file then grows no array by
  /// copying it.
  void reserve_elements(std::size_t count);
  /// Adds node `id`; throws at `where` for a non-finite coordinate.
  void add_node(long id, const double xyz[3], Location where);
  /// Adds an element: `nodes` are file node ids in our node order,
  /// `groups` the keys of the groups it belongs to.
  void add_element(const Shape& shape, long id, std::span<const long> nodes, std::span<const long> groups,
                   Location where);

  /// Builds and validates the mesh; `describe` names each group key.
  Mesh build(const std::function<GroupInfo(long key)>& describe);

 private:
  class NodeIndex;
  struct Resolved;
  int mesh_dimension() const;
  Resolved resolve() const;
  void fill_nodes(Mesh& mesh, const Resolved& r) const;
  void fill_blocks(Mesh& mesh, Resolved& r) const;
  void fill_groups(Mesh& mesh, const Resolved& r, const std::function<GroupInfo(long key)>& describe) const;
  void add_to_group(Group& group, std::size_t e, const Resolved& r) const;
  void flatten_2d(Mesh& mesh) const;
  [[noreturn]] void fail_element(std::size_t e, const std::string& message) const;

  std::string source_;
  std::string element_word_;
  std::vector<long> node_ids_;
  std::vector<double> xyz_;
  std::vector<Location> node_where_;
  std::vector<const Shape*> shapes_;
  std::vector<long> element_ids_;
  std::vector<std::size_t> node_offsets_{0};
  std::vector<long> element_nodes_;
  std::vector<std::size_t> group_offsets_{0};
  std::vector<long> element_groups_;
  std::vector<Location> element_where_;
};

}  // namespace tensormass::detail

#endif
