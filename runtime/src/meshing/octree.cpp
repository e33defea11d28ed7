// Linear octree with strong 2:1 balance (see octree.hpp).
#include "meshing/octree.hpp"

#include <stdexcept>

namespace tensormass::detail {

Octree::Octree(std::array<double, 3> origin, double base_size, std::array<int, 3> counts, int max_depth)
    : origin_(origin), base_size_(base_size), counts_(counts), max_depth_(max_depth) {
  if (max_depth < 0 || max_depth > 14) throw std::invalid_argument("octree depth out of range");
  for (int a = 0; a < 3; ++a) {
    if (counts[a] < 1) throw std::invalid_argument("octree lattice empty: no base cell along an axis");
    if ((static_cast<std::int64_t>(counts[a]) << (max_depth + 1)) >= (std::int64_t{1} << 20))
      throw std::invalid_argument("octree lattice too large");
  }
  for (int i = 0; i < counts[0]; ++i)
    for (int j = 0; j < counts[1]; ++j)
      for (int k = 0; k < counts[2]; ++k) leaves_.insert(cell_key(0, i, j, k));
}

std::array<std::int64_t, 3> Octree::lattice_origin(const OctreeCell& cell) const {
  const std::int64_t span = lattice_span(cell.depth);
  return {cell.index[0] * span, cell.index[1] * span, cell.index[2] * span};
}

std::array<double, 3> Octree::position(std::int64_t x, std::int64_t y, std::int64_t z) const {
  const double unit = base_size_ / static_cast<double>(std::int64_t{2} << max_depth_);
  return {origin_[0] + unit * static_cast<double>(x), origin_[1] + unit * static_cast<double>(y),
          origin_[2] + unit * static_cast<double>(z)};
}

std::array<double, 3> Octree::centre(const OctreeCell& cell) const {
  const auto o = lattice_origin(cell);
  const std::int64_t half = lattice_span(cell.depth) / 2;
  return position(o[0] + half, o[1] + half, o[2] + half);
}

bool Octree::in_grid(const OctreeCell& cell) const {
  for (int a = 0; a < 3; ++a)
    if (cell.index[a] < 0 || cell.index[a] >= (counts_[a] << cell.depth)) return false;
  return true;
}

bool Octree::find_containing_leaf(const OctreeCell& cell, OctreeCell& leaf) const {
  if (!in_grid(cell)) return false;
  for (int depth = cell.depth; depth >= 0; --depth) {
    const int shift = cell.depth - depth;
    const OctreeCell ancestor{depth, {cell.index[0] >> shift, cell.index[1] >> shift, cell.index[2] >> shift}};
    if (is_leaf(ancestor)) {
      leaf = ancestor;
      return true;
    }
  }
  return false;
}

void Octree::split(const OctreeCell& leaf) {
  leaves_.erase(cell_key(leaf));
  for (int c = 0; c < 8; ++c)
    leaves_.insert(cell_key(leaf.depth + 1, 2 * leaf.index[0] + (c & 1), 2 * leaf.index[1] + ((c >> 1) & 1),
                            2 * leaf.index[2] + ((c >> 2) & 1)));
}

void Octree::refine(
    const std::function<void(const std::vector<OctreeCell>&, std::vector<char>&, std::vector<char>&)>& decide) {
  for (int depth = 0; depth <= max_depth_; ++depth) {
    std::vector<OctreeCell> cells;
    for (std::uint64_t key : leaves_) {
      const OctreeCell cell = cell_of_key(key);
      if (cell.depth == depth) cells.push_back(cell);
    }
    std::vector<char> refine(cells.size(), 0), drop(cells.size(), 0);
    decide(cells, refine, drop);
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (drop[c]) leaves_.erase(cell_key(cells[c]));
      else if (refine[c] && depth < max_depth_) split(cells[c]);
    }
  }
}

void Octree::balance() {
  std::vector<std::uint64_t> work(leaves_.begin(), leaves_.end());
  while (!work.empty()) {
    const std::uint64_t key = work.back();
    work.pop_back();
    if (!leaves_.count(key)) continue;
    const OctreeCell cell = cell_of_key(key);
    if (cell.depth < 2) continue;
    bool split_any = false;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          if (!dx && !dy && !dz) continue;
          const OctreeCell neighbour{cell.depth, {cell.index[0] + dx, cell.index[1] + dy, cell.index[2] + dz}};
          OctreeCell leaf;
          if (!find_containing_leaf(neighbour, leaf) || leaf.depth >= cell.depth - 1) continue;
          split(leaf);
          for (int c = 0; c < 8; ++c)
            work.push_back(cell_key(leaf.depth + 1, 2 * leaf.index[0] + (c & 1), 2 * leaf.index[1] + ((c >> 1) & 1),
                                    2 * leaf.index[2] + ((c >> 2) & 1)));
          split_any = true;
        }
    if (split_any) work.push_back(key);  // the new children may still be two levels coarser
  }
}

}  // namespace tensormass::detail
