/// \file mesh_cut.hpp
/// A mesh cut among MPI ranks, each rank holding its part only: the cells
/// it assembles (its own and those touching one of its nodes) and their
/// nodes, numbered in the part (in the whole mesh's order), so that a
/// rank's mesh, model and state grow with its part and not with the whole.
#ifndef TENSORMASS_PARALLEL_MESH_CUT_HPP
#define TENSORMASS_PARALLEL_MESH_CUT_HPP

#include <span>
#include <vector>

#include "tensormass/mesh/mesh.hpp"

namespace tensormass {

/// What a rank knows of the cut besides its part of the mesh.
struct CellCut {
  std::vector<int> global_cell;  ///< per cell of the part: its index in the whole mesh (increasing)
  std::vector<int> cell_owner;   ///< per cell of the part: the rank that owns it
  std::vector<int> global_node;  ///< per node of the part: its index in the whole mesh (increasing)
  std::vector<int> node_owner;   ///< per node of the part: the rank that owns it
  int whole_cell_count = 0;      ///< cells of the whole mesh
  int whole_node_count = 0;      ///< nodes of the whole mesh
};

/// A rank's part of a mesh and the cut it comes from.
struct MeshPart {
  Mesh mesh;
  CellCut cut;
};

namespace parallel {

/// Per node of `mesh`: the lowest rank among the owners of its cells
/// (cell_owner: per cell), rank 0 for a node in no cell.
std::vector<int> node_owners(const Mesh& mesh, std::span<const int> cell_owner, int ranks);

/// Rank `rank`'s part of `whole`: the cells it owns or that touch a node it
/// owns, the nodes of those cells, its own nodes and the nodes of group
/// facets touching its nodes (each in the whole mesh's order, renumbered);
/// the groups with their cells, nodes and facets among those (a facet when
/// all its nodes are).
MeshPart cut_mesh(const Mesh& whole, std::span<const int> cell_owner, std::span<const int> node_owner, int rank);

}  // namespace parallel

}  // namespace tensormass

#endif
