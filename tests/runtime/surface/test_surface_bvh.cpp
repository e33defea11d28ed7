// The box tree over a surface's triangles (TriangleBVH in
// tensormass/surface/surface.hpp): a permutation of the triangles in leaves
// of at most leaf_size, each node's box holding its triangles', the depth
// bounded on degenerate input, clusters split apart, and closed-box queries.
// (Box queries against brute force on a torus: test_surface_distance.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <vector>

#include "support/test_surfaces.hpp"
#include "tensormass/surface/surface.hpp"

namespace {

using surfacetest::make_box;
using surfacetest::make_icosphere;
using tensormass::SurfaceBox;
using tensormass::TriangleBVH;
using tensormass::TriangleSurface;

/// Each triangle's box (min x y z, max x y z), surface order.
std::vector<double> triangle_box(const TriangleSurface& surface, int t) {
  std::vector<double> box{INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
  for (int c = 0; c < 3; ++c)
    for (int a = 0; a < 3; ++a) {
      const double x = surface.points[3 * surface.triangles[3 * t + c] + a];
      box[a] = std::min(box[a], x);
      box[3 + a] = std::max(box[3 + a], x);
    }
  return box;
}

/// Checks the subtree at `index`: a leaf holds 1 .. leaf_size slots, an
/// internal node two non-empty children, and every node's box is the union
/// of the boxes of the slots below it, which are one run [first, end).
/// Counts in `covered` how often each slot is reached; returns the depth
/// (a leaf: 1) and the run.
int check_subtree(const TriangleBVH& tree, int index, int leaf_size, std::vector<int>& covered, int& first, int& end) {
  const TriangleBVH::Node& node = tree.nodes()[index];
  int depth = 1;
  if (node.count > 0) {
    EXPECT_LE(node.count, leaf_size) << "node " << index;
    first = node.first;
    end = node.first + node.count;
    for (int k = first; k < end; ++k) ++covered[k];
  } else {
    int left_first = 0, left_end = 0, right_first = 0, right_end = 0;
    const int left = check_subtree(tree, index + 1, leaf_size, covered, left_first, left_end);
    const int right = check_subtree(tree, node.first, leaf_size, covered, right_first, right_end);
    EXPECT_EQ(left_end, right_first) << "node " << index << ": its children's slots are not one run";
    first = left_first;
    end = right_end;
    depth = 1 + std::max(left, right);
  }
  for (int a = 0; a < 3; ++a) {
    double lo = INFINITY, hi = -INFINITY;
    for (int k = first; k < end; ++k) {
      lo = std::min(lo, tree.boxes()[6 * k + a]);
      hi = std::max(hi, tree.boxes()[6 * k + 3 + a]);
    }
    EXPECT_EQ(node.min[a], lo) << "node " << index << " axis " << a;
    EXPECT_EQ(node.max[a], hi) << "node " << index << " axis " << a;
  }
  return depth;
}

/// Checks the whole tree over `surface`; returns its depth.
int check_tree(const TriangleSurface& surface, const TriangleBVH& tree, int leaf_size) {
  const int count = surface.triangle_count();
  std::vector<int> order = tree.order();
  std::sort(order.begin(), order.end());
  std::vector<int> all(count);
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(order, all) << "order() is not a permutation of the triangles";
  EXPECT_EQ(tree.boxes().size(), 6u * count);
  for (int k = 0; k < count; ++k)
    EXPECT_EQ(std::vector<double>(tree.boxes().begin() + 6 * k, tree.boxes().begin() + 6 * k + 6),
              triangle_box(surface, tree.order()[k]))
        << "slot " << k;
  std::vector<int> covered(count, 0);
  int first = 0, end = 0;
  const int depth = check_subtree(tree, 0, leaf_size, covered, first, end);
  EXPECT_EQ(covered, std::vector<int>(count, 1)) << "each slot is in exactly one leaf";
  EXPECT_EQ(first, 0);
  EXPECT_EQ(end, count);
  return depth;
}

/// `count` copies of one small triangle: no split separates any of them.
TriangleSurface stacked_triangles(int count) {
  TriangleSurface surface;
  surface.points = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  for (int t = 0; t < count; ++t) surface.triangles.insert(surface.triangles.end(), {0, 1, 2});
  return surface;
}

TEST(TriangleBvh, NodesHoldTheirTrianglesForEveryLeafSize) {
  const TriangleSurface ball = make_icosphere(1, 3);  // 1280 triangles
  for (int leaf_size : {1, 2, 4, 7, 16}) {
    const TriangleBVH tree(ball, leaf_size);
    const int depth = check_tree(ball, tree, leaf_size);
    EXPECT_GE(depth, static_cast<int>(std::ceil(std::log2(1280.0 / leaf_size)))) << leaf_size;
    EXPECT_LE(depth, 40) << leaf_size;
  }
}

TEST(TriangleBvh, ALeafSizeBelowOneMeansOne) {
  const TriangleSurface box = make_box({0, 0, 0}, {1, 1, 1}, 2);
  const TriangleBVH tree(box, 0);
  check_tree(box, tree, 1);
  for (const TriangleBVH::Node& node : tree.nodes()) EXPECT_LE(node.count, 1);
}

TEST(TriangleBvh, ASurfaceOfAtMostALeafIsOneLeaf) {
  const TriangleSurface tet = surfacetest::unit_tetrahedron();
  const TriangleBVH tree(tet, 4);
  ASSERT_EQ(tree.nodes().size(), 1u);
  EXPECT_EQ(tree.nodes()[0].first, 0);
  EXPECT_EQ(tree.nodes()[0].count, 4);
  check_tree(tet, tree, 4);
}

TEST(TriangleBvh, ASurfaceWithoutTrianglesHasNoNodes) {
  const TriangleBVH tree{TriangleSurface{}};
  EXPECT_TRUE(tree.nodes().empty());
  EXPECT_TRUE(tree.order().empty());
  EXPECT_TRUE(tree.overlapping(SurfaceBox{{-1e9, -1e9, -1e9}, {1e9, 1e9, 1e9}}).empty());
}

TEST(TriangleBvh, CoincidentTrianglesAreSplitByTheMedianWithBoundedDepth) {
  const TriangleSurface surface = stacked_triangles(1000);
  const TriangleBVH tree(surface, 4);
  const int depth = check_tree(surface, tree, 4);
  EXPECT_LE(depth, 9);  // halving 1000 down to 4: 8 levels of splits
  EXPECT_EQ(tree.overlapping(SurfaceBox{{0.2, 0.2, 0}, {0.3, 0.3, 0}}).size(), 1000u);
}

TEST(TriangleBvh, DepthStaysBoundedOnGeometricallySpacedTriangles) {
  // Centroids at +-2^-k crowd ever closer to 0: each level of binned splits
  // separates only a few; below depth 48 median splits take over.
  TriangleSurface surface;
  for (int k = 0; k < 2000; ++k) {
    const double x = std::ldexp(1.0, -k % 1000) * (k < 1000 ? 1 : -1);
    const int base = surface.point_count();
    surface.points.insert(surface.points.end(), {x, 0, 0, x, 1e-3, 0, x, 0, 1e-3});
    surface.triangles.insert(surface.triangles.end(), {base, base + 1, base + 2});
  }
  const TriangleBVH tree(surface, 1);
  const int depth = check_tree(surface, tree, 1);
  EXPECT_GT(depth, 48);  // the median splits were reached
  EXPECT_LT(depth, 80);
}

TEST(TriangleBvh, TwoDistantClustersAreTheRootsTwoChildren) {
  TriangleSurface surface = make_icosphere(1, 2);
  surfacetest::append(surface, make_icosphere(1, 2, {100, 0, 0}));
  const TriangleBVH tree(surface, 4);
  check_tree(surface, tree, 4);
  const TriangleBVH::Node& left = tree.nodes()[1];
  const TriangleBVH::Node& right = tree.nodes()[tree.nodes()[0].first];
  EXPECT_TRUE((left.max[0] < 50 && right.min[0] > 50) || (right.max[0] < 50 && left.min[0] > 50))
      << left.min[0] << " " << left.max[0] << " / " << right.min[0] << " " << right.max[0];
}

TEST(TriangleBvh, BoxesTouchingATriangleOverlapIt) {
  // Unit cube, 2 x 2 squares a face: the face x = 1 has 8 triangles.
  const TriangleSurface cube = make_box({0, 0, 0}, {1, 1, 1}, 2);
  const TriangleBVH tree(cube, 2);
  std::vector<int> touching = tree.overlapping(SurfaceBox{{1, 0.25, 0.25}, {2, 0.75, 0.75}});
  std::vector<int> expected;
  for (int t = 0; t < cube.triangle_count(); ++t)
    if (triangle_box(cube, t)[3] >= 1 && triangle_box(cube, t)[1] <= 0.75 && triangle_box(cube, t)[4] >= 0.25 &&
        triangle_box(cube, t)[2] <= 0.75 && triangle_box(cube, t)[5] >= 0.25)
      expected.push_back(t);
  std::sort(touching.begin(), touching.end());
  EXPECT_EQ(touching, expected);
  EXPECT_GE(touching.size(), 8u);
  EXPECT_TRUE(tree.overlapping(SurfaceBox{{1.000001, 0, 0}, {2, 1, 1}}).empty());
  // for_each_overlapping visits the same triangles as overlapping() returns.
  const double min[3] = {1, 0.25, 0.25}, max[3] = {2, 0.75, 0.75};
  std::vector<int> visited;
  tree.for_each_overlapping(min, max, [&](int t) { visited.push_back(t); });
  std::sort(visited.begin(), visited.end());
  EXPECT_EQ(visited, touching);
}

}  // namespace
