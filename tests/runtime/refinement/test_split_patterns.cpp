// One cell's split into children (tensormass/refinement/split_patterns.hpp),
// checked on reference cells: the children tile the parent with its
// orientation (measures positive and summing to the parent's), meet face to
// face, the refined nodes are distinct means of corners, a quad face's centre
// lists its corners in cycle, and the tet's three cuts use their diagonal.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "tensormass/refinement/split_patterns.hpp"

namespace tensormass {
namespace {

using Point = std::array<double, 3>;

/// Corners of each element's reference cell, in VTK order.
const std::map<std::string, std::vector<Point>>& reference_corners() {
  static const std::map<std::string, std::vector<Point>> corners = {
      {"tri3", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}},
      {"quad4", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}},
      {"tet4", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
      {"pyramid5", {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 1}}},
      {"prism6", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}}},
      {"hex8", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}},
  };
  return corners;
}

/// Faces (edges in 2D) of each element, as local corner lists in VTK order.
const std::vector<std::vector<int>>& faces_of(const std::string& element) {
  static const std::map<std::string, std::vector<std::vector<int>>> faces = {
      {"tri3", {{0, 1}, {1, 2}, {2, 0}}},
      {"quad4", {{0, 1}, {1, 2}, {2, 3}, {3, 0}}},
      {"tet4", {{0, 1, 2}, {0, 1, 3}, {1, 2, 3}, {0, 2, 3}}},
      {"pyramid5", {{0, 1, 2, 3}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}},
      {"prism6", {{0, 1, 2}, {3, 4, 5}, {0, 1, 4, 3}, {1, 2, 5, 4}, {2, 0, 3, 5}}},
      {"hex8", {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}},
  };
  return faces.at(element);
}

Point minus(const Point& a, const Point& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Point cross(const Point& a, const Point& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Point& a) { return std::sqrt(dot(a, a)); }

/// Six times the signed volume of the tet (a, b, c, d).
double tet6(const Point& a, const Point& b, const Point& c, const Point& d) {
  return dot(minus(b, a), cross(minus(c, a), minus(d, a)));
}

/// Signed area (2D) or volume (3D) of a cell with straight edges and planar
/// faces, from its corners in VTK order.
double signed_measure(const std::string& element, const std::vector<Point>& p) {
  if (element == "tri3") return cross(minus(p[1], p[0]), minus(p[2], p[0]))[2] / 2;
  if (element == "quad4")
    return signed_measure("tri3", {p[0], p[1], p[2]}) + signed_measure("tri3", {p[0], p[2], p[3]});
  if (element == "tet4") return tet6(p[0], p[1], p[2], p[3]) / 6;
  if (element == "pyramid5") return (tet6(p[0], p[1], p[2], p[4]) + tet6(p[0], p[2], p[3], p[4])) / 6;
  if (element == "prism6")
    return (tet6(p[0], p[1], p[2], p[3]) + tet6(p[1], p[2], p[3], p[4]) + tet6(p[2], p[3], p[4], p[5])) / 6;
  // hex8: six tets around the diagonal 0-6.
  const int around[6][2] = {{1, 2}, {2, 3}, {3, 7}, {7, 4}, {4, 5}, {5, 1}};
  double sum = 0;
  for (const auto& [b, c] : around) sum += tet6(p[0], p[b], p[c], p[6]);
  return sum / 6;
}

/// Length of an edge or area of a planar face.
double face_measure(const std::vector<Point>& p) {
  if (p.size() == 2) return norm(minus(p[1], p[0]));
  double area = 0;
  for (std::size_t k = 1; k + 1 < p.size(); ++k) area += norm(cross(minus(p[k], p[0]), minus(p[k + 1], p[0]))) / 2;
  return area;
}

/// The reference positions of a pattern's nodes.
std::vector<Point> node_points(const std::string& element, const SplitPattern& pattern) {
  const std::vector<Point>& corner = reference_corners().at(element);
  std::vector<Point> points;
  for (const SplitNode& node : pattern.nodes) {
    Point x{0, 0, 0};
    for (int k = 0; k < node.count; ++k)
      for (int a = 0; a < 3; ++a) x[a] += corner.at(static_cast<std::size_t>(node.corners[k]))[a] / node.count;
    points.push_back(x);
  }
  return points;
}

/// The element of child `c`.
std::string child_element(const std::string& element, const SplitPattern& pattern, std::size_t c) {
  return pattern.child_elements.empty() ? element : std::string(pattern.child_elements.at(c));
}

/// Every (element, tet diagonal) pattern.
std::vector<std::pair<std::string, int>> all_patterns() {
  return {{"tri3", 0}, {"quad4", 0},    {"tet4", 0},   {"tet4", 1},
          {"tet4", 2}, {"pyramid5", 0}, {"prism6", 0}, {"hex8", 0}};
}

TEST(SplitPatterns, ChildrenTileTheParentWithItsOrientation) {
  for (const auto& [element, diagonal] : all_patterns()) {
    const SplitPattern& pattern = split_pattern(element, diagonal);
    const std::vector<Point> points = node_points(element, pattern);
    const double parent = signed_measure(element, reference_corners().at(element));
    ASSERT_GT(parent, 0) << element;
    double sum = 0;
    for (std::size_t c = 0; c < pattern.children.size(); ++c) {
      std::vector<Point> child;
      for (int node : pattern.children[c]) child.push_back(points.at(static_cast<std::size_t>(node)));
      const double measure = signed_measure(child_element(element, pattern, c), child);
      EXPECT_GT(measure, 1e-12) << element << " diagonal " << diagonal << " child " << c;
      sum += measure;
    }
    EXPECT_NEAR(sum, parent, 1e-14) << element << " diagonal " << diagonal;
  }
}

TEST(SplitPatterns, ChildrenMeetFaceToFaceAndCoverTheParentsBoundaryOnce) {
  for (const auto& [element, diagonal] : all_patterns()) {
    const SplitPattern& pattern = split_pattern(element, diagonal);
    const std::vector<Point> points = node_points(element, pattern);
    std::map<std::set<int>, int> uses;
    for (std::size_t c = 0; c < pattern.children.size(); ++c)
      for (const std::vector<int>& face : faces_of(child_element(element, pattern, c))) {
        std::set<int> nodes;
        for (int k : face) nodes.insert(pattern.children[c].at(static_cast<std::size_t>(k)));
        ++uses[nodes];
      }
    for (const auto& [nodes, count] : uses) EXPECT_LE(count, 2) << element << ": a face of three children";
    // The faces used once, the children's boundary, measure what the parent's faces measure.
    double boundary = 0;
    double parent_boundary = 0;
    const std::vector<Point>& corner = reference_corners().at(element);
    for (const std::vector<int>& face : faces_of(element)) {
      std::vector<Point> p;
      for (int k : face) p.push_back(corner[static_cast<std::size_t>(k)]);
      parent_boundary += face_measure(p);
    }
    for (std::size_t c = 0; c < pattern.children.size(); ++c)
      for (const std::vector<int>& face : faces_of(child_element(element, pattern, c))) {
        std::set<int> nodes;
        std::vector<Point> p;
        for (int k : face) {
          const int node = pattern.children[c].at(static_cast<std::size_t>(k));
          nodes.insert(node);
          p.push_back(points[static_cast<std::size_t>(node)]);
        }
        if (uses[nodes] == 1) boundary += face_measure(p);
      }
    EXPECT_NEAR(boundary, parent_boundary, 1e-13) << element << " diagonal " << diagonal;
  }
}

TEST(SplitPatterns, NodesAreDistinctMeansOfDistinctCornersAndAllUsed) {
  for (const auto& [element, diagonal] : all_patterns()) {
    const SplitPattern& pattern = split_pattern(element, diagonal);
    const int corners = static_cast<int>(reference_corners().at(element).size());
    for (const SplitNode& node : pattern.nodes) {
      EXPECT_TRUE(node.count == 1 || node.count == 2 || node.count == 4 || node.count == 8) << element;
      std::set<int> distinct(node.corners.begin(), node.corners.begin() + node.count);
      EXPECT_EQ(static_cast<int>(distinct.size()), node.count) << element;
      for (int k = 0; k < 8; ++k)
        if (k < node.count) {
          EXPECT_GE(node.corners[k], 0) << element;
          EXPECT_LT(node.corners[k], corners) << element;
        } else {
          EXPECT_EQ(node.corners[k], -1) << element;
        }
    }
    const std::vector<Point> points = node_points(element, pattern);
    for (std::size_t a = 0; a < points.size(); ++a)
      for (std::size_t b = a + 1; b < points.size(); ++b)
        EXPECT_GT(norm(minus(points[a], points[b])), 1e-12) << element << ": nodes " << a << " and " << b;
    std::set<int> used;
    for (const auto& child : pattern.children) used.insert(child.begin(), child.end());
    EXPECT_EQ(used.size(), pattern.nodes.size()) << element;
    EXPECT_EQ(*used.rbegin(), static_cast<int>(pattern.nodes.size()) - 1) << element;
  }
}

TEST(SplitPatterns, EachElementSplitsIntoTheDocumentedChildren) {
  const std::map<std::string, std::pair<std::size_t, std::size_t>> expected = {
      // element: children, nodes of the refined grid
      {"tri3", {4, 6}},    {"quad4", {4, 9}}, {"tet4", {8, 10}},
      {"prism6", {8, 18}}, {"hex8", {8, 27}}, {"pyramid5", {10, 14}},
  };
  for (const auto& [element, sizes] : expected) {
    const SplitPattern& pattern = split_pattern(element);
    EXPECT_EQ(pattern.children.size(), sizes.first) << element;
    EXPECT_EQ(pattern.nodes.size(), sizes.second) << element;
    const std::size_t corners = reference_corners().at(element).size();
    for (std::size_t c = 0; c < pattern.children.size(); ++c) {
      const std::string type = child_element(element, pattern, c);
      EXPECT_EQ(pattern.children[c].size(), reference_corners().at(type).size()) << element << " child " << c;
      if (element != "pyramid5") {
        EXPECT_EQ(pattern.children[c].size(), corners) << element;
        EXPECT_TRUE(pattern.child_elements.empty()) << element;
      }
    }
  }
  const SplitPattern& pyramid = split_pattern("pyramid5");
  EXPECT_EQ(std::count(pyramid.child_elements.begin(), pyramid.child_elements.end(), "pyramid5"), 6);
  EXPECT_EQ(std::count(pyramid.child_elements.begin(), pyramid.child_elements.end(), "tet4"), 4);
}

TEST(SplitPatterns, EachCornerBelongsToExactlyOneChild) {
  for (const auto& [element, diagonal] : all_patterns()) {
    const SplitPattern& pattern = split_pattern(element, diagonal);
    const std::vector<Point> points = node_points(element, pattern);
    const std::vector<Point>& corner = reference_corners().at(element);
    for (std::size_t k = 0; k < corner.size(); ++k) {
      int holders = 0;
      for (const auto& child : pattern.children)
        holders += std::any_of(child.begin(), child.end(), [&](int node) {
          return norm(minus(points[static_cast<std::size_t>(node)], corner[k])) == 0;
        });
      EXPECT_EQ(holders, 1) << element << " corner " << k;
    }
  }
}

TEST(SplitPatterns, QuadFaceCentresListTheirCornersInCycle) {
  for (const char* element : {"quad4", "hex8", "pyramid5", "prism6"}) {
    // Consecutive corners of a cycle are joined by an edge of the element.
    std::set<std::set<int>> edges;
    for (const std::vector<int>& face : faces_of(element))
      for (std::size_t k = 0; k < face.size(); ++k) edges.insert({face[k], face[(k + 1) % face.size()]});
    for (const SplitNode& node : split_pattern(element).nodes) {
      if (node.count != 4) continue;
      for (int k = 0; k < 4; ++k)
        EXPECT_EQ(edges.count({node.corners[k], node.corners[(k + 1) % 4]}), 1u)
            << element << ": corners " << node.corners[k] << " and " << node.corners[(k + 1) % 4];
    }
  }
}

TEST(SplitPatterns, TheTetsInnerChildrenShareTheChosenDiagonal) {
  // Diagonal 0 joins the midpoints of edges 0-1 and 2-3, 1 those of 0-2 and 1-3, 2 those of 0-3 and 1-2.
  const std::array<std::array<std::set<int>, 2>, 3> diagonals{
      {{{{0, 1}, {2, 3}}}, {{{0, 2}, {1, 3}}}, {{{0, 3}, {1, 2}}}}};
  for (int d = 0; d < 3; ++d) {
    const SplitPattern& pattern = split_pattern("tet4", d);
    std::array<int, 2> ends{-1, -1};
    for (std::size_t n = 0; n < pattern.nodes.size(); ++n)
      for (int e = 0; e < 2; ++e)
        if (std::set<int>(pattern.nodes[n].corners.begin(),
                          pattern.nodes[n].corners.begin() + pattern.nodes[n].count) == diagonals[d][e])
          ends[e] = static_cast<int>(n);
    ASSERT_GE(std::min(ends[0], ends[1]), 0) << d;
    int with_diagonal = 0;
    for (const auto& child : pattern.children)
      with_diagonal +=
          std::count(child.begin(), child.end(), ends[0]) && std::count(child.begin(), child.end(), ends[1]);
    EXPECT_EQ(with_diagonal, 4) << "diagonal " << d;
  }
}

TEST(SplitPatterns, OnlyTheSixFirstOrderElementsHaveAPattern) {
  for (const char* element : {"tri3", "quad4", "tet4", "prism6", "hex8", "pyramid5"})
    EXPECT_TRUE(has_split_pattern(element));
  for (const char* element : {"tet10", "hex20", "tri6", "quad8", "line2", ""}) EXPECT_FALSE(has_split_pattern(element));
}

TEST(SplitPatterns, AnotherElementOrTetDiagonalIsRefused) {
  try {
    split_pattern("tet10");
    ADD_FAILURE() << "tet10 has no pattern";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "split_pattern: no split pattern for tet10");
  }
  for (int diagonal : {-1, 3}) {
    try {
      split_pattern("tet4", diagonal);
      ADD_FAILURE() << "diagonal " << diagonal;
    } catch (const std::invalid_argument& error) {
      EXPECT_EQ(std::string(error.what()),
                "split_pattern: tet4 diagonal " + std::to_string(diagonal) + " is not 0, 1 or 2");
    }
  }
  EXPECT_NO_THROW(split_pattern("hex8", 7));  // the diagonal matters to tet4 alone
}

}  // namespace
}  // namespace tensormass
