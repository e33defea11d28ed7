/// \file calculix_runner.hpp
/// Runs CalculiX (`ccx`) on a tensormass Mesh and Scene: writes an .inp deck
/// (node order per each element's [calculix] node_order), runs ccx in a
/// fresh temporary directory and reads the displacements back from its .dat
/// printout (7 significant digits), in our node order.
///
/// What the deck can express (anything else throws std::runtime_error):
///   - elements with a CalculiX type (calculix_type non-empty); 2D meshes
///     become plane-strain elements of unit thickness;
///   - materials by region (first match wins, as in Model), every one with
///     the same law: stvk -> linear elastic + NLGEOM (total Lagrangian, the
///     same St Venant-Kirchhoff model), hooke -> linear elastic, small strain;
///   - `fixed` groups (all components), gravity (*DLOAD GRAV, dead load on the
///     reference configuration) and nodal forces (*CLOAD on each node);
///   - a static solve: NLGEOM in `increments` equal fixed increments
///     (*STATIC, DIRECT), with tightened Newton controls by default.
#ifndef TENSORMASS_BENCH_CALCULIX_RUNNER_HPP
#define TENSORMASS_BENCH_CALCULIX_RUNNER_HPP

#include <string>
#include <vector>

#include "tensormass/mesh/mesh.hpp"
#include "tensormass/scene/scene.hpp"

namespace tensormass::bench {

struct CalculixOptions {
  std::string executable = "ccx";  ///< a path, or a name looked up in PATH by the shell
  int increments = 10;             ///< NLGEOM: equal fixed increments of the load
  int threads = 1;                 ///< OMP_NUM_THREADS given to ccx
  /// *CONTROLS, PARAMETERS=FIELD tightened by 8 to 10 orders, so that ccx
  /// converges each increment to round-off (the defaults stop at ~1e-3).
  bool tight_controls = true;
  bool keep_directory = false;  ///< keep the work directory (deck, .dat, .sta, log)
};

struct CalculixResult {
  std::vector<double> displacement;  ///< node_count by 3, our node order
  double wall_seconds = 0;           ///< wall clock of the ccx process (start-up, deck parsing, solve, output)
  double reported_seconds = 0;       ///< "Total CalculiX Time" from its log (0 when absent)
  int increments = 0;                ///< increments in the .sta file
  int iterations = 0;                ///< Newton iterations, summed over the increments (.sta)
  std::string directory;             ///< the work directory (removed unless keep_directory)
};

/// The ccx executable to use: `name` (a path, or a name looked up in PATH)
/// when given, else $TENSORMASS_CCX when set, else `ccx` from PATH; "" when
/// there is none.
std::string find_calculix(const std::string& name = "");

/// The .inp deck for `mesh` under `scene` (see the file comment).
std::string calculix_deck(const Mesh& mesh, const Scene& scene, const CalculixOptions& options);

/// Writes the deck into a new temporary directory, runs ccx there, checks
/// that it finished the step and returns the displacements. Throws
/// std::runtime_error (with the end of ccx's log) on any failure.
CalculixResult run_calculix(const Mesh& mesh, const Scene& scene, const CalculixOptions& options);

}  // namespace tensormass::bench

#endif
