// Refinement during a run (internal header): the hierarchy of the scene's
// mesh, R_ZZ on each solution, the cells it refines, and in dynamic runs
// the calm cells it coarsens back (scene key adaptivity.refine).
#ifndef TENSORMASS_SIMULATION_RUN_REFINEMENT_HPP
#define TENSORMASS_SIMULATION_RUN_REFINEMENT_HPP

#include <span>
#include <vector>

#include "tensormass/adaptivity/zz_indicator.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/refinement/hierarchical_mesh.hpp"
#include "tensormass/refinement/refinement_settings.hpp"
#include "tensormass/simulation/checkpoint.hpp"

namespace tensormass::detail {

class RunRefinement {
 public:
  /// Wraps the scene's (validated) mesh; InputError when it cannot be refined.
  RunRefinement(const RefinementSettings& settings, Mesh original);

  const Mesh& leaf_mesh() const { return hierarchy_.leaf_mesh(); }
  /// Per leaf-mesh cell: its level (0 = an original cell).
  std::span<const int> levels() const { return hierarchy_.leaf_levels(); }
  std::vector<int> leaves_per_level() const { return hierarchy_.leaves_per_level(); }

  /// Static load steps: R_ZZ of `model` (the leaf mesh's) at `u`, and the
  /// cells at or above threshold x its largest split (up to max_level).
  /// Returns the transfers from the previous leaf mesh, in order; empty
  /// when the mesh did not change.
  std::vector<LeafTransfer> refine(const Model& model, std::span<const double> u);
  /// Dynamic runs: the same, measured against the largest R_ZZ seen so far
  /// in the run (cells calm down when the load goes away), then the calm
  /// sibling sets are merged back (settings.coarsen).
  std::vector<LeafTransfer> adapt(const Model& model, std::span<const double> u);

  const Mesh& original_mesh() const { return hierarchy_.original_mesh(); }
  /// The operations that changed the mesh and the coarsening memory, for a
  /// checkpoint (the caller adds the mesh events).
  SavedRefinement save() const;
  /// Replays `saved`'s operations on this (not yet changed) hierarchy and
  /// takes its coarsening memory. InputError when it does not fit.
  void restore(const SavedRefinement& saved);

 private:
  /// Whether the leaf mesh differs from one with these node, cell counts and levels.
  bool changed(int nodes, int cells, const std::vector<int>& levels) const;
  /// Refines (or coarsens) the marked cells; records the operation when the
  /// mesh changed.
  LeafTransfer apply(bool coarsen, std::span<const int> cells, int max_level);
  /// Carries the calm counters through `transfer`.
  void carry_calm(const LeafTransfer& transfer);
  /// Replaces each cell's R_ZZ by its hierarchy leaf's (the norm over the
  /// leaf's transition cells); fills owner_squares_.
  void indicator_per_leaf();
  /// R_ZZ expected of the cell's parent once its children merge back (0 for an original cell).
  double merged_estimate(int cell) const;

  RefinementSettings settings_;
  HierarchicalMesh hierarchy_;
  ZzIndicator zz_;
  std::vector<double> indicator_;
  std::vector<double> owner_squares_;  ///< hierarchy size: sum of R_ZZ^2 over each leaf's cells
  std::vector<int> calm_;              ///< per leaf-mesh cell: evaluations in a row it was calm
  double peak_ = 0;                    ///< dynamic: the largest R_ZZ so far
  SavedRefinement history_;            ///< the operations that changed the mesh (save() adds calm and peak)
};

}  // namespace tensormass::detail

#endif
