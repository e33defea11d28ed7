// Transition patterns: every pattern covers its cell exactly once with
// counter-clockwise triangles that use every hanging midpoint.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <vector>

#include "tensormass/refinement/transition_patterns.hpp"

namespace {

using tensormass::Triangle;

/// Nodes 0-3: a distorted quad; 4-7: its edge midpoints; 8: its centre;
/// 9: the middle of the diagonal 1-3.
const std::vector<double> kPositions = {0.0, 0.0,  0, 2.0,  0.2, 0, 2.2,   1.7,  0, -0.1,  1.5,  0, 1.0,  0.1,  0,
                                        2.1, 0.95, 0, 1.05, 1.6, 0, -0.05, 0.75, 0, 1.025, 0.85, 0, 0.95, 0.85, 0};

double signed_area(const Triangle& t) {
  const double* a = &kPositions[3 * t[0]];
  const double* b = &kPositions[3 * t[1]];
  const double* c = &kPositions[3 * t[2]];
  return ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) / 2;
}

double polygon_area(const std::vector<int>& nodes) {
  double sum = 0;
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const double* p = &kPositions[3 * nodes[k]];
    const double* q = &kPositions[3 * nodes[(k + 1) % nodes.size()]];
    sum += p[0] * q[1] - q[0] * p[1];
  }
  return sum / 2;
}

void expect_covers(const std::vector<Triangle>& triangles, const std::vector<int>& outline, std::size_t count) {
  EXPECT_EQ(triangles.size(), count);
  double area = 0;
  for (const Triangle& t : triangles) {
    EXPECT_GT(signed_area(t), 0.0);
    area += signed_area(t);
  }
  EXPECT_NEAR(area, polygon_area(outline), 1e-14);
  for (int node : outline)  // every outline node (corners, hanging midpoints) is used
    EXPECT_TRUE(std::any_of(triangles.begin(), triangles.end(), [&](const Triangle& t) {
      return std::find(t.begin(), t.end(), node) != t.end();
    })) << node;
}

TEST(TransitionPatterns, QuadFanHasTwoTrianglesPerSplitEdge) {
  const std::array<int, 4> corners{0, 1, 2, 3};
  for (int mask = 1; mask < 16; ++mask) {
    std::array<int, 4> midpoints{-1, -1, -1, -1};
    std::vector<int> outline;
    for (int k = 0; k < 4; ++k) {
      outline.push_back(corners[k]);
      if (mask >> k & 1) outline.push_back(midpoints[k] = 4 + k);
    }
    const auto triangles = tensormass::quad_transition(corners, midpoints, 8);
    expect_covers(triangles, outline, 4 + static_cast<std::size_t>(__builtin_popcount(mask)));
  }
}

TEST(TransitionPatterns, TriangleRedGreenPatterns) {
  // The triangle 0, 1, 3 with midpoints 4 (edge 0-1), 9 (1-3), 7 (3-0).
  const std::array<int, 3> corners{0, 1, 3};
  const std::array<int, 3> all{4, 9, 7};
  for (int mask = 0; mask < 8; ++mask) {
    std::array<int, 3> midpoints{-1, -1, -1};
    std::vector<int> outline;
    for (int k = 0; k < 3; ++k) {
      outline.push_back(corners[k]);
      if (mask >> k & 1) outline.push_back(midpoints[k] = all[k]);
    }
    const auto triangles = tensormass::triangle_transition(corners, midpoints, kPositions);
    expect_covers(triangles, outline, static_cast<std::size_t>(1 + __builtin_popcount(mask)));
  }
}

}  // namespace
