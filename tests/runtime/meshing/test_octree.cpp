// The octree under the octree mesher (meshing/octree.hpp): packed cell and
// lattice keys, cell geometry on the lattice, splitting, depth-by-depth
// refinement with dropped cells, the containing-leaf search, and strong 2:1
// balance checked against every pair of touching leaves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "meshing/octree.hpp"

namespace tensormass::detail {
namespace {

/// The leaves, sorted by key.
std::vector<std::uint64_t> sorted_leaves(const Octree& tree) {
  std::vector<std::uint64_t> keys(tree.leaves().begin(), tree.leaves().end());
  std::sort(keys.begin(), keys.end());
  return keys;
}

/// The message of the std::invalid_argument building the octree throws ("" for none).
std::string construction_error(std::array<int, 3> counts, int max_depth) {
  try {
    Octree({0, 0, 0}, 1, counts, max_depth);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

/// Lattice box [lo, hi] of a leaf.
struct LatticeBox {
  std::array<std::int64_t, 3> lo, hi;
};
LatticeBox box_of(const Octree& tree, const OctreeCell& cell) {
  const auto lo = tree.lattice_origin(cell);
  const std::int64_t span = tree.lattice_span(cell.depth);
  return {lo, {lo[0] + span, lo[1] + span, lo[2] + span}};
}

/// Expects the leaves to be disjoint, to fill `volume` lattice units and,
/// when `balanced`, every two leaves that touch (a face, an edge or a
/// corner) to differ by at most one depth.
void expect_valid_leaves(const Octree& tree, std::int64_t volume, bool balanced) {
  std::vector<OctreeCell> cells;
  for (std::uint64_t key : tree.leaves()) cells.push_back(cell_of_key(key));
  std::int64_t filled = 0;
  for (const OctreeCell& cell : cells) {
    const std::int64_t span = tree.lattice_span(cell.depth);
    filled += span * span * span;
    for (int depth = cell.depth - 1; depth >= 0; --depth) {
      const int shift = cell.depth - depth;
      const OctreeCell ancestor{depth, {cell.index[0] >> shift, cell.index[1] >> shift, cell.index[2] >> shift}};
      EXPECT_FALSE(tree.is_leaf(ancestor)) << "a leaf inside a leaf";
    }
  }
  EXPECT_EQ(filled, volume);
  if (!balanced) return;
  int touching = 0;
  for (std::size_t a = 0; a < cells.size(); ++a)
    for (std::size_t b = a + 1; b < cells.size(); ++b) {
      const LatticeBox p = box_of(tree, cells[a]), q = box_of(tree, cells[b]);
      bool touch = true;
      for (int axis = 0; axis < 3; ++axis) touch = touch && p.lo[axis] <= q.hi[axis] && q.lo[axis] <= p.hi[axis];
      if (!touch) continue;
      ++touching;
      EXPECT_LE(std::abs(cells[a].depth - cells[b].depth), 1)
          << "depth " << cells[a].depth << " cell touches depth " << cells[b].depth;
    }
  EXPECT_GT(touching, 0);
}

/// Refines the leaf holding the point at lattice `target` down to max depth, and only it.
void refine_towards(Octree& tree, std::array<std::int64_t, 3> target) {
  tree.refine([&](const std::vector<OctreeCell>& cells, std::vector<char>& refine, std::vector<char>&) {
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const LatticeBox box = box_of(tree, cells[c]);
      bool inside = true;
      for (int a = 0; a < 3; ++a) inside = inside && box.lo[a] <= target[a] && target[a] < box.hi[a];
      refine[c] = inside;
    }
  });
}

TEST(OctreeKeys, CellKeysRoundTripAtTheirLimits) {
  for (const OctreeCell& cell : {OctreeCell{0, {0, 0, 0}}, OctreeCell{3, {5, 6, 7}},
                                 OctreeCell{15, {0xFFFFF, 0xFFFFF, 0xFFFFF}}, OctreeCell{14, {0xFFFFF, 0, 1}}}) {
    const OctreeCell back = cell_of_key(cell_key(cell));
    EXPECT_EQ(back.depth, cell.depth);
    EXPECT_EQ(back.index, cell.index);
  }
  EXPECT_EQ(cell_key(1, 2, 3, 4), (std::uint64_t{1} << 60) | (std::uint64_t{2} << 40) | (std::uint64_t{3} << 20) | 4);
  EXPECT_NE(cell_key(1, 0, 0, 0), cell_key(0, 1, 0, 0));
  EXPECT_NE(cell_key(0, 1, 0, 0), cell_key(0, 0, 1, 0));
}

TEST(OctreeKeys, LatticeKeysGiveEachCoordinateTwentyOneBits) {
  EXPECT_EQ(lattice_key(1, 0, 0), std::uint64_t{1} << 42);
  EXPECT_EQ(lattice_key(0, 1, 0), std::uint64_t{1} << 21);
  EXPECT_EQ(lattice_key(0, 0, 1), 1u);
  const std::int64_t top = (std::int64_t{1} << 21) - 1;
  EXPECT_EQ(lattice_key(top, top, top), (std::uint64_t{1} << 63) - 1);
  EXPECT_NE(lattice_key(top, 0, 0), lattice_key(0, top, top));
}

TEST(Octree, StartsWithTheBaseGridAsLeaves) {
  const Octree tree({0, 0, 0}, 1, {3, 2, 4}, 2);
  EXPECT_EQ(tree.leaves().size(), 24u);
  EXPECT_TRUE(tree.is_leaf({0, {2, 1, 3}}));
  EXPECT_FALSE(tree.is_leaf({0, {3, 0, 0}}));
  EXPECT_FALSE(tree.is_leaf({1, {0, 0, 0}}));
}

TEST(Octree, RefusesDepthsAndGridsItsKeysCannotHold) {
  EXPECT_EQ(construction_error({1, 1, 1}, -1), "octree depth out of range");
  EXPECT_EQ(construction_error({1, 1, 1}, 15), "octree depth out of range");
  EXPECT_EQ(construction_error({1, 1, 1}, 14), "");
  // 31 base cells of 2^15 lattice units fit below 2^20; 32 do not.
  EXPECT_EQ(construction_error({31, 1, 1}, 14), "");
  EXPECT_EQ(construction_error({1, 32, 1}, 14), "octree lattice too large");
  EXPECT_EQ(construction_error({1, 1, 0}, 2), "octree lattice empty: no base cell along an axis");
}

TEST(Octree, CellGeometryLiesOnTheLattice) {
  const Octree tree({1, 2, 3}, 2.0, {2, 2, 2}, 3);  // lattice unit 2 / 16
  EXPECT_EQ(tree.cell_size(0), 2.0);
  EXPECT_EQ(tree.cell_size(3), 0.25);
  EXPECT_EQ(tree.lattice_span(0), 16);
  EXPECT_EQ(tree.lattice_span(3), 2);
  EXPECT_EQ(tree.lattice_origin({2, {3, 1, 0}}), (std::array<std::int64_t, 3>{12, 4, 0}));
  EXPECT_EQ(tree.position(16, 8, 0), (std::array<double, 3>{3, 3, 3}));
  // Base cell (1, 0, 0) spans [3, 5] x [2, 4] x [3, 5].
  EXPECT_EQ(tree.centre({0, {1, 0, 0}}), (std::array<double, 3>{4, 3, 4}));
  // The finest cell (3, (0, 0, 0)) spans [1, 1.25] x [2, 2.25] x [3, 3.25].
  EXPECT_EQ(tree.centre({3, {0, 0, 0}}), (std::array<double, 3>{1.125, 2.125, 3.125}));
}

TEST(Octree, InGridScalesTheBaseGridWithDepth) {
  const Octree tree({0, 0, 0}, 1, {3, 1, 2}, 4);
  EXPECT_TRUE(tree.in_grid({0, {2, 0, 1}}));
  EXPECT_FALSE(tree.in_grid({0, {3, 0, 0}}));
  EXPECT_TRUE(tree.in_grid({2, {11, 3, 7}}));
  EXPECT_FALSE(tree.in_grid({2, {12, 0, 0}}));
  EXPECT_FALSE(tree.in_grid({2, {0, 4, 0}}));
  EXPECT_FALSE(tree.in_grid({1, {0, 0, -1}}));
}

TEST(Octree, SplitReplacesALeafByItsEightChildren) {
  Octree tree({0, 0, 0}, 1, {2, 1, 1}, 3);
  tree.split({0, {1, 0, 0}});
  std::vector<std::uint64_t> expected{cell_key(0, 0, 0, 0)};
  for (int i = 2; i < 4; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) expected.push_back(cell_key(1, i, j, k));
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(sorted_leaves(tree), expected);
  expect_valid_leaves(tree, 2 * 16 * 16 * 16, false);
}

TEST(Octree, FindContainingLeafClimbsToTheLeafAbove) {
  Octree tree({0, 0, 0}, 1, {2, 2, 2}, 4);
  tree.split({0, {0, 0, 0}});
  OctreeCell leaf;
  ASSERT_TRUE(tree.find_containing_leaf({3, {7, 7, 7}}, leaf));  // deep inside base cell (0, 0, 0)'s child (1, 1, 1)
  EXPECT_EQ(leaf.depth, 1);
  EXPECT_EQ(leaf.index, (std::array<int, 3>{1, 1, 1}));
  ASSERT_TRUE(tree.find_containing_leaf({2, {4, 0, 0}}, leaf));  // inside base cell (1, 0, 0)
  EXPECT_EQ(leaf.depth, 0);
  EXPECT_EQ(leaf.index, (std::array<int, 3>{1, 0, 0}));
  ASSERT_TRUE(tree.find_containing_leaf({1, {1, 0, 1}}, leaf));  // a leaf itself
  EXPECT_EQ(leaf.depth, 1);
  EXPECT_FALSE(tree.find_containing_leaf({0, {0, 0, 0}}, leaf));  // split: no leaf holds all of it
  EXPECT_FALSE(tree.find_containing_leaf({1, {4, 0, 0}}, leaf));  // outside the grid
  EXPECT_FALSE(tree.find_containing_leaf({1, {-1, 0, 0}}, leaf));
}

TEST(Octree, RefineAsksDepthByDepthAndStopsAtTheMaximumDepth) {
  Octree tree({0, 0, 0}, 1, {1, 1, 1}, 2);
  std::vector<std::pair<int, std::size_t>> asked;
  tree.refine([&](const std::vector<OctreeCell>& cells, std::vector<char>& refine, std::vector<char>& drop) {
    ASSERT_EQ(refine.size(), cells.size());
    ASSERT_EQ(drop.size(), cells.size());
    asked.emplace_back(cells.empty() ? -1 : cells[0].depth, cells.size());
    for (const OctreeCell& cell : cells) EXPECT_EQ(cell.depth, cells[0].depth);
    std::fill(refine.begin(), refine.end(), 1);
  });
  EXPECT_EQ(asked, (std::vector<std::pair<int, std::size_t>>{{0, 1}, {1, 8}, {2, 64}}));
  EXPECT_EQ(tree.leaves().size(), 64u);  // the depth-2 cells asked to split stay leaves
  for (std::uint64_t key : tree.leaves()) EXPECT_EQ(cell_of_key(key).depth, 2);
}

TEST(Octree, DroppedCellsLeaveHolesThatNothingContains) {
  Octree tree({0, 0, 0}, 1, {2, 1, 1}, 2);
  tree.refine([](const std::vector<OctreeCell>& cells, std::vector<char>& refine, std::vector<char>& drop) {
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (cells[c].depth == 0) refine[c] = cells[c].index[0] == 0;
      if (cells[c].depth == 1) drop[c] = cells[c].index[2] == 1;  // the upper half of base cell 0
      if (cells[c].depth == 1) refine[c] = 1;                     // drop wins over refine
    }
  });
  EXPECT_EQ(tree.leaves().size(), 1u + 4 * 8);
  OctreeCell leaf;
  EXPECT_FALSE(tree.find_containing_leaf({1, {0, 0, 1}}, leaf));
  EXPECT_TRUE(tree.find_containing_leaf({2, {0, 0, 0}}, leaf));
  expect_valid_leaves(tree, 8 * 8 * 8 + 32 * 2 * 2 * 2, false);
}

TEST(Octree, BalanceLeavesTouchingLeavesAtMostOneDepthApart) {
  Octree tree({0, 0, 0}, 1, {2, 2, 2}, 4);
  const std::int64_t span = tree.lattice_span(0);
  refine_towards(tree, {span, span, span});  // the centre: the corner of all 8 base cells
  // Only the cell holding the point is split: a depth-4 leaf next to depth-0 ones.
  EXPECT_EQ(tree.leaves().size(), 7u + 3 * 7 + 8);
  tree.balance();
  EXPECT_GT(tree.leaves().size(), 36u);
  expect_valid_leaves(tree, 8 * span * span * span, true);
}

TEST(Octree, BalanceHoldsAcrossEdgesAndCornersAndIsIdempotent) {
  Octree tree({0, 0, 0}, 1, {3, 3, 3}, 5);
  const std::int64_t span = tree.lattice_span(0);
  // A point on a base cell's edge midpoint and one on a corner: neighbours
  // across edges and corners only.
  refine_towards(tree, {span, span, span / 2});
  refine_towards(tree, {2 * span, 2 * span, 2 * span});
  tree.balance();
  expect_valid_leaves(tree, 27 * span * span * span, true);
  const std::vector<std::uint64_t> balanced = sorted_leaves(tree);
  tree.balance();
  EXPECT_EQ(sorted_leaves(tree), balanced);
}

TEST(Octree, BalanceSplitsNothingInATreeAlreadyBalanced) {
  Octree tree({0, 0, 0}, 1, {2, 1, 1}, 3);
  tree.split({0, {0, 0, 0}});
  tree.split({1, {0, 0, 0}});  // depths 0, 1 and 2, each touching the next only
  const std::vector<std::uint64_t> before = sorted_leaves(tree);
  tree.balance();
  EXPECT_EQ(sorted_leaves(tree), before);
}

TEST(Octree, BalanceKeepsHoles) {
  Octree tree({0, 0, 0}, 1, {2, 1, 1}, 3);
  tree.refine([&](const std::vector<OctreeCell>& cells, std::vector<char>& refine, std::vector<char>& drop) {
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (cells[c].depth == 0) drop[c] = cells[c].index[0] == 1;
      refine[c] = cells[c].index[0] == 0 && cells[c].index[1] == 0 && cells[c].index[2] == 0;
    }
  });
  tree.balance();
  const std::int64_t span = tree.lattice_span(0);
  expect_valid_leaves(tree, span * span * span, true);
  OctreeCell leaf;
  EXPECT_FALSE(tree.find_containing_leaf({0, {1, 0, 0}}, leaf));
}

}  // namespace
}  // namespace tensormass::detail
