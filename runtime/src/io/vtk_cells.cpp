// VTK cells shared by the legacy and XML readers (io/vtk_cells.hpp): the
// VTK cell type names, their mapping to our shapes and node orders (from
// the element registry), and the Grid-to-Mesh step with its checks.
#include "io/vtk_cells.hpp"

#include <cmath>
#include <span>
#include <string>

#include "mesh/mesh_builder.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass::detail::vtk {

namespace {

struct VtkType {
  long id;
  const char* name;
};

constexpr VtkType kVtkTypes[] = {
    {1, "VTK_VERTEX"},
    {2, "VTK_POLY_VERTEX"},
    {3, "VTK_LINE"},
    {4, "VTK_POLY_LINE"},
    {5, "VTK_TRIANGLE"},
    {6, "VTK_TRIANGLE_STRIP"},
    {7, "VTK_POLYGON"},
    {8, "VTK_PIXEL"},
    {9, "VTK_QUAD"},
    {10, "VTK_TETRA"},
    {11, "VTK_VOXEL"},
    {12, "VTK_HEXAHEDRON"},
    {13, "VTK_WEDGE"},
    {14, "VTK_PYRAMID"},
    {15, "VTK_PENTAGONAL_PRISM"},
    {16, "VTK_HEXAGONAL_PRISM"},
    {21, "VTK_QUADRATIC_EDGE"},
    {22, "VTK_QUADRATIC_TRIANGLE"},
    {23, "VTK_QUADRATIC_QUAD"},
    {24, "VTK_QUADRATIC_TETRA"},
    {25, "VTK_QUADRATIC_HEXAHEDRON"},
    {26, "VTK_QUADRATIC_WEDGE"},
    {27, "VTK_QUADRATIC_PYRAMID"},
    {28, "VTK_BIQUADRATIC_QUAD"},
    {29, "VTK_TRIQUADRATIC_HEXAHEDRON"},
    {42, "VTK_POLYHEDRON"},
    {68, "VTK_LAGRANGE_CURVE"},
    {69, "VTK_LAGRANGE_TRIANGLE"},
    {70, "VTK_LAGRANGE_QUADRILATERAL"},
    {71, "VTK_LAGRANGE_TETRAHEDRON"},
    {72, "VTK_LAGRANGE_HEXAHEDRON"},
};

std::string vtk_type_name(long id) {
  for (const VtkType& type : kVtkTypes)
    if (type.id == id) return type.name;
  return "unknown";
}

/// Our shape of a VTK cell type and order[k] = our index of the k-th VTK node (nullptr: same).
struct Mapping {
  const Shape* shape = nullptr;
  const int* order = nullptr;
};

Mapping vtk_mapping(long id) {
  if (id == 1) return {find_shape("point"), nullptr};
  if (id == 3) return {find_shape("line2"), nullptr};
  if (id == 21) return {find_shape("line3"), nullptr};
  for (const tm_element_info* element : Registry::instance().elements())
    if (element->vtk_type == id) return {shape_of(element), element->vtk_order};
  return {};
}

std::string supported_list() {
  std::string text = "VTK_VERTEX (1), VTK_LINE (3), VTK_QUADRATIC_EDGE (21)";
  for (const tm_element_info* element : Registry::instance().elements())
    text += ", " + vtk_type_name(element->vtk_type) + " (" + std::to_string(element->vtk_type) + ")";
  return text;
}

}  // namespace

int region_priority(std::string_view name) {
  if (name == "gmsh:physical") return 0;
  if (name == "region") return 1;
  if (name == "group") return 2;
  return -1;
}

Mesh build_mesh(const InputCursor& in, const Grid& grid) {
  MeshBuilder builder(in.path(), "cell");
  const std::size_t point_count = grid.points.size() / 3;
  builder.reserve_nodes(point_count);
  for (std::size_t i = 0; i < point_count; ++i)
    builder.add_node(static_cast<long>(i), &grid.points[3 * i], grid.points_where);
  std::vector<long> ours;
  for (std::size_t c = 0; c + 1 < grid.offsets.size(); ++c) {
    const Mapping mapping = vtk_mapping(grid.types[c]);
    const std::string cell = "cell " + std::to_string(c);
    if (!mapping.shape)
      in.fail_at(grid.cell_where[c], cell + " has VTK type " + std::to_string(grid.types[c]) + " (" +
                                         vtk_type_name(grid.types[c]) +
                                         "), which is not supported; supported: " + supported_list());
    const long count = grid.offsets[c + 1] - grid.offsets[c];
    if (count != mapping.shape->nodes)
      in.fail_at(grid.cell_where[c], cell + " (" + vtk_type_name(grid.types[c]) + ") has " + std::to_string(count) +
                                         " nodes, expected " + std::to_string(mapping.shape->nodes));
    const auto first = grid.connectivity.begin() + grid.offsets[c];
    ours.assign(first, first + count);
    if (mapping.order)
      for (long k = 0; k < count; ++k) ours[static_cast<std::size_t>(mapping.order[k])] = first[k];
    const std::span<const long> groups =
        grid.regions.empty() ? std::span<const long>() : std::span<const long>(&grid.regions[c], 1);
    builder.add_element(*mapping.shape, static_cast<long>(c), ours, groups, grid.cell_where[c]);
  }
  return builder.build([](long key) { return GroupInfo{"region_" + std::to_string(key), -1}; });
}

void check_offsets(const InputCursor& in, const Grid& grid, Location where, std::size_t first_cell) {
  for (std::size_t c = first_cell; c + 1 < grid.offsets.size(); ++c)
    if (grid.offsets[c + 1] < grid.offsets[c] || grid.offsets[c + 1] > static_cast<long>(grid.connectivity.size()))
      in.fail_at(where,
                 "cell offsets are not increasing within the connectivity size (cell " + std::to_string(c) + ")");
  if (grid.offsets.back() != static_cast<long>(grid.connectivity.size()))
    in.fail_at(where, "the offsets end at " + std::to_string(grid.offsets.back()) + " but the connectivity has " +
                          std::to_string(grid.connectivity.size()) + " entries");
}

bool is_integer_value(double value) {
  return std::isfinite(value) && value == std::floor(value) && std::abs(value) < 9.0e15;
}

std::vector<long> to_integers(const InputCursor& in, const std::vector<double>& values, Location where,
                              std::string_view what) {
  std::vector<long> result(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!is_integer_value(values[i]))
      in.fail_at(where, std::string(what) + " value " + std::to_string(i) + " is not an integer");
    result[i] = static_cast<long>(values[i]);
  }
  return result;
}

}  // namespace tensormass::detail::vtk
