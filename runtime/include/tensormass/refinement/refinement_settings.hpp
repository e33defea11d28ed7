/// \file refinement_settings.hpp
/// The settings of geometric refinement during a run (the scene's
/// `adaptivity.refine`, docs/scene.md) as plain data: the R_ZZ threshold
/// that refines, the deepest level, how often to evaluate and when cells
/// are calm enough to coarsen back. Filled and validated by the scene
/// reader (scene/).
#ifndef TENSORMASS_REFINEMENT_REFINEMENT_SETTINGS_HPP
#define TENSORMASS_REFINEMENT_REFINEMENT_SETTINGS_HPP

namespace tensormass {

struct RefinementSettings {
  bool enabled = false;
  /// A cell is refined when its R_ZZ is at least threshold x the largest
  /// (zz_indicator.hpp); in [0, 1].
  double threshold = 0;
  int max_level = 2;  ///< no cell is split below this level (0 = the original cells)
  int every = 1;      ///< dynamic runs: evaluate every this many steps
  /// Dynamic runs: sibling cells merge back once all of them have been calm
  /// (R_ZZ < hysteresis x threshold x the largest) for calm_steps evaluations.
  bool coarsen = true;
  double hysteresis = 0.5;
  int calm_steps = 5;
  int line = 0;  ///< 1-based line of `adaptivity.refine` in the scene file (0: not from a file)
};

}  // namespace tensormass

#endif
