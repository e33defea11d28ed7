#include "tensormass/mesh/mesh_arrays.hpp"

#include <array>
#include <cmath>
#include <string_view>

#include "mesh/mesh_builder.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass {

namespace {

/// meshio's cell type names for our elements (VTK node order on both sides).
const detail::Shape* shape_named(std::string_view name) {
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 10> meshio_names{{
      {"triangle", "tri3"},
      {"triangle6", "tri6"},
      {"quad", "quad4"},
      {"quad8", "quad8"},
      {"tetra", "tet4"},
      {"tetra10", "tet10"},
      {"hexahedron", "hex8"},
      {"hexahedron20", "hex20"},
      {"wedge", "prism6"},
      {"pyramid", "pyramid5"},
  }};
  for (const auto& [meshio, ours] : meshio_names)
    if (name == meshio) return detail::find_shape(ours);
  const detail::Shape* shape = detail::find_shape(name);
  return shape && shape->element ? shape : nullptr;
}

std::string known_elements() {
  return "tri3 (triangle), tri6 (triangle6), quad4 (quad), quad8, tet4 (tetra), tet10 (tetra10), hex8 (hexahedron), "
         "hex20 (hexahedron20), prism6 (wedge), pyramid5 (pyramid)";
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
