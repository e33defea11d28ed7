// Reading and validating a scene file (docs/scene.md is the reference of
// every key). The tree is read, overrides are applied, unknown keys are
// rejected, then each section is read into its specification or settings with typed checks.
#include "tensormass/scene/scene.hpp"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <new>
#include <set>

#include "common/input_cursor.hpp"
#include "scene/yaml_reader.hpp"
#include "tensormass/adaptivity/criteria.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/track_csv.hpp"
#include "tensormass/kernels/law_parameters.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"

namespace tensormass {

namespace {

using scene_yaml::KeyTable;
using scene_yaml::Value;
namespace fs = std::filesystem;

const std::vector<std::string> kProfileKeys = {"type", "duration", "period", "phase"};
/// A material's keys besides its laws' constants.
const std::vector<std::string> kMaterialKeys = {"region", "law", "split", "density", "fibres", "fibres2"};

/// kMaterialKeys and every parameter name of the registry's laws (which
/// constants a material takes is checked against its laws in read_material).
std::vector<std::string> material_keys() {
  std::set<std::string> keys(kMaterialKeys.begin(), kMaterialKeys.end());
  const Registry& registry = Registry::instance();
  for (const std::string& law : registry.laws())
    for (const std::string& name : parameter_names(*registry.law_kernel(law)))
      if (!is_fibre_parameter(name)) keys.insert(name);
  return {keys.begin(), keys.end()};
}

/// Every map of the schema and its keys, by path pattern.
const KeyTable& scene_keys() {
  static const KeyTable table = {
      {"", {"mesh", "materials", "fixed", "prescribed", "loads", "solver", "adaptivity", "output"}},
      {"materials[]", material_keys()},
      {"materials[].fibres", {"file"}},
      {"materials[].fibres2", {"file"}},
      {"prescribed[]", {"region", "displacement", "rotation", "profile"}},
      {"prescribed[].rotation", {"axis", "centre", "angle"}},
      {"prescribed[].profile", kProfileKeys},
      {"loads", {"gravity", "nodal_forces", "pressure", "profile"}},
      {"loads.nodal_forces[]", {"region", "force"}},
      {"loads.pressure[]", {"region", "pressure"}},
      {"loads.profile", kProfileKeys},
      {"solver",
       {"type", "load_steps", "tolerance", "max_iterations", "dt", "steps", "newton_iterations", "predictor", "damping",
        "linear", "threads", "project_hessian", "backend"}},
      {"solver.damping", {"mass", "stiffness"}},
      {"solver.linear", {"type", "tolerance", "max_iterations", "reuse_iterations", "petsc_options"}},
      {"adaptivity", {"criteria", "ladder", "action", "every", "blend_steps", "downgrade", "refine"}},
      {"adaptivity.criteria[]", {"name", "threshold", "rung"}},
      {"adaptivity.downgrade", {"hysteresis", "calm_steps"}},
      {"adaptivity.refine", {"criteria", "max_level", "every", "coarsen"}},
      {"adaptivity.refine.criteria[]", {"name", "threshold"}},
      {"adaptivity.refine.coarsen", {"hysteresis", "calm_steps"}},
      {"output", {"directory", "every", "track", "checkpoint_every"}},
  };
  return table;
}

}  // namespace

std::vector<std::pair<std::string, std::vector<std::string>>> scene_schema() {
  std::vector<std::pair<std::string, std::vector<std::string>>> schema(scene_keys().begin(), scene_keys().end());
  for (auto& [path, keys] : schema)
    if (path == "materials[]") keys = kMaterialKeys;
  return schema;
}

namespace {

// --- Typed reads with ranges -------------------------------------------------

/// Reads `key` of `map` into `target` with `read` when it is present.
template <class T, class Read>
void read_optional(const Value& map, std::string_view key, T& target, Read read) {
  const Value value = map.child(key);
  if (value.present()) target = read(value);
}

std::string one_of(const Value& value, const std::vector<std::string>& known, const std::string& what) {
  const std::string name = value.text();
  if (std::find(known.begin(), known.end(), name) == known.end())
    value.fail("unknown " + what + " '" + name + "' (known: " + scene_yaml::join(known) + ")");
  return name;
}

/// The enumerator of `all` whose scene name (`name(e)`) the value holds.
template <class Enum, class Name>
Enum one_of_enum(const Value& value, std::initializer_list<Enum> all, Name name, const std::string& what) {
  std::vector<std::string> known;
  for (Enum e : all) known.emplace_back(name(e));
  const std::string text = one_of(value, known, what);
  return *std::find_if(all.begin(), all.end(), [&](Enum e) { return name(e) == text; });
}

ProfileKind read_profile_kind(const Value& value, const std::string& what) {
  return one_of_enum(value, {ProfileKind::constant, ProfileKind::ramp, ProfileKind::sinusoid}, profile_kind_name, what);
}

double positive(const Value& value) {
  const double x = value.number();
  if (!(x > 0)) value.fail("must be > 0, got " + value.scalar());
  return x;
}

double non_negative(const Value& value) {
  const double x = value.number();
  if (!(x >= 0)) value.fail("must be >= 0, got " + value.scalar());
  return x;
}

/// A number strictly between 0 and 1 (tolerances, hysteresis).
double open_fraction(const Value& value) {
  const double x = value.number();
  if (!(x > 0 && x < 1)) value.fail("must be > 0 and < 1, got " + value.scalar());
  return x;
}

bool boolean(const Value& value) {
  const std::string text = value.scalar();
  if (!value.is_scalar() || (text != "true" && text != "false"))
    value.fail("expected true or false, got " + value.describe());
  return text == "true";
}

std::function<int(const Value&)> at_least(int minimum) {
  return [minimum](const Value& value) {
    const int n = value.integer();
    if (n < minimum) value.fail("must be >= " + std::to_string(minimum) + ", got " + value.scalar());
    return n;
  };
}

/// 2 or 3 numbers; a 2D vector gets z = 0.
std::array<double, 3> vector3(const Value& value) {
  if (!value.is_list()) value.fail("expected a list of 2 or 3 numbers, got " + value.describe());
  const std::vector<Value> items = value.items();
  if (items.size() != 2 && items.size() != 3)
    value.fail("expected 2 or 3 numbers, got " + std::to_string(items.size()));
  std::array<double, 3> out{};
  for (std::size_t c = 0; c < items.size(); ++c) out[c] = items[c].number();
  return out;
}

std::string resolve_path(const fs::path& directory, const std::string& path) {
  const fs::path given(path);
  if (given.is_absolute() || directory.empty()) return given.lexically_normal().string();
  return (directory / given).lexically_normal().string();
}

// --- Sections ------------------------------------------------------------------

/// The laws whose constants a material needs: its own, and the ladder's
/// when the adaptive model may move it (its law is on the ladder).
std::vector<std::string> material_laws(const std::string& law, const AdaptivitySettings& adaptivity) {
  const std::vector<std::string>& ladder = adaptivity.ladder;
  if (!adaptivity.enabled || std::find(ladder.begin(), ladder.end(), law) == ladder.end()) return {law};
  return ladder;
}

/// Every constant the material's laws need is given, within each law's
/// limits, and every constant given is a parameter of one of them.
void check_constants(const Value& item, const MaterialSpec& m, const std::vector<std::string>& laws) {
  std::vector<std::string> used;  // the laws' parameters, in kernel order
  for (const std::string& law : laws) {
    const tm_kernel& kernel = *Registry::instance().law_kernel(law);
    for (int p = 0; p < kernel.params; ++p) {
      const std::string name = kernel.param_names[p];
      if (is_fibre_parameter(name)) continue;  // set per cell from `fibres`
      if (std::find(used.begin(), used.end(), name) == used.end()) used.push_back(name);
      const auto given = m.constants.find(name);
      if (given == m.constants.end())
        item.fail("law " + law + " needs the constant '" + name +
                  "' (its parameters: " + scene_yaml::join(parameter_names(kernel)) + ")");
      if (!within_limit(given->second, kernel.param_limits[p]))
        item.child(name).fail("must be " + describe_limit(kernel.param_limits[p]) + " for law " + law + ", got " +
                              item.child(name).scalar());
    }
  }
  for (const auto& [name, value] : m.constants)
    if (std::find(used.begin(), used.end(), name) == used.end())
      item.child(name).fail("is not a parameter of " + std::string(laws.size() > 1 ? "the laws " : "law ") +
                            scene_yaml::join(laws) + " (parameters: " + scene_yaml::join(used) +
                            "; other keys: " + scene_yaml::join(kMaterialKeys) + ")");
}

/// A fibre field: [ax, ay, az] (numbers: constant; any a formula of x, y,
/// z: formulas) or {file: path} (samples x y z ax ay az).
FibreField read_fibre_field(const Value& value, const fs::path& directory) {
  const std::string owner = value.location();
  if (value.is_map()) return FibreField::samples(resolve_path(directory, value.required("file").text()), owner);
  const std::vector<Value> items = value.items();
  if (items.size() != 3) value.fail("expected [ax, ay, az] (numbers or formulas of x, y, z) or {file: path}");
  std::array<std::string, 3> text;
  bool numbers = true;
  std::array<double, 3> direction{};
  for (std::size_t c = 0; c < 3; ++c) {
    text[c] = items[c].text();
    numbers = numbers && detail::parse_real(text[c], direction[c]);
  }
  return numbers ? FibreField::constant(direction, owner) : FibreField::formula(text, owner);
}

/// `fibres` (and `fibres2`) exactly where one of the material's laws reads that family.
void read_fibres(const Value& item, MaterialSpec& m, const std::vector<std::string>& laws, const fs::path& directory) {
  int families = 0;
  std::string reader;
  for (const std::string& law : laws) {
    const int f = fibre_families(*Registry::instance().law_kernel(law));
    if (f > families) reader = law;
    families = std::max(families, f);
  }
  for (int f = 0; f < 2; ++f) {
    const char* key = f == 0 ? "fibres" : "fibres2";
    const Value value = item.child(key);
    if (value.present() && f >= families)
      value.fail(families == 0 ? "no law of the material reads fibre directions (" + scene_yaml::join(laws) + ")"
                               : "law " + reader + " reads one fibre family (`fibres`)");
    if (!value.present() && f < families)
      item.fail("law " + reader + " reads " + (families == 2 ? "two fibre families" : "a fibre direction") +
                ": give `" + key + ": [ax, ay, az]` (or formulas of x, y, z, or {file: path})");
    if (value.present()) m.fibres[static_cast<std::size_t>(f)] = read_fibre_field(value, directory);
  }
}

MaterialSpec read_material(const Value& item, const AdaptivitySettings& adaptivity, const fs::path& directory) {
  item.expect_map();
  const Registry& registry = Registry::instance();
  MaterialSpec m;
  m.line = item.line();
  read_optional(item, "region", m.region, [](const Value& v) { return v.text(); });
  m.law = one_of(item.required("law"), registry.laws(), "law");
  const Value split = item.child("split");
  if (split.present() && !split.scalar().empty()) m.split = one_of(split, registry.splits(), "split");
  for (const auto& [key, value] : item.entries())
    if (std::find(kMaterialKeys.begin(), kMaterialKeys.end(), key.scalar()) == kMaterialKeys.end())
      m.constants[key.scalar()] = value.number();
  check_constants(item, m, material_laws(m.law, adaptivity));
  read_fibres(item, m, material_laws(m.law, adaptivity), directory);
  m.density = positive(item.required("density"));
  return m;
}

std::vector<MaterialSpec> read_materials(const Value& list, const AdaptivitySettings& adaptivity,
                                         const fs::path& directory) {
  const std::vector<Value> items = list.items();
  if (items.empty()) list.fail("needs at least one material");
  std::vector<MaterialSpec> out;
  for (const Value& item : items) out.push_back(read_material(item, adaptivity, directory));
  return out;
}

void read_fixed(const Value& list, ModelSpec& model) {
  if (!list.present()) return;
  for (const Value& item : list.items()) {
    model.fixed.push_back(item.text());
    model.fixed_lines.push_back(item.line());
  }
}

TimeProfile read_profile(const Value& value) {
  TimeProfile p;
  if (value.is_scalar()) {
    p.kind = read_profile_kind(value, "profile");
    return p;
  }
  if (!value.is_map()) value.fail("expected a profile name or a map {type: ...}, got " + value.describe());
  p.kind = read_profile_kind(value.required("type"), "profile type");
  read_optional(value, "duration", p.duration, positive);
  read_optional(value, "period", p.period, positive);
  read_optional(value, "phase", p.phase, [](const Value& v) { return v.number(); });
  return p;
}

/// Like vector3, but a null entry leaves that component free.
void read_displacement(const Value& value, PrescribedSpec& spec) {
  if (!value.is_list()) value.fail("expected a list of 2 or 3 numbers or nulls, got " + value.describe());
  const std::vector<Value> items = value.items();
  if (items.size() != 2 && items.size() != 3)
    value.fail("expected 2 or 3 components, got " + std::to_string(items.size()));
  spec.components = {false, false, false};
  for (std::size_t c = 0; c < items.size(); ++c) {
    spec.components[c] = items[c].present();
    spec.displacement[c] = spec.components[c] ? items[c].number() : 0.0;
  }
}

/// {axis, centre, angle}: axis 2 or 3 numbers, not zero (default z);
/// centre (default the origin); angle in degrees (required).
RotationSpec read_rotation(const Value& value) {
  value.expect_map();
  RotationSpec rotation;
  read_optional(value, "axis", rotation.axis, vector3);
  const auto& a = rotation.axis;
  if (a[0] == 0 && a[1] == 0 && a[2] == 0) value.child("axis").fail("must not be zero");
  read_optional(value, "centre", rotation.centre, vector3);
  rotation.angle = value.required("angle").number();
  return rotation;
}

std::vector<PrescribedSpec> read_prescribed(const Value& list) {
  std::vector<PrescribedSpec> out;
  if (!list.present()) return out;
  for (const Value& item : list.items()) {
    item.expect_map();
    PrescribedSpec spec;
    spec.line = item.line();
    spec.region = item.required("region").text();
    const Value rotation = item.child("rotation");
    if (rotation.present()) {
      spec.rotates = true;
      spec.rotation = read_rotation(rotation);
      spec.displacement = {0.0, 0.0, 0.0};
      read_optional(item, "displacement", spec.displacement, vector3);
    } else {
      read_displacement(item.required("displacement", "(or 'rotation')"), spec);
    }
    read_optional(item, "profile", spec.profile, read_profile);
    out.push_back(spec);
  }
  return out;
}

std::vector<NodalForceSpec> read_nodal_forces(const Value& list) {
  std::vector<NodalForceSpec> out;
  if (!list.present()) return out;
  for (const Value& item : list.items()) {
    item.expect_map();
    out.push_back({item.required("region").text(), vector3(item.required("force")), item.line()});
  }
  return out;
}

std::vector<PressureSpec> read_pressures(const Value& list) {
  std::vector<PressureSpec> out;
  if (!list.present()) return out;
  for (const Value& item : list.items()) {
    item.expect_map();
    out.push_back({item.required("region").text(), item.required("pressure").number(), item.line()});
  }
  return out;
}

LoadsSpec read_loads(const Value& section) {
  LoadsSpec loads;
  if (!section.present()) return loads;
  section.expect_map();
  read_optional(section, "gravity", loads.gravity, vector3);
  loads.nodal_forces = read_nodal_forces(section.child("nodal_forces"));
  loads.pressures = read_pressures(section.child("pressure"));
  read_optional(section, "profile", loads.profile, read_profile);
  return loads;
}

void read_damping(const Value& section, SolverSettings& solver) {
  if (!section.present()) return;
  read_optional(section, "mass", solver.damping_mass, non_negative);
  read_optional(section, "stiffness", solver.damping_stiffness, non_negative);
  const Value stiffness = section.child("stiffness");
  if (solver.type == SolverType::explicit_euler && solver.damping_stiffness != 0.0)
    stiffness.fail("is not supported by the explicit solver (use damping.mass)");
}

LinearSolverSettings read_linear(const Value& section) {
  LinearSolverSettings linear;
  if (!section.present()) return linear;
  read_optional(section, "type", linear.type, [](const Value& v) {
    return one_of_enum(v, {LinearSolverType::cholmod, LinearSolverType::cg, LinearSolverType::petsc},
                       linear_solver_type_name, "linear solver");
  });
  if (linear.type == LinearSolverType::petsc && !petsc_available())
    section.child("type").fail(
        "petsc: this build has no PETSc (apt-get install libpetsc-real-dev libopenmpi-dev, "
        "then configure again; or use cholmod or cg)");
  read_optional(section, "petsc_options", linear.petsc_options, [](const Value& v) { return v.text(); });
  read_optional(section, "tolerance", linear.tolerance, open_fraction);
  read_optional(section, "max_iterations", linear.max_iterations, at_least(1));
  read_optional(section, "reuse_iterations", linear.reuse_iterations, at_least(0));
  return linear;
}

/// solver.backend: serial (the default: the linear solver of solver.linear)
/// or petsc (PETSc's KSP, which also runs on several MPI ranks).
void read_backend(const Value& section, LinearSolverSettings& linear) {
  const Value backend = section.child("backend");
  if (!backend.present()) return;
  const std::string name = one_of(backend, {"serial", "petsc"}, "backend");
  if (name == "serial") return;
  const Value linear_section = section.child("linear");
  if (linear_section.present() && linear_section.child("type").present() && linear.type != LinearSolverType::petsc)
    linear_section.child("type").fail(
        "is " + std::string(linear_solver_type_name(linear.type)) +
        ", but solver.backend is petsc (PETSc solves the linear systems: leave linear.type out)");
  if (!petsc_available())
    backend.fail(
        "petsc: this build has no PETSc (apt-get install libpetsc-real-dev libopenmpi-dev, "
        "then configure again)");
  linear.type = LinearSolverType::petsc;
}

SolverSettings read_solver(const Value& section) {
  section.expect_map();
  SolverSettings solver;
  solver.type = one_of_enum(section.required("type"),
                            {SolverType::static_newton, SolverType::implicit_euler, SolverType::explicit_euler},
                            solver_type_name, "solver type");
  read_optional(section, "load_steps", solver.load_steps, at_least(1));
  read_optional(section, "tolerance", solver.tolerance, open_fraction);
  read_optional(section, "max_iterations", solver.max_iterations, at_least(1));
  // Keys of the other solver types are read (and checked) but not required.
  const std::string reason = "(needed by solver type " + std::string(solver_type_name(solver.type)) + ")";
  if (solver.is_dynamic()) {
    section.required("dt", reason);
    section.required("steps", reason);
  }
  read_optional(section, "dt", solver.dt, positive);
  read_optional(section, "steps", solver.steps, at_least(1));
  read_optional(section, "newton_iterations", solver.newton_iterations, at_least(1));
  read_optional(section, "predictor", solver.predictor, [](const Value& v) {
    return one_of_enum(v, {StepPredictor::velocity, StepPredictor::none}, step_predictor_name, "predictor");
  });
  read_optional(section, "project_hessian", solver.project_hessian, boolean);
  read_damping(section.child("damping"), solver);
  solver.linear = read_linear(section.child("linear"));
  read_backend(section, solver.linear);
  read_optional(section, "threads", solver.threads, at_least(0));
  return solver;
}

CriterionSpec read_criterion(const Value& item) {
  item.expect_map();
  CriterionSpec c;
  c.line = item.line();
  c.name = one_of(item.required("name"), criterion_names(), "criterion");
  c.threshold = non_negative(item.required("threshold"));
  const Value rung = item.child("rung");
  if (rung.present()) c.rung = one_of(rung, Registry::instance().laws(), "law");
  return c;
}

void read_downgrade(const Value& value, AdaptivitySettings& spec) {
  if (!value.present()) return;
  if (value.is_scalar() && (value.scalar() == "true" || value.scalar() == "false")) {
    spec.downgrade = value.scalar() == "true";
    return;
  }
  if (!value.is_map()) value.fail("expected a map {hysteresis, calm_steps} or true/false, got " + value.describe());
  spec.downgrade = true;
  read_optional(value, "hysteresis", spec.hysteresis, open_fraction);
  read_optional(value, "calm_steps", spec.calm_steps, at_least(1));
}

/// At least two known laws, each once.
void read_ladder(const Value& list, AdaptivitySettings& spec) {
  if (!list.present()) return;
  if (!list.is_list()) list.fail("expected a list of laws from the cheapest to the richest, got " + list.describe());
  spec.ladder.clear();
  spec.ladder_line = list.line();
  for (const Value& item : list.items()) {
    const std::string law = one_of(item, Registry::instance().laws(), "law");
    for (const std::string& before : spec.ladder)
      if (before == law) item.fail("law " + law + " is on the ladder twice");
    spec.ladder.push_back(law);
  }
  if (spec.ladder.size() < 2) list.fail("a ladder needs at least two laws (the first is where cells start)");
}

/// A criterion's rung is a law of the ladder above its first.
void check_rungs(const Value& criteria, const AdaptivitySettings& spec) {
  const std::vector<Value> items = criteria.items();
  for (std::size_t i = 0; i < spec.criteria.size(); ++i) {
    const std::string& rung = spec.criteria[i].rung;
    if (rung.empty()) continue;
    const auto found = std::find(spec.ladder.begin(), spec.ladder.end(), rung);
    if (found == spec.ladder.end())
      items[i].child("rung").fail("law " + rung + " is not on the ladder (" + scene_yaml::join(spec.ladder) + ")");
    if (found == spec.ladder.begin())
      items[i].child("rung").fail("law " + rung + " is the ladder's first law, where cells start: a rung above it");
  }
}

AdaptivitySettings read_adaptivity(const Value& section) {
  AdaptivitySettings spec;
  if (!section.present()) return spec;
  section.expect_map();
  // Refinement alone (no criteria) switches no laws; with criteria, both run.
  if (section.child("refine").present() && !section.child("criteria").present()) return spec;
  spec.enabled = true;
  const Value criteria = section.required("criteria", "(or 'refine')");
  for (const Value& item : criteria.items()) {
    const CriterionSpec c = read_criterion(item);
    for (const CriterionSpec& before : spec.criteria)
      if (before.name == c.name) item.fail("criterion " + c.name + " is listed twice");
    spec.criteria.push_back(c);
  }
  if (spec.criteria.empty()) criteria.fail("needs at least one criterion");
  read_ladder(section.child("ladder"), spec);
  check_rungs(criteria, spec);
  read_optional(section, "action", spec.action, [](const Value& v) {
    return one_of_enum(v, {AdaptivityAction::upgrade}, adaptivity_action_name, "action");
  });
  read_optional(section, "every", spec.every, at_least(1));
  read_optional(section, "blend_steps", spec.blend_steps, at_least(0));
  read_downgrade(section.child("downgrade"), spec);
  return spec;
}

/// The criteria of `adaptivity.refine`: R_ZZ, once, with a threshold in [0, 1].
double read_refine_threshold(const Value& criteria) {
  if (!criteria.is_list())
    criteria.fail("expected a list of criteria [{name: R_ZZ, threshold: T}], got " + criteria.describe());
  const std::vector<Value> items = criteria.items();
  if (items.size() != 1) criteria.fail("needs exactly one criterion (R_ZZ), got " + std::to_string(items.size()));
  items[0].expect_map();
  one_of(items[0].required("name"), {"R_ZZ"}, "refinement criterion");
  const Value threshold = items[0].required("threshold");
  const double t = threshold.number();
  if (!(t >= 0 && t <= 1))
    threshold.fail("must be >= 0 and <= 1 (a fraction of the largest R_ZZ), got " + threshold.scalar());
  return t;
}

/// coarsen: a map {hysteresis, calm_steps} or true/false.
void read_coarsen(const Value& value, RefinementSettings& spec) {
  if (!value.present()) return;
  if (value.is_scalar() && (value.scalar() == "true" || value.scalar() == "false")) {
    spec.coarsen = value.scalar() == "true";
    return;
  }
  if (!value.is_map()) value.fail("expected a map {hysteresis, calm_steps} or true/false, got " + value.describe());
  read_optional(value, "hysteresis", spec.hysteresis, open_fraction);
  read_optional(value, "calm_steps", spec.calm_steps, at_least(1));
}

/// adaptivity.refine, with what it cannot run with yet (the checks that
/// need the mesh are in scene_validation.cpp).
RefinementSettings read_refinement(const Value& section, const Scene& scene) {
  RefinementSettings spec;
  if (!section.present()) return spec;
  section.expect_map();
  spec.enabled = true;
  spec.line = section.line();
  spec.threshold = read_refine_threshold(section.required("criteria"));
  read_optional(section, "max_level", spec.max_level, at_least(0));
  read_optional(section, "every", spec.every, at_least(1));
  read_coarsen(section.child("coarsen"), spec);
  if (!scene.model.loads.nodal_forces.empty())
    section.fail(
        "is not supported with loads.nodal_forces (the same force on each node of a group: refinement adds "
        "nodes to the group and would change the total force): use loads.pressure");
  return spec;
}

/// Group names, each once and each with its own track file name.
void read_track(const Value& list, OutputSettings& output) {
  if (!list.present()) return;
  if (!list.is_list()) list.fail("expected a list of group names, got " + list.describe());
  for (const Value& item : list.items()) {
    const std::string name = item.text();
    for (const std::string& before : output.track) {
      if (before == name) item.fail("group '" + name + "' is listed twice");
      if (track_file_name(before) == track_file_name(name))
        item.fail("groups '" + before + "' and '" + name + "' would both write " + track_file_name(name));
    }
    output.track.push_back(name);
    output.track_lines.push_back(item.line());
  }
}

OutputSettings read_output(const Value& section, const fs::path& directory) {
  OutputSettings output;
  if (section.present()) {
    section.expect_map();
    read_optional(section, "directory", output.directory, [](const Value& v) { return v.text(); });
    read_optional(section, "every", output.every, at_least(0));
    read_optional(section, "checkpoint_every", output.checkpoint_every, at_least(0));
    read_track(section.child("track"), output);
  }
  output.directory = resolve_path(directory, output.directory);
  return output;
}

Scene read_scene(const Value& root, const std::string& path) {
  const fs::path directory = fs::path(path).parent_path();
  Scene scene;
  scene.path = path;
  scene.mesh = resolve_path(directory, root.required("mesh").text());
  scene.model.source = path;
  // The ladder first: a material on it takes the constants of every ladder law.
  scene.adaptivity = read_adaptivity(root.child("adaptivity"));
  scene.model.materials = read_materials(root.required("materials"), scene.adaptivity, directory);
  read_fixed(root.child("fixed"), scene.model);
  scene.model.prescribed = read_prescribed(root.child("prescribed"));
  scene.model.loads = read_loads(root.child("loads"));
  scene.solver = read_solver(root.required("solver"));
  if (root.child("adaptivity").is_map())
    scene.refinement = read_refinement(root.child("adaptivity").child("refine"), scene);
  scene.output = read_output(root.child("output"), directory);
  return scene;
}

}  // namespace

namespace {

/// Overrides, key checks and the read, for a scene parsed by `parse` (the file or the text).
template <class Parse>
Scene scene_from(const std::string& path, const std::vector<std::string>& overrides, Parse parse) {
  scene_yaml::Source source(path);
  try {
    YAML::Node root = parse();
    if (!root.IsMap())
      Value(source, root, {})
          .fail_here("a scene is a map of keys (mesh, materials, solver, ...), got " +
                     Value(source, root, {}).describe());
    for (const std::string& text : overrides) scene_yaml::apply_override(root, text, scene_keys(), source);
    const Value top(source, root, {});
    scene_yaml::check_keys(top, scene_keys());
    return read_scene(top, path);
  } catch (const YAML::Exception& e) {  // defensive: yaml-cpp errors not caught above
    throw InputError(path + ": " + e.what());
  } catch (const std::bad_alloc&) {  // a scene too large for this machine: say which file
    throw InputError(path + ": not enough memory to read this scene");
  }
}

}  // namespace

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  return scene_from(path, overrides, [&] { return scene_yaml::read_yaml_file(path); });
}

Scene parse_scene(const std::string& text, const std::string& name, const std::vector<std::string>& overrides) {
  return scene_from(name, overrides, [&] { return scene_yaml::read_yaml_text(text, name); });
}

}  // namespace tensormass
