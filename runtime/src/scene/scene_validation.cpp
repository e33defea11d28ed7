// validate_against_mesh: what the scene asks of its mesh (the checks that
// need no mesh are in scene.cpp, made while reading).
#include <algorithm>
#include <span>
#include <string>
#include <vector>

#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/mesh/mesh_topology.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/refinement/split_patterns.hpp"
#include "tensormass/refinement/transition_patterns.hpp"
#include "tensormass/scene/scene.hpp"

namespace tensormass {

namespace {

std::string group_names(const Mesh& mesh) {
  if (mesh.groups.empty()) return "the mesh has no groups";
  std::string names;
  for (const Group& g : mesh.groups) names += (names.empty() ? "groups: " : ", ") + g.name;
  return names;
}

std::string mesh_name(const Mesh& mesh) { return mesh.source.empty() ? std::string("the mesh") : mesh.source; }

/// "scene.yaml:7: fixed[0]: " (no line when the value came from --set).
std::string place(const Scene& scene, int line, const std::string& key) {
  return scene.path + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + key + ": ";
}

const Group& require_group(const Scene& scene, const Mesh& mesh, const std::string& region, int line,
                           const std::string& key) {
  const Group* group = mesh.group(region);
  if (!group)
    throw InputError(place(scene, line, key) + "no group '" + region + "' in " + mesh_name(mesh) + " (" +
                     group_names(mesh) + ")");
  return *group;
}

std::string indexed(const std::string& list, std::size_t i, const std::string& field) {
  return list + "[" + std::to_string(i) + "]" + field;
}

void check_groups(const Scene& scene, const Mesh& mesh) {
  for (std::size_t i = 0; i < scene.model.materials.size(); ++i) {
    const MaterialSpec& m = scene.model.materials[i];
    if (m.region != "all") require_group(scene, mesh, m.region, m.line, indexed("materials", i, ".region"));
  }
  for (std::size_t i = 0; i < scene.model.fixed.size(); ++i) {
    const int line = i < scene.model.fixed_lines.size() ? scene.model.fixed_lines[i] : 0;
    require_group(scene, mesh, scene.model.fixed[i], line, indexed("fixed", i, ""));
  }
  for (std::size_t i = 0; i < scene.model.prescribed.size(); ++i) {
    const PrescribedSpec& p = scene.model.prescribed[i];
    require_group(scene, mesh, p.region, p.line, indexed("prescribed", i, ".region"));
    if (p.rotates && mesh.dim == 2 && (p.rotation.axis[0] != 0 || p.rotation.axis[1] != 0))
      throw InputError(place(scene, p.line, indexed("prescribed", i, ".rotation.axis")) +
                       "a 2D mesh turns in its plane, about z: give axis [0, 0, 1] or leave it out");
  }
  for (std::size_t i = 0; i < scene.model.loads.nodal_forces.size(); ++i) {
    const NodalForceSpec& f = scene.model.loads.nodal_forces[i];
    require_group(scene, mesh, f.region, f.line, indexed("loads.nodal_forces", i, ".region"));
  }
  for (std::size_t i = 0; i < scene.model.loads.pressures.size(); ++i) {
    const PressureSpec& p = scene.model.loads.pressures[i];
    const std::string key = indexed("loads.pressure", i, ".region");
    const Group& group = require_group(scene, mesh, p.region, p.line, key);
    if (group.facets.count() == 0)
      throw InputError(place(scene, p.line, key) + "group '" + p.region +
                       "' has no boundary facets (elements of dimension " + std::to_string(mesh.dim - 1) + ") in " +
                       mesh_name(mesh) + ", so no pressure can act on it");
  }
  for (std::size_t i = 0; i < scene.output.track.size(); ++i) {
    const int line = i < scene.output.track_lines.size() ? scene.output.track_lines[i] : 0;
    const std::string key = indexed("output.track", i, "");
    const Group& group = require_group(scene, mesh, scene.output.track[i], line, key);
    if (group.cells.empty())
      throw InputError(place(scene, line, key) + "group '" + group.name + "' has no cells (elements of dimension " +
                       std::to_string(mesh.dim) + ") in " + mesh_name(mesh) + ", so it has no centroid to track");
  }
}

/// Every cell has a material, and the registry a kernel for it.
void check_materials(const Scene& scene, const Mesh& mesh) {
  for (const ElementBlock& block : mesh.blocks) {
    std::vector<char> checked(scene.model.materials.size(), 0);  // kernel looked up for this block
    for (int local = 0; local < block.count(); ++local) {
      const int cell = block.first_cell + local;
      const int m = material_of_cell(scene.model, mesh, cell);
      if (m < 0)
        throw InputError(scene.path + ": no material region contains " + mesh.describe_cell(cell) +
                         " (add a material with region: all)");
      if (checked[m]) continue;
      checked[m] = 1;
      const MaterialSpec& material = scene.model.materials[m];
      if (!material_kernel(material, *block.element))
        throw InputError(place(scene, material.line, "materials[" + std::to_string(m) + "]") + "no kernel for law '" +
                         material.law + "', element '" + block.element->name + "', split '" +
                         material_split(material, *block.element) + "' (see `tensormass kernels`)");
    }
  }
}

/// Every law of the adaptivity ladder has a kernel for every element type of
/// the mesh, and for the transition cells refinement may add.
void check_ladder(const Scene& scene, const Mesh& mesh) {
  if (!scene.adaptivity.enabled) return;
  std::vector<std::string> elements;
  for (const ElementBlock& block : mesh.blocks) elements.push_back(block.element->name);
  if (scene.refinement.enabled)
    for (const char* name : transition_element_names(mesh.dim)) elements.emplace_back(name);
  for (const std::string& law : scene.adaptivity.ladder)
    for (std::size_t e = 0; e < elements.size(); ++e)
      if (!Registry::instance().find(law, elements[e], "whole"))
        throw InputError(place(scene, scene.adaptivity.ladder_line, "adaptivity.ladder") + "no kernel for law '" + law +
                         "' on element '" + elements[e] + "'" +
                         (e >= mesh.blocks.size() ? " (refinement adds " + elements[e] + " cells)" : std::string()) +
                         " (see `tensormass kernels`)");
}

/// Refinement runs on 2D meshes of quad4 and tri3 cells and 3D meshes of
/// hex8, tet4, prism6 and pyramid5 cells (hierarchical_mesh.hpp); every material has
/// a kernel for the transition cells too.
void check_refinement(const Scene& scene, const Mesh& mesh) {
  if (!scene.refinement.enabled) return;
  const std::string where = place(scene, scene.refinement.line, "adaptivity.refine");
  for (const ElementBlock& block : mesh.blocks) {
    const std::string name = block.element->name;
    if (!has_split_pattern(name))
      throw InputError(where +
                       "refinement supports quad4 and tri3 cells in 2D, hex8, tet4, prism6 and pyramid5 cells in 3D; " +
                       mesh_name(mesh) + " has " + name + " cells");
  }
  for (const char* name : transition_element_names(mesh.dim)) {
    const tm_element_info& element = *Registry::instance().element(name);
    for (std::size_t m = 0; m < scene.model.materials.size(); ++m) {
      const MaterialSpec& material = scene.model.materials[m];
      if (!material_kernel(material, element))
        throw InputError(place(scene, material.line, "materials[" + std::to_string(m) + "]") + "no kernel for law '" +
                         material.law + "', element '" + name + "', split '" + material_split(material, element) +
                         "', which refinement's transition cells need (see `tensormass kernels`)");
    }
  }
}

/// Every facet of a pressure group can carry a load and is a face of a cell.
void check_pressure_facets(const Scene& scene, const Mesh& mesh) {
  if (scene.model.loads.pressures.empty()) return;
  const std::vector<std::vector<int>> node_cells = cells_around_nodes(mesh);
  for (std::size_t i = 0; i < scene.model.loads.pressures.size(); ++i) {
    const PressureSpec& load = scene.model.loads.pressures[i];
    const FacetSet& facets = mesh.group(load.region)->facets;
    const std::string where =
        place(scene, load.line, indexed("loads.pressure", i, "")) + "pressure on group '" + load.region + "': facet ";
    for (int f = 0; f < facets.count(); ++f) {
      const int count = facets.offsets[f + 1] - facets.offsets[f];
      if (!is_load_facet(mesh.dim, count))
        throw InputError(where + "with " + std::to_string(count) + " nodes is not supported");
      const std::span<const int> nodes(facets.nodes.data() + facets.offsets[f], static_cast<std::size_t>(count));
      if (facet_owner(mesh, node_cells, nodes) < 0)
        throw InputError(where + std::to_string(f) + " is not a face of any element");
    }
  }
}

/// A static solve needs a constraint; some dof must stay free.
void check_constraints(const Scene& scene, const Mesh& mesh) {
  const int dim = mesh.dim;
  std::vector<char> constrained(static_cast<std::size_t>(mesh.node_count()) * dim, 0);
  for (const std::string& region : scene.model.fixed)
    for (int node : mesh.group(region)->nodes)
      for (int a = 0; a < dim; ++a) constrained[static_cast<std::size_t>(node) * dim + a] = 1;
  for (const PrescribedSpec& p : scene.model.prescribed)
    for (int node : mesh.group(p.region)->nodes)
      for (int a = 0; a < dim; ++a)
        if (p.components[a] || p.rotates) constrained[static_cast<std::size_t>(node) * dim + a] = 1;
  const std::size_t count = std::count(constrained.begin(), constrained.end(), 1);
  if (scene.solver.is_static() && count == 0)
    throw InputError(scene.path + ": a static solve needs fixed or prescribed nodes (key 'fixed' or 'prescribed')");
  if (count == constrained.size())
    throw InputError(scene.path + ": every degree of freedom is constrained; nothing to solve");
}

}  // namespace

void validate_against_mesh(const Scene& scene, const Mesh& mesh) {
  check_groups(scene, mesh);
  check_refinement(scene, mesh);
  check_materials(scene, mesh);
  check_ladder(scene, mesh);
  check_pressure_facets(scene, mesh);
  check_constraints(scene, mesh);
}

}  // namespace tensormass
