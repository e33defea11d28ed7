// The integrator settings (tensormass/integrators/solver_settings.hpp): the
// scene's names of the solver types and predictors, read back by the scene
// reader as the same values, the defaults a scene without them gets, and
// the step counts of static and dynamic solves.
#include <gtest/gtest.h>

#include <string>

#include "tensormass/integrators/solver_settings.hpp"
#include "tensormass/scene/scene.hpp"

namespace tensormass {
namespace {

const std::string kScene =
    "mesh: beam.msh\n"
    "materials: [{region: all, law: stvk, young: 1.0e6, poisson: 0.3, density: 1000}]\n"
    "fixed: [clamp]\n"
    "solver: {type: static}\n";

/// The solver settings of kScene with `overrides`.
SolverSettings read_solver(const std::vector<std::string>& overrides = {}) {
  return parse_scene(kScene, "scene.yaml", overrides).solver;
}

TEST(SolverSettings, SolverTypesHaveTheScenesNames) {
  EXPECT_EQ(solver_type_name(SolverType::static_newton), "static");
  EXPECT_EQ(solver_type_name(SolverType::implicit_euler), "implicit");
  EXPECT_EQ(solver_type_name(SolverType::explicit_euler), "explicit");
}

TEST(SolverSettings, PredictorsHaveTheScenesNames) {
  EXPECT_EQ(step_predictor_name(StepPredictor::velocity), "velocity");
  EXPECT_EQ(step_predictor_name(StepPredictor::none), "none");
}

TEST(SolverSettings, TheSceneReaderReadsEachNameAsItsValue) {
  for (SolverType type : {SolverType::static_newton, SolverType::implicit_euler, SolverType::explicit_euler}) {
    const std::string name(solver_type_name(type));
    EXPECT_EQ(read_solver({"solver={type: " + name + ", dt: 0.01, steps: 3}"}).type, type) << name;
  }
  for (StepPredictor predictor : {StepPredictor::velocity, StepPredictor::none}) {
    const std::string name(step_predictor_name(predictor));
    EXPECT_EQ(read_solver({"solver={type: implicit, dt: 0.01, steps: 3, predictor: " + name + "}"}).predictor,
              predictor)
        << name;
  }
}

TEST(SolverSettings, ASceneWithoutSettingsGetsTheDefaults) {
  const SolverSettings read = read_solver();
  const SolverSettings defaults;
  EXPECT_EQ(read.type, SolverType::static_newton);
  EXPECT_EQ(read.load_steps, defaults.load_steps);
  EXPECT_EQ(read.tolerance, defaults.tolerance);
  EXPECT_EQ(read.max_iterations, defaults.max_iterations);
  EXPECT_EQ(read.newton_iterations, defaults.newton_iterations);
  EXPECT_EQ(read.predictor, defaults.predictor);
  EXPECT_EQ(read.project_hessian, defaults.project_hessian);
  EXPECT_EQ(read.threads, defaults.threads);
  EXPECT_EQ(defaults.load_steps, 1);
  EXPECT_EQ(defaults.tolerance, 1e-10);
  EXPECT_EQ(defaults.max_iterations, 50);
  EXPECT_EQ(defaults.newton_iterations, 1);
  EXPECT_EQ(defaults.predictor, StepPredictor::velocity);
  EXPECT_EQ(defaults.damping_mass, 0);
  EXPECT_EQ(defaults.damping_stiffness, 0);
}

TEST(SolverSettings, TotalStepsAreLoadStepsWhenStaticAndTimeStepsOtherwise) {
  SolverSettings settings;
  settings.load_steps = 4;
  settings.steps = 30;
  EXPECT_TRUE(settings.is_static());
  EXPECT_FALSE(settings.is_dynamic());
  EXPECT_EQ(settings.total_steps(), 4);
  for (SolverType type : {SolverType::implicit_euler, SolverType::explicit_euler}) {
    settings.type = type;
    EXPECT_FALSE(settings.is_static());
    EXPECT_TRUE(settings.is_dynamic());
    EXPECT_EQ(settings.total_steps(), 30);
  }
}

}  // namespace
}  // namespace tensormass
