// A full scene read back field by field, defaults, and path resolution.
#include <gtest/gtest.h>

#include "scene_test_support.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/simulation/checkpoint.hpp"

namespace {

using scene_test::TempDir;
using tensormass::Scene;

const char* const kFullScene = R"(# every key of the schema
mesh: meshes/beam.msh
materials:
  - {region: tumor, law: stvk, young: 2.0e6, poisson: 0.45, density: 1050, split: whole}
  - region: all
    law: hooke
    young: 1.0e6
    poisson: 0.3
    density: 1000
fixed: [clamp, base]
prescribed:
  - region: diaphragm
    displacement: [0, 0.015, null]
    profile: {type: sinusoid, period: 4.0, phase: 0.5}
  - region: wall
    displacement: [~, -0.01]
    profile: ramp
  - {region: end, rotation: {axis: [1, 0, 0], centre: [0, 0.5, 0.5], angle: 180}, displacement: [0.1, 0]}
loads:
  gravity: [0, -9.81]
  nodal_forces: [{region: tip, force: [0, -1.5, 0.4]}]
  pressure:
    - {region: top, pressure: -1000}
  profile: {type: ramp, duration: 2.0}
solver:
  type: implicit
  load_steps: 4
  tolerance: 1.0e-8
  max_iterations: 20
  dt: 0.01
  steps: 100
  newton_iterations: 3
  predictor: none
  project_hessian: true
  damping: {mass: 0.1, stiffness: 0.001}
  linear: {type: cg, tolerance: 1.0e-9, max_iterations: 500}
  threads: 2
adaptivity:
  criteria:
    - {name: R_EL, threshold: 0.03}
    - {name: R_V, threshold: 0.1, rung: stvk}
  action: upgrade
  every: 2
  blend_steps: 5
  downgrade: {hysteresis: 0.25, calm_steps: 7}
  ladder: [hooke, stvk, neohookean]
output: {directory: results, every: 10}
)";

/// A law's own constants by name; materials off the ladder need only their law's.
TEST(SceneLoad, MaterialsTakeTheirLawsOwnConstants) {
  TempDir dir;
  const std::string path =
      dir.write("scene.yaml",
                "mesh: beam.msh\n"
                "materials:\n"
                "  - {region: tumor, law: mooney_rivlin, c10: 2.0e3, c01: 5.0e2, kappa: 1.0e5, "
                "density: 1050}\n"
                "  - {region: all, law: hooke, young: 5.0e3, poisson: 0.45, density: 1000}\n"
                "solver: {type: static}\n"
                "adaptivity: {criteria: [{name: R_EL, threshold: 0.01}], ladder: [hooke, stvk]}\n");
  const Scene s = tensormass::load_scene(path);
  ASSERT_EQ(s.model.materials.size(), 2u);
  EXPECT_EQ(s.model.materials[0].constants,
            (std::map<std::string, double>{{"c10", 2.0e3}, {"c01", 5.0e2}, {"kappa", 1.0e5}}));
  EXPECT_EQ(s.model.materials[1].constants, tensormass::elastic_constants(5.0e3, 0.45));
}

TEST(SceneLoad, FullSceneMaterialsAndConstraints) {
  TempDir dir;
  const std::string path = dir.write("scene.yaml", kFullScene);
  const Scene s = tensormass::load_scene(path);
  EXPECT_EQ(s.path, path);
  EXPECT_EQ(s.mesh, (dir.path() / "meshes" / "beam.msh").string());

  ASSERT_EQ(s.model.materials.size(), 2u);
  EXPECT_EQ(s.model.materials[0].region, "tumor");
  EXPECT_EQ(s.model.materials[0].law, "stvk");
  EXPECT_EQ(s.model.materials[0].split, "whole");
  EXPECT_DOUBLE_EQ(s.model.materials[0].constants.at("young"), 2.0e6);
  EXPECT_DOUBLE_EQ(s.model.materials[0].constants.at("poisson"), 0.45);
  EXPECT_DOUBLE_EQ(s.model.materials[0].density, 1050);
  EXPECT_EQ(s.model.materials[0].line, 4);
  EXPECT_EQ(s.model.materials[1].region, "all");
  EXPECT_EQ(s.model.materials[1].law, "hooke");
  EXPECT_EQ(s.model.materials[1].split, "");
  EXPECT_DOUBLE_EQ(s.model.materials[1].constants.at("young"), 1.0e6);
  EXPECT_EQ(s.model.materials[1].line, 5);

  EXPECT_EQ(s.model.fixed, (std::vector<std::string>{"clamp", "base"}));
  EXPECT_EQ(s.model.fixed_lines, (std::vector<int>{10, 10}));

  ASSERT_EQ(s.model.prescribed.size(), 3u);
  const tensormass::PrescribedSpec& d = s.model.prescribed[0];
  EXPECT_EQ(d.region, "diaphragm");
  EXPECT_EQ(d.line, 12);
  EXPECT_EQ(d.components, (std::array<bool, 3>{true, true, false}));
  EXPECT_EQ(d.displacement, (std::array<double, 3>{0, 0.015, 0}));
  EXPECT_EQ(d.profile.kind, tensormass::ProfileKind::sinusoid);
  EXPECT_DOUBLE_EQ(d.profile.period, 4.0);
  EXPECT_DOUBLE_EQ(d.profile.phase, 0.5);
  const tensormass::PrescribedSpec& w = s.model.prescribed[1];
  EXPECT_EQ(w.components, (std::array<bool, 3>{false, true, false}));
  EXPECT_EQ(w.displacement, (std::array<double, 3>{0, -0.01, 0}));
  EXPECT_EQ(w.profile.kind, tensormass::ProfileKind::ramp);
  EXPECT_DOUBLE_EQ(w.profile.duration, 1.0);
  EXPECT_FALSE(w.rotates);
  const tensormass::PrescribedSpec& r = s.model.prescribed[2];
  EXPECT_TRUE(r.rotates);
  EXPECT_EQ(r.rotation.axis, (std::array<double, 3>{1, 0, 0}));
  EXPECT_EQ(r.rotation.centre, (std::array<double, 3>{0, 0.5, 0.5}));
  EXPECT_DOUBLE_EQ(r.rotation.angle, 180.0);
  EXPECT_EQ(r.displacement, (std::array<double, 3>{0.1, 0, 0}));
}

TEST(SceneLoad, FullSceneLoadsSolverAdaptivityOutput) {
  TempDir dir;
  const Scene s = tensormass::load_scene(dir.write("scene.yaml", kFullScene));
  EXPECT_EQ(s.model.loads.gravity, (std::array<double, 3>{0, -9.81, 0}));
  ASSERT_EQ(s.model.loads.nodal_forces.size(), 1u);
  EXPECT_EQ(s.model.loads.nodal_forces[0].region, "tip");
  EXPECT_EQ(s.model.loads.nodal_forces[0].force, (std::array<double, 3>{0, -1.5, 0.4}));
  EXPECT_EQ(s.model.loads.nodal_forces[0].line, 21);
  ASSERT_EQ(s.model.loads.pressures.size(), 1u);
  EXPECT_EQ(s.model.loads.pressures[0].region, "top");
  EXPECT_DOUBLE_EQ(s.model.loads.pressures[0].pressure, -1000);
  EXPECT_EQ(s.model.loads.pressures[0].line, 23);
  EXPECT_EQ(s.model.loads.profile.kind, tensormass::ProfileKind::ramp);
  EXPECT_DOUBLE_EQ(s.model.loads.profile.duration, 2.0);

  const tensormass::SolverSettings& v = s.solver;
  EXPECT_EQ(v.type, tensormass::SolverType::implicit_euler);
  EXPECT_EQ(v.load_steps, 4);
  EXPECT_DOUBLE_EQ(v.tolerance, 1e-8);
  EXPECT_EQ(v.max_iterations, 20);
  EXPECT_DOUBLE_EQ(v.dt, 0.01);
  EXPECT_EQ(v.steps, 100);
  EXPECT_EQ(v.newton_iterations, 3);
  EXPECT_EQ(v.predictor, tensormass::StepPredictor::none);
  EXPECT_TRUE(v.project_hessian);
  EXPECT_DOUBLE_EQ(v.damping_mass, 0.1);
  EXPECT_DOUBLE_EQ(v.damping_stiffness, 0.001);
  EXPECT_EQ(v.linear.type, tensormass::LinearSolverType::cg);
  EXPECT_DOUBLE_EQ(v.linear.tolerance, 1e-9);
  EXPECT_EQ(v.linear.max_iterations, 500);
  EXPECT_EQ(v.threads, 2);

  const tensormass::AdaptivitySettings& a = s.adaptivity;
  EXPECT_TRUE(a.enabled);
  ASSERT_EQ(a.criteria.size(), 2u);
  EXPECT_EQ(a.criteria[0].name, "R_EL");
  EXPECT_DOUBLE_EQ(a.criteria[0].threshold, 0.03);
  EXPECT_EQ(a.criteria[0].line, 40);
  EXPECT_EQ(a.criteria[1].name, "R_V");
  EXPECT_EQ(a.criteria[0].rung, "");  // the ladder's last law
  EXPECT_EQ(a.criteria[1].rung, "stvk");
  EXPECT_EQ(a.action, tensormass::AdaptivityAction::upgrade);
  EXPECT_EQ(a.every, 2);
  EXPECT_EQ(a.blend_steps, 5);
  EXPECT_TRUE(a.downgrade);
  EXPECT_DOUBLE_EQ(a.hysteresis, 0.25);
  EXPECT_EQ(a.calm_steps, 7);
  EXPECT_EQ(a.ladder, (std::vector<std::string>{"hooke", "stvk", "neohookean"}));
  EXPECT_EQ(a.ladder_line, 46);

  EXPECT_EQ(s.output.directory, (dir.path() / "results").string());
  EXPECT_EQ(s.output.every, 10);
}

TEST(SceneLoad, MinimalSceneGetsDefaults) {
  TempDir dir;
  const Scene s = tensormass::load_scene(dir.write("scene.yaml", scene_test::kBaseScene));
  EXPECT_EQ(s.mesh, (dir.path() / "beam.msh").string());
  ASSERT_EQ(s.model.materials.size(), 1u);
  EXPECT_EQ(s.model.materials[0].split, "");
  EXPECT_TRUE(s.model.prescribed.empty());
  EXPECT_EQ(s.model.loads.gravity, (std::array<double, 3>{0, 0, 0}));
  EXPECT_TRUE(s.model.loads.nodal_forces.empty());
  EXPECT_TRUE(s.model.loads.pressures.empty());
  EXPECT_EQ(s.model.loads.profile.kind, tensormass::ProfileKind::constant);
  EXPECT_EQ(s.solver.type, tensormass::SolverType::static_newton);
  EXPECT_EQ(s.solver.load_steps, 10);
  EXPECT_DOUBLE_EQ(s.solver.tolerance, 1e-10);
  EXPECT_EQ(s.solver.max_iterations, 50);
  EXPECT_EQ(s.solver.predictor, tensormass::StepPredictor::velocity);
  EXPECT_FALSE(s.solver.project_hessian);
  EXPECT_EQ(s.solver.linear.type, tensormass::LinearSolverType::cholmod);
  EXPECT_EQ(s.solver.threads, 0);
  EXPECT_FALSE(s.adaptivity.enabled);
  EXPECT_FALSE(s.adaptivity.downgrade);
  EXPECT_EQ(s.output.directory, (dir.path() / "out").string());
  EXPECT_EQ(s.output.every, 0);
}

TEST(SceneLoad, AbsolutePathsAreKept) {
  TempDir dir;
  std::string text = scene_test::replaced(scene_test::kBaseScene, "mesh: beam.msh", "mesh: /data/m/beam.vtu");
  text += "output: {directory: /tmp/tm_out}\n";
  const Scene s = tensormass::load_scene(dir.write("scene.yaml", text));
  EXPECT_EQ(s.mesh, "/data/m/beam.vtu");
  EXPECT_EQ(s.output.directory, "/tmp/tm_out");
}

TEST(SceneLoad, DynamicKeysAreAcceptedByAStaticSolver) {
  TempDir dir;
  const std::string text = scene_test::kBaseScene + "  dt: 0.5\n  steps: 3\n  linear: {type: cg}\n";
  const Scene s = tensormass::load_scene(dir.write("scene.yaml", text));
  EXPECT_EQ(s.solver.type, tensormass::SolverType::static_newton);
  EXPECT_DOUBLE_EQ(s.solver.dt, 0.5);
  EXPECT_EQ(s.solver.steps, 3);
}

TEST(SceneLoad, EmptyValuesCountAsAbsent) {
  TempDir dir;
  const std::string text = scene_test::kBaseScene + "loads:\noutput:\nprescribed:\n";
  const Scene s = tensormass::load_scene(dir.write("scene.yaml", text));
  EXPECT_TRUE(s.model.loads.nodal_forces.empty());
  EXPECT_TRUE(s.model.prescribed.empty());
  EXPECT_EQ(s.output.directory, (dir.path() / "out").string());
}

TEST(SceneLoad, DowngradeAsBooleanAndExponentIntegers) {
  TempDir dir;
  const std::string text = scene_test::replaced(scene_test::kBaseScene, "load_steps: 10", "load_steps: 1e2") +
                           "adaptivity: {criteria: [{name: R_VLX, threshold: 0.5}], downgrade: true}\n";
  const Scene s = tensormass::load_scene(dir.write("scene.yaml", text));
  EXPECT_EQ(s.solver.load_steps, 100);
  EXPECT_TRUE(s.adaptivity.enabled);
  EXPECT_TRUE(s.adaptivity.downgrade);
  EXPECT_DOUBLE_EQ(s.adaptivity.hysteresis, 0.5);
  EXPECT_EQ(s.adaptivity.calm_steps, 10);
  EXPECT_EQ(s.adaptivity.ladder, (std::vector<std::string>{"hooke", "stvk"}));  // today's behaviour
}

TEST(SceneLoad, SceneInCurrentDirectoryKeepsRelativePaths) {
  TempDir dir;
  dir.write("scene.yaml", scene_test::kBaseScene);
  const auto previous = std::filesystem::current_path();
  std::filesystem::current_path(dir.path());
  const Scene s = tensormass::load_scene("scene.yaml");
  std::filesystem::current_path(previous);
  EXPECT_EQ(s.mesh, "beam.msh");
  EXPECT_EQ(s.output.directory, "out");
}

TEST(SceneLoad, ProfileReadFromTheScene) {
  TempDir dir;
  const std::string text = scene_test::kBaseScene + "loads:\n  profile: sinusoid\n";
  const Scene s = tensormass::load_scene(dir.write("scene.yaml", text));
  EXPECT_EQ(s.model.loads.profile.kind, tensormass::ProfileKind::sinusoid);
  EXPECT_DOUBLE_EQ(s.model.loads.profile.period, 1.0);
  EXPECT_NEAR(s.model.loads.profile.factor(0.5), 1, 1e-15);
}

}  // namespace

TEST(SceneLoad, SceneFromTextEqualsTheSameFile) {
  TempDir dir;
  const std::string path = dir.write("scene.yaml", kFullScene);
  const Scene file = tensormass::load_scene(path, {"solver.steps=7"});
  const Scene text = tensormass::parse_scene(kFullScene, path, {"solver.steps=7"});
  EXPECT_EQ(text.path, file.path);
  EXPECT_EQ(text.mesh, file.mesh);
  EXPECT_EQ(text.solver.steps, 7);
  EXPECT_EQ(tensormass::scene_fingerprint(text), tensormass::scene_fingerprint(file));
}

TEST(SceneLoad, SceneFromTextErrorsNameItsLabelAndLine) {
  try {
    tensormass::parse_scene("mesh: m.msh\nmaterials: [\n", "from_arrays");
    FAIL() << "a syntax error was accepted";
  } catch (const tensormass::InputError& e) {
    test_support::expect_contains(e.what(), {"from_arrays:", "YAML syntax error"});
  }
  try {
    tensormass::parse_scene(scene_test::kBaseScene + "  stepz: 3\n", "from_arrays");
    FAIL() << "an unknown key was accepted";
  } catch (const tensormass::InputError& e) {
    test_support::expect_contains(e.what(), {"from_arrays:", "stepz"});
  }
}

TEST(SceneLoad, PetscLinearSolverAndItsOptions) {
  const std::string text =
      scene_test::kBaseScene + "  linear: {type: petsc, petsc_options: \"-ksp_type cg -pc_type jacobi\"}\n";
  if (!tensormass::petsc_available()) {
    try {
      tensormass::parse_scene(text, "petsc.yaml");
      FAIL() << "linear.type petsc accepted by a build without PETSc";
    } catch (const tensormass::InputError& e) {
      test_support::expect_contains(e.what(), {"petsc.yaml:", "solver.linear.type", "no PETSc"});
    }
    return;
  }
  const Scene s = tensormass::parse_scene(text, "petsc.yaml");
  EXPECT_EQ(s.solver.linear.type, tensormass::LinearSolverType::petsc);
  EXPECT_EQ(s.solver.linear.petsc_options, "-ksp_type cg -pc_type jacobi");
  const Scene defaults = tensormass::parse_scene(scene_test::kBaseScene + "  linear: {type: petsc}\n", "petsc.yaml");
  EXPECT_EQ(defaults.solver.linear.petsc_options, "-ksp_type cg -pc_type gamg");
}

TEST(SceneLoad, PetscBackendSelectsPetscAndRefusesAnotherLinearType) {
  const std::string text = scene_test::kBaseScene + "  backend: petsc\n";
  if (!tensormass::petsc_available()) {
    try {
      tensormass::parse_scene(text, "backend.yaml");
      FAIL() << "backend petsc accepted by a build without PETSc";
    } catch (const tensormass::InputError& e) {
      test_support::expect_contains(e.what(), {"backend.yaml:8", "solver.backend", "no PETSc"});
    }
    return;
  }
  EXPECT_EQ(tensormass::parse_scene(text, "backend.yaml").solver.linear.type, tensormass::LinearSolverType::petsc);
  const Scene serial = tensormass::parse_scene(scene_test::kBaseScene + "  backend: serial\n", "backend.yaml");
  EXPECT_EQ(serial.solver.linear.type, tensormass::LinearSolverType::cholmod);
  const Scene options =
      tensormass::parse_scene(text + "  linear: {type: petsc, petsc_options: \"-ksp_type gmres\"}\n", "backend.yaml");
  EXPECT_EQ(options.solver.linear.petsc_options, "-ksp_type gmres");
  try {
    tensormass::parse_scene(text + "  linear: {type: cholmod}\n", "backend.yaml");
    FAIL() << "backend petsc beside linear.type cholmod was accepted";
  } catch (const tensormass::InputError& e) {
    test_support::expect_contains(e.what(),
                                  {"backend.yaml:9", "solver.linear.type", "cholmod", "solver.backend is petsc"});
  }
  try {
    tensormass::parse_scene(scene_test::kBaseScene + "  backend: mpi\n", "backend.yaml");
    FAIL() << "backend mpi was accepted";
  } catch (const tensormass::InputError& e) {
    test_support::expect_contains(e.what(), {"backend.yaml:8", "solver.backend", "mpi", "serial", "petsc"});
  }
}
