/// \file leaf_transfer.hpp
/// How the fields of a leaf mesh before a refinement or coarsening become
/// fields of the leaf mesh after it (see hierarchical_mesh.hpp).
///
/// Nodal fields (node_count by components, node-major: displacement,
/// velocity): a node of the new mesh that was a node of the old one keeps
/// its value bit for bit; a new node takes the parent cell's shape
/// functions' value in the reference configuration: the mean of its
/// edge's two ends (edge midpoint), of a quad's (or quad face's) four
/// corners (the bilinear value at its centre) or of a cell's corners (a
/// hex8's centre: the trilinear value; a transition's centre node). Linear
/// fields are transferred exactly.
///
/// Cell fields (cell_count values: law index, blend weight): each new cell
/// takes the value of one old cell. Children and transition cells take
/// their parent's (the first old cell that covered it); a parent restored by
/// coarsening takes its first child's.
#ifndef TENSORMASS_REFINEMENT_LEAF_TRANSFER_HPP
#define TENSORMASS_REFINEMENT_LEAF_TRANSFER_HPP

#include <span>
#include <string>
#include <vector>

#include "tensormass/common/errors.hpp"

namespace tensormass {

struct LeafTransfer {
  int old_node_count = 0;
  int old_cell_count = 0;
  /// New node i takes the sum over k in [node_offsets[i], node_offsets[i+1])
  /// of node_weights[k] times old node node_sources[k]'s value.
  std::vector<int> node_offsets{0};
  std::vector<int> node_sources;
  std::vector<double> node_weights;
  /// new cell count: the old cell whose value each new cell takes.
  std::vector<int> cell_sources;

  int new_node_count() const { return static_cast<int>(node_offsets.size()) - 1; }
  int new_cell_count() const { return static_cast<int>(cell_sources.size()); }
};

/// old_values: old_node_count by components -> new_node_count by
/// components. Throws InputError when the size does not match.
std::vector<double> transfer_nodal_field(const LeafTransfer& transfer, std::span<const double> old_values,
                                         int components);

/// Throws InputError unless `size` old cell values were given.
void check_cell_field_size(const LeafTransfer& transfer, std::size_t size);

/// old_values: old_cell_count -> new_cell_count, each new cell copying its
/// source's value. Throws InputError when the size does not match.
template <typename T>
std::vector<T> transfer_cell_field(const LeafTransfer& transfer, std::span<const T> old_values) {
  check_cell_field_size(transfer, old_values.size());
  std::vector<T> values;
  values.reserve(transfer.cell_sources.size());
  for (int source : transfer.cell_sources) values.push_back(old_values[static_cast<std::size_t>(source)]);
  return values;
}

}  // namespace tensormass

#endif
