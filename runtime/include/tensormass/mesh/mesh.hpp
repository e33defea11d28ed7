/// \file mesh.hpp
/// A mixed-element mesh stored for fast loops: cells grouped in blocks by
/// reference element (structure of arrays), nodes in one flat array, named
/// groups with their nodes, cells and boundary facets.
///
/// Glossary:
///   node      a point; index 0 .. node_count()-1
///   cell      an element of the mesh's own dimension (dim 3: volumes,
///             dim 2: surfaces); numbered block by block, 0 .. cell_count()-1
///   facet     an element of dimension dim-1 kept only as part of a group
///             (for pressure loads and output); not simulated
///   source id the element's number in the file it came from (for messages)
#ifndef TENSORMASS_MESH_HPP
#define TENSORMASS_MESH_HPP

#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tensormass/kernels/kernel_abi.h"

namespace tensormass {

/// Cells of one reference element type.
struct ElementBlock {
  const tm_element_info* element = nullptr;  ///< reference element (registry)
  std::vector<int> connectivity;             ///< count() by element->nodes, our (VTK) node order
  std::vector<long> source_ids;              ///< count(): element number in the source file
  int first_cell = 0;                        ///< mesh-wide index of this block's first cell

  int nodes_per_cell() const { return element->nodes; }
  int count() const { return element->nodes ? static_cast<int>(connectivity.size()) / element->nodes : 0; }
  std::span<const int> cell_nodes(int local) const {
    return {connectivity.data() + static_cast<std::size_t>(local) * element->nodes,
            static_cast<std::size_t>(element->nodes)};
  }
};

/// Lower-dimensional elements of a group: line2/line3 in 2D, tri3/tri6/quad4/quad8 in 3D.
struct FacetSet {
  std::vector<int> offsets{0};  ///< facet f's nodes are nodes[offsets[f] .. offsets[f+1])
  std::vector<int> nodes;       ///< corners first (counter-clockwise as in the file), then mid-edge nodes
  std::vector<int> orders;      ///< 1 or 2 per facet
  int count() const { return static_cast<int>(offsets.size()) - 1; }
};

/// A named physical group: its nodes are the nodes of its elements of any dimension.
struct Group {
  std::string name;
  int dim = 0;             ///< the group's physical dimension (0 points .. 3 volumes)
  std::vector<int> nodes;  ///< sorted, unique
  std::vector<int> cells;  ///< sorted mesh-wide cell indices that belong to the group
  FacetSet facets;         ///< elements of dimension mesh.dim-1 in the group
};

struct Mesh {
  int dim = 3;                         ///< 2 (plane strain, z = 0) or 3
  std::vector<double> rest_positions;  ///< node_count() by 3 (z = 0 in 2D)
  std::vector<long> node_source_ids;   ///< node_count(): node number in the source file
  std::vector<ElementBlock> blocks;    ///< one per element type present, in registry order
  std::vector<Group> groups;
  std::string source;  ///< file the mesh came from, for messages
  /// Empty, or for a mesh that is one MPI rank's part of a larger one
  /// (parallel::cut_mesh): per cell, its number in the whole mesh, which
  /// messages give (describe_cell).
  std::vector<int> cell_numbers;

  int node_count() const { return static_cast<int>(rest_positions.size() / 3); }
  int cell_count() const;
  /// The group named `name`, or nullptr.
  const Group* group(std::string_view name) const;
  /// Block index and local index of mesh-wide cell `cell`.
  std::pair<int, int> locate(int cell) const;
  /// "element 12 (tet4, id 57 in beam.msh)": for messages (12: the cell's
  /// number in the whole mesh, cell_numbers[cell] when given).
  std::string describe_cell(int cell) const;
  /// Checks indices, finite coordinates and block numbering; throws InputError.
  void validate() const;
  /// Adds a node group (dim 0) of the nodes whose rest position x (3
  /// coordinates) satisfies inside(x[0], x[1], x[2]); returns it. For meshes
  /// built in code (tests, benchmarks, Python): files carry their groups.
  const Group& add_node_group(std::string name, const std::function<bool(double, double, double)>& inside);
};

}  // namespace tensormass

#endif
