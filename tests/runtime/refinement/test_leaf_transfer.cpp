// State transfer between leaf meshes: linear displacement fields exactly,
// kept nodes and cell data bit for bit, refine then coarsen back to the
// original state, size checks.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <span>
#include <vector>

#include "refinement_checks.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/refinement/leaf_transfer.hpp"

namespace {

using refinement_test::all_cells;
using refinement_test::mixed_beam;
using refinement_test::position;
using refinement_test::same_bits;
using tensormass::HierarchicalMesh;
using tensormass::LeafTransfer;
using tensormass::Mesh;

/// u(x, y) = (0.1 + 0.02 x - 0.03 y, -0.2 + 0.05 x + 0.01 y), node-major by 2.
std::vector<double> linear_field(const Mesh& mesh) {
  std::vector<double> u;
  for (int node = 0; node < mesh.node_count(); ++node) {
    const double* x = position(mesh, node);
    u.push_back(0.1 + 0.02 * x[0] - 0.03 * x[1]);
    u.push_back(-0.2 + 0.05 * x[0] + 0.01 * x[1]);
  }
  return u;
}

/// Random leaf-mesh cells, a share `fraction` of them.
std::vector<int> random_cells(const Mesh& mesh, std::mt19937& random, double fraction) {
  std::bernoulli_distribution pick(fraction);
  std::vector<int> cells;
  for (int cell = 0; cell < mesh.cell_count(); ++cell)
    if (pick(random)) cells.push_back(cell);
  return cells;
}

TEST(LeafTransfer, LinearFieldIsTransferredExactlyThroughRefinementsAndCoarsenings) {
  HierarchicalMesh hierarchy(mixed_beam());
  std::vector<double> u = linear_field(hierarchy.leaf_mesh());
  std::mt19937 random(7);
  for (int step = 0; step < 12; ++step) {
    const std::vector<int> marked = random_cells(hierarchy.leaf_mesh(), random, step % 4 == 3 ? 0.6 : 0.2);
    const LeafTransfer transfer = step % 4 == 3 ? hierarchy.coarsen(marked) : hierarchy.refine(marked, 4);
    u = tensormass::transfer_nodal_field(transfer, u, 2);
    const std::vector<double> exact = linear_field(hierarchy.leaf_mesh());
    ASSERT_EQ(u.size(), exact.size()) << "step " << step;
    for (std::size_t k = 0; k < u.size(); ++k) ASSERT_NEAR(u[k], exact[k], 1e-14) << "step " << step << " dof " << k;
  }
  EXPECT_GT(hierarchy.leaves_per_level().size(), 2u);
}

TEST(LeafTransfer, NewNodesTakeTheParentsShapeFunctionValues) {
  // One quad (x in [1, 2]) refined: its midpoints and centre are means of its corners' values.
  HierarchicalMesh hierarchy(mixed_beam(2, 1));
  const Mesh before = hierarchy.leaf_mesh();
  std::vector<double> values;
  for (int node = 0; node < before.node_count(); ++node) values.push_back(node * node + 0.5);  // not linear
  const LeafTransfer transfer = hierarchy.refine(std::vector<int>{0});
  const std::vector<double> after = tensormass::transfer_nodal_field(transfer, values, 1);
  const Mesh& mesh = hierarchy.leaf_mesh();
  ASSERT_EQ(mesh.node_count(), before.node_count() + 5);
  for (int node = 0; node < before.node_count(); ++node) EXPECT_EQ(after[node], values[node]);
  const tensormass::HierarchyCell& quad = hierarchy.hierarchy_cell(0);
  const auto child = [&](int k) { return hierarchy.hierarchy_cell(quad.children[k]).corners; };
  // Children {c0, m0, z, m3}, {m0, c1, m1, z}, {z, m1, c2, m2}, {m3, z, m2, c3}.
  const int midpoints[4] = {child(0)[1], child(1)[2], child(2)[3], child(0)[3]};
  const auto c = quad.corners;
  for (int k = 0; k < 4; ++k)
    EXPECT_EQ(after[midpoints[k]], 0.5 * values[c[k]] + 0.5 * values[c[(k + 1) % 4]]) << "edge " << k;
  EXPECT_EQ(child(0)[2], quad.centre);
  EXPECT_DOUBLE_EQ(after[quad.centre], (values[c[0]] + values[c[1]] + values[c[2]] + values[c[3]]) / 4);
}

TEST(LeafTransfer, RefineThenCoarsenGivesBackTheOriginalStateBitwise) {
  const Mesh original = mixed_beam();
  HierarchicalMesh hierarchy(original);
  std::mt19937 random(99);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<double> displacement(2 * static_cast<std::size_t>(original.node_count()));
  std::vector<double> velocity(displacement.size());
  for (double& u : displacement) u = value(random);
  for (double& v : velocity) v = value(random);
  displacement[3] = -0.0;
  std::vector<int> law(static_cast<std::size_t>(original.cell_count()));
  std::vector<double> blend(law.size());
  for (std::size_t cell = 0; cell < law.size(); ++cell) {
    law[cell] = static_cast<int>(cell % 3);
    blend[cell] = value(random);
  }
  const std::vector<double> displacement0 = displacement, velocity0 = velocity, blend0 = blend;
  const std::vector<int> law0 = law;
  const auto carry = [&](const LeafTransfer& transfer) {
    displacement = tensormass::transfer_nodal_field(transfer, displacement, 2);
    velocity = tensormass::transfer_nodal_field(transfer, velocity, 2);
    law = tensormass::transfer_cell_field<int>(transfer, law);
    blend = tensormass::transfer_cell_field<double>(transfer, blend);
  };
  for (int round = 0; round < 3; ++round) carry(hierarchy.refine(random_cells(hierarchy.leaf_mesh(), random, 0.3)));
  ASSERT_GT(hierarchy.leaf_mesh().node_count(), original.node_count());
  // Children and transition triangles carry their original cell's data.
  for (int cell = 0; cell < hierarchy.leaf_mesh().cell_count(); ++cell) {
    const int origin = hierarchy.hierarchy_cell(hierarchy.leaf_owners()[cell]).origin;
    EXPECT_EQ(law[cell], law0[origin]) << "cell " << cell;
    EXPECT_EQ(blend[cell], blend0[origin]) << "cell " << cell;
  }
  for (int round = 0; round < 5; ++round) carry(hierarchy.coarsen(all_cells(hierarchy.leaf_mesh())));
  refinement_test::expect_same_mesh(hierarchy.leaf_mesh(), original);
  EXPECT_TRUE(same_bits(displacement, displacement0));
  EXPECT_TRUE(same_bits(velocity, velocity0));
  EXPECT_TRUE(same_bits(blend, blend0));
  EXPECT_EQ(law, law0);
}

TEST(LeafTransfer, WrongSizesAreInputErrors) {
  HierarchicalMesh hierarchy(mixed_beam());
  const int nodes = hierarchy.leaf_mesh().node_count(), cells = hierarchy.leaf_mesh().cell_count();
  const LeafTransfer transfer = hierarchy.refine(std::vector<int>{0});
  EXPECT_EQ(transfer.old_node_count, nodes);
  EXPECT_EQ(transfer.old_cell_count, cells);
  EXPECT_EQ(transfer.new_node_count(), hierarchy.leaf_mesh().node_count());
  EXPECT_EQ(transfer.new_cell_count(), hierarchy.leaf_mesh().cell_count());
  const std::vector<double> short_field(2 * static_cast<std::size_t>(nodes) - 1, 0.0);
  EXPECT_THROW(tensormass::transfer_nodal_field(transfer, short_field, 2), tensormass::InputError);
  EXPECT_THROW(tensormass::transfer_nodal_field(transfer, short_field, 0), tensormass::InputError);
  const std::vector<int> cell_field(static_cast<std::size_t>(cells) + 1, 0);
  EXPECT_THROW(tensormass::transfer_cell_field<int>(transfer, cell_field), tensormass::InputError);
}

}  // namespace
