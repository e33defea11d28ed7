// CriteriaScreen: the change bounds it rests on hold for R_NL and R_E on
// every kind of element, and an adaptive model that screens decides every
// cell as one that evaluates every cell every time (same moves, same laws,
// same values once refreshed), while evaluating fewer cells.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "support/cantilever.hpp"
#include "tensormass/adaptivity/adaptivity.hpp"
#include "tensormass/adaptivity/criteria_screen.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

ModelSpec material_spec(const std::string& law) {
  ModelSpec spec;
  MaterialSpec material;
  material.law = law;
  material.constants = elastic_constants(1e6, 0.3);
  material.density = 1000;
  spec.materials = {material};
  return spec;
}

/// Every criterion's values on every cell at u.
std::vector<double> values_at(const Criterion& criterion, const Model& model, const std::vector<double>& u) {
  std::vector<double> values(model.cell_count(), 0.0);
  for (const ElementBlock& block : model.mesh().blocks) criterion.evaluate_block({model, block, u, u}, values);
  return values;
}

TEST(CriteriaScreen, ShapeGradientSumOfRightTriangles) {
  // A unit square cut into two right triangles with unit legs: gradients
  // (-1, -1), (1, 0), (0, 1) in some order, so G = 2 + sqrt(2) on both.
  const Mesh mesh = test::beam(2, "tri3", {1, 1, 1});
  const Model model(mesh, material_spec("stvk"));
  ASSERT_EQ(model.cell_count(), 2);
  for (int cell = 0; cell < 2; ++cell) EXPECT_NEAR(shape_gradient_sum(model, cell), 2.0 + std::sqrt(2.0), 1e-12);
}

TEST(CriteriaScreen, ChangeBoundsHoldOnEveryShape) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const std::vector<Mesh> meshes{test::beam(3, "tet6", {3, 1, 1}), test::beam(3, "hex8", {3, 1, 1}),
                                 test::beam(3, "tet6", {2, 1, 1}, 2), test::beam(2, "quad4", {3, 1, 1}),
                                 test::beam(2, "tri3", {3, 1, 1}, 2)};
  int checked = 0;
  for (const Mesh& mesh : meshes) {
    const Model model(mesh, material_spec("stvk"));
    for (const std::string name : {"R_NL", "R_E"}) {
      const auto criterion = make_criterion(name);
      ASSERT_TRUE(criterion->screenable()) << name;
      for (double size : {1e-3, 0.05, 0.5}) {  // small strain to large rotation and strain
        std::vector<double> u(model.dof_count()), moved(model.dof_count());
        for (double& x : u) x = size * unit(random);
        for (double step : {1e-6, 1e-3, 0.05}) {
          // A rigid translation on top, which leaves H unchanged: the bound measures motion less a common w.
          const double shift[3] = {0.7, -0.3, 0.2};
          for (std::size_t i = 0; i < u.size(); ++i) moved[i] = u[i] + step * unit(random) + shift[i % model.dim()];
          const std::vector<double> before = values_at(*criterion, model, u),
                                    after = values_at(*criterion, model, moved);
          for (int cell = 0; cell < model.cell_count(); ++cell) {
            const int d = model.dim();
            double low[3] = {1e300, 1e300, 1e300}, high[3] = {-1e300, -1e300, -1e300};
            for (int node : model.cell_nodes(cell))
              for (int a = 0; a < d; ++a) {
                low[a] = std::min(low[a], moved[node * d + a] - u[node * d + a]);
                high[a] = std::max(high[a], moved[node * d + a] - u[node * d + a]);
              }
            double largest_move = 0.0;
            for (int node : model.cell_nodes(cell)) {
              double squared = 0.0;
              for (int a = 0; a < d; ++a) {
                const double delta = moved[node * d + a] - u[node * d + a] - 0.5 * (low[a] + high[a]);
                squared += delta * delta;
              }
              largest_move = std::max(largest_move, std::sqrt(squared));
            }
            const double delta = shape_gradient_sum(model, cell) * largest_move;
            const double slope = criterion->change_slope(criterion->gradient_norm_bound(before[cell], model.dim()));
            const double bound = slope * delta + 0.5 * delta * delta;
            ASSERT_LE(std::abs(after[cell] - before[cell]), bound * (1 + 1e-12) + 1e-13)
                << name << " on " << mesh.describe_cell(cell) << ", |u| ~ " << size << ", move ~ " << step;
            ++checked;
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 700);
}

TEST(CriteriaScreen, OnlyCriteriaOfTheDisplacementGradientAreScreened) {
  for (const std::string name : {"R_EL", "R_V", "R_VL", "R_VLX", "R_S"})
    EXPECT_FALSE(make_criterion(name)->screenable()) << name;
  const Mesh mesh = test::beam(3, "tet6", {3, 1, 1});
  Model model(mesh, material_spec("hooke"));
  const Assembler assembler(model);
  AdaptivitySettings settings;
  settings.enabled = true;
  settings.criteria = {{"R_NL", 0.01, 0, ""}, {"R_S", 1e9, 0, ""}};
  EXPECT_EQ(Adaptivity(settings, model, assembler).screen(), nullptr);
  settings.criteria = {{"R_NL", 0.01, 0, ""}};
  EXPECT_NE(Adaptivity(settings, model, assembler).screen(), nullptr);
  settings.screen = false;
  EXPECT_EQ(Adaptivity(settings, model, assembler).screen(), nullptr);
}

/// A bending of the beam growing then shrinking, with a dent that travels
/// along it: cells climb, descend (with downgrade) and stay still in turn.
std::vector<double> displacement_at(const Mesh& mesh, int step, int steps) {
  const int d = mesh.dim;
  const double bend = 0.4 * std::sin(M_PI * step / steps), along = 8.0 * step / steps;
  std::vector<double> u(static_cast<std::size_t>(mesh.node_count()) * d, 0.0);
  for (int node = 0; node < mesh.node_count(); ++node) {
    const double x = mesh.rest_positions[3 * node], y = mesh.rest_positions[3 * node + 1];
    u[node * d + 1] = bend * x * x / 64.0;
    u[node * d] = -bend * x * (y - 0.5) / 32.0;
    const double distance = std::abs(x - along);
    if (distance < 1.0 && y > 0.99) u[node * d + 1] -= 0.15 * (1.0 - distance);
  }
  return u;
}

struct Ladder {
  std::vector<std::string> laws;
  std::vector<CriterionSpec> criteria;
  bool downgrade;
};

TEST(CriteriaScreen, DecidesEveryCellAsAFullEvaluationDoes) {
  const Mesh mesh = test::beam(3, "tet6", {16, 2, 2});
  const std::vector<Ladder> ladders{
      {{"hooke", "stvk"}, {{"R_NL", 0.01, 0, ""}}, false},
      {{"hooke", "stvk"}, {{"R_NL", 0.004, 0, ""}}, true},
      {{"hooke", "corotational", "stvk"}, {{"R_NL", 0.002, 0, "corotational"}, {"R_E", 0.01, 0, ""}}, true}};
  const int steps = 40;
  for (const Ladder& ladder : ladders) {
    Model screened_model(mesh, material_spec("hooke")), full_model(mesh, material_spec("hooke"));
    const Assembler screened_assembler(screened_model), full_assembler(full_model);
    AdaptivitySettings settings;
    settings.enabled = true;
    settings.ladder = ladder.laws;
    settings.criteria = ladder.criteria;
    settings.downgrade = ladder.downgrade;
    settings.calm_steps = 2;
    Adaptivity screened(settings, screened_model, screened_assembler);
    settings.screen = false;
    Adaptivity full(settings, full_model, full_assembler);
    ASSERT_NE(screened.screen(), nullptr);
    int downgrades = 0;
    for (int step = 0; step <= steps; ++step) {
      const std::vector<double> u = displacement_at(mesh, step, steps);
      if (step == 0) ASSERT_EQ(screened.start(u), full.start(u));
      else ASSERT_EQ(screened.update(u, step), full.update(u, step)) << "step " << step;
      if (step > 0) downgrades += full.records().listed.back().downgrades;
      for (int cell = 0; cell < mesh.cell_count(); ++cell)
        ASSERT_EQ(&screened_model.kernel(cell), screened_model.law_kernel(cell, full_model.kernel(cell).law))
            << "step " << step << ", " << mesh.describe_cell(cell);
      if (step % 10 == 0) {  // refreshed: the values of a full evaluation, bit for bit
        for (std::size_t c = 0; c < ladder.criteria.size(); ++c)
          ASSERT_EQ(screened.criterion_values(static_cast<int>(c)), full.criterion_values(static_cast<int>(c)));
      }
    }
    EXPECT_EQ(screened.total_switches(), full.total_switches());
    EXPECT_GT(full.total_switches(), 0);
    if (ladder.downgrade) {
      EXPECT_GT(downgrades, 0);
    }
    const CriteriaScreen& screen = *screened.screen();  // the whole beam bends: it skips few cells
    EXPECT_LT(screen.evaluated_cells(), screen.evaluations() * mesh.cell_count());
  }
}

TEST(CriteriaScreen, AStillRegionIsNotEvaluatedAgain) {
  const Mesh mesh = test::beam(3, "tet6", {16, 2, 2});
  Model model(mesh, material_spec("hooke"));
  const Assembler assembler(model);
  AdaptivitySettings settings;
  settings.enabled = true;
  settings.criteria = {{"R_NL", 0.01, 0, ""}};
  Adaptivity adaptivity(settings, model, assembler);
  std::vector<double> u(model.dof_count(), 0.0);
  adaptivity.start(u);
  const long first = adaptivity.screen()->evaluated_cells();
  EXPECT_EQ(first, mesh.cell_count());  // nothing known yet
  for (int node = 0; node < mesh.node_count(); ++node)
    if (mesh.rest_positions[3 * node] > 7.5) u[node * 3 + 1] = 0.05;  // the tip's last layer of cells
  adaptivity.update(u, 1);
  const long moved = adaptivity.screen()->evaluated_cells() - first;
  EXPECT_GT(moved, 0);
  EXPECT_LE(moved, 2 * 64 + 2 * 2 * 6);  // the cells touching the tip, rounded up to chunks
  adaptivity.update(u, 2);               // nothing moved since
  EXPECT_EQ(adaptivity.screen()->evaluated_cells() - first, moved);
}

}  // namespace
}  // namespace tensormass
