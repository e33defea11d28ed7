// The tangent's product by node blocks (SparseMatrix::node_runs) equals the
// row-by-row product to rounding, on nodes with all, some and none of their
// dofs free, in 2D and 3D, with the same bits on one and two threads.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "support/cantilever.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/assembly/sparse_matrix.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

/// The assembled tangent of a clamped beam whose tip is held in y only (its
/// nodes keep x and z free: runs shorter than d), at a wavy displacement.
SparseMatrix tangent(const Model& model) {
  const Assembler assembler(model);
  std::vector<double> u(model.dof_count()), g(model.dof_count());
  for (int i = 0; i < model.dof_count(); ++i) u[i] = 0.01 * std::sin(0.7 * i + 0.3);
  SparseMatrix K = assembler.pattern();
  assembler.assemble(u, g, &K);
  return K;
}

Scene tip_held_in_y() {
  Scene scene = test::cantilever("stvk");
  PrescribedSpec held;
  held.region = "tip";
  held.components = {false, true, false};
  scene.model.prescribed = {held};
  return scene;
}

void expect_block_product_is_the_row_product(const Mesh& mesh) {
  const Model model(mesh, tip_held_in_y().model);
  const SparseMatrix K = tangent(model);
  ASSERT_TRUE(K.node_runs) << "the assembler's pattern carries its node blocks";
  const NodeRuns& runs = *K.node_runs;
  const int d = mesh.dim;
  // Fixed nodes have no rows, held ones fewer than d, the others d.
  int partial = 0, none = 0;
  for (std::size_t n = 0; n + 1 < runs.node_row_start.size(); ++n) {
    const int rows = runs.node_row_start[n + 1] - runs.node_row_start[n];
    partial += rows > 0 && rows < d;
    none += rows == 0;
  }
  EXPECT_GT(partial, 0);
  EXPECT_GT(none, 0);
  std::vector<double> x(K.rows), by_rows(K.rows), by_blocks(K.rows);
  for (int i = 0; i < K.rows; ++i) x[i] = std::cos(1.3 * i);
  K.multiply_by_rows(x, by_rows);
  const int threads = omp_get_max_threads();
  std::vector<double> on_one;
  for (int t : {1, 2}) {
    omp_set_num_threads(t);
    std::fill(by_blocks.begin(), by_blocks.end(), NAN);
    K.multiply(x, by_blocks);
    double scale = 0.0;
    for (double v : by_rows) scale = std::max(scale, std::abs(v));
    for (int i = 0; i < K.rows; ++i) ASSERT_NEAR(by_blocks[i], by_rows[i], 1e-14 * scale) << "row " << i;
    if (t == 1) on_one = by_blocks;
    else EXPECT_EQ(by_blocks, on_one) << "one and two threads";
  }
  omp_set_num_threads(threads);
}

TEST(SparseMatrix, BlockProductIsTheRowProductOnAMixed3dBeam) {
  BeamSpec spec;
  spec.dim = 3;
  spec.cells = {8, 2, 2};
  spec.size = {4, 1, 1};
  spec.phases = {{"hex8", 0.25}, {"tet6", 0.25}, {"prism6", 0.25}, {"pyramid5", 0.25}};
  expect_block_product_is_the_row_product(make_beam(spec));
}

TEST(SparseMatrix, BlockProductIsTheRowProductOnA2dBeam) {
  expect_block_product_is_the_row_product(test::beam(2, "quad4", {12, 3, 1}));
}

TEST(SparseMatrix, BlockProductIsTheRowProductAboveTheParallelThreshold) {
  // 23k free rows: the product runs on the threads of a parallel region.
  expect_block_product_is_the_row_product(test::beam(3, "tet6", {40, 8, 8}));
}

TEST(SparseMatrix, WithoutNodeBlocksTheProductGoesRowByRow) {
  SparseMatrix A;
  A.rows = 2;
  A.row_start = {0, 2, 3};
  A.columns = {0, 1, 1};
  A.values = {2.0, -1.0, 3.0};
  A.diagonal = {0, 2};
  std::vector<double> y(2);
  A.multiply(std::vector<double>{1.0, 2.0}, y);
  EXPECT_EQ(y, (std::vector<double>{0.0, 6.0}));
}

}  // namespace
}  // namespace tensormass
