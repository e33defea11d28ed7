// The children of tri3, quad4, tet4, prism6 and hex8 over their refined
// grids (see split_patterns.hpp).
#include "tensormass/refinement/split_patterns.hpp"

#include <stdexcept>
#include <string>

namespace tensormass {
namespace {

SplitNode node_of(std::initializer_list<int> corners) {
  SplitNode node;
  for (int corner : corners) node.corners[node.count++] = corner;
  return node;
}

/// The red refinement of triangle (0, 1, 2) over midpoints (3 = 0-1, 4 = 1-2, 5 = 2-0).
constexpr std::array<std::array<int, 3>, 4> kRedTriangles{{{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}}};

SplitPattern tri3_pattern() {
  SplitPattern pattern;
  pattern.nodes = {node_of({0}), node_of({1}), node_of({2}), node_of({0, 1}), node_of({1, 2}), node_of({2, 0})};
  for (const auto& triangle : kRedTriangles) pattern.children.push_back({triangle.begin(), triangle.end()});
  return pattern;
}

SplitPattern quad4_pattern() {
  SplitPattern pattern;
  pattern.nodes = {node_of({0}),    node_of({1}),    node_of({2}),    node_of({3}),         node_of({0, 1}),
                   node_of({1, 2}), node_of({2, 3}), node_of({3, 0}), node_of({0, 1, 2, 3})};
  pattern.children = {{0, 4, 8, 7}, {4, 1, 5, 8}, {8, 5, 2, 6}, {7, 8, 6, 3}};
  return pattern;
}

/// Signed volume (x 6) of the tet over reference points a, b, c, d.
double orientation(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c,
                   const std::array<double, 3>& d) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

/// The mean of a pattern node's corners in reference coordinates `corner`.
template <std::size_t N>
std::array<double, 3> reference_point(const SplitNode& node, const std::array<std::array<double, 3>, N>& corner) {
  std::array<double, 3> x{0, 0, 0};
  for (int k = 0; k < node.count; ++k)
    for (int c = 0; c < 3; ++c) x[c] += corner[node.corners[k]][c] / node.count;
  return x;
}

/// Orders a tet child (indices into pattern.nodes) for a positive volume.
template <std::size_t N>
std::vector<int> oriented_tet(std::vector<int> tet, const SplitPattern& pattern,
                              const std::array<std::array<double, 3>, N>& corner) {
  const auto point = [&](int k) { return reference_point(pattern.nodes[static_cast<std::size_t>(tet[k])], corner); };
  if (orientation(point(0), point(1), point(2), point(3)) < 0) std::swap(tet[2], tet[3]);
  return tet;
}

SplitPattern tet4_pattern(int diagonal) {
  SplitPattern pattern;
  // Corners 0-3, then the midpoints of edges 0-1, 1-2, 2-0, 0-3, 1-3, 2-3 (nodes 4-9).
  pattern.nodes = {node_of({0}),    node_of({1}),    node_of({2}),    node_of({3}),    node_of({0, 1}),
                   node_of({1, 2}), node_of({2, 0}), node_of({0, 3}), node_of({1, 3}), node_of({2, 3})};
  pattern.children = {{0, 4, 6, 7}, {4, 1, 5, 8}, {6, 5, 2, 9}, {7, 8, 9, 3}};
  // The diagonal's two ends and the four octahedron vertices around it, in a cycle.
  constexpr std::array<std::array<int, 6>, 3> kCuts{{{4, 9, 6, 5, 8, 7}, {6, 8, 4, 5, 9, 7}, {7, 5, 4, 6, 9, 8}}};
  const std::array<int, 6>& cut = kCuts.at(static_cast<std::size_t>(diagonal));
  const std::array<std::array<double, 3>, 4> corner{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (int k = 0; k < 4; ++k)
    pattern.children.push_back(oriented_tet({cut[0], cut[1], cut[2 + k], cut[2 + (k + 1) % 4]}, pattern, corner));
  return pattern;
}

SplitPattern pyramid5_pattern() {
  // Corners 0-3 (base, counter-clockwise seen from the apex) and 4 (apex);
  // base edge midpoints e_k (nodes 5-8), lateral edge midpoints l_k (9-12),
  // the base's centre (13).
  SplitPattern pattern;
  pattern.nodes = {node_of({0}), node_of({1}), node_of({2}), node_of({3}), node_of({4})};
  for (int k = 0; k < 4; ++k) pattern.nodes.push_back(node_of({k, (k + 1) % 4}));
  for (int k = 0; k < 4; ++k) pattern.nodes.push_back(node_of({k, 4}));
  pattern.nodes.push_back(node_of({0, 1, 2, 3}));
  const auto e = [](int k) { return 5 + (k + 4) % 4; };
  const auto l = [](int k) { return 9 + (k + 4) % 4; };
  for (int k = 0; k < 4; ++k) pattern.children.push_back({k, e(k), 13, e(k - 1), l(k)});
  pattern.children.push_back({l(0), l(1), l(2), l(3), 4});
  pattern.children.push_back({l(0), l(3), l(2), l(1), 13});
  const std::array<std::array<double, 3>, 5> corner{{{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 1}}};
  for (int k = 0; k < 4; ++k) pattern.children.push_back(oriented_tet({e(k), l(k + 1), l(k), 13}, pattern, corner));
  pattern.child_elements = {"pyramid5", "pyramid5", "pyramid5", "pyramid5", "pyramid5",
                            "pyramid5", "tet4",     "tet4",     "tet4",     "tet4"};
  return pattern;
}

SplitPattern prism6_pattern() {
  // Layer l (0 bottom, 1 middle, 2 top) of the six red-refinement points
  // (corners 0-2 of the triangle, then midpoints of 0-1, 1-2, 2-0).
  SplitPattern pattern;
  const std::array<std::array<int, 2>, 6> triangle_points{{{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {2, 0}}};
  for (int layer = 0; layer < 3; ++layer)
    for (const auto& [a, b] : triangle_points) {
      if (layer != 1) {
        const int offset = layer == 0 ? 0 : 3;
        pattern.nodes.push_back(a == b ? node_of({a + offset}) : node_of({a + offset, b + offset}));
      } else {
        pattern.nodes.push_back(a == b ? node_of({a, a + 3}) : node_of({a, b, b + 3, a + 3}));
      }
    }
  for (int layer = 0; layer < 2; ++layer)
    for (const auto& triangle : kRedTriangles) {
      std::vector<int> child;
      for (int k = 0; k < 3; ++k) child.push_back(6 * layer + triangle[k]);
      for (int k = 0; k < 3; ++k) child.push_back(6 * (layer + 1) + triangle[k]);
      pattern.children.push_back(child);
    }
  return pattern;
}

SplitPattern hex8_pattern() {
  // Grid point (i, j, k), each 0..2, is node 9k + 3j + i; a coordinate at 1
  // spans both corners' values along its axis.
  constexpr std::array<std::array<int, 3>, 8> kCorner{
      {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 2}, {2, 0, 2}, {2, 2, 2}, {0, 2, 2}}};
  const auto corner_at = [&](int i, int j, int k) {
    for (int c = 0; c < 8; ++c)
      if (kCorner[c][0] == i && kCorner[c][1] == j && kCorner[c][2] == k) return c;
    return -1;
  };
  SplitPattern pattern;
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        SplitNode node;
        // The free axes walk their corners in a cycle: (0,0), (2,0), (2,2), (0,2).
        constexpr std::array<std::array<int, 2>, 4> kCycle{{{0, 0}, {2, 0}, {2, 2}, {0, 2}}};
        std::vector<int> free;
        const std::array<int, 3> at{i, j, k};
        for (int axis = 0; axis < 3; ++axis)
          if (at[axis] == 1) free.push_back(axis);
        const int count = 1 << free.size();
        for (int n = 0; n < count; ++n) {
          std::array<int, 3> p = at;
          if (free.size() == 1) p[free[0]] = 2 * n;
          else if (free.size() == 2) p[free[0]] = kCycle[n][0], p[free[1]] = kCycle[n][1];
          else if (free.size() == 3) p = {2 * (n & 1), (n & 2), (n & 4) / 2};
          node.corners[node.count++] = corner_at(p[0], p[1], p[2]);
        }
        pattern.nodes.push_back(node);
      }
  for (int c = 0; c < 8; ++c) {  // child c holds corner c
    const int i0 = kCorner[c][0] / 2, j0 = kCorner[c][1] / 2, k0 = kCorner[c][2] / 2;
    std::vector<int> child;
    for (const auto& [i, j, k] : kCorner) child.push_back(9 * (k0 + k / 2) + 3 * (j0 + j / 2) + (i0 + i / 2));
    pattern.children.push_back(child);
  }
  return pattern;
}

}  // namespace

bool has_split_pattern(std::string_view element) {
  return element == "tri3" || element == "quad4" || element == "tet4" || element == "prism6" || element == "hex8" ||
         element == "pyramid5";
}

const SplitPattern& split_pattern(std::string_view element, int tet_diagonal) {
  static const SplitPattern tri3 = tri3_pattern(), quad4 = quad4_pattern(), prism6 = prism6_pattern(),
                            hex8 = hex8_pattern(), pyramid5 = pyramid5_pattern();
  static const std::array<SplitPattern, 3> tet4{tet4_pattern(0), tet4_pattern(1), tet4_pattern(2)};
  if (element == "tri3") return tri3;
  if (element == "quad4") return quad4;
  if (element == "prism6") return prism6;
  if (element == "hex8") return hex8;
  if (element == "pyramid5") return pyramid5;
  if (element == "tet4") {
    if (tet_diagonal < 0 || tet_diagonal > 2)
      throw std::invalid_argument("split_pattern: tet4 diagonal " + std::to_string(tet_diagonal) + " is not 0, 1 or 2");
    return tet4[static_cast<std::size_t>(tet_diagonal)];
  }
  throw std::invalid_argument("split_pattern: no split pattern for " + std::string(element));
}

}  // namespace tensormass
