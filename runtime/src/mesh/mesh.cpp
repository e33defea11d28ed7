#include "tensormass/mesh/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "tensormass/common/errors.hpp"

namespace tensormass {

int Mesh::cell_count() const {
  int total = 0;
  for (const ElementBlock& block : blocks) total += block.count();
  return total;
}

const Group* Mesh::group(std::string_view name) const {
  for (const Group& g : groups)
    if (g.name == name) return &g;
  return nullptr;
}

const Group& Mesh::add_node_group(std::string name, const std::function<bool(double, double, double)>& inside) {
  Group group;
  group.name = std::move(name);
  group.dim = 0;
  for (int node = 0; node < node_count(); ++node) {
    const double* x = &rest_positions[3 * node];
    if (inside(x[0], x[1], x[2])) group.nodes.push_back(node);
  }
  groups.push_back(std::move(group));
  return groups.back();
}

std::pair<int, int> Mesh::locate(int cell) const {
  for (int b = 0; b < static_cast<int>(blocks.size()); ++b) {
    const ElementBlock& block = blocks[b];
    if (cell >= block.first_cell && cell < block.first_cell + block.count()) return {b, cell - block.first_cell};
  }
  return {-1, -1};
}

std::string Mesh::describe_cell(int cell) const {
  const auto [b, local] = locate(cell);
  std::ostringstream text;
  const bool numbered = cell >= 0 && cell < static_cast<int>(cell_numbers.size());
  text << "element " << (numbered ? cell_numbers[static_cast<std::size_t>(cell)] : cell);
  if (b >= 0) {
    const ElementBlock& block = blocks[b];
    text << " (" << block.element->name;
    if (local < static_cast<int>(block.source_ids.size()))
      text << ", id " << block.source_ids[local] << " in " << (source.empty() ? "the mesh" : source);
    text << ")";
  }
  return text.str();
}

void Mesh::validate() const {
  const std::string where = source.empty() ? std::string("mesh") : source;
  if (dim != 2 && dim != 3) throw InputError(where + ": dimension " + std::to_string(dim) + " is not 2 or 3");
  if (rest_positions.size() % 3 != 0) throw InputError(where + ": positions are not n by 3");
  const int n = node_count();
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(rest_positions[3 * i + c]))
        throw InputError(where + ": node " + std::to_string(node_source_ids.empty() ? i : node_source_ids[i]) +
                         " has a non-finite coordinate");
  int next = 0;
  for (const ElementBlock& block : blocks) {
    if (!block.element) throw InputError(where + ": element block without a reference element");
    if (block.element->dim != dim)
      throw InputError(where + ": " + block.element->name + " cells in a " + std::to_string(dim) + "D mesh");
    if (block.first_cell != next) throw InputError(where + ": block numbering is not contiguous");
    if (block.connectivity.size() % block.element->nodes != 0)
      throw InputError(where + ": " + block.element->name + " connectivity is not a multiple of its node count");
    for (int local = 0; local < block.count(); ++local)
      for (int node : block.cell_nodes(local))
        if (node < 0 || node >= n)
          throw InputError(where + ": " + describe_cell(block.first_cell + local) + " refers to node index " +
                           std::to_string(node) + ", outside 0.." + std::to_string(n - 1));
    next += block.count();
  }
  if (next == 0) throw InputError(where + ": no " + std::to_string(dim) + "D elements");
  if (!cell_numbers.empty() && cell_numbers.size() != static_cast<std::size_t>(next))
    throw InputError(where + ": " + std::to_string(cell_numbers.size()) + " whole-mesh cell numbers for " +
                     std::to_string(next) + " cells");
  for (const Group& g : groups) {
    for (int node : g.nodes)
      if (node < 0 || node >= n) throw InputError(where + ": group '" + g.name + "' refers to a missing node");
    for (int cell : g.cells)
      if (cell < 0 || cell >= next) throw InputError(where + ": group '" + g.name + "' refers to a missing element");
    for (int node : g.facets.nodes)
      if (node < 0 || node >= n) throw InputError(where + ": group '" + g.name + "' has a facet on a missing node");
  }
}

}  // namespace tensormass
