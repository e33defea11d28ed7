/// \file octree.hpp
/// Internal to the octree mesher (not installed): a linear octree of cubic
/// cells over a base grid, stored as a hash set of leaf keys, with strong
/// 2:1 balance (a leaf's face, edge and corner neighbours differ from it by
/// at most one level).
///
/// Glossary:
///   depth     0 for base cells (edge `base_size`), d for cells of edge base_size / 2^d
///   index     (i, j, k) of a cell among the cells of its depth
///   lattice   integer points at half the finest cell edge: a cell's corners,
///             edge midpoints, face centres and centre all lie on it
#ifndef TENSORMASS_OCTREE_HPP
#define TENSORMASS_OCTREE_HPP

#include <array>
#include <cstdint>
#include <functional>
#include <unordered_set>
#include <vector>

namespace tensormass::detail {

/// A cell of the octree: depth and index.
struct OctreeCell {
  int depth = 0;
  std::array<int, 3> index{};
};

/// Packs a cell into 64 bits (4 bits of depth, 20 per index).
inline std::uint64_t cell_key(int depth, int i, int j, int k) {
  return (static_cast<std::uint64_t>(depth) << 60) | (static_cast<std::uint64_t>(i) << 40) |
         (static_cast<std::uint64_t>(j) << 20) | static_cast<std::uint64_t>(k);
}
inline std::uint64_t cell_key(const OctreeCell& c) { return cell_key(c.depth, c.index[0], c.index[1], c.index[2]); }
inline OctreeCell cell_of_key(std::uint64_t key) {
  const auto field = [&](int shift) { return static_cast<int>((key >> shift) & 0xFFFFF); };
  return {static_cast<int>(key >> 60), {field(40), field(20), field(0)}};
}

/// Packs a lattice point into 63 bits (21 per coordinate).
inline std::uint64_t lattice_key(std::int64_t x, std::int64_t y, std::int64_t z) {
  return (static_cast<std::uint64_t>(x) << 42) | (static_cast<std::uint64_t>(y) << 21) | static_cast<std::uint64_t>(z);
}

class Octree {
 public:
  /// Base grid of `counts` cells of edge `base_size` from `origin`; cells
  /// may be refined down to depth `max_depth`.
  Octree(std::array<double, 3> origin, double base_size, std::array<int, 3> counts, int max_depth);

  int max_depth() const { return max_depth_; }
  double base_size() const { return base_size_; }
  double cell_size(int depth) const { return base_size_ / static_cast<double>(1 << depth); }
  /// Lattice units per cell edge at `depth`.
  std::int64_t lattice_span(int depth) const { return std::int64_t{2} << (max_depth_ - depth); }
  /// Lattice coordinates of the cell's minimum corner.
  std::array<std::int64_t, 3> lattice_origin(const OctreeCell& cell) const;
  /// World position of a lattice point.
  std::array<double, 3> position(std::int64_t x, std::int64_t y, std::int64_t z) const;
  std::array<double, 3> centre(const OctreeCell& cell) const;

  const std::unordered_set<std::uint64_t>& leaves() const { return leaves_; }
  bool is_leaf(const OctreeCell& cell) const { return leaves_.count(cell_key(cell)) != 0; }
  /// True when the cell index lies inside the base grid at its depth.
  bool in_grid(const OctreeCell& cell) const;
  /// The leaf that contains `cell` (which is at that leaf's depth or deeper), if any.
  bool find_containing_leaf(const OctreeCell& cell, OctreeCell& leaf) const;

  /// Refines, depth by depth, every leaf for which `refine` says so (asked
  /// for all leaves of one depth at once, so the caller can evaluate them in
  /// parallel); leaves for which `drop` says so are removed instead.
  void refine(const std::function<void(const std::vector<OctreeCell>&, std::vector<char>& refine,
                                       std::vector<char>& drop)>& decide);
  /// Splits leaves until no two leaves sharing a face, an edge or a corner
  /// differ by more than one depth.
  void balance();
  /// Replaces a leaf by its 8 children.
  void split(const OctreeCell& leaf);

 private:
  std::array<double, 3> origin_;
  double base_size_;
  std::array<int, 3> counts_;
  int max_depth_;
  std::unordered_set<std::uint64_t> leaves_;
};

}  // namespace tensormass::detail

#endif
