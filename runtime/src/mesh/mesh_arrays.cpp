#include "tensormass/mesh/mesh_arrays.hpp"

#include <array>
#include <cmath>
#include <string_view>

#include "mesh/mesh_builder.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass {

namespace {

/// meshio's cell type names by VTK type (meshio/_vtk_common.py,
/// vtk_to_meshio_type); meshio keeps VTK's node order, which is ours.
constexpr std::array<std::pair<int, std::string_view>, 19> kMeshioNames{{
    {5, "triangle"}, {9, "quad"},       {10, "tetra"},        {12, "hexahedron"},   {13, "wedge"},
    {14, "pyramid"}, {22, "triangle6"}, {23, "quad8"},        {24, "tetra10"},      {25, "hexahedron20"},
    {26, "wedge15"}, {27, "pyramid13"}, {28, "quad9"},        {29, "hexahedron27"}, {30, "quad6"},
    {31, "wedge12"}, {32, "wedge18"},   {33, "hexahedron24"}, {34, "triangle7"},
}};

std::string_view meshio_name(int vtk_type) {
  for (const auto& [type, name] : kMeshioNames)
    if (type == vtk_type) return name;
  return {};
}

/// The registry element a meshio cell type or one of our names denotes.
const detail::Shape* shape_named(std::string_view name) {
  for (const tm_element_info* element : Registry::instance().elements())
    if (name == meshio_name(element->vtk_type)) return detail::shape_of(element);
  const detail::Shape* shape = detail::find_shape(name);
  return shape && shape->element ? shape : nullptr;
}

std::string known_elements() {
  std::string text;
  for (const tm_element_info* element : Registry::instance().elements()) {
    text += (text.empty() ? "" : ", ") + std::string(element->name);
    const std::string_view meshio = meshio_name(element->vtk_type);
    if (!meshio.empty() && meshio != element->name) text += " (" + std::string(meshio) + ")";
  }
  return text;
}

/// Group keys per element: point groups first, then cell groups.
struct GroupKeys {
  std::vector<std::vector<long>> of_point, of_cell;
};

GroupKeys group_keys(const MeshArrays& arrays, long points, long cells, const std::string& source) {
  GroupKeys keys{std::vector<std::vector<long>>(points), std::vector<std::vector<long>>(cells)};
  long key = 0;  // point groups first, then cell groups
  auto add = [&](const auto& groups, std::vector<std::vector<long>>& of, const char* kind, const char* member) {
    for (const auto& [name, members] : groups) {
      for (long m : members) {
        if (m < 0 || m >= static_cast<long>(of.size()))
          throw InputError(source + ": " + kind + " group '" + name + "' holds " + member + " " + std::to_string(m) +
                           ", not in 0.." + std::to_string(static_cast<long>(of.size()) - 1));
        of[m].push_back(key);
      }
      ++key;
    }
  };
  add(arrays.point_groups, keys.of_point, "point", "point");
  add(arrays.cell_groups, keys.of_cell, "cell", "cell");
  return keys;
}

}  // namespace

Mesh mesh_from_arrays(const MeshArrays& arrays, const std::string& source) {
  if (arrays.points.size() % 3 != 0) throw InputError(source + ": points must hold 3 coordinates each");
  const long points = static_cast<long>(arrays.points.size() / 3);
  long cells = 0;
  std::vector<const detail::Shape*> shapes;
  for (const CellArray& block : arrays.cells) {
    const detail::Shape* shape = shape_named(block.element);
    if (!shape)
      throw InputError(source + ": unknown element '" + block.element + "' (known: " + known_elements() + ")");
    if (block.nodes.size() % static_cast<std::size_t>(shape->nodes) != 0)
      throw InputError(source + ": the " + block.element + " cells need " + std::to_string(shape->nodes) +
                       " points each, got " + std::to_string(block.nodes.size()) + " indices");
    shapes.push_back(shape);
    cells += static_cast<long>(block.nodes.size()) / shape->nodes;
  }
  const GroupKeys keys = group_keys(arrays, points, cells, source);
  detail::MeshBuilder builder(source, "cell");
  builder.reserve_nodes(static_cast<std::size_t>(points));
  for (long p = 0; p < points; ++p) builder.add_node(p, &arrays.points[3 * static_cast<std::size_t>(p)], {p});
  long cell = 0;
  for (std::size_t b = 0; b < arrays.cells.size(); ++b) {
    const std::vector<long>& nodes = arrays.cells[b].nodes;
    const int per_cell = shapes[b]->nodes;
    for (std::size_t first = 0; first < nodes.size(); first += per_cell, ++cell) {
      for (int k = 0; k < per_cell; ++k)
        if (nodes[first + k] < 0 || nodes[first + k] >= points)
          throw InputError(source + ": " + arrays.cells[b].element + " cell " + std::to_string(first / per_cell) +
                           " uses point " + std::to_string(nodes[first + k]) + ", not in 0.." +
                           std::to_string(points - 1));
      builder.add_element(*shapes[b], cell, {nodes.data() + first, static_cast<std::size_t>(per_cell)},
                          keys.of_cell[cell], {cell});
    }
  }
  // A point group's points join it as point elements.
  const detail::Shape& point_shape = *detail::find_shape("point");
  for (long p = 0; p < points; ++p)
    if (!keys.of_point[p].empty()) builder.add_element(point_shape, cells + p, {&p, 1}, keys.of_point[p], {p});
  Mesh mesh = builder.build([&](long key) {
    const std::size_t k = static_cast<std::size_t>(key);
    if (k < arrays.point_groups.size()) return detail::GroupInfo{arrays.point_groups[k].first, 0};
    return detail::GroupInfo{arrays.cell_groups[k - arrays.point_groups.size()].first, -1};
  });
  if (mesh.node_count() != points)
    throw InputError(source + ": " + std::to_string(points - mesh.node_count()) + " of the " + std::to_string(points) +
                     " points belong to no cell; every point must (the results are numbered like the points)");
  return mesh;
}

}  // namespace tensormass
