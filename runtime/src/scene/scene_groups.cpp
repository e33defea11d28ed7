// check_groups: every region a scene names must be a group of the mesh.
#include <string>

#include "tensormass/common/errors.hpp"
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

}  // namespace

void check_groups(const Scene& scene, const Mesh& mesh) {
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    const MaterialSpec& m = scene.materials[i];
    if (m.region != "all") require_group(scene, mesh, m.region, m.line, indexed("materials", i, ".region"));
  }
  for (std::size_t i = 0; i < scene.fixed.size(); ++i) {
    const int line = i < scene.fixed_lines.size() ? scene.fixed_lines[i] : 0;
    require_group(scene, mesh, scene.fixed[i], line, indexed("fixed", i, ""));
  }
  for (std::size_t i = 0; i < scene.prescribed.size(); ++i) {
    const PrescribedSpec& p = scene.prescribed[i];
    require_group(scene, mesh, p.region, p.line, indexed("prescribed", i, ".region"));
  }
  for (std::size_t i = 0; i < scene.loads.nodal_forces.size(); ++i) {
    const NodalForceSpec& f = scene.loads.nodal_forces[i];
    require_group(scene, mesh, f.region, f.line, indexed("loads.nodal_forces", i, ".region"));
  }
  for (std::size_t i = 0; i < scene.loads.pressures.size(); ++i) {
    const PressureSpec& p = scene.loads.pressures[i];
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

}  // namespace tensormass
