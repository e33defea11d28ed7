/// \file node_graph.hpp
/// Which nodes share a cell: the node adjacency of a model in compressed
/// rows (each node lists every node of its cells, itself included, sorted; a node
/// in no cell has an empty row). The
/// sparsity of every stiffness matrix follows from it, one d by d block per
/// entry.
#ifndef TENSORMASS_ASSEMBLY_NODE_GRAPH_HPP
#define TENSORMASS_ASSEMBLY_NODE_GRAPH_HPP

#include <vector>

#include "tensormass/assembly/nodal_pressure.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {

struct NodeGraph {
  std::vector<int> row_start;  ///< node_count+1
  std::vector<int> columns;    ///< neighbour nodes, sorted within each row

  int node_count() const { return static_cast<int>(row_start.size()) - 1; }
  /// Position of (node, neighbour) in `columns`; the pair must be adjacent.
  int position(int node, int neighbour) const;
};

/// The adjacency of every node of the model's mesh through its cells, and
/// through the patches of `nodal` when given (each patch couples all its nodes).
NodeGraph make_node_graph(const Model& model, const NodalPressure* nodal = nullptr);

}  // namespace tensormass

#endif
