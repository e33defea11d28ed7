/// \file cell_partition.hpp
/// Cuts a mesh's cells into parts of nearly equal size with short borders:
/// Scotch on the cells' face graph, in a deterministic context: the same
/// mesh gets the same cut on every run.
#ifndef TENSORMASS_PARALLEL_CELL_PARTITION_HPP
#define TENSORMASS_PARALLEL_CELL_PARTITION_HPP

#include <vector>

#include "tensormass/mesh/mesh.hpp"

namespace tensormass::parallel {

/// The cell graph the partitioner reads: two cells are neighbours when they
/// share at least `dim` corners (a face in 3D, an edge in 2D; mid-edge nodes
/// are not counted), in compressed rows.
struct CellGraph {
  std::vector<int> row_start;  ///< cell_count+1
  std::vector<int> columns;    ///< neighbour cells, sorted within each row
};
CellGraph make_cell_graph(const Mesh& mesh);

/// The part (0 .. parts-1) of every cell, computed by this process alone
/// (compute it on one rank and broadcast it). parts = 1 puts every cell in part 0; throws
/// InputError without PETSc when parts > 1.
std::vector<int> partition_cells(const Mesh& mesh, int parts);

}  // namespace tensormass::parallel

#endif
