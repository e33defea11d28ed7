// R_ZZ, the Zienkiewicz-Zhu recovered-stress indicator (zz_indicator.hpp):
// zero for a linear field on every element type and on refined leaf meshes,
// the compliance formula against engineering constants, convergence under
// uniform refinement, a localised field selecting the cells near it, the
// threshold selection, errors, and no allocation when reused.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <new>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "runtime/refinement/refinement_checks.hpp"
#include "support/cantilever.hpp"
#include "tensormass/adaptivity/zz_indicator.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

constexpr double kYoung = 1e6;
constexpr double kPoisson = 0.3;

/// One Hooke material (or `law`) on every cell, nothing fixed or loaded.
ModelSpec material_spec(const std::string& law = "hooke") {
  ModelSpec spec;
  MaterialSpec material;
  material.law = law;
  material.constants = elastic_constants(kYoung, kPoisson);
  material.density = 1000;
  spec.materials = {material};
  return spec;
}

using Field = std::function<std::array<double, 3>(const double* x)>;

/// The field at every node's rest position (dof_count, node-major).
std::vector<double> nodal_field(const Mesh& mesh, const Field& field) {
  std::vector<double> u(static_cast<std::size_t>(mesh.node_count() * mesh.dim));
  for (int node = 0; node < mesh.node_count(); ++node) {
    const std::array<double, 3> value = field(&mesh.rest_positions[3 * static_cast<std::size_t>(node)]);
    for (int a = 0; a < mesh.dim; ++a) u[static_cast<std::size_t>(node * mesh.dim + a)] = value[a];
  }
  return u;
}

/// u = A x + b with a general A (stretch, shear and rotation) of size 1e-3.
std::array<double, 3> linear_field(const double* x) {
  const double A[3][3] = {{1.0e-3, 0.4e-3, -0.3e-3}, {-0.2e-3, -0.6e-3, 0.5e-3}, {0.7e-3, 0.1e-3, 0.8e-3}};
  std::array<double, 3> u{2e-4, -1e-4, 3e-4};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) u[a] += A[a][b] * x[b];
  return u;
}

/// Pure bending about z: strain e_xx = 1e-3 y, the stress linear in y.
std::array<double, 3> bending_field(const double* x) { return {1e-3 * x[0] * x[1], -0.5e-3 * x[0] * x[0], 0.0}; }

/// The energy norm of the stress itself, sqrt(integral of s : e): R_ZZ's scale.
double energy_norm(const Model& model, const std::vector<double>& u) { return std::sqrt(2 * model.strain_energy(u)); }

double sum_of_squares(const std::vector<double>& values) {
  double sum = 0;
  for (double v : values) sum += v * v;
  return sum;
}

/// Moves every node off the box [0, size] by up to `amount` along each axis.
void distort(Mesh& mesh, std::array<double, 3> size, double amount, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> shift(-amount, amount);
  for (int node = 0; node < mesh.node_count(); ++node) {
    double* x = &mesh.rest_positions[3 * static_cast<std::size_t>(node)];
    bool inside = true;
    for (int a = 0; a < mesh.dim; ++a) inside = inside && x[a] > 1e-9 && x[a] < size[a] - 1e-9;
    if (!inside) continue;
    for (int a = 0; a < mesh.dim; ++a) x[a] += shift(random);
  }
}

Mesh mixed_beam(int dim, std::vector<BeamPhase> phases, std::array<int, 3> cells, std::array<double, 3> size,
                int order) {
  BeamSpec spec;
  spec.dim = dim;
  spec.cells = cells;
  spec.size = size;
  spec.phases = std::move(phases);
  spec.order = order;
  return make_beam(spec);
}

std::array<double, 3> centroid(const Mesh& mesh, int cell) {
  const auto [b, local] = mesh.locate(cell);
  const auto nodes = mesh.blocks[b].cell_nodes(local);
  std::array<double, 3> c{};
  for (int node : nodes)
    for (int a = 0; a < 3; ++a) c[a] += mesh.rest_positions[3 * static_cast<std::size_t>(node) + a] / nodes.size();
  return c;
}

/// The compact symmetric part of P (zz_stress_components order).
std::vector<double> symmetric(const double* P, int dim) {
  if (dim == 2) return {P[0], P[3], 0.5 * (P[1] + P[2])};
  return {P[0], P[4], P[8], 0.5 * (P[5] + P[7]), 0.5 * (P[2] + P[6]), 0.5 * (P[1] + P[3])};
}

/// The kernel's stress at the first quadrature point of `cell` (symmetric part).
std::vector<double> first_point_stress(const Model& model, const tm_kernel& kernel, int cell,
                                       const std::vector<double>& u) {
  std::vector<double> local(static_cast<std::size_t>(kernel.dofs));
  model.gather(cell, u, local.data());
  std::vector<double> P(static_cast<std::size_t>(kernel.quadrature_points * kernel.dim * kernel.dim));
  kernel.stress(local.data(), model.consts(cell), P.data());
  return symmetric(P.data(), kernel.dim);
}

// --- Linear fields: constant stress, zero indicator ----------------------------

struct NamedMesh {
  std::string name;
  Mesh mesh;
};

/// Meshes that hold, together, every element type of the registry, their
/// inner nodes moved (second-order cells get curved edges).
std::vector<NamedMesh> every_element_meshes() {
  std::vector<NamedMesh> meshes;
  const std::array<double, 3> box2{3.0, 1.5, 1.0}, box3{3.0, 1.0, 1.0};
  meshes.push_back({"2D tri3+quad4", mixed_beam(2, {{"tri3", 0.5}, {"quad4", 0.5}}, {6, 3, 1}, box2, 1)});
  meshes.push_back({"2D tri6+quad8", mixed_beam(2, {{"tri3", 0.5}, {"quad4", 0.5}}, {6, 3, 1}, box2, 2)});
  meshes.push_back({"3D hex8+tet4+prism6+pyramid5",
                    mixed_beam(3, {{"hex8", 0.2}, {"tet5", 0.2}, {"prism6", 0.2}, {"pyramid5", 0.2}, {"tet6", 0.2}},
                               {10, 2, 2}, {5.0, 1.0, 1.0}, 1)});
  meshes.push_back({"3D tet10", mixed_beam(3, {{"tet5", 0.5}, {"tet6", 0.5}}, {6, 2, 2}, box3, 2)});
  meshes.push_back({"3D hex20", mixed_beam(3, {{"hex8", 1.0}}, {6, 2, 2}, box3, 2)});
  // One beam per other quadratic element the beam generator makes (quad9, hex27, prism15, pyramid13, ...).
  for (const tm_element_info* element : Registry::instance().elements()) {
    const std::string name = element->name;
    if (element->order != 2 || name == "tri6" || name == "quad8" || name == "tet10" || name == "hex20") continue;
    try {
      const bool plane = element->dim == 2;
      meshes.push_back({name, mixed_beam(element->dim, {{name, 1.0}},
                                         plane ? std::array<int, 3>{6, 3, 1} : std::array<int, 3>{6, 2, 2},
                                         plane ? box2 : box3, 2)});
    } catch (const InputError&) {  // not a type the beam generator makes
    }
  }
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    Mesh& mesh = meshes[m].mesh;
    const std::array<double, 3> size = m == 2 ? std::array<double, 3>{5.0, 1.0, 1.0} : mesh.dim == 2 ? box2 : box3;
    // Second-order meshes move less: a mid-edge node moved by a quarter of
    // its edge folds the cell at a corner (0.06 does on these 0.5 cells).
    const bool second_order = mesh.blocks.front().element->order == 2;
    distort(mesh, size, second_order ? 0.02 : 0.06, static_cast<unsigned>(m + 1));
  }
  return meshes;
}

/// R_ZZ of the linear field is 0 on every cell, and every recovered nodal
/// stress is the field's constant stress.
void expect_zero_for_linear_field(const Mesh& mesh, const std::string& where) {
  const Model model(mesh, material_spec());
  const std::vector<double> u = nodal_field(mesh, linear_field);
  ZzIndicator zz;
  std::vector<double> indicator(static_cast<std::size_t>(model.cell_count()), -1.0);
  zz.compute(model, u, indicator);
  const double scale = energy_norm(model, u);
  ASSERT_GT(scale, 0.0) << where;
  for (int cell = 0; cell < model.cell_count(); ++cell)
    EXPECT_LE(indicator[static_cast<std::size_t>(cell)], 1e-12 * scale) << where << ": " << mesh.describe_cell(cell);
  const std::vector<double> stress = first_point_stress(model, model.kernel(0), 0, u);
  double size = 0;
  for (double s : stress) size = std::max(size, std::abs(s));
  ASSERT_GT(size, 100.0) << where;
  const int components = zz_stress_components(mesh.dim);
  ASSERT_EQ(zz.nodal_stress().size(), static_cast<std::size_t>(mesh.node_count() * components)) << where;
  for (int node = 0; node < mesh.node_count(); ++node)
    for (int c = 0; c < components; ++c)
      ASSERT_NEAR(zz.nodal_stress()[static_cast<std::size_t>(node * components + c)], stress[c], 1e-9 * size)
          << where << ": node " << node << " component " << c;
}

TEST(ZzIndicator, LinearFieldGivesZeroOnEveryElementType) {
  std::set<std::string> seen;
  for (const NamedMesh& named : every_element_meshes()) {
    for (const ElementBlock& block : named.mesh.blocks) seen.insert(block.element->name);
    expect_zero_for_linear_field(named.mesh, named.name);
  }
  // Every element type is covered, but those the beam generator cannot make.
  for (const tm_element_info* element : Registry::instance().elements())
    if (!seen.count(element->name))
      EXPECT_THROW(mixed_beam(element->dim, {{element->name, 1.0}}, {2, 2, 2}, {2.0, 1.0, 1.0}, element->order),
                   InputError)
          << element->name << " is made by the beam generator but not covered";
}

TEST(ZzIndicator, LinearFieldGivesZeroOnARefinedLeafMeshWithTransitions) {
  Mesh beam = refinement_test::mixed_beam(6, 3);
  distort(beam, {6.0, 3.0, 1.0}, 0.12, 7);
  HierarchicalMesh hierarchy(std::move(beam));
  hierarchy.refine(std::vector<int>{4, 12, 20});
  const auto levels = hierarchy.leaf_levels();
  hierarchy.refine(std::vector<int>{static_cast<int>(std::find(levels.begin(), levels.end(), 1) - levels.begin())});
  refinement_test::expect_valid_leaf_mesh(hierarchy, "zz refined");
  ASSERT_GT(hierarchy.leaves_per_level().size(), 2u);
  int transitions = 0;
  for (char transition : hierarchy.leaf_transitions()) transitions += transition;
  ASSERT_GT(transitions, 4);
  expect_zero_for_linear_field(hierarchy.leaf_mesh(), "refined leaf mesh");
}

TEST(ZzIndicator, BlendingCellsUseTheBlendedStress) {
  // Every cell switched to St Venant-Kirchhoff and blending from Hooke at
  // w = 0.25; a 5 % linear strain, where the two laws differ.
  const Mesh mesh = refinement_test::mixed_beam(6, 3);
  Model model(mesh, material_spec());
  const tm_kernel* hooke_quad = nullptr;
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const tm_kernel* hooke = &model.kernel(cell);
    if (std::string(hooke->element) == "quad4") hooke_quad = hooke;
    model.set_law(cell, "stvk");
    model.start_blend(cell, hooke);
    model.set_blend_weight(cell, 0.25);
  }
  ASSERT_NE(hooke_quad, nullptr);
  const std::vector<double> u = nodal_field(mesh, [](const double* x) {
    return std::array<double, 3>{0.05 * x[0] + 0.02 * x[1], 0.0, 0.0};
  });
  ZzIndicator zz;
  std::vector<double> indicator(static_cast<std::size_t>(model.cell_count()));
  zz.compute(model, u, indicator);
  const double scale = energy_norm(model, u);
  for (double value : indicator) EXPECT_LE(value, 1e-12 * scale);
  int cell = 0;
  while (std::string(model.kernel(cell).element) != "quad4") ++cell;
  const std::vector<double> stvk = first_point_stress(model, model.kernel(cell), cell, u);
  const std::vector<double> hooke = first_point_stress(model, *hooke_quad, cell, u);
  ASSERT_GT(std::abs(stvk[0] - hooke[0]), 1e-2 * std::abs(hooke[0])) << "the laws should differ at this strain";
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(zz.nodal_stress()[c], 0.25 * stvk[c] + 0.75 * hooke[c], 1e-9 * std::abs(hooke[0])) << c;
}

// --- The compliance ---------------------------------------------------------------

/// s : e(s) with the engineering compliance of kYoung and kPoisson (plane strain in 2D).
double engineering_energy(const std::vector<double>& d, int dim) {
  const double E = kYoung, nu = kPoisson;
  if (dim == 2) {  // e_xx = (1+nu)/E ((1-nu) s_xx - nu s_yy), gamma_xy = 2 (1+nu)/E s_xy
    const double exx = (1 + nu) / E * ((1 - nu) * d[0] - nu * d[1]);
    const double eyy = (1 + nu) / E * ((1 - nu) * d[1] - nu * d[0]);
    return d[0] * exx + d[1] * eyy + d[2] * 2 * (1 + nu) / E * d[2];
  }
  double energy = 0;  // e_ii = (s_ii - nu (s_jj + s_kk)) / E, gamma_ij = 2 (1+nu)/E s_ij
  for (int i = 0; i < 3; ++i) energy += d[i] * (d[i] - nu * (d[(i + 1) % 3] + d[(i + 2) % 3])) / E;
  for (int c = 3; c < 6; ++c) energy += d[c] * 2 * (1 + nu) / E * d[c];
  return energy;
}

/// One cell: s* is the cell average everywhere, so R_ZZ^2 is the integral
/// of (s_bar - s_h) : eps(s_bar - s_h), here with the compliance written
/// with Young's modulus and Poisson's ratio (plane strain in 2D).
void expect_single_cell_value(int dim, const std::string& cut) {
  const Mesh mesh = test::beam(dim, cut, {1, 1, 1});
  ASSERT_EQ(mesh.cell_count(), 1);
  const Model model(mesh, material_spec());
  const std::vector<double> u = nodal_field(mesh, [](const double* x) {
    return std::array<double, 3>{1e-3 * x[0] * x[1] + 2e-3 * x[1] * x[2], -0.5e-3 * x[0] * x[0] + 1e-3 * x[0] * x[2],
                                 0.7e-3 * x[0] * x[1]};
  });
  const std::vector<double> indicator = zz_indicator(model, u);
  const tm_kernel& kernel = model.kernel(0);
  std::vector<double> local(static_cast<std::size_t>(kernel.dofs));
  model.gather(0, u, local.data());
  std::vector<double> P(static_cast<std::size_t>(kernel.quadrature_points * dim * dim));
  kernel.stress(local.data(), model.consts(0), P.data());
  const int stride = 1 + dim * kernel.nodes;
  const int components = zz_stress_components(dim);
  std::vector<double> average(static_cast<std::size_t>(components), 0.0);
  double volume = 0;
  for (int q = 0; q < kernel.quadrature_points; ++q) {
    const double w = model.consts(0)[kernel.derived_params + q * stride];
    const std::vector<double> s = symmetric(&P[static_cast<std::size_t>(q * dim * dim)], dim);
    for (int c = 0; c < components; ++c) average[c] += w * s[c];
    volume += w;
  }
  EXPECT_NEAR(volume, 1.0, 1e-12);
  for (double& s : average) s /= volume;
  double expected = 0;
  for (int q = 0; q < kernel.quadrature_points; ++q) {
    const double w = model.consts(0)[kernel.derived_params + q * stride];
    const std::vector<double> s_h = symmetric(&P[static_cast<std::size_t>(q * dim * dim)], dim);
    std::vector<double> d(static_cast<std::size_t>(components));
    for (int c = 0; c < components; ++c) d[c] = average[c] - s_h[c];
    expected += w * engineering_energy(d, dim);
  }
  ASSERT_GT(expected, 0.0);
  EXPECT_NEAR(indicator[0], std::sqrt(expected), 1e-10 * std::sqrt(expected)) << cut;
}

TEST(ZzIndicator, SingleCellMatchesTheEngineeringCompliance) {
  expect_single_cell_value(2, "quad4");
  expect_single_cell_value(3, "hex8");
}

/// R_ZZ and the nodal stresses written out plainly from their definition
/// (zz_indicator.hpp), for comparison.
struct Reference {
  std::vector<double> indicator, nodal_stress;
};

Reference reference_zz(const Model& model, const std::vector<double>& u) {
  const Mesh& mesh = model.mesh();
  const int dim = mesh.dim, components = zz_stress_components(dim);
  std::vector<std::vector<std::vector<double>>> point_stress(static_cast<std::size_t>(model.cell_count()));
  std::vector<std::vector<double>> point_weight(static_cast<std::size_t>(model.cell_count()));
  std::vector<double> nodal(static_cast<std::size_t>(mesh.node_count() * components), 0.0);
  std::vector<double> nodal_volume(static_cast<std::size_t>(mesh.node_count()), 0.0);
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const tm_kernel& kernel = model.kernel(cell);
    std::vector<double> local(static_cast<std::size_t>(kernel.dofs));
    model.gather(cell, u, local.data());
    std::vector<double> P(static_cast<std::size_t>(kernel.quadrature_points * dim * dim));
    kernel.stress(local.data(), model.consts(cell), P.data());
    std::vector<double> average(static_cast<std::size_t>(components), 0.0);
    double volume = 0;
    for (int q = 0; q < kernel.quadrature_points; ++q) {
      const double w = model.consts(cell)[kernel.derived_params + q * (1 + dim * kernel.nodes)];
      point_stress[cell].push_back(symmetric(&P[static_cast<std::size_t>(q * dim * dim)], dim));
      point_weight[cell].push_back(w);
      for (int c = 0; c < components; ++c) average[c] += w * point_stress[cell].back()[c];
      volume += w;
    }
    for (double& value : average) value /= volume;
    for (int node : model.cell_nodes(cell)) {
      for (int c = 0; c < components; ++c)
        nodal[static_cast<std::size_t>(node * components + c)] += volume * average[c];
      nodal_volume[static_cast<std::size_t>(node)] += volume;
    }
  }
  for (int node = 0; node < mesh.node_count(); ++node)
    for (int c = 0; c < components; ++c) nodal[static_cast<std::size_t>(node * components + c)] /= nodal_volume[node];
  Reference reference{{}, nodal};
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const tm_element_info& element = *mesh.blocks[mesh.locate(cell).first].element;
    const auto nodes = model.cell_nodes(cell);
    double sum = 0;
    for (int q = 0; q < element.quadrature_points; ++q) {
      std::vector<double> d(static_cast<std::size_t>(components), 0.0);
      for (std::size_t j = 0; j < nodes.size(); ++j)
        for (int c = 0; c < components; ++c)
          d[c] += element.shape_values[q * element.nodes + static_cast<int>(j)] *
                  nodal[static_cast<std::size_t>(nodes[j] * components + c)];
      for (int c = 0; c < components; ++c) d[c] -= point_stress[cell][q][c];
      sum += point_weight[cell][q] * engineering_energy(d, dim);
    }
    reference.indicator.push_back(std::sqrt(sum));
  }
  return reference;
}

void expect_matches_reference(const Mesh& mesh, const Field& field, const std::string& where) {
  const Model model(mesh, material_spec());
  const std::vector<double> u = nodal_field(mesh, field);
  ZzIndicator zz;
  std::vector<double> indicator(static_cast<std::size_t>(model.cell_count()));
  zz.compute(model, u, indicator);
  const Reference reference = reference_zz(model, u);
  const double largest = *std::max_element(reference.indicator.begin(), reference.indicator.end());
  ASSERT_GT(largest, 0.0) << where;
  for (int cell = 0; cell < model.cell_count(); ++cell)
    EXPECT_NEAR(indicator[cell], reference.indicator[cell], 1e-10 * largest) << where << ": cell " << cell;
  double stress_size = 0;
  for (double s : reference.nodal_stress) stress_size = std::max(stress_size, std::abs(s));
  for (std::size_t k = 0; k < reference.nodal_stress.size(); ++k)
    ASSERT_NEAR(zz.nodal_stress()[k], reference.nodal_stress[k], 1e-12 * stress_size) << where << ": value " << k;
}

TEST(ZzIndicator, MatchesItsDefinitionOnEveryElementTypeAndARefinedMesh) {
  // A quadratic field in x, y, z: stress gradients along every axis.
  const Field field = [](const double* x) {
    return std::array<double, 3>{1e-3 * x[0] * x[1] + 2e-3 * x[1] * x[2], -0.5e-3 * x[0] * x[0] + 1e-3 * x[2] * x[2],
                                 0.7e-3 * x[0] * x[1] - 0.4e-3 * x[2] * x[0]};
  };
  for (const NamedMesh& named : every_element_meshes()) expect_matches_reference(named.mesh, field, named.name);
  // Leaves of two levels and transition triangles: cells of different
  // sizes around a node, where the volume weights matter.
  Mesh beam = refinement_test::mixed_beam(6, 3);
  distort(beam, {6.0, 3.0, 1.0}, 0.12, 11);
  HierarchicalMesh hierarchy(std::move(beam));
  hierarchy.refine(std::vector<int>{4, 12, 20});
  expect_matches_reference(hierarchy.leaf_mesh(), field, "refined leaf mesh");
}

// --- Stress gradients: positive, and smaller on finer meshes ----------------------

TEST(ZzIndicator, BendingIndicatorDecreasesUnderUniformRefinementOfTheHierarchy) {
  // The 2D mixed beam and its leaf meshes refined once and twice everywhere.
  HierarchicalMesh hierarchy(refinement_test::mixed_beam(6, 3));
  std::vector<double> sums;
  for (int level = 0; level < 3; ++level) {
    if (level > 0) hierarchy.refine(refinement_test::all_cells(hierarchy.leaf_mesh()));
    const Mesh& mesh = hierarchy.leaf_mesh();
    const Model model(mesh, material_spec());
    const std::vector<double> u = nodal_field(mesh, bending_field);
    const std::vector<double> indicator = zz_indicator(model, u);
    for (int cell = 0; cell < model.cell_count(); ++cell)
      EXPECT_GT(indicator[static_cast<std::size_t>(cell)], 0.0) << "level " << level << " cell " << cell;
    sums.push_back(sum_of_squares(indicator));
  }
  std::printf("2D hierarchy, sum R_ZZ^2: %.4g %.4g %.4g (ratios %.3f %.3f)\n", sums[0], sums[1], sums[2],
              sums[1] / sums[0], sums[2] / sums[1]);
  EXPECT_LT(sums[1] / sums[0], 0.35);
  EXPECT_LT(sums[2] / sums[1], 0.35);
  EXPECT_GT(sums[2] / sums[1], 0.1) << "the first-order rate is h^2, not faster";
}

struct RefinementCase {
  std::string name;
  int dim;
  std::vector<BeamPhase> phases;
  int order;
  double max_ratio;
};

// Halving h: sum R_ZZ^2 goes as h^2 for first-order cells (ratio about
// 0.21 measured; below 0.35 asked) and about h^3 for second-order ones
// (the element stress is exact for this field, the recovery errs near the
// boundary: ratio about 0.13; below 0.2 asked).
TEST(ZzIndicator, BendingIndicatorDecreasesUnderUniformRefinementOfBeams) {
  const std::vector<RefinementCase> cases = {
      {"2D tri3+quad4", 2, {{"tri3", 0.5}, {"quad4", 0.5}}, 1, 0.35},
      {"2D tri6+quad8", 2, {{"tri3", 0.5}, {"quad4", 0.5}}, 2, 0.2},
      {"3D hex8+tet4+prism6+pyramid5",
       3,
       {{"hex8", 0.25}, {"tet5", 0.25}, {"prism6", 0.25}, {"pyramid5", 0.25}},
       1,
       0.35},
      {"3D tet10", 3, {{"tet6", 1.0}}, 2, 0.2},
      {"3D hex20", 3, {{"hex8", 1.0}}, 2, 0.2},
  };
  for (const RefinementCase& c : cases) {
    double sums[2];
    for (int fine = 0; fine < 2; ++fine) {
      const int n = fine ? 2 : 1;
      const Mesh mesh = mixed_beam(c.dim, c.phases, {8 * n, 2 * n, 2 * n}, {4.0, 1.0, 1.0}, c.order);
      const Model model(mesh, material_spec());
      const std::vector<double> u = nodal_field(mesh, bending_field);
      const std::vector<double> indicator = zz_indicator(model, u);
      double smallest = std::numeric_limits<double>::infinity();
      for (double value : indicator) smallest = std::min(smallest, value);
      EXPECT_GT(smallest, 0.0) << c.name;
      sums[fine] = sum_of_squares(indicator);
    }
    std::printf("%s: sum R_ZZ^2 %.4g -> %.4g, ratio %.3f\n", c.name.c_str(), sums[0], sums[1], sums[1] / sums[0]);
    EXPECT_LT(sums[1] / sums[0], c.max_ratio) << c.name;
  }
}

// --- A localised field selects the cells near it -------------------------------

TEST(ZzIndicator, LocalisedFieldSelectsCellsNearTheCornerAndRefiningThemLowersTheLargest) {
  // A 6 x 3 plate of 24 x 12 squares (triangles for x < 3, quads beyond),
  // a displacement bump of width 0.4 at each of two corners in turn.
  for (const std::array<double, 3> corner : {std::array<double, 3>{6.0, 0.0, 0.0}, {0.0, 3.0, 0.0}}) {
    const Field bump = [corner](const double* x) {
      const double r2 = (x[0] - corner[0]) * (x[0] - corner[0]) + (x[1] - corner[1]) * (x[1] - corner[1]);
      const double g = 1e-3 * std::exp(-r2 / (0.4 * 0.4));
      return std::array<double, 3>{g, 0.5 * g, 0.0};
    };
    const auto distance = [corner](const std::array<double, 3>& c) {
      return std::hypot(c[0] - corner[0], c[1] - corner[1]);
    };
    HierarchicalMesh hierarchy(refinement_test::mixed_beam(24, 12));
    const Mesh& mesh = hierarchy.leaf_mesh();
    double largest_before = 0;
    std::vector<int> selected;
    {
      const Model model(mesh, material_spec());
      const std::vector<double> indicator = zz_indicator(model, nodal_field(mesh, bump));
      selected = select_cells_at_threshold(indicator, 0.5);
      ASSERT_FALSE(selected.empty());
      EXPECT_LT(selected.size(), 40u) << "a localised field selects few of the 864 cells";
      for (int cell : selected) EXPECT_LT(distance(centroid(mesh, cell)), 1.0) << "selected cell " << cell;
      largest_before = *std::max_element(indicator.begin(), indicator.end());
      // Far from the bump the indicator is negligible.
      for (int cell = 0; cell < mesh.cell_count(); ++cell) {
        if (distance(centroid(mesh, cell)) > 2.5) {
          EXPECT_LT(indicator[static_cast<std::size_t>(cell)], 1e-3 * largest_before) << "far cell " << cell;
        }
      }
    }
    hierarchy.refine(selected);
    const Model model(mesh, material_spec());
    const std::vector<double> indicator = zz_indicator(model, nodal_field(mesh, bump));
    for (int cell = 0; cell < mesh.cell_count(); ++cell) {
      if (hierarchy.leaf_levels()[static_cast<std::size_t>(cell)] > 0) {
        EXPECT_LT(distance(centroid(mesh, cell)), 1.25) << "refined cell " << cell;
      }
    }
    const double largest_after = *std::max_element(indicator.begin(), indicator.end());
    std::printf("corner (%g, %g): %zu cells selected, largest R_ZZ %.4g -> %.4g\n", corner[0], corner[1],
                selected.size(), largest_before, largest_after);
    EXPECT_LT(largest_after, 0.8 * largest_before);
  }
}

// --- Selection and errors -------------------------------------------------------------

TEST(ZzIndicator, ThresholdSelectsCellsAtLeastThatFractionOfTheLargest) {
  const std::vector<double> indicator{1.0, 4.0, 2.0, 3.0, 0.0, 4.0};
  EXPECT_EQ(select_cells_at_threshold(indicator, 0.5), (std::vector<int>{1, 2, 3, 5}));
  EXPECT_EQ(select_cells_at_threshold(indicator, 1.0), (std::vector<int>{1, 5}));
  EXPECT_EQ(select_cells_at_threshold(indicator, 0.0), (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(select_cells_at_threshold(indicator, 0.75), (std::vector<int>{1, 3, 5}));
  const std::vector<double> zero(5, 0.0);
  EXPECT_TRUE(select_cells_at_threshold(zero, 0.5).empty());
  EXPECT_TRUE(select_cells_at_threshold(zero, 0.0).empty());
  EXPECT_TRUE(select_cells_at_threshold(std::vector<double>{}, 0.5).empty());
}

TEST(ZzIndicator, BadThresholdOrIndicatorIsAClearError) {
  const std::vector<double> indicator{1.0, 2.0};
  for (double threshold : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    try {
      select_cells_at_threshold(indicator, threshold);
      FAIL() << "threshold " << threshold << " accepted";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find("outside [0, 1]"), std::string::npos) << error.what();
    }
  }
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), -1.0}) {
    try {
      select_cells_at_threshold(std::vector<double>{1.0, bad, 2.0}, 0.5);
      FAIL() << "indicator " << bad << " accepted";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find("cell 1"), std::string::npos) << error.what();
    }
  }
}

TEST(ZzIndicator, WrongSizesAreInputErrorsAndANonFiniteFieldGivesANonFiniteIndicator) {
  const Mesh mesh = refinement_test::mixed_beam(6, 3);
  const Model model(mesh, material_spec());
  std::vector<double> u = nodal_field(mesh, bending_field);
  std::vector<double> indicator(static_cast<std::size_t>(model.cell_count()));
  ZzIndicator zz;
  EXPECT_THROW(zz.compute(model, std::span<const double>(u).first(u.size() - 1), indicator), InputError);
  EXPECT_THROW(zz.compute(model, u, std::span<double>(indicator).first(indicator.size() - 1)), InputError);
  u[0] = std::numeric_limits<double>::quiet_NaN();
  zz.compute(model, u, indicator);
  int around_node_0 = 0;
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const auto nodes = model.cell_nodes(cell);
    if (std::find(nodes.begin(), nodes.end(), 0) == nodes.end()) continue;
    EXPECT_TRUE(std::isnan(indicator[static_cast<std::size_t>(cell)])) << "cell " << cell;
    ++around_node_0;
  }
  EXPECT_GT(around_node_0, 0);
  EXPECT_THROW(select_cells_at_threshold(indicator, 0.5), InputError);
}

// --- Cost -------------------------------------------------------------------------------

TEST(ZzIndicator, ReusedIndicatorAllocatesNothing) {
  const Mesh mesh = mixed_beam(3, {{"hex8", 0.5}, {"tet5", 0.5}}, {8, 4, 4}, {2.0, 1.0, 1.0}, 1);
  const Model model(mesh, material_spec());
  const std::vector<double> u = nodal_field(mesh, bending_field);
  std::vector<double> indicator(static_cast<std::size_t>(model.cell_count()));
  ZzIndicator zz;
  zz.compute(model, u, indicator);
  const long before = test_support::allocation_count.load();
  zz.compute(model, u, indicator);
  EXPECT_EQ(test_support::allocation_count.load() - before, 0);
  // For the record (no bound: the machine is shared): R_ZZ against one
  // energy pass over the same cells.
  const auto start = std::chrono::steady_clock::now();
  for (int repeat = 0; repeat < 20; ++repeat) zz.compute(model, u, indicator);
  const auto middle = std::chrono::steady_clock::now();
  double energy = 0;
  for (int repeat = 0; repeat < 20; ++repeat) energy += model.strain_energy(u);
  const auto end = std::chrono::steady_clock::now();
  const double zz_time = std::chrono::duration<double>(middle - start).count() / 20;
  const double energy_time = std::chrono::duration<double>(end - middle).count() / 20;
  std::printf("R_ZZ on %d cells: %.3g us per cell, %.2fx one energy pass (%g)\n", model.cell_count(),
              1e6 * zz_time / model.cell_count(), zz_time / energy_time, energy);
}

}  // namespace
}  // namespace tensormass
