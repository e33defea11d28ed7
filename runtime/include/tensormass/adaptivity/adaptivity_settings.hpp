/// \file adaptivity_settings.hpp
/// The adaptive model's settings as plain data: the criteria and their
/// thresholds, the action, how often to evaluate, blending and downgrade.
/// Filled and validated by the scene reader (scene/) or by another front end.
#ifndef TENSORMASS_ADAPTIVITY_ADAPTIVITY_SETTINGS_HPP
#define TENSORMASS_ADAPTIVITY_ADAPTIVITY_SETTINGS_HPP

#include <string>
#include <string_view>
#include <vector>

namespace tensormass {

struct CriterionSpec {
  std::string name;  ///< R_EL, R_V, R_VL, R_VLX, R_S, R_NL, R_E (criteria.hpp)
  double threshold = 0;
  int line = 0;  ///< 1-based line in the scene file (0: not from a file)
  /// The law this criterion asks for when it fails: a failing cell climbs
  /// towards it, never past it, and it no longer holds a cell above it.
  /// Empty: the ladder's last law.
  std::string rung;
};

/// What happens to an element that fails a criterion.
enum class AdaptivityAction { upgrade };  ///< one rung up the ladder

/// The scene's name of an action ("upgrade").
inline std::string_view adaptivity_action_name(AdaptivityAction) { return "upgrade"; }

struct AdaptivitySettings {
  bool enabled = false;
  std::vector<CriterionSpec> criteria;
  /// Laws from the cheapest to the richest: a cell failing a criterion whose
  /// rung is above the cell's law climbs one rung; with downgrade, a cell that
  /// is calm for every criterion whose rung is at or above its law descends one
  /// rung, never below its initial law. Cells whose initial law is not on the
  /// ladder never switch.
  std::vector<std::string> ladder{"hooke", "stvk"};
  int ladder_line = 0;  ///< 1-based line of `ladder` in the scene file (0: default or not from a file)
  AdaptivityAction action = AdaptivityAction::upgrade;
  int every = 1;        ///< evaluate every this many steps
  int blend_steps = 0;  ///< steps over which a switched cell blends to its new law (0 = at once)
  bool downgrade = false;
  double hysteresis = 0.5;
  int calm_steps = 10;
  /// Evaluate only the cells that can move and whose nodes moved far enough
  /// to change a decision (criteria_screen.hpp; R_NL and R_E only, else
  /// every cell). Decisions and written values are the same either way;
  /// false is for benchmarks and tests.
  bool screen = true;
};

}  // namespace tensormass

#endif
