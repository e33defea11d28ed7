// Keys and distances of node pairs, shared by the refinement sources
// (internal header).
#ifndef TENSORMASS_REFINEMENT_NODE_PAIRS_HPP
#define TENSORMASS_REFINEMENT_NODE_PAIRS_HPP

#include <algorithm>
#include <cstdint>
#include <span>

namespace tensormass::detail {

/// The key of the edge (a, b), whichever way round: low node, high node.
inline std::uint64_t edge_key(int a, int b) {
  return static_cast<std::uint64_t>(std::min(a, b)) << 32 | static_cast<std::uint32_t>(std::max(a, b));
}

/// Squared distance between nodes a and b of `positions` (node count by 3).
inline double squared_distance(std::span<const double> positions, int a, int b) {
  double sum = 0;
  for (int c = 0; c < 3; ++c) {
    const double d = positions[3 * static_cast<std::size_t>(a) + c] - positions[3 * static_cast<std::size_t>(b) + c];
    sum += d * d;
  }
  return sum;
}

}  // namespace tensormass::detail

#endif
