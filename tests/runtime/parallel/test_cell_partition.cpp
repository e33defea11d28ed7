// Cutting a mesh's cells among MPI ranks (partition_cells in
// tensormass/parallel/cell_partition.hpp): one part without cutting, every
// part non-empty and within Scotch's 1 % imbalance, a short border, the same
// cut on every call, and too many parts refused; a build without PETSc
// refuses to cut. (Balance on a larger beam: test_distribution.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <set>
#include <string>
#include <vector>

#include "support/cantilever.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/parallel/cell_partition.hpp"

namespace tensormass {
namespace {

/// Pairs of neighbouring cells (the cell graph's edges) in different parts.
int border_edges(const Mesh& mesh, const std::vector<int>& owner) {
  const parallel::CellGraph graph = parallel::make_cell_graph(mesh);
  int cut = 0;
  for (int cell = 0; cell < mesh.cell_count(); ++cell)
    for (int k = graph.row_start[cell]; k < graph.row_start[cell + 1]; ++k)
      if (graph.columns[k] > cell && owner[cell] != owner[graph.columns[k]]) ++cut;
  return cut;
}

/// The cuts Scotch makes (builds with PETSc).
class ScotchCut : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!petsc_available()) GTEST_SKIP() << "this build has no PETSc and Scotch";
  }
};

TEST_F(ScotchCut, PartsAreNonEmptyAndBalanced) {
  const Mesh mesh = test::beam(3, "hex8", {20, 4, 4});  // 320 hexes
  for (int parts : {2, 4, 5, 8}) {
    const std::vector<int> owner = parallel::partition_cells(mesh, parts);
    ASSERT_EQ(owner.size(), 320u);
    std::vector<int> count(parts, 0);
    for (int p : owner) {
      ASSERT_GE(p, 0);
      ASSERT_LT(p, parts);
      ++count[p];
    }
    for (int p = 0; p < parts; ++p)
      EXPECT_LE(std::abs(count[p] - 320.0 / parts), 0.01 * 320 / parts + 1) << parts << " parts, part " << p;
  }
}

TEST_F(ScotchCut, TwoPartsOfABeamMeetAcrossOneCrossSection) {
  // 20 x 4 x 4 hexes: a cut across the beam crosses 16 faces; a cut along
  // it would cross at least 80.
  const Mesh mesh = test::beam(3, "hex8", {20, 4, 4});
  const std::vector<int> owner = parallel::partition_cells(mesh, 2);
  EXPECT_LE(border_edges(mesh, owner), 2 * 16);
}

TEST_F(ScotchCut, TheSameMeshIsCutTheSameWayEveryTime) {
  const Mesh mesh = test::beam(3, "tet5", {8, 3, 3});
  const std::vector<int> first = parallel::partition_cells(mesh, 3);
  for (int again = 0; again < 3; ++again) EXPECT_EQ(parallel::partition_cells(mesh, 3), first);
}

TEST_F(ScotchCut, AsManyPartsAsCellsGivesEachCellItsOwn) {
  const Mesh mesh = test::beam(2, "quad4", {3, 2, 1});
  std::vector<int> owner = parallel::partition_cells(mesh, 6);
  std::sort(owner.begin(), owner.end());
  std::vector<int> each(6);
  std::iota(each.begin(), each.end(), 0);
  EXPECT_EQ(owner, each);
}

TEST_F(ScotchCut, MorePartsThanCellsAreRefusedNamingBoth) {
  const Mesh mesh = test::beam(2, "quad4", {3, 2, 1});
  try {
    parallel::partition_cells(mesh, 7);
    ADD_FAILURE() << "7 parts of 6 cells were accepted";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "cannot share 6 cells among 7 MPI ranks (run on fewer ranks)");
  }
}

// In builds with PETSc or without.
TEST(PartitionCells, OnePartPutsEveryCellInPartZero) {
  const Mesh mesh = test::beam(3, "tet6", {3, 2, 2});
  EXPECT_EQ(parallel::partition_cells(mesh, 1), std::vector<int>(mesh.cell_count(), 0));
  EXPECT_EQ(parallel::partition_cells(mesh, 0), std::vector<int>(mesh.cell_count(), 0));
}

TEST(PartitionCells, ABuildWithoutPetscRefusesToCut) {
  if (petsc_available()) GTEST_SKIP() << "this build has PETSc and Scotch: ScotchCut.*";
  const Mesh mesh = test::beam(2, "quad4", {3, 2, 1});
  try {
    parallel::partition_cells(mesh, 2);
    ADD_FAILURE() << "a build without PETSc cut the mesh";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "cutting the mesh for MPI ranks needs PETSc, which this build lacks");
  }
}

}  // namespace
}  // namespace tensormass
