/// \file refine_indentation.hpp
/// The 3D half of `tensormass bench refine`: tool indentation
/// from a coarse hex mesh. The scene of the adaptive-model benchmark's
/// indentation (adaptive_bench.cpp): a 10 x 5 x 10 cm soft block (E 5 kPa,
/// nu 0.45, density 1000), the base y = 0 fixed, the nodes of a 2 x 2 cm
/// patch in the middle of the top pushed down by a ramp, implicit Euler at
/// dt 0.01; meshed with hex8 (make_beam), coarse cells of 1 cm.
///
/// Every run goes through Simulation (the scene keys adaptivity.refine and
/// adaptivity.criteria), one after the other in one process, default
/// solver settings and threads:
///   - Hooke on the coarse mesh, and on meshes refined uniformly to level 1
///     and to max_level (make_beam at 2x and 4x the cells: the reference,
///     whose nodes are matched to the coarse ones by position);
///   - Hooke with dynamic refinement: R_ZZ at or above a threshold times the
///     run's largest, every `every` steps, up to max_level, coarsening on
///     (hysteresis 0.5, 5 calm checks);
///   - against the neo-Hookean uniform max_level mesh: pure neo-Hookean on
///     the coarse mesh, law switching alone on the coarse mesh (ladder
///     [hooke, neohookean], R_NL), refinement alone under neo-Hookean, and
///     both kinds of adaptivity together.
/// Per run: the mean wall time per step (everything Simulation::step does
/// but writing the final output: integrator step, criteria, R_ZZ,
/// refinement events, rebuilds), the cost of each refinement event (the
/// step's wall time minus its integrator step) against a step of the
/// refined mesh, the cells at the end and per level, and the error: the
/// largest displacement difference at the coarse mesh's nodes at the final
/// time against the reference, over the reference's largest displacement.
/// Targets: error <= 2 % at <= 0.3x the reference's time per
/// step; refining or coarsening costs at most one step of the refined mesh.
#ifndef TENSORMASS_BENCH_REFINE_INDENTATION_HPP
#define TENSORMASS_BENCH_REFINE_INDENTATION_HPP

#include "bench_json.hpp"

namespace tensormass::bench {

/// What the 3D indentation gives back to refine_command.
struct IndentationResult {
  Json json;  ///< a JSON object (the "indentation" member of --json)
  /// A uniform run failed, a scene was refused, or (quick) any run failed;
  /// an adaptive run's numerical failure is reported, not fatal, in a full run.
  bool failed = false;
};

/// Runs the 3D indentation (quick: a smaller reference and fewer steps, a
/// smoke test whose figures are not the targets'), printing its tables.
IndentationResult refine_indentation(bool quick);

}  // namespace tensormass::bench

#endif
