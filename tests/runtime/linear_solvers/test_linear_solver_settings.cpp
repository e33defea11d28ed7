// The linear solver settings (tensormass/linear_solvers/linear_solver_settings.hpp):
// the scene's names of the solver types, read back by the scene reader as
// the same values, and the defaults a scene without them gets.
#include <gtest/gtest.h>

#include <string>

#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/linear_solvers/linear_solver_settings.hpp"
#include "tensormass/scene/scene.hpp"

namespace tensormass {
namespace {

const std::string kScene =
    "mesh: beam.msh\n"
    "materials: [{region: all, law: stvk, young: 1.0e6, poisson: 0.3, density: 1000}]\n"
    "fixed: [clamp]\n"
    "solver: {type: static}\n";

TEST(LinearSolverSettings, TypesHaveTheScenesNames) {
  EXPECT_EQ(linear_solver_type_name(LinearSolverType::cholmod), "cholmod");
  EXPECT_EQ(linear_solver_type_name(LinearSolverType::cg), "cg");
  EXPECT_EQ(linear_solver_type_name(LinearSolverType::petsc), "petsc");
}

TEST(LinearSolverSettings, TheSceneReaderReadsEachNameAsItsValue) {
  for (LinearSolverType type : {LinearSolverType::cholmod, LinearSolverType::cg, LinearSolverType::petsc}) {
    if (type == LinearSolverType::petsc && !petsc_available()) continue;  // refused, saying so (test_scene_load.cpp)
    const std::string name(linear_solver_type_name(type));
    EXPECT_EQ(parse_scene(kScene, "scene.yaml", {"solver.linear.type=" + name}).solver.linear.type, type) << name;
  }
}

TEST(LinearSolverSettings, ASceneWithoutThemGetsTheDefaults) {
  const LinearSolverSettings read = parse_scene(kScene, "scene.yaml").solver.linear;
  const LinearSolverSettings defaults;
  EXPECT_EQ(read.type, LinearSolverType::cholmod);
  EXPECT_EQ(read.tolerance, defaults.tolerance);
  EXPECT_EQ(read.max_iterations, defaults.max_iterations);
  EXPECT_EQ(read.reuse_iterations, defaults.reuse_iterations);
  EXPECT_EQ(read.petsc_options, defaults.petsc_options);
  EXPECT_EQ(defaults.tolerance, 1e-6);
  EXPECT_EQ(defaults.max_iterations, 10000);
  EXPECT_EQ(defaults.reuse_iterations, 12);
  EXPECT_EQ(defaults.petsc_options, "-ksp_type cg -pc_type gamg");
}

}  // namespace
}  // namespace tensormass
