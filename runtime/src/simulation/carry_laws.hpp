// Laws carried over a refinement: each cell of the refined mesh takes the
// law and blend of the cell it comes from. Internal header.
#ifndef TENSORMASS_SIMULATION_CARRY_LAWS_HPP
#define TENSORMASS_SIMULATION_CARRY_LAWS_HPP

#include <span>
#include <vector>

#include "tensormass/kernels/kernel_abi.h"
#include "tensormass/model/model.hpp"
#include "tensormass/refinement/leaf_transfer.hpp"

namespace tensormass::detail {

/// Per cell of a model: its kernel, and the kernel it blends from (nullptr
/// when it does not blend) with the blend's weight. Kernels live in the
/// registry: the pointers outlive the model.
struct CellLaws {
  std::vector<const tm_kernel*> kernels, blend_from;
  std::vector<double> blend_weights;
};

CellLaws cell_laws(const Model& model);

/// Per cell of the leaf mesh after `transfers` (applied in order): the cell
/// of the mesh before them whose state it takes.
std::vector<int> cell_origins(const std::vector<LeafTransfer>& transfers);

/// Gives each cell of `model` (just built on the new mesh, under its
/// materials' laws) the law of the old cell it comes from, and its blend
/// (the law blended from and the weight). Returns the cells that could not
/// take the law (no kernel for their element): they keep their initial law.
int carry_laws(const CellLaws& before, std::span<const int> origin, Model& model);

}  // namespace tensormass::detail

#endif
