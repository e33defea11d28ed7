// Centroid tracks of groups (output.track): fixed node weights from the rest
// volumes, one row per recorded state (the run streams them as io/track_csv rows).
#include "tensormass/simulation/track.hpp"

#include <algorithm>

#include "tensormass/common/errors.hpp"
#include "tensormass/mesh/mesh_quality.hpp"

namespace tensormass {

GroupTrack::GroupTrack(const Mesh& mesh, const Group& group) : GroupTrack(mesh, group.name, group.cells) {}

GroupTrack::GroupTrack(const Mesh& mesh, std::string name, std::span<const int> cells)
    : name_(std::move(name)), dim_(mesh.dim) {
  if (cells.empty()) throw InputError("cannot track group '" + name_ + "': it has no cells");
  // Per node: sum over its cells of V_c / n_c (divided by the total below).
  std::vector<double> node_weight(static_cast<std::size_t>(mesh.node_count()), 0.0);
  std::vector<char> used(node_weight.size(), 0);
  for (int cell : cells) {
    const auto [b, local] = mesh.locate(cell);
    const ElementBlock& block = mesh.blocks[static_cast<std::size_t>(b)];
    const double volume = cell_volume(*block.element, mesh.dim, cell_coordinates(mesh, block, local));
    if (!(volume > 0))
      throw InputError("cannot track group '" + name_ + "': " + mesh.describe_cell(cell) +
                       " has no positive volume at rest");
    rest_volume_ += volume;
    for (int node : block.cell_nodes(local)) {
      node_weight[static_cast<std::size_t>(node)] += volume / block.nodes_per_cell();
      used[static_cast<std::size_t>(node)] = 1;
    }
  }
  for (int node = 0; node < mesh.node_count(); ++node) {
    if (!used[static_cast<std::size_t>(node)]) continue;
    nodes_.push_back(node);
    weights_.push_back(node_weight[static_cast<std::size_t>(node)] / rest_volume_);
  }
  rest_centroid_ = weighted_sum(mesh.rest_positions, 3);
}

std::array<double, 3> GroupTrack::weighted_sum(std::span<const double> values, int stride) const {
  // sum_i W_i v_i = v_0 + sum_i W_i (v_i - v_0) as sum_i W_i = 1: exact when
  // every v_i is the same (a rigid translation), and less cancellation.
  auto value = [&](std::size_t k, int c) {
    return values[static_cast<std::size_t>(nodes_[k]) * static_cast<std::size_t>(stride) + static_cast<std::size_t>(c)];
  };
  std::array<double, 3> sum{};
  for (int c = 0; c < std::min(dim_, stride); ++c) {
    double offset = 0;
    for (std::size_t k = 0; k < nodes_.size(); ++k) offset += weights_[k] * (value(k, c) - value(0, c));
    sum[c] = value(0, c) + offset;
  }
  return sum;
}

std::array<double, 3> GroupTrack::weighted_displacement(std::span<const double> u) const {
  return weighted_sum(u, dim_);
}

std::array<double, 3> GroupTrack::centroid(std::span<const double> u) const {
  const std::array<double, 3> shift = weighted_displacement(u);
  return {rest_centroid_[0] + shift[0], rest_centroid_[1] + shift[1], rest_centroid_[2] + shift[2]};
}

TrackRow GroupTrack::record(double time, std::span<const double> u) {
  const std::array<double, 3> shift = weighted_displacement(u);
  if (!recorded_) first_ = shift, recorded_ = true;
  TrackRow row;
  row.time = time;
  for (int c = 0; c < 3; ++c) {
    row.position[c] = rest_centroid_[c] + shift[c];
    row.displacement[c] = shift[c] - first_[c];
  }
  return row;
}

}  // namespace tensormass
