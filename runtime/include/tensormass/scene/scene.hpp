/// \file scene.hpp
/// A simulation scene read from YAML (DESIGN.md's contract): the mesh,
/// materials by region, constraints, loads, solver, adaptivity and output.
/// Parsing validates everything it can without the mesh (keys, types,
/// ranges, known laws and solver types); `check_groups` validates region
/// names once the mesh is read. Errors are InputError naming file, line, key.
#ifndef TENSORMASS_SCENE_HPP
#define TENSORMASS_SCENE_HPP

#include <array>
#include <string>
#include <vector>

#include "tensormass/mesh/mesh.hpp"

namespace tensormass {

/// First match wins; region is a physical group name or "all".
struct MaterialSpec {
  std::string region = "all";
  std::string law;             ///< a law of the registry (hooke, stvk, neohookean)
  std::string split;           ///< "" = the default split for the law and element
  double young = 0;            ///< > 0
  double poisson = 0;          ///< in (-1, 0.5)
  double density = 0;          ///< > 0
  int line = 0;                ///< 1-based line in the scene file, for messages
};

/// How a prescribed value evolves with time t (dynamic) or load factor (static).
struct TimeProfile {
  std::string kind = "constant";  ///< constant | ramp | sinusoid
  double duration = 1.0;          ///< ramp: time to reach the full value
  double period = 1.0;            ///< sinusoid: full cycle; value = amplitude * (1 - cos(2 pi t / period)) / 2
  double phase = 0.0;             ///< sinusoid: phase shift in seconds
  /// Factor at time t: 1 (constant), min(max(t / duration, 0), 1) (ramp),
  /// (1 - cos(2 pi (t + phase) / period)) / 2 (sinusoid); always in [0, 1].
  double factor(double t) const;
};

/// Prescribed displacement of every node of a group (components given).
struct PrescribedSpec {
  std::string region;
  std::array<double, 3> displacement{};  ///< amplitude per component
  std::array<bool, 3> components{true, true, true};  ///< which components are constrained
  TimeProfile profile;
  int line = 0;
};

/// The same force on EACH node of the group.
struct NodalForceSpec {
  std::string region;
  std::array<double, 3> force{};
  int line = 0;
};

/// Pressure (force per reference area) on the boundary facets of a group,
/// positive pushing into the body.
struct PressureSpec {
  std::string region;
  double pressure = 0;
  int line = 0;
};

struct LoadsSpec {
  std::array<double, 3> gravity{};
  std::vector<NodalForceSpec> nodal_forces;
  std::vector<PressureSpec> pressures;
  TimeProfile profile;  ///< dynamic solvers: time profile of all loads (constant by default)
};

struct LinearSolverSpec {
  std::string type = "cholmod";   ///< cholmod | cg
  double tolerance = 1e-10;       ///< cg: relative residual
  int max_iterations = 10000;     ///< cg
  /// cholmod: when the matrix changed, first try at most this many CG
  /// iterations preconditioned by the previous factor (0 = always refactorise)
  int reuse_iterations = 12;
};

struct SolverSpec {
  std::string type = "static";    ///< static | implicit | explicit
  // static
  int load_steps = 1;
  double tolerance = 1e-10;       ///< Newton: relative residual
  int max_iterations = 50;        ///< Newton iterations per load step
  // dynamic
  double dt = 0;                  ///< > 0 for implicit and explicit
  int steps = 0;                  ///< > 0 for implicit and explicit
  int newton_iterations = 1;      ///< implicit: Newton iterations per step (1 = linearised step)
  double damping_mass = 0;        ///< Rayleigh alpha (1/s)
  double damping_stiffness = 0;   ///< Rayleigh beta (s)
  LinearSolverSpec linear;
  int threads = 0;                ///< 0 = OpenMP default
};

struct CriterionSpec {
  std::string name;      ///< R_EL, R_V, R_VL, R_VLX, R_S, R_NL
  double threshold = 0;
  int line = 0;
};

struct AdaptivitySpec {
  bool enabled = false;
  std::vector<CriterionSpec> criteria;
  std::string action = "upgrade";
  int every = 1;
  int blend_steps = 0;
  bool downgrade = false;
  double hysteresis = 0.5;
  int calm_steps = 10;
};

struct OutputSpec {
  std::string directory = "out";  ///< resolved relative to the scene file (absolute paths kept)
  int every = 0;                  ///< 0 = final state only
  /// Groups (with cells) whose centroid is written to track_<group>.csv every step (track.hpp).
  std::vector<std::string> track;
  std::vector<int> track_lines;   ///< 1-based line of each `track` entry (0: from --set), for messages
};

struct Scene {
  std::string path;        ///< the scene file
  std::string mesh;        ///< mesh path, resolved relative to the scene file
  std::vector<MaterialSpec> materials;
  std::vector<std::string> fixed;
  std::vector<int> fixed_lines;  ///< 1-based line of each `fixed` entry (0: from --set), for messages
  std::vector<PrescribedSpec> prescribed;
  LoadsSpec loads;
  SolverSpec solver;
  AdaptivitySpec adaptivity;
  OutputSpec output;
};

/// Reads and validates a scene. `overrides` are "a.b=value" strings (value in
/// YAML syntax, list indices as numbers: materials.0.young=2e6) applied
/// before validation; an override of an unknown key is an error too.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

/// Checks that every region named by the scene is a group of the mesh (or
/// "all" for materials); throws InputError naming the key, line and the groups that exist.
void check_groups(const Scene& scene, const Mesh& mesh);

}  // namespace tensormass

#endif
