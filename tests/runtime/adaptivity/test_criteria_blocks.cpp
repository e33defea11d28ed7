// Criterion::evaluate_block (the per-block loops compiled for each element
// shape) gives the same values as evaluate() cell by cell, for every
// criterion on meshes holding every element type of the registry, serially
// and inside a parallel region.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "support/cantilever.hpp"
#include "tensormass/adaptivity/criteria.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

/// The registry elements `tensormass beam` makes on its own (order 2: the
/// quadratic elements with a cut's corners, e.g. quad9, hex27, prism15,
/// pyramid13), each as a small beam.
std::vector<Mesh> beams_of_each_element() {
  std::vector<Mesh> out;
  for (const tm_element_info* element : Registry::instance().elements()) {
    if (element->order != 2) continue;
    try {
      out.push_back(test::beam(element->dim, element->name, {3, 2, 2}, 2));
    } catch (const InputError&) {  // not a type the beam generator makes
    }
  }
  return out;
}

/// Beams of every element type: mixed first-order 3D (hex8, tet4, prism6,
/// pyramid5 between them), second order (tet10, hex20), 2D, and one beam
/// per quadratic element the beam generator makes.
std::vector<Mesh> meshes() {
  std::vector<Mesh> out;
  BeamSpec mixed;
  mixed.dim = 3;
  mixed.cells = {9, 3, 3};
  mixed.size = {3.0, 1.0, 1.0};
  mixed.phases = {{"hex8", 0.34}, {"tet6", 0.33}, {"prism6", 0.33}};
  out.push_back(make_beam(mixed));
  out.push_back(test::beam(3, "tet6", {3, 2, 2}, 2));
  out.push_back(test::beam(3, "hex8", {3, 2, 2}, 2));
  BeamSpec plane;
  plane.dim = 2;
  plane.cells = {8, 3, 1};
  plane.size = {3.0, 1.0, 1.0};
  plane.phases = {{"tri3", 0.5}, {"quad4", 0.5}};
  out.push_back(make_beam(plane));
  out.push_back(test::beam(2, "quad4", {4, 2, 1}, 2));
  out.push_back(test::beam(2, "tri3", {4, 2, 1}, 2));
  for (Mesh& mesh : beams_of_each_element()) out.push_back(std::move(mesh));
  return out;
}

TEST(CriteriaBlocks, EqualEvaluateCellByCellOnEveryElementType) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> small(-0.05, 0.05);
  std::set<std::string> covered;
  for (const Mesh& mesh : meshes()) {
    for (const ElementBlock& block : mesh.blocks) covered.insert(block.element->name);
    ModelSpec spec;
    MaterialSpec material;
    material.law = "stvk";
    material.constants = elastic_constants(1e6, 0.3);
    material.density = 1000;
    spec.materials = {material};
    const Model model(mesh, spec);
    const Assembler assembler(model);
    std::vector<double> u(model.dof_count()), forces(model.dof_count());
    for (double& x : u) x = small(random);
    assembler.assemble(u, forces, nullptr);
    for (const std::string& name : criterion_names()) {
      const auto criterion = make_criterion(name);
      std::vector<double> serial(model.cell_count(), -1.0), parallel(model.cell_count(), -1.0);
      for (const ElementBlock& block : mesh.blocks) criterion->evaluate_block({model, block, u, forces}, serial);
#pragma omp parallel num_threads(2)
      for (const ElementBlock& block : mesh.blocks) criterion->evaluate_block({model, block, u, forces}, parallel);
      const int d = model.dim();
      std::vector<double> rest(81), local_u(81), local_force(81);
      for (const ElementBlock& block : mesh.blocks)
        for (int local = 0; local < block.count(); ++local) {
          const int cell = block.first_cell + local;
          const auto nodes = model.cell_nodes(cell);
          for (std::size_t j = 0; j < nodes.size(); ++j)
            for (int a = 0; a < d; ++a) rest[j * d + a] = mesh.rest_positions[3 * nodes[j] + a];
          model.gather(cell, u, local_u.data());
          model.gather(cell, forces, local_force.data());
          const ElementView view{*block.element,
                                 model.kernel(cell),
                                 model.consts(cell),
                                 rest.data(),
                                 local_u.data(),
                                 local_force.data(),
                                 d,
                                 model.cell_modulus(cell)};
          const double expected = criterion->evaluate(view);
          const double tolerance = 1e-13 * std::max(1.0, std::abs(expected));
          ASSERT_NEAR(serial[cell], expected, tolerance) << name << " on " << mesh.describe_cell(cell);
          ASSERT_EQ(parallel[cell], serial[cell]) << name << " on " << mesh.describe_cell(cell);
        }
    }
  }
  // Every element type was checked, but those the beam generator cannot make.
  for (const tm_element_info* element : Registry::instance().elements())
    if (!covered.count(element->name))
      EXPECT_THROW(test::beam(element->dim, element->name, {3, 2, 2}, element->order), InputError)
          << element->name << " is made by the beam generator but was not checked";
}

}  // namespace
}  // namespace tensormass
