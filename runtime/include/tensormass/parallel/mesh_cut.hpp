/// \file mesh_cut.hpp
/// A mesh cut among MPI ranks, each rank holding its part only: the cells
/// it assembles (its own and those touching one of its nodes) with every
/// node, so that node and dof numbers stay those of the whole mesh while
/// the cells, the bulk of a mesh and of a model, are divided.
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
  std::vector<int> node_owner;   ///< per node (all of them): the rank that owns it
  int whole_cell_count = 0;      ///< cells of the whole mesh
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

/// Rank `rank`'s part of `whole`: every node, the cells it owns or that
/// touch a node it owns (in the whole mesh's order), the groups with their
/// cells among those (renumbered) and all their nodes and facets.
MeshPart cut_mesh(const Mesh& whole, std::span<const int> cell_owner, std::span<const int> node_owner, int rank);

}  // namespace parallel

}  // namespace tensormass

#endif
