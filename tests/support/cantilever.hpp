/// \file cantilever.hpp
/// Beams and a clamped-beam scene built in code, for the model, assembly,
/// solver and adaptivity tests.
#ifndef TENSORMASS_TESTS_SUPPORT_CANTILEVER_HPP
#define TENSORMASS_TESTS_SUPPORT_CANTILEVER_HPP

#include <array>
#include <string>

#include "tensormass/meshing/beam.hpp"
#include "tensormass/scene/scene.hpp"

namespace tensormass::test {

/// A beam of cells[0] by cells[1] (by cells[2]) square cells one unit high, all of type `cut`.
inline Mesh beam(int dim, const std::string& cut, std::array<int, 3> cells, int order = 1) {
  BeamSpec spec;
  spec.dim = dim;
  spec.cells = cells;
  spec.size = {double(cells[0]) / cells[1], 1.0, double(cells[2]) / cells[1]};
  spec.phases = {{cut, 1.0}};
  spec.order = order;
  return make_beam(spec);
}

/// A clamped beam under gravity with one material on every cell.
inline Scene cantilever(const std::string& law, SolverType type = SolverType::static_newton) {
  Scene scene;
  scene.path = "test-scene.yaml";
  scene.mesh = "test-beam.msh";
  MaterialSpec material;
  material.law = law;
  material.constants = elastic_constants(1e6, 0.3);
  material.density = 1000;
  scene.model.materials = {material};
  scene.model.fixed = {"clamp"};
  scene.model.loads.gravity = {0, -9.81, 0};
  scene.solver.type = type;
  scene.solver.tolerance = 1e-10;
  return scene;
}

}  // namespace tensormass::test

#endif
