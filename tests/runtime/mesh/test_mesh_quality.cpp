// mesh_quality: the ideal shape of every element gives a scaled Jacobian of
// 1 and its exact volume; mirrored cells are inverted; a curved quadratic
// cell can be inverted at a quadrature point with good corners; mesh-wide
// summaries.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/test_meshes.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/mesh/mesh.hpp"
#include "tensormass/mesh/mesh_quality.hpp"

namespace {

using Coordinates = std::vector<double>;

const tm_element_info& element(const std::string& name) {
  const tm_element_info* info = tensormass::Registry::instance().element(name);
  if (!info) throw std::runtime_error("no element " + name);
  return *info;
}

const double kS3 = std::sqrt(3.0);
const double kS2 = std::sqrt(2.0);

/// Corners of the ideal linear shapes, our (VTK) node order.
Coordinates ideal_corners(const std::string& linear) {
  if (linear == "tri3") return {0, 0, 0, 1, 0, 0, 0.5, kS3 / 2, 0};
  if (linear == "quad4") return {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  if (linear == "tet4") return {0, 0, 0, 1, 0, 0, 0.5, kS3 / 2, 0, 0.5, kS3 / 6, std::sqrt(2.0 / 3.0)};
  if (linear == "hex8") return {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  // VTK wedge: triangle 0,1,2 turns clockwise seen from the top face 3,4,5.
  if (linear == "prism6") return {0, 0, 0, 0.5, kS3 / 2, 0, 1, 0, 0, 0, 0, 1, 0.5, kS3 / 2, 1, 1, 0, 1};
  return {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.5, 1 / kS2};  // pyramid5
}

double ideal_volume(const std::string& linear) {
  if (linear == "tri3") return kS3 / 4;
  if (linear == "tet4") return 1 / (6 * kS2);
  if (linear == "prism6") return kS3 / 4;
  if (linear == "pyramid5") return 1 / (3 * kS2);
  return 1;  // quad4, hex8
}

/// The first-order registry element with the corners of `name` (itself for one of order 1).
std::string linear_of(const std::string& name) {
  const tm_element_info* linear = tensormass::linear_version(*tensormass::Registry::instance().element(name));
  return linear ? linear->name : name;
}

/// Sets node m of x to the mean of `nodes`.
void place_at_mean(Coordinates& x, int m, const std::vector<int>& nodes) {
  for (int c = 0; c < 3; ++c) {
    double sum = 0;
    for (int n : nodes) sum += x[static_cast<std::size_t>(3 * n + c)];
    x[static_cast<std::size_t>(3 * m + c)] = sum / static_cast<double>(nodes.size());
  }
}

/// The ideal shape of `e`: corners, then mid-edge nodes at edge midpoints,
/// face nodes at face centres, interior nodes at the centre.
Coordinates ideal(const tm_element_info& e) {
  Coordinates x = ideal_corners(linear_of(e.name));
  x.resize(3 * static_cast<std::size_t>(e.nodes));
  std::vector<bool> placed(static_cast<std::size_t>(e.nodes), false);
  for (int n = 0; n < e.corner_count; ++n) placed[static_cast<std::size_t>(n)] = true;
  if (e.edge_size == 3)
    for (int k = 0; k < e.edge_count; ++k) {
      const int a = e.edges[3 * k], b = e.edges[3 * k + 1], m = e.edges[3 * k + 2];
      place_at_mean(x, m, {a, b});
      placed[static_cast<std::size_t>(m)] = true;
    }
  for (int f = 0; f < e.face_count; ++f) {
    const int* face = e.faces + e.face_offsets[f];
    const int last = face[e.face_sizes[f] - 1];
    if (placed[static_cast<std::size_t>(last)]) continue;
    place_at_mean(x, last, std::vector<int>(face, face + tensormass::face_corner_count(e, f)));
    placed[static_cast<std::size_t>(last)] = true;
  }
  std::vector<int> corners(static_cast<std::size_t>(e.corner_count));
  for (int n = 0; n < e.corner_count; ++n) corners[static_cast<std::size_t>(n)] = n;
  for (int n = 0; n < e.nodes; ++n)
    if (!placed[static_cast<std::size_t>(n)]) place_at_mean(x, n, corners);
  return x;
}

/// The mirror image (x -> -x): every Jacobian changes sign.
Coordinates mirrored(Coordinates x) {
  for (std::size_t i = 0; i < x.size(); i += 3) x[i] = -x[i];
  return x;
}

class EveryElement : public testing::TestWithParam<const tm_element_info*> {};

TEST_P(EveryElement, IdealShapeHasScaledJacobianOneAndItsVolume) {
  const tm_element_info& e = *GetParam();
  const tensormass::CellQuality q = tensormass::cell_quality(e, e.dim, ideal(e));
  EXPECT_NEAR(q.scaled_jacobian, 1.0, 1e-12);
  EXPECT_NEAR(q.volume, ideal_volume(linear_of(e.name)), 1e-12);
  EXPECT_FALSE(q.inverted);
  EXPECT_GE(q.edge_ratio, 1.0);
}

TEST_P(EveryElement, MirrorImageIsInverted) {
  const tm_element_info& e = *GetParam();
  const tensormass::CellQuality q = tensormass::cell_quality(e, e.dim, mirrored(ideal(e)));
  EXPECT_LT(q.scaled_jacobian, 0);
  EXPECT_TRUE(q.inverted);
  EXPECT_TRUE(std::isnan(q.volume));
}

TEST_P(EveryElement, StretchingChangesTheEdgeRatioAndVolume) {
  const tm_element_info& e = *GetParam();
  Coordinates x = ideal(e);
  for (std::size_t i = 0; i < x.size(); i += 3) x[i] *= 3;
  const tensormass::CellQuality q = tensormass::cell_quality(e, e.dim, x);
  EXPECT_GT(q.edge_ratio, 1.5);
  EXPECT_GT(q.scaled_jacobian, 0);
  EXPECT_NEAR(q.volume, 3 * ideal_volume(linear_of(e.name)), 1e-12);
}

TEST_P(EveryElement, ShearingLowersTheScaledJacobianNotTheVolume) {
  const tm_element_info& e = *GetParam();
  Coordinates x = ideal(e);
  for (std::size_t i = 0; i < x.size(); i += 3) x[i] += 0.5 * x[i + 1] + 0.3 * x[i + 2];
  const tensormass::CellQuality q = tensormass::cell_quality(e, e.dim, x);
  EXPECT_GT(q.scaled_jacobian, 0);
  EXPECT_LT(q.scaled_jacobian, 0.99);
  EXPECT_FALSE(q.inverted);
  EXPECT_NEAR(q.volume, ideal_volume(linear_of(e.name)), 1e-12);
}

TEST_P(EveryElement, CollapsedEdgeIsDegenerate) {
  const tm_element_info& e = *GetParam();
  Coordinates x = ideal(e);
  const int a = e.edges[0], b = e.edges[1];
  for (int c = 0; c < 3; ++c) x[static_cast<std::size_t>(3 * b + c)] = x[static_cast<std::size_t>(3 * a + c)];
  const tensormass::CellQuality q = tensormass::cell_quality(e, e.dim, x);
  EXPECT_TRUE(std::isinf(q.edge_ratio));
  EXPECT_LE(q.scaled_jacobian, 0);
  EXPECT_TRUE(q.inverted);
}

std::vector<const tm_element_info*> elements() {
  const auto all = tensormass::Registry::instance().elements();
  return {all.begin(), all.end()};
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryElement, testing::ValuesIn(elements()),
                         [](const testing::TestParamInfo<const tm_element_info*>& info) {
                           return std::string(info.param->name);
                         });

TEST(MeshQuality, RegularTetrahedronMatchesTheStandardDefinitions) {
  const tm_element_info& tet = element("tet4");
  EXPECT_NEAR(tensormass::scaled_jacobian(tet, 3, ideal(tet)), 1.0, 1e-14);
  EXPECT_NEAR(tensormass::edge_ratio(tet, ideal(tet)), 1.0, 1e-14);
  // The right-angled corner tetrahedron: worst corner sqrt(2)/2 (standard value).
  const Coordinates corner{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  EXPECT_NEAR(tensormass::scaled_jacobian(tet, 3, corner), std::sqrt(0.5), 1e-14);
  EXPECT_NEAR(tensormass::edge_ratio(tet, corner), std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(tensormass::cell_volume(tet, 3, corner), 1.0 / 6, 1e-15);
}

TEST(MeshQuality, CurvedTet10InvertedInsideWithGoodCorners) {
  const tm_element_info& tet10 = element("tet10");
  Coordinates x{0,   0,   0, 1, 0,   0, 0, 1, 0,   0,   0, 1,   0.5, 0,   0,
                0.5, 0.5, 0, 0, 0.5, 0, 0, 0, 0.5, 0.5, 0, 0.5, 0,   0.5, 0.5};
  x[13] = x[14] = 0.1;  // mid node of edge 0-1 pushed inwards a little: still valid
  EXPECT_FALSE(tensormass::cell_quality(tet10, 3, x).inverted);
  x[13] = x[14] = 0.4;  // pushed far: det J < 0 at a quadrature point
  const tensormass::CellQuality q = tensormass::cell_quality(tet10, 3, x);
  EXPECT_GT(q.scaled_jacobian, 0);
  EXPECT_TRUE(q.inverted);
}

TEST(MeshQuality, MeshSummaryPerTypeAndInvertedCells) {
  tensormass::Mesh mesh = tensormass::read_mesh(meshtest::data_file("hybrid_o1.msh41.msh"));
  const tensormass::MeshQuality clean = tensormass::mesh_quality(mesh);
  ASSERT_EQ(clean.cells.size(), static_cast<std::size_t>(mesh.cell_count()));
  ASSERT_EQ(clean.types.size(), mesh.blocks.size());
  EXPECT_TRUE(clean.inverted_cells.empty());
  EXPECT_NEAR(clean.volume, 1.0, 1e-12);
  for (const tensormass::ElementTypeQuality& t : clean.types) {
    EXPECT_GT(t.min_scaled_jacobian, 0) << t.element->name;
    EXPECT_LE(t.min_scaled_jacobian, t.max_scaled_jacobian);
    EXPECT_LE(t.max_scaled_jacobian, 1 + 1e-12);
    EXPECT_LE(t.max_edge_ratio, clean.max_edge_ratio);
  }
  // Swap two nodes of the first tetrahedron: it turns inside out.
  tensormass::ElementBlock& tets = mesh.blocks.back();
  ASSERT_STREQ(tets.element->name, "tet4");
  std::swap(tets.connectivity[0], tets.connectivity[1]);
  const tensormass::MeshQuality bad = tensormass::mesh_quality(mesh);
  EXPECT_EQ(bad.inverted_cells, (std::vector<int>{tets.first_cell}));
  EXPECT_EQ(bad.types.back().inverted, 1);
  EXPECT_LT(bad.types.back().min_scaled_jacobian, 0);
  EXPECT_LT(bad.volume, 1.0);
}

}  // namespace
