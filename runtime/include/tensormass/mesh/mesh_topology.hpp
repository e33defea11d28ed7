/// \file mesh_topology.hpp
/// Adjacency queries on a Mesh: the cells around each node and the cell a
/// boundary facet belongs to (pressure loads orient their normals by it).
#ifndef TENSORMASS_MESH_MESH_TOPOLOGY_HPP
#define TENSORMASS_MESH_MESH_TOPOLOGY_HPP

#include <span>
#include <vector>

#include "tensormass/mesh/mesh.hpp"

namespace tensormass {

/// node_count() lists: the mesh-wide cells using each node, ascending.
std::vector<std::vector<int>> cells_around_nodes(const Mesh& mesh);

/// The registry's 2D element a facet of `nodes` nodes is in a 3D mesh (tri3,
/// quad4, tri6, quad8, quad9, ...: the faces of the 3D elements list their
/// nodes in the order of that element), or nullptr when there is none.
const tm_element_info* facet_element(int nodes);
/// Whether a facet of `nodes` nodes can carry a load in a mesh of dimension
/// `dim`: line2/line3 in 2D, a registry 2D element in 3D.
bool is_load_facet(int dim, int nodes);
/// Corner count of such a facet (2 in 2D, its element's corners in 3D).
int facet_corners(int dim, int nodes);

/// The first cell (in cells_around_nodes order) holding every corner of the
/// facet (`facet` lists corners first), or -1 when it is no cell's face.
int facet_owner(const Mesh& mesh, const std::vector<std::vector<int>>& node_cells, std::span<const int> facet);

}  // namespace tensormass

#endif
