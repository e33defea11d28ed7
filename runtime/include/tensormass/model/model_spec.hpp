/// \file model_spec.hpp
/// What a Model is built from, as plain data: materials by region,
/// constraints and loads. The scene reader (scene/) fills it from YAML and
/// validates it against the mesh; other front ends (Python, PETSc) may fill
/// it directly. `line` fields are 1-based lines of the scene file for
/// messages (0: not from a file).
#ifndef TENSORMASS_MODEL_MODEL_SPEC_HPP
#define TENSORMASS_MODEL_MODEL_SPEC_HPP

#include <array>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "tensormass/model/fibre_field.hpp"

namespace tensormass {

/// First match wins; region is a physical group name or "all".
struct MaterialSpec {
  std::string region = "all";
  std::string law;    ///< a law of the registry (hooke, stvk, mooney_rivlin, ...)
  std::string split;  ///< "" = the default split for the law and element
  /// The laws' own constants by parameter name (young, poisson; c10, c01,
  /// kappa; ...): every parameter of `law` and of the adaptive ladder's laws
  /// when `law` is on the ladder, within the laws' limits.
  std::map<std::string, double> constants;
  double density = 0;  ///< > 0
  int line = 0;
  /// The directions of the first and second fibre family, for laws that
  /// read fibre invariants (fibre_families > 0); not given otherwise.
  std::array<FibreField, 2> fibres;
};

/// The constants of a law with Young's modulus and Poisson's ratio (hooke,
/// stvk, neohookean, corotational, stable_neohookean).
std::map<std::string, double> elastic_constants(double young, double poisson);

enum class ProfileKind { constant, ramp, sinusoid };

/// The scene's name of a profile kind ("constant", "ramp", "sinusoid").
std::string_view profile_kind_name(ProfileKind kind);

/// How a prescribed value evolves with time t (dynamic) or load factor (static).
struct TimeProfile {
  ProfileKind kind = ProfileKind::constant;
  double duration = 1.0;  ///< ramp: time to reach the full value
  double period = 1.0;    ///< sinusoid: full cycle; value = amplitude * (1 - cos(2 pi t / period)) / 2
  double phase = 0.0;     ///< sinusoid: phase shift in seconds
  /// Factor at time t: 1 (constant), min(max(t / duration, 0), 1) (ramp),
  /// (1 - cos(2 pi (t + phase) / period)) / 2 (sinusoid); always in [0, 1].
  double factor(double t) const;
};

/// A rigid rotation about the line through `centre` along `axis` (2D: the
/// z axis through centre), by `angle` degrees at full profile.
struct RotationSpec {
  std::array<double, 3> axis{0.0, 0.0, 1.0};  ///< any non-zero length
  std::array<double, 3> centre{};
  double angle = 0;  ///< degrees, right-handed about axis
};

/// Prescribed motion of every node of a group. Without a rotation: the
/// given components of `displacement` times the profile. With one: every
/// component, the node at rest X going to R(p angle)(X - c) + c + p d, with
/// p the profile's factor and d `displacement` (zero unless given).
struct PrescribedSpec {
  std::string region;
  std::array<double, 3> displacement{};              ///< amplitude per component
  std::array<bool, 3> components{true, true, true};  ///< which components are constrained
  TimeProfile profile;
  bool rotates = false;
  RotationSpec rotation;  ///< when rotates
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

struct ModelSpec {
  std::string source;  ///< where the spec came from (the scene file), for messages
  std::vector<MaterialSpec> materials;
  std::vector<std::string> fixed;  ///< groups whose nodes are fully fixed
  std::vector<int> fixed_lines;    ///< line of each `fixed` entry (0: from --set or not from a file)
  std::vector<PrescribedSpec> prescribed;
  LoadsSpec loads;
};

}  // namespace tensormass

#endif
