// HierarchicalMesh on 3D blocks of hex8, prism6, tet4 and pyramid5 cells:
// children that fill their parent, conformity (every interior face shared by two
// cells with the same nodes), 2:1 balance and volume after random
// refinements and coarsenings, bitwise restoration, linear fields carried
// exactly, groups and facets, bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "refinement_checks.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"

namespace {

using refinement_test::all_cells;
using refinement_test::expect_same_mesh;
using refinement_test::position;
using tensormass::HierarchicalMesh;
using tensormass::Mesh;

constexpr double kLength = 4.0, kHeight = 2.0, kWidth = 2.0;

/// A 4 x 2 x 2 block of unit cubes cut by `phases` (beam.hpp), with the node
/// group "bottom" (y = 0) besides the beam's groups.
Mesh block(std::vector<tensormass::BeamPhase> phases, std::array<int, 3> cells = {4, 2, 2}) {
  tensormass::BeamSpec spec;
  spec.dim = 3;
  spec.cells = cells;
  spec.size = {kLength, kHeight, kWidth};
  spec.phases = std::move(phases);
  Mesh mesh = tensormass::make_beam(spec);
  mesh.add_node_group("bottom", [](double, double y, double) { return y == 0.0; });
  return mesh;
}

Mesh hex_prism_block() { return block({{"hex8", 0.5}, {"prism6", 0.5}}); }
Mesh tet_block() { return block({{"tet6", 1.0}}); }
Mesh tet5_block() { return block({{"tet5", 1.0}}); }
Mesh pyramid_block() { return block({{"pyramid5", 1.0}}); }

std::array<double, 3> point(const Mesh& mesh, int node) {
  const double* p = position(mesh, node);
  return {p[0], p[1], p[2]};
}

/// Six times the signed volume of the tet (a, b, c, d).
double six_volume(const std::array<double, 3>& a, const std::array<double, 3>& b, const std::array<double, 3>& c,
                  const std::array<double, 3>& d) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

/// A cell's volume as tets from its mean point to the fans of its faces
/// around their mean points; `smallest` gets the smallest such tet (a
/// twisted or inverted cell has a non-positive one).
double cell_volume(const Mesh& mesh, int cell, double* smallest = nullptr) {
  const auto [b, local] = mesh.locate(cell);
  const tm_element_info& element = *mesh.blocks[b].element;
  const auto nodes = mesh.blocks[b].cell_nodes(local);
  std::array<double, 3> centre{0, 0, 0};
  for (int node : nodes)
    for (int c = 0; c < 3; ++c) centre[c] += point(mesh, node)[c] / static_cast<double>(nodes.size());
  double volume = 0, least = 1e300;
  for (int f = 0; f < element.face_count; ++f) {
    const int size = element.face_sizes[f];
    const int* face = element.faces + element.face_offsets[f];
    std::array<double, 3> middle{0, 0, 0};
    for (int k = 0; k < size; ++k)
      for (int c = 0; c < 3; ++c) middle[c] += point(mesh, nodes[face[k]])[c] / size;
    for (int k = 0; k < size; ++k) {
      // The face runs counter-clockwise seen from outside: (middle, p, q) faces away from the centre.
      const double piece =
          -six_volume(middle, point(mesh, nodes[face[k]]), point(mesh, nodes[face[(k + 1) % size]]), centre) / 6;
      volume += piece;
      least = std::min(least, piece);
    }
  }
  if (smallest) *smallest = least;
  return volume;
}

double total_volume(const Mesh& mesh) {
  double volume = 0;
  for (int cell = 0; cell < mesh.cell_count(); ++cell) volume += cell_volume(mesh, cell);
  return volume;
}

/// Whether every node of a face lies on one side of the block.
bool on_block_surface(const Mesh& mesh, const std::vector<int>& face) {
  const std::array<double, 3> size{kLength, kHeight, kWidth};
  for (int axis = 0; axis < 3; ++axis)
    for (double side : {0.0, size[axis]})
      if (std::all_of(face.begin(), face.end(),
                      [&](int node) { return std::abs(point(mesh, node)[axis] - side) < 1e-12; }))
        return true;
  return false;
}

/// The leaf mesh conforms (no face used thrice, every face used once lies
/// on the block's surface: a hanging node inside would leave faces used
/// once there), every cell has a positive volume (also every piece of it),
/// the volume is the block's, and cells sharing a face differ by at most
/// one level.
void expect_valid_leaf_mesh_3d(const HierarchicalMesh& hierarchy, const std::string& where) {
  const Mesh& mesh = hierarchy.leaf_mesh();
  const tensormass::ConformityReport conformity = tensormass::check_conformity(mesh);
  EXPECT_EQ(conformity.overused_faces, 0) << where;
  for (const std::vector<int>& face : conformity.boundary_faces)
    ASSERT_TRUE(on_block_surface(mesh, face)) << where << ": a face used once inside the block (hanging node)";
  for (int cell = 0; cell < mesh.cell_count(); ++cell) {
    double smallest = 0;
    const double volume = cell_volume(mesh, cell, &smallest);
    ASSERT_GT(volume, 0.0) << where << " cell " << cell;
    ASSERT_GT(smallest, 0.0) << where << " cell " << cell << " is twisted";
  }
  EXPECT_NEAR(total_volume(mesh), kLength * kHeight * kWidth, 1e-15 * mesh.cell_count() + 1e-12) << where;
  std::map<std::vector<int>, std::vector<int>> faces;
  for (int cell = 0; cell < mesh.cell_count(); ++cell) {
    const auto [b, local] = mesh.locate(cell);
    const tm_element_info& element = *mesh.blocks[b].element;
    const auto nodes = mesh.blocks[b].cell_nodes(local);
    for (int f = 0; f < element.face_count; ++f) {
      std::vector<int> face;
      for (int k = 0; k < element.face_sizes[f]; ++k) face.push_back(nodes[element.faces[element.face_offsets[f] + k]]);
      std::sort(face.begin(), face.end());
      faces[face].push_back(cell);
    }
  }
  for (const auto& [face, cells] : faces) {
    if (cells.size() != 2) continue;
    ASSERT_LE(std::abs(hierarchy.leaf_levels()[cells[0]] - hierarchy.leaf_levels()[cells[1]]), 1)
        << where << ": 2:1 balance broken across a face of cells " << cells[0] << " and " << cells[1];
  }
}

int coarsen_all(HierarchicalMesh& hierarchy) {
  int calls = 0;
  for (int before = -1; before != hierarchy.hierarchy_size(); ++calls) {
    before = hierarchy.hierarchy_size();
    hierarchy.coarsen(all_cells(hierarchy.leaf_mesh()));
  }
  return calls;
}

class HierarchicalMesh3d : public testing::TestWithParam<const char*> {
 protected:
  Mesh original() const {
    const std::string name = GetParam();
    if (name == "hex8+prism6") return hex_prism_block();
    if (name == "tet6") return tet_block();
    if (name == "pyramid5") return pyramid_block();
    return tet5_block();
  }
};

TEST_P(HierarchicalMesh3d, EveryCellSplitsIntoChildrenThatFillIt) {
  // hex8, prism6, tet4: 8 children of an eighth of the volume; pyramid5: 6 pyramids and 4 tets.
  const Mesh mesh = original();
  const bool pyramids = std::string(GetParam()) == "pyramid5";
  const int children = pyramids ? 10 : 8;
  HierarchicalMesh hierarchy(mesh);
  expect_same_mesh(hierarchy.leaf_mesh(), mesh);
  hierarchy.refine(all_cells(hierarchy.leaf_mesh()));
  const Mesh& leaves = hierarchy.leaf_mesh();
  ASSERT_EQ(leaves.cell_count(), children * mesh.cell_count());
  std::vector<double> filled(static_cast<std::size_t>(mesh.cell_count()), 0.0);
  for (int cell = 0; cell < leaves.cell_count(); ++cell) {
    const int origin = hierarchy.hierarchy_cell(hierarchy.leaf_owners()[cell]).origin;
    filled[static_cast<std::size_t>(origin)] += cell_volume(leaves, cell);
    if (!pyramids) {
      EXPECT_NEAR(cell_volume(leaves, cell), cell_volume(mesh, origin) / 8, 1e-14) << "cell " << cell;
    }
    EXPECT_EQ(hierarchy.leaf_levels()[cell], 1);
    EXPECT_EQ(hierarchy.leaf_transitions()[cell], 0);
  }
  for (int cell = 0; cell < mesh.cell_count(); ++cell)
    EXPECT_NEAR(filled[static_cast<std::size_t>(cell)], cell_volume(mesh, cell), 1e-14) << "cell " << cell;
  for (int parent = 0; parent < mesh.cell_count(); ++parent) {
    const tensormass::HierarchyCell& cell = hierarchy.hierarchy_cell(parent);
    ASSERT_EQ(cell.child_count(), children);
    for (int k = 0; k < cell.corner_count(); ++k)  // some child holds the parent's corner k
      EXPECT_TRUE(std::any_of(cell.children.begin(), cell.children.begin() + cell.child_count(),
                              [&](int child) {
                                const auto& corners = hierarchy.hierarchy_cell(child).corners;
                                return std::find(corners.begin(), corners.end(), cell.corners[k]) != corners.end();
                              }))
          << "cell " << parent << " corner " << k;
  }
  expect_valid_leaf_mesh_3d(hierarchy, "all refined");
}

TEST_P(HierarchicalMesh3d, NeighboursOfARefinedCellGetConformingTransitionCells) {
  HierarchicalMesh hierarchy(original());
  hierarchy.refine(std::vector<int>{5});
  expect_valid_leaf_mesh_3d(hierarchy, "one cell refined");
  const auto transitions = hierarchy.leaf_transitions();
  EXPECT_GT(std::count(transitions.begin(), transitions.end(), 1), 0);
  const tensormass::Registry& registry = tensormass::Registry::instance();
  for (const tensormass::ElementBlock& leaf_block : hierarchy.leaf_mesh().blocks)
    for (int local = 0; local < leaf_block.count(); ++local) {
      if (!transitions[leaf_block.first_cell + local]) continue;
      EXPECT_TRUE(leaf_block.element == registry.element("tet4") || leaf_block.element == registry.element("pyramid5"))
          << leaf_block.element->name;
    }
  // One more level in the same place: balance spreads it.
  std::vector<int> level_one;
  for (int cell = 0; cell < hierarchy.leaf_mesh().cell_count(); ++cell)
    if (hierarchy.leaf_levels()[cell] == 1) level_one.push_back(cell);
  hierarchy.refine(std::vector<int>{level_one.front()});
  expect_valid_leaf_mesh_3d(hierarchy, "two levels");
  EXPECT_EQ(hierarchy.leaves_per_level().size(), 3u);
}

TEST_P(HierarchicalMesh3d, RandomRefinementsAndCoarseningsStayConformingAndComeBack) {
  const Mesh mesh = original();
  HierarchicalMesh hierarchy(mesh);
  std::mt19937 random(2026);
  int refined = 0, coarsened = 0;
  for (int step = 0; step < 12; ++step) {
    std::vector<int> marked;
    std::bernoulli_distribution pick(step % 3 == 2 ? 0.7 : 0.08);
    for (int cell = 0; cell < hierarchy.leaf_mesh().cell_count(); ++cell)
      if (pick(random)) marked.push_back(cell);
    const int before = hierarchy.hierarchy_size();
    if (step % 3 == 2) {
      hierarchy.coarsen(marked);
      coarsened += hierarchy.hierarchy_size() < before;
    } else {
      hierarchy.refine(marked, 3);
      refined += hierarchy.hierarchy_size() > before;
    }
    expect_valid_leaf_mesh_3d(hierarchy, "step " + std::to_string(step));
    if (testing::Test::HasFatalFailure() || testing::Test::HasFailure()) return;
  }
  EXPECT_GE(refined, 6);
  EXPECT_GE(coarsened, 2);
  EXPECT_GE(hierarchy.leaves_per_level().size(), 3u);
  coarsen_all(hierarchy);
  expect_same_mesh(hierarchy.leaf_mesh(), mesh);
  EXPECT_EQ(hierarchy.hierarchy_size(), mesh.cell_count());
}

TEST_P(HierarchicalMesh3d, LinearFieldsAreCarriedExactlyThroughRefinementAndCoarsening) {
  HierarchicalMesh hierarchy(original());
  const auto linear = [](const Mesh& mesh) {
    std::vector<double> field;
    for (int node = 0; node < mesh.node_count(); ++node) {
      const auto x = point(mesh, node);
      field.insert(field.end(), {0.1 + 0.3 * x[0] - 0.2 * x[1] + 0.05 * x[2], -0.4 * x[2] + 0.7 * x[0],
                                 0.25 * x[1] - 0.125 * x[0] + 1.0});
    }
    return field;
  };
  std::vector<double> field = linear(hierarchy.leaf_mesh());
  const std::vector<std::vector<int>> rounds{{3, 5}, {0, 1, 2, 40}, {7, 9, 11, 30, 31}};
  for (const std::vector<int>& marked : rounds) {
    std::vector<int> in_range;
    for (int cell : marked)
      if (cell < hierarchy.leaf_mesh().cell_count()) in_range.push_back(cell);
    field = tensormass::transfer_nodal_field(hierarchy.refine(in_range), field, 3);
    const std::vector<double> expected = linear(hierarchy.leaf_mesh());
    ASSERT_EQ(field.size(), expected.size());
    for (std::size_t i = 0; i < field.size(); ++i) ASSERT_NEAR(field[i], expected[i], 1e-13) << i;
  }
  field = tensormass::transfer_nodal_field(hierarchy.coarsen(all_cells(hierarchy.leaf_mesh())), field, 3);
  const std::vector<double> expected = linear(hierarchy.leaf_mesh());
  ASSERT_EQ(field.size(), expected.size());
  for (std::size_t i = 0; i < field.size(); ++i) EXPECT_NEAR(field[i], expected[i], 1e-13) << i;
}

TEST_P(HierarchicalMesh3d, NodeGroupsAndFacetsFollowTheLeaves) {
  HierarchicalMesh hierarchy(original());
  hierarchy.refine(std::vector<int>{0, 1, 2});  // cells at x = 0, by the clamp
  hierarchy.refine(std::vector<int>{0});
  const Mesh& mesh = hierarchy.leaf_mesh();
  const tensormass::Group& bottom = mesh.groups.back();
  ASSERT_EQ(bottom.name, "bottom");
  std::vector<int> expected;
  for (int node = 0; node < mesh.node_count(); ++node)
    if (point(mesh, node)[1] == 0.0) expected.push_back(node);
  EXPECT_EQ(bottom.nodes, expected) << "the bottom group holds exactly the nodes at y = 0";
  const tensormass::Group& clamp = *std::find_if(mesh.groups.begin(), mesh.groups.end(),
                                                 [](const tensormass::Group& group) { return group.name == "clamp"; });
  ASSERT_GT(clamp.facets.count(), 8);
  std::vector<std::vector<int>> boundary = tensormass::check_conformity(mesh).boundary_faces;
  std::sort(boundary.begin(), boundary.end());
  double area = 0;
  for (int f = 0; f < clamp.facets.count(); ++f) {
    std::vector<int> facet(clamp.facets.nodes.begin() + clamp.facets.offsets[f],
                           clamp.facets.nodes.begin() + clamp.facets.offsets[f + 1]);
    for (int node : facet) EXPECT_EQ(point(mesh, node)[0], 0.0);
    // Counter-clockwise seen from outside (-x): the fan's normal points along -x.
    for (std::size_t k = 1; k + 1 < facet.size(); ++k) {
      const auto a = point(mesh, facet[0]), b = point(mesh, facet[k]), c = point(mesh, facet[k + 1]);
      const double normal_x = (b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]);
      EXPECT_LT(normal_x, 0.0) << "facet " << f;
      area -= normal_x / 2;
    }
    std::sort(facet.begin(), facet.end());
    EXPECT_TRUE(std::binary_search(boundary.begin(), boundary.end(), facet)) << "facet " << f << " is no leaf face";
  }
  EXPECT_NEAR(area, kHeight * kWidth, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Blocks, HierarchicalMesh3d, testing::Values("hex8+prism6", "tet6", "tet5", "pyramid5"),
                         [](const testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '+', '_');
                           return name;
                         });

TEST(HierarchicalMesh3dTets, TheOctahedronIsCutAlongItsShortestDiagonal) {
  Mesh mesh;
  mesh.dim = 3;
  mesh.rest_positions = {0, 0, 0, 4, 0, 0, 1, 2, 0, 0.5, 0.5, 3};
  mesh.blocks.push_back({tensormass::Registry::instance().element("tet4"), {0, 1, 2, 3}, {}, 0});
  // The diagonals join the midpoints of opposite edges: 0-1/2-3, 0-2/1-3, 0-3/1-2.
  const auto distance = [&](std::array<int, 2> e, std::array<int, 2> f) {
    double sum = 0;
    for (int c = 0; c < 3; ++c) {
      const double d = (mesh.rest_positions[3 * e[0] + c] + mesh.rest_positions[3 * e[1] + c] -
                        mesh.rest_positions[3 * f[0] + c] - mesh.rest_positions[3 * f[1] + c]) /
                       2;
      sum += d * d;
    }
    return std::sqrt(sum);
  };
  std::array<double, 3> diagonals{distance({0, 1}, {2, 3}), distance({0, 2}, {1, 3}), distance({0, 3}, {1, 2})};
  const double shortest = *std::min_element(diagonals.begin(), diagonals.end());
  std::sort(diagonals.begin(), diagonals.end());
  ASSERT_GT(diagonals[1] - diagonals[0], 0.1) << "the test tet needs one clearly shortest diagonal";
  HierarchicalMesh hierarchy(mesh);
  hierarchy.refine(std::vector<int>{0});
  const Mesh& leaves = hierarchy.leaf_mesh();
  ASSERT_EQ(leaves.cell_count(), 8);
  for (int cell = 4; cell < 8; ++cell) {  // the octahedron's four tets all hold the diagonal first
    const auto nodes = leaves.blocks[0].cell_nodes(cell);
    const auto a = point(leaves, nodes[0]), b = point(leaves, nodes[1]);
    EXPECT_NEAR(std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]), shortest, 1e-12) << "cell " << cell;
    EXPECT_NEAR(cell_volume(leaves, cell), cell_volume(mesh, 0) / 8, 1e-14);
  }
}

TEST(HierarchicalMesh3dInput, BadInputIsAnInputErrorThatSaysWhy) {
  tensormass::BeamSpec tets;
  tets.dim = 3;
  tets.cells = {1, 1, 1};
  tets.phases = {{"tet6", 1.0}};
  tets.order = 2;
  refinement_test::expect_input_error([&] { (void)HierarchicalMesh(tensormass::make_beam(tets)); },
                                      "tet10 cells cannot be refined");
  tensormass::BeamSpec quadratic;
  quadratic.dim = 3;
  quadratic.cells = {2, 1, 1};
  quadratic.phases = {{"hex8", 1.0}};
  quadratic.order = 2;
  refinement_test::expect_input_error([&] { (void)HierarchicalMesh(tensormass::make_beam(quadratic)); },
                                      "hex20 cells cannot be refined");
  Mesh inverted = hex_prism_block();
  std::swap(inverted.blocks[0].connectivity[0], inverted.blocks[0].connectivity[4]);
  std::swap(inverted.blocks[0].connectivity[1], inverted.blocks[0].connectivity[5]);
  std::swap(inverted.blocks[0].connectivity[2], inverted.blocks[0].connectivity[6]);
  std::swap(inverted.blocks[0].connectivity[3], inverted.blocks[0].connectivity[7]);
  refinement_test::expect_input_error([&] { (void)HierarchicalMesh(inverted); }, "inverted or flat");
  Mesh loose_facet = hex_prism_block();
  loose_facet.groups.front().facets.nodes[1] = loose_facet.groups.front().facets.nodes[3];  // not a cell's face
  refinement_test::expect_input_error([&] { (void)HierarchicalMesh(loose_facet); }, "is not a face of any cell");
}

}  // namespace
