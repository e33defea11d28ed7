// Fans and red-green patterns over hanging midpoints (see transition_patterns.hpp).
#include "tensormass/refinement/transition_patterns.hpp"

#include <algorithm>

#include "refinement/node_pairs.hpp"

namespace tensormass {
namespace {

using detail::squared_distance;

/// Two split edges: `whole` is the edge without a midpoint (corners a = whole,
/// b = whole + 1), m1 splits edge b-c, m2 splits edge c-a.
std::vector<Triangle> green_pattern(int a, int b, int c, int m1, int m2, std::span<const double> positions) {
  std::vector<Triangle> triangles{{m1, c, m2}};
  // The trapezoid a, b, m1, m2 along its shorter diagonal; a tie goes by node
  // index, so that the cells on both sides of a 3D face choose alike.
  const double from_a = squared_distance(positions, a, m1), from_b = squared_distance(positions, b, m2);
  if (from_a < from_b || (from_a == from_b && a < b)) {
    triangles.push_back({a, b, m1});
    triangles.push_back({a, m1, m2});
  } else {
    triangles.push_back({a, b, m2});
    triangles.push_back({b, m1, m2});
  }
  return triangles;
}

}  // namespace

std::vector<Triangle> quad_transition(std::span<const int, 4> corners, std::span<const int, 4> midpoints, int centre) {
  std::vector<Triangle> triangles;
  for (int k = 0; k < 4; ++k) {
    const int from = corners[k], to = corners[(k + 1) % 4];
    if (midpoints[k] < 0) {
      triangles.push_back({from, to, centre});
    } else {
      triangles.push_back({from, midpoints[k], centre});
      triangles.push_back({midpoints[k], to, centre});
    }
  }
  return triangles;
}

std::vector<Triangle> triangle_transition(std::span<const int, 3> corners, std::span<const int, 3> midpoints,
                                          std::span<const double> positions) {
  const int split = static_cast<int>(std::count_if(midpoints.begin(), midpoints.end(), [](int m) { return m >= 0; }));
  const auto corner = [&](int k) { return corners[k % 3]; };
  const auto midpoint = [&](int k) { return midpoints[k % 3]; };
  if (split == 0) return {Triangle{corners[0], corners[1], corners[2]}};
  if (split == 3)
    return {Triangle{corners[0], midpoints[0], midpoints[2]}, Triangle{midpoints[0], corners[1], midpoints[1]},
            Triangle{midpoints[2], midpoints[1], corners[2]}, Triangle{midpoints[0], midpoints[1], midpoints[2]}};
  if (split == 1) {
    const int k = static_cast<int>(std::find_if(midpoints.begin(), midpoints.end(), [](int m) { return m >= 0; }) -
                                   midpoints.begin());
    return {Triangle{corner(k), midpoint(k), corner(k + 2)}, Triangle{midpoint(k), corner(k + 1), corner(k + 2)}};
  }
  const int whole =
      static_cast<int>(std::find(midpoints.begin(), midpoints.end(), -1) - midpoints.begin());  // split == 2
  return green_pattern(corner(whole), corner(whole + 1), corner(whole + 2), midpoint(whole + 1), midpoint(whole + 2),
                       positions);
}

std::vector<const char*> transition_element_names(int dim) {
  if (dim == 2) return {"tri3"};
  return {"tet4", "pyramid5"};
}

std::vector<int> cone(const FacePiece& piece, int apex) {
  if (piece[3] < 0) return {piece[0], piece[2], piece[1], apex};
  return {piece[0], piece[3], piece[2], piece[1], apex};
}

}  // namespace tensormass
