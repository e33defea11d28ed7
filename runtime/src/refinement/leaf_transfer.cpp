// Fields carried from one leaf mesh to the next (see leaf_transfer.hpp).
#include "tensormass/refinement/leaf_transfer.hpp"

#include <algorithm>

namespace tensormass {

std::vector<double> transfer_nodal_field(const LeafTransfer& transfer, std::span<const double> old_values,
                                         int components) {
  if (components < 1) throw InputError("transfer: a nodal field needs at least one component");
  const std::size_t d = static_cast<std::size_t>(components);
  if (old_values.size() != static_cast<std::size_t>(transfer.old_node_count) * d)
    throw InputError("transfer: nodal field has " + std::to_string(old_values.size()) + " values, expected " +
                     std::to_string(transfer.old_node_count) + " nodes by " + std::to_string(components));
  std::vector<double> values(static_cast<std::size_t>(transfer.new_node_count()) * d, 0.0);
  for (int node = 0; node < transfer.new_node_count(); ++node) {
    const int first = transfer.node_offsets[node], last = transfer.node_offsets[node + 1];
    double* target = values.data() + static_cast<std::size_t>(node) * d;
    if (last - first == 1 && transfer.node_weights[first] == 1.0) {  // a kept node: bit for bit
      const double* source = old_values.data() + static_cast<std::size_t>(transfer.node_sources[first]) * d;
      std::copy(source, source + d, target);
      continue;
    }
    for (int k = first; k < last; ++k) {
      const double* source = old_values.data() + static_cast<std::size_t>(transfer.node_sources[k]) * d;
      for (std::size_t c = 0; c < d; ++c) target[c] += transfer.node_weights[k] * source[c];
    }
  }
  return values;
}

void check_cell_field_size(const LeafTransfer& transfer, std::size_t size) {
  if (size != static_cast<std::size_t>(transfer.old_cell_count))
    throw InputError("transfer: cell field has " + std::to_string(size) + " values, expected " +
                     std::to_string(transfer.old_cell_count) + " (one per cell of the mesh before the change)");
}

}  // namespace tensormass
