/// \file assembler.hpp
/// Assembly of the internal forces g(u) = dW/du and the tangent stiffness
/// K = dg/du over the free dofs. The sparsity pattern and an
/// element-to-matrix scatter map are built once; cells are coloured so that
/// no two cells of a colour share a node, each colour is assembled in
/// parallel with plain stores, and colours run in a fixed order: results do
/// not depend on the number of threads.
#ifndef TENSORMASS_ASSEMBLER_HPP
#define TENSORMASS_ASSEMBLER_HPP

#include <span>
#include <vector>

#include "tensormass/model.hpp"
#include "tensormass/sparse_matrix.hpp"

namespace tensormass {

class Assembler {
 public:
  explicit Assembler(const Model& model);
  explicit Assembler(Model&&) = delete;  ///< keeps a reference to the model

  /// An empty matrix with the pattern of K (free dofs by free dofs).
  const SparseMatrix& pattern() const { return pattern_; }
  /// gradient (dof_count) = g(u); when `stiffness` is non-null it gets K(u)
  /// restricted to the free dofs (its pattern must be pattern()).
  void assemble(std::span<const double> u, std::span<double> gradient, SparseMatrix* stiffness) const;
  int colour_count() const { return static_cast<int>(colour_start_.size()) - 1; }

 private:
  void build_pattern();
  void build_colours();

  const Model* model_;
  SparseMatrix pattern_;
  std::vector<std::size_t> scatter_offsets_;  ///< cell_count+1
  std::vector<int> scatter_;                  ///< per cell, dofs by dofs: index in values or -1
  std::vector<int> colour_start_;             ///< colours+1, into coloured_cells_
  std::vector<int> coloured_cells_;
};

}  // namespace tensormass

#endif
