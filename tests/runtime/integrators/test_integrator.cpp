// The integrator a run steps with (make_integrator and Integrator::run in
// tensormass/integrators/integrators.hpp): the integrator of each solver
// type, stepping one call at a time giving the whole solve's bits, every
// finished step reported once, a finished state stepped no further, a
// static load step solved again while the observer asks, and the explicit
// integrator's stable step estimated when it is made. (Each integrator's
// physics: test_static_solver.cpp, test_implicit_solver.cpp, test_explicit_solver.cpp.)
#include <gtest/gtest.h>

#include <vector>

#include "support/cantilever.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/integrators/integrators.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

/// A small clamped beam under gravity and what an integrator runs on.
struct BeamRun {
  explicit BeamRun(SolverType type)
      : mesh(test::beam(2, "quad4", {4, 1, 1})),
        scene(test::cantilever("stvk", type)),
        model(mesh, scene.model),
        assembler(model),
        linear(make_linear_solver(scene.solver.linear)) {
    scene.solver.load_steps = 3;
    scene.solver.steps = 4;
    scene.solver.dt = type == SolverType::explicit_euler ? 0.5 * estimate_stable_time_step(model, assembler) : 1e-3;
  }
  Integration integration() { return {model, assembler, *linear, scene.solver, statistics}; }

  Mesh mesh;
  Scene scene;
  Model model;
  Assembler assembler;
  std::unique_ptr<LinearSolver> linear;
  SolveStatistics statistics;
};

/// The whole solve of `type` by solve_static, solve_implicit or solve_explicit.
State whole_solve(SolverType type) {
  BeamRun run(type);
  Integration integration = run.integration();
  State state;
  if (type == SolverType::static_newton) solve_static(integration, state, {});
  else if (type == SolverType::implicit_euler) solve_implicit(integration, state, {});
  else solve_explicit(integration, state, {});
  return state;
}

const SolverType kTypes[] = {SolverType::static_newton, SolverType::implicit_euler, SolverType::explicit_euler};

TEST(Integrator, RunGivesTheWholeSolveOfItsSolverType) {
  for (SolverType type : kTypes) {
    BeamRun run(type);
    Integration integration = run.integration();
    const auto integrator = make_integrator(integration);
    State state;
    std::vector<int> reported;
    integrator->run(state, [&](const State& s) {
      reported.push_back(s.step);
      return false;
    });
    const State whole = whole_solve(type);
    const int steps = run.scene.solver.total_steps();
    EXPECT_EQ(reported,
              type == SolverType::static_newton ? (std::vector<int>{1, 2, 3}) : (std::vector<int>{1, 2, 3, 4}))
        << solver_type_name(type);
    EXPECT_EQ(state.step, steps);
    EXPECT_TRUE(integrator->finished(state));
    EXPECT_EQ(state.displacement, whole.displacement) << solver_type_name(type);
    EXPECT_EQ(state.velocity, whole.velocity) << solver_type_name(type);
    EXPECT_EQ(state.time, whole.time) << solver_type_name(type);
  }
}

TEST(Integrator, SteppingOneCallAtATimeGivesTheSameBits) {
  for (SolverType type : kTypes) {
    BeamRun run(type);
    Integration integration = run.integration();
    const auto integrator = make_integrator(integration);
    State state;
    int steps = 0;
    while (!integrator->finished(state)) {
      integrator->step(state, {});
      ++steps;
      EXPECT_EQ(state.step, steps);
    }
    integrator->finish(state);
    EXPECT_EQ(state.displacement, whole_solve(type).displacement) << solver_type_name(type);
  }
}

TEST(Integrator, AFinishedStateIsSteppedNoFurther) {
  BeamRun run(SolverType::implicit_euler);
  Integration integration = run.integration();
  const auto integrator = make_integrator(integration);
  State state = whole_solve(SolverType::implicit_euler);
  const State before = state;
  int reported = 0;
  integrator->run(state, [&](const State&) { return ++reported, false; });
  EXPECT_EQ(reported, 0);
  EXPECT_EQ(state.step, before.step);
  EXPECT_EQ(state.displacement, before.displacement);
}

TEST(Integrator, AStaticLoadStepIsSolvedAgainWhileTheObserverAsks) {
  BeamRun run(SolverType::static_newton);
  Integration integration = run.integration();
  const auto integrator = make_integrator(integration);
  State state;
  std::vector<int> reported;
  integrator->run(state, [&](const State& s) {
    reported.push_back(s.step);
    return s.step == 2 && reported.size() < 4;  // load step 2 twice more
  });
  EXPECT_EQ(reported, (std::vector<int>{1, 2, 2, 2, 3}));
  EXPECT_EQ(state.step, 3);
  // Solved again with the same laws, the load step ends where it did, to Newton's tolerance.
  const State whole = whole_solve(SolverType::static_newton);
  ASSERT_EQ(state.displacement.size(), whole.displacement.size());
  for (std::size_t i = 0; i < whole.displacement.size(); ++i)
    EXPECT_NEAR(state.displacement[i], whole.displacement[i], 1e-8) << i;
}

TEST(Integrator, TheExplicitIntegratorEstimatesItsStableStepWhenMade) {
  for (SolverType type : kTypes) {
    BeamRun run(type);
    Integration integration = run.integration();
    const auto integrator = make_integrator(integration);
    if (type == SolverType::explicit_euler) {
      EXPECT_NEAR(run.statistics.stable_dt, 2 * run.scene.solver.dt, 1e-9 * run.scene.solver.dt);
    } else {
      EXPECT_EQ(run.statistics.stable_dt, 0) << solver_type_name(type);
    }
  }
}

}  // namespace
}  // namespace tensormass
