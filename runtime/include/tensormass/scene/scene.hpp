/// \file scene.hpp
/// A simulation scene read from YAML (docs/scene.md lists every key): the
/// mesh file and the plain specifications the numerics take (ModelSpec,
/// SolverSettings, AdaptivitySettings, RefinementSettings, OutputSettings). This folder is the
/// only one that reads YAML and the one place input is validated:
/// `load_scene` checks keys, types, ranges and names without the mesh;
/// `validate_against_mesh` checks what needs the mesh (groups, materials
/// covering every cell, kernels, pressure facets, constraints). Errors are
/// InputError naming the file, line and key.
#ifndef TENSORMASS_SCENE_SCENE_HPP
#define TENSORMASS_SCENE_SCENE_HPP

#include <string>
#include <utility>
#include <vector>

#include "tensormass/adaptivity/adaptivity_settings.hpp"
#include "tensormass/integrators/solver_settings.hpp"
#include "tensormass/io/output_settings.hpp"
#include "tensormass/mesh/mesh.hpp"
#include "tensormass/model/model_spec.hpp"
#include "tensormass/refinement/refinement_settings.hpp"

namespace tensormass {

struct Scene {
  std::string path;  ///< the scene file
  std::string mesh;  ///< mesh path, resolved relative to the scene file
  ModelSpec model;   ///< model.source == path
  SolverSettings solver;
  AdaptivitySettings adaptivity;  ///< law switching (enabled: adaptivity.criteria given)
  RefinementSettings refinement;  ///< adaptivity.refine
  OutputSettings output;
};

/// Reads and validates a scene. `overrides` are "a.b=value" strings (value in
/// YAML syntax, list indices as numbers: materials.0.young=2e6) applied
/// before validation; an override of an unknown key is an error too.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

/// The same for a scene given as YAML text (Python's Simulation.from_arrays):
/// `name` stands for the file in messages, and relative paths (mesh,
/// output.directory) are taken relative to its folder.
Scene parse_scene(const std::string& text, const std::string& name, const std::vector<std::string>& overrides = {});

/// Checks the scene against its mesh; throws InputError naming the key, line
/// and what exists (the groups of the mesh, the kernels of the registry):
/// every region named is a group of the mesh ("all" for materials), every
/// cell has a material and a kernel for its law, element and split, pressure
/// groups have facets that are faces of cells, tracked groups have cells, a
/// static solve has a constraint, and not every dof is constrained.
void validate_against_mesh(const Scene& scene, const Mesh& mesh);

/// Every map of the scene and the keys the reader accepts in it, by path:
/// "" for the top level, "materials[]" for a material, "solver.linear", ...
/// A material's law constants are not listed: each law declares its own
/// (`tensormass kernels`, docs/laws.md). docs/scene.md documents every key
/// (ctest scene.SceneReference.*).
std::vector<std::pair<std::string, std::vector<std::string>>> scene_schema();

}  // namespace tensormass

#endif
