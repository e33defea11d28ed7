// PT-Scotch through PETSc's MatPartitioning, run by one process on
// PETSC_COMM_SELF.
#include "tensormass/parallel/cell_partition.hpp"

#include <petscmat.h>

#include <algorithm>
#include <string>

#include "parallel/petsc_start.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::parallel {

namespace {
void check(PetscErrorCode code, const char* what) {
  if (code != 0) throw NumericalError(std::string("PETSc: ") + what + " failed while cutting the mesh for MPI ranks");
}
}  // namespace

std::vector<int> partition_cells(const Mesh& mesh, int parts) {
  const int cells = mesh.cell_count();
  if (parts <= 1 || cells == 0) return std::vector<int>(cells, 0);
  if (parts > cells)
    throw InputError("cannot share " + std::to_string(cells) + " cells among " + std::to_string(parts) +
                     " MPI ranks (run on fewer ranks)");
  detail::ensure_petsc_started();
  const CellGraph graph = make_cell_graph(mesh);
  // MatCreateMPIAdj takes ownership of arrays from PetscMalloc.
  PetscInt *row_start = nullptr, *columns = nullptr;
  check(PetscMalloc1(graph.row_start.size(), &row_start), "PetscMalloc1");
  check(PetscMalloc1(std::max<std::size_t>(1, graph.columns.size()), &columns), "PetscMalloc1");
  std::copy(graph.row_start.begin(), graph.row_start.end(), row_start);
  std::copy(graph.columns.begin(), graph.columns.end(), columns);
  Mat adjacency;
  check(MatCreateMPIAdj(PETSC_COMM_SELF, cells, cells, row_start, columns, nullptr, &adjacency), "MatCreateMPIAdj");
  MatPartitioning partitioning;
  check(MatPartitioningCreate(PETSC_COMM_SELF, &partitioning), "MatPartitioningCreate");
  check(MatPartitioningSetAdjacency(partitioning, adjacency), "MatPartitioningSetAdjacency");
  check(MatPartitioningSetType(partitioning, MATPARTITIONINGPTSCOTCH), "MatPartitioningSetType");
  check(MatPartitioningSetNParts(partitioning, parts), "MatPartitioningSetNParts");
  IS part_of_cell;
  const PetscErrorCode applied = MatPartitioningApply(partitioning, &part_of_cell);
  MatPartitioningDestroy(&partitioning);
  MatDestroy(&adjacency);
  check(applied, "MatPartitioningApply (PT-Scotch)");
  const PetscInt* part = nullptr;
  ISGetIndices(part_of_cell, &part);
  std::vector<int> owner(part, part + cells);
  ISRestoreIndices(part_of_cell, &part);
  ISDestroy(&part_of_cell);
  for (int p = 0; p < parts; ++p)
    if (std::find(owner.begin(), owner.end(), p) == owner.end())
      throw NumericalError("the mesh cut for " + std::to_string(parts) + " MPI ranks left rank " + std::to_string(p) +
                           " without cells");
  return owner;
}

}  // namespace tensormass::parallel
