// Patch tests on small meshes assembled here from the Hooke kernels' element
// stiffnesses (the Hessian at u = 0): the MacNeal-Harder distorted patch of
// seven hexahedra in the unit cube (hex8, tet4 by a conforming
// five-tetrahedra split, pyramid5 by six pyramids per hexahedron), the 2D
// patch of five distorted quadrilaterals of the same paper (quad4, tri3) and
// its triangles extruded into a warped two-layer prism6 patch; a quadratic
// element runs on the patch of the linear element with its corners, its
// other nodes added where its geometry stays the linear one. The outer
// nodes carry the exact linear field, the inner ones are solved for; the
// solution must be the exact field and the stress constant.
//
// MacNeal R. H., Harder R. L., "A proposed standard set of problems to test
// finite element accuracy", Finite Elements in Analysis and Design 1 (1985).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "kernel_test_support.hpp"

namespace tmtest {
namespace {

/// A mesh of one element type: node coordinates (nodes by dim) and
/// connectivities in tensormass (VTK) order.
struct Mesh {
  int dim = 3;
  Vector coordinates;
  std::vector<std::vector<int>> elements;

  int node_count() const { return static_cast<int>(coordinates.size()) / dim; }
  double x(int node, int a) const { return coordinates[static_cast<std::size_t>(node * dim + a)]; }
  int add_node(const double* point) {
    coordinates.insert(coordinates.end(), point, point + dim);
    return node_count() - 1;
  }
};

// --- 3D: the seven-hexahedra patch -----------------------------------------

/// Unit-cube corners in hex8 (VTK) order.
constexpr double kCubeCorners[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                       {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
/// The inner nodes of the patch, inner node k next to corner k.
constexpr double kInnerCorners[8][3] = {{0.249, 0.342, 0.192}, {0.826, 0.288, 0.288}, {0.850, 0.649, 0.263},
                                        {0.273, 0.750, 0.230}, {0.320, 0.186, 0.643}, {0.677, 0.305, 0.683},
                                        {0.788, 0.693, 0.644}, {0.165, 0.745, 0.702}};
/// Hexahedron faces, corners counter-clockwise seen from outside (VTK).
constexpr int kHexFaces[6][4] = {{0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 3, 2, 1}, {4, 5, 6, 7}};
constexpr int kHexEdges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                  {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

/// Nodes 0-7 the outer corners, 8-15 the inner ones; element 0 the inner
/// hexahedron, then one per face of the cube between the inner face (its
/// bottom, normal towards the outer face) and the outer face.
Mesh macneal_harder_hex8() {
  Mesh mesh;
  for (const auto& corner : kCubeCorners) mesh.add_node(corner);
  for (const auto& corner : kInnerCorners) mesh.add_node(corner);
  mesh.elements.push_back({8, 9, 10, 11, 12, 13, 14, 15});
  for (const auto& face : kHexFaces)
    mesh.elements.push_back({8 + face[0], 8 + face[1], 8 + face[2], 8 + face[3], face[0], face[1], face[2], face[3]});
  return mesh;
}

/// A node at the mean of `corners` (of one element), one per distinct set.
int centre_node(Mesh& mesh, std::map<std::vector<int>, int>& made, std::vector<int> corners) {
  std::sort(corners.begin(), corners.end());
  if (const auto found = made.find(corners); found != made.end()) return found->second;
  double point[3] = {0, 0, 0};
  for (int node : corners)
    for (int c = 0; c < mesh.dim; ++c) point[c] += mesh.x(node, c) / static_cast<double>(corners.size());
  return made.emplace(corners, mesh.add_node(point)).first->second;
}

/// The patch of `linear` with each element turned into the quadratic
/// element `info` with its corners: mid-edge nodes at edge midpoints, face
/// nodes at the centres of their faces' corners, interior nodes at the mean
/// of all corners (node kinds as the element files order them: corners,
/// mid-edge, face, interior). The geometry stays the linear element's.
Mesh with_quadratic_nodes(const Mesh& linear, const tm_element_info& info) {
  Mesh mesh = linear;
  std::map<std::vector<int>, int> made;
  for (std::vector<int>& element : mesh.elements) {
    std::vector<int> quadratic(static_cast<std::size_t>(info.nodes), -1);
    std::copy(element.begin(), element.end(), quadratic.begin());
    for (int edge = 0; edge < info.edge_count; ++edge) {
      const int* nodes = info.edges + edge * info.edge_size;
      quadratic[nodes[2]] = centre_node(mesh, made, {quadratic[nodes[0]], quadratic[nodes[1]]});
    }
    for (int f = 0; f < info.face_count; ++f) {
      const int* face = info.faces + info.face_offsets[f];
      const int last = face[info.face_sizes[f] - 1];
      if (quadratic[last] >= 0) continue;
      std::vector<int> corners;
      for (int k = 0; k < tensormass::face_corner_count(info, f); ++k) corners.push_back(quadratic[face[k]]);
      quadratic[last] = centre_node(mesh, made, corners);
    }
    for (int& node : quadratic)
      if (node < 0) node = centre_node(mesh, made, element);
    element = quadratic;
  }
  return mesh;
}

double signed_volume(const double* p0, const double* p1, const double* p2, const double* p3) {
  double a[3], b[3], c[3];
  for (int i = 0; i < 3; ++i) {
    a[i] = p1[i] - p0[i];
    b[i] = p2[i] - p0[i];
    c[i] = p3[i] - p0[i];
  }
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

/// Five tetrahedra per hexahedron: the central one on the four corners of
/// colour 0 of a global two-colouring of the nodes (outer node k has the
/// parity of corner k, inner node k the other one; the opposite choice
/// inverts a tetrahedron of the third outer hexahedron), plus one per
/// remaining corner with its three neighbours. Every face diagonal joins the two
/// nodes of colour 0 on that face, so neighbouring hexahedra split shared
/// faces the same way. Orientation from the reference cube (VTK tet: nodes
/// 1, 2, 3 counter-clockwise seen from node 0's opposite side).
Mesh macneal_harder_tet4() {
  const Mesh hexes = macneal_harder_hex8();
  auto colour = [](int node) {
    const int corner = node % 8;
    const int parity =
        static_cast<int>(kCubeCorners[corner][0] + kCubeCorners[corner][1] + kCubeCorners[corner][2]) % 2;
    return node < 8 ? parity : 1 - parity;
  };
  Mesh mesh;
  mesh.coordinates = hexes.coordinates;
  for (const std::vector<int>& hex : hexes.elements) {
    std::vector<int> centre, others;
    for (int v = 0; v < 8; ++v) (colour(hex[static_cast<std::size_t>(v)]) == 0 ? centre : others).push_back(v);
    std::vector<std::array<int, 4>> tets = {{centre[0], centre[1], centre[2], centre[3]}};
    for (const int v : others) {
      std::array<int, 4> tet = {v, -1, -1, -1};
      int k = 1;
      for (const auto& edge : kHexEdges)
        if (edge[0] == v || edge[1] == v) tet[static_cast<std::size_t>(k++)] = edge[0] == v ? edge[1] : edge[0];
      tets.push_back(tet);
    }
    for (std::array<int, 4>& tet : tets) {
      if (signed_volume(kCubeCorners[tet[0]], kCubeCorners[tet[1]], kCubeCorners[tet[2]], kCubeCorners[tet[3]]) < 0)
        std::swap(tet[1], tet[2]);
      mesh.elements.push_back({hex[static_cast<std::size_t>(tet[0])], hex[static_cast<std::size_t>(tet[1])],
                               hex[static_cast<std::size_t>(tet[2])], hex[static_cast<std::size_t>(tet[3])]});
    }
  }
  return mesh;
}

/// Six pyramids per hexahedron, one on each face, apex at the hexahedron's
/// vertex centroid (VTK pyramid: base normal towards the apex).
Mesh macneal_harder_pyramid5() {
  const Mesh hexes = macneal_harder_hex8();
  Mesh mesh;
  mesh.coordinates = hexes.coordinates;
  for (const std::vector<int>& hex : hexes.elements) {
    double centre[3] = {0, 0, 0};
    for (const int node : hex)
      for (int c = 0; c < 3; ++c) centre[c] += hexes.x(node, c) / 8;
    const int apex = mesh.add_node(centre);
    for (const auto& face : kHexFaces)
      mesh.elements.push_back({hex[static_cast<std::size_t>(face[0])], hex[static_cast<std::size_t>(face[3])],
                               hex[static_cast<std::size_t>(face[2])], hex[static_cast<std::size_t>(face[1])], apex});
  }
  return mesh;
}

// --- 2D: the five-quadrilaterals patch --------------------------------------

/// The 0.24 by 0.12 rectangle, inner nodes (0.04, 0.02), (0.18, 0.03),
/// (0.16, 0.08), (0.08, 0.08); quad4 elements counter-clockwise.
Mesh macneal_harder_quad4() {
  Mesh mesh;
  mesh.dim = 2;
  const double points[8][2] = {{0, 0},       {0.24, 0},    {0.24, 0.12}, {0, 0.12},
                               {0.04, 0.02}, {0.18, 0.03}, {0.16, 0.08}, {0.08, 0.08}};
  for (const auto& point : points) mesh.add_node(point);
  mesh.elements = {{4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  return mesh;
}

/// Each quadrilateral split along its diagonal from its first node (faces
/// are edges in 2D, so any split conforms).
Mesh macneal_harder_tri3() {
  const Mesh quads = macneal_harder_quad4();
  Mesh mesh;
  mesh.dim = 2;
  mesh.coordinates = quads.coordinates;
  for (const std::vector<int>& quad : quads.elements) {
    mesh.elements.push_back({quad[0], quad[1], quad[2]});
    mesh.elements.push_back({quad[0], quad[2], quad[3]});
  }
  return mesh;
}

/// Prisms: the triangles of the 2D patch extruded through three layers z =
/// 0, z = 0.06 (0.05 to 0.07 at the inner nodes, warping the middle layer)
/// and z = 0.12; the free nodes are the four inner nodes of the middle
/// layer. VTK wedge: triangle 0, 1, 2 with its normal away from 3, 4, 5.
Mesh macneal_harder_prism6() {
  const Mesh triangles = macneal_harder_tri3();
  const int base = triangles.node_count();
  Mesh mesh;
  const double middle[8] = {0.06, 0.06, 0.06, 0.06, 0.05, 0.07, 0.065, 0.055};
  for (int layer = 0; layer < 3; ++layer)
    for (int node = 0; node < base; ++node) {
      const double point[3] = {triangles.x(node, 0), triangles.x(node, 1),
                               layer == 0   ? 0.0
                               : layer == 1 ? middle[node]
                                            : 0.12};
      mesh.add_node(point);
    }
  for (int layer = 0; layer < 2; ++layer)
    for (const std::vector<int>& t : triangles.elements) {  // t counter-clockwise seen from +z
      const int low = layer * base, high = (layer + 1) * base;
      mesh.elements.push_back({low + t[0], low + t[2], low + t[1], high + t[0], high + t[2], high + t[1]});
    }
  return mesh;
}

using PatchMaker = Mesh (*)();

/// The maker of a first-order element's patch, or nullptr when there is none.
PatchMaker linear_patch(const std::string& element) {
  static const std::map<std::string, PatchMaker> patches{
      {"hex8", macneal_harder_hex8},     {"tet4", macneal_harder_tet4},   {"pyramid5", macneal_harder_pyramid5},
      {"prism6", macneal_harder_prism6}, {"quad4", macneal_harder_quad4}, {"tri3", macneal_harder_tri3}};
  const auto found = patches.find(element);
  return found == patches.end() ? nullptr : found->second;
}

/// The patch of `element`: its own for a first-order element, the patch of
/// its linear version with quadratic nodes for a second-order one; an empty
/// mesh when there is none (the test then says so and skips).
Mesh patch_for(const std::string& element) {
  const tm_element_info& info = *registry().element(element);
  const tm_element_info* linear = tensormass::linear_version(info);
  const PatchMaker make = linear ? linear_patch(linear->name) : nullptr;
  if (!make) return Mesh{info.dim, {}, {}};
  return info.order == 1 ? make() : with_quadratic_nodes(make(), info);
}

/// The exact fields of the paper: 3D u = 1e-3 (x + y/2 + z/2), v = 1e-3
/// (y + x/2 + z/2), w = 1e-3 (z + x/2 + y/2); 2D u = 1e-3 (x + y/2),
/// v = 1e-3 (y + x/2).
double exact_displacement(int dim, const double* x, int component) {
  double sum = 0.0;
  for (int c = 0; c < dim; ++c) sum += (c == component ? 1.0 : 0.5) * x[c];
  return 1e-3 * sum;
}

/// On the boundary of the mesh's bounding box (every patch here fills a box).
bool on_boundary(const Mesh& mesh, int node) {
  for (int c = 0; c < mesh.dim; ++c) {
    double low = 1e300, high = -1e300;
    for (int k = 0; k < mesh.node_count(); ++k) {
      low = std::min(low, mesh.x(k, c));
      high = std::max(high, mesh.x(k, c));
    }
    if (std::abs(mesh.x(node, c) - low) < 1e-12 || std::abs(mesh.x(node, c) - high) < 1e-12) return true;
  }
  return false;
}

class MacNealHarderPatch : public testing::TestWithParam<const tm_kernel*> {};

/// E = 1e6, nu = 0.25 (lam = mu = 4e5). 3D: sigma_x = sigma_y = sigma_z =
/// 2000, tau_xy = tau_yz = tau_zx = 400. 2D (plane strain, where the paper
/// has plane stress): sigma_x = sigma_y = lam 2e-3 + 2 mu 1e-3 = 1600,
/// tau_xy = 400.
TEST_P(MacNealHarderPatch, InnerNodesAndStressAreExact) {
  const tm_kernel& kernel = *GetParam();
  const Mesh mesh = patch_for(kernel.element);
  if (mesh.elements.empty())
    GTEST_SKIP() << "no patch for " << kernel.element << " (nor for a linear element with its corners)";
  const int dim = mesh.dim, nodes = mesh.node_count(), dofs = nodes * dim;
  const int element_dofs = kernel.dofs;
  ASSERT_EQ(dim, kernel.dim);
  const double params[2] = {1e6, 0.25};

  // Assemble the global stiffness (the Hessian at u = 0).
  const auto n = static_cast<std::size_t>(dofs);
  Vector K(n * n, 0.0);
  std::vector<Vector> consts(mesh.elements.size(), Vector(static_cast<std::size_t>(kernel.consts)));
  const Vector zero(static_cast<std::size_t>(element_dofs), 0.0);
  Vector Ke(static_cast<std::size_t>(element_dofs * element_dofs));
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    const std::vector<int>& element = mesh.elements[e];
    ASSERT_EQ(static_cast<int>(element.size()), kernel.nodes);
    Vector rest;
    for (const int node : element)
      for (int c = 0; c < dim; ++c) rest.push_back(mesh.x(node, c));
    ASSERT_EQ(kernel.precompute(rest.data(), params, 2, consts[e].data()), 0) << "element " << e << " is inverted";
    kernel.hessian(zero.data(), consts[e].data(), Ke.data());
    for (int i = 0; i < element_dofs; ++i)
      for (int j = 0; j < element_dofs; ++j) {
        const auto row = static_cast<std::size_t>(element[static_cast<std::size_t>(i / dim)] * dim + i % dim);
        const auto col = static_cast<std::size_t>(element[static_cast<std::size_t>(j / dim)] * dim + j % dim);
        K[row * n + col] += Ke[static_cast<std::size_t>(i * element_dofs + j)];
      }
  }

  // Exact field on the boundary, solve K_II u_I = -K_IB u_B.
  Vector exact(n), u(n, 0.0);
  std::vector<std::size_t> inner;
  for (int node = 0; node < nodes; ++node)
    for (int c = 0; c < dim; ++c) {
      const auto dof = static_cast<std::size_t>(node * dim + c);
      exact[dof] = exact_displacement(dim, &mesh.coordinates[static_cast<std::size_t>(node * dim)], c);
      if (on_boundary(mesh, node)) u[dof] = exact[dof];
      else inner.push_back(dof);
    }
  ASSERT_FALSE(inner.empty());
  const std::size_t m = inner.size();
  Vector A(m * m), b(m);
  for (std::size_t i = 0; i < m; ++i) {
    double rhs = 0.0;
    for (std::size_t j = 0; j < n; ++j) rhs -= K[inner[i] * n + j] * u[j];  // inner entries of u are 0
    b[i] = rhs;
    for (std::size_t j = 0; j < m; ++j) A[i * m + j] = K[inner[i] * n + inner[j]];
  }
  const Vector solution = solve_dense(A, b);
  for (std::size_t i = 0; i < m; ++i) u[inner[i]] = solution[i];
  EXPECT_LE(max_abs_difference(u, exact), 1e-10 * max_abs(exact)) << "inner displacements";

  // Constant stress at every quadrature point of every element.
  const Vector expected_point =
      dim == 3 ? Vector{2000, 400, 400, 400, 2000, 400, 400, 400, 2000} : Vector{1600, 400, 400, 1600};
  for (std::size_t e = 0; e < mesh.elements.size(); ++e) {
    Vector ue;
    for (const int node : mesh.elements[e])
      for (int c = 0; c < dim; ++c) ue.push_back(u[static_cast<std::size_t>(node * dim + c)]);
    Vector P(static_cast<std::size_t>(kernel.quadrature_points * dim * dim));
    kernel.stress(ue.data(), consts[e].data(), P.data());
    Vector expected;
    for (int q = 0; q < kernel.quadrature_points; ++q)
      expected.insert(expected.end(), expected_point.begin(), expected_point.end());
    EXPECT_LE(relative_error(P, expected), 1e-9) << "stress in element " << e;
  }
}

std::vector<const tm_kernel*> patch_kernels() {
  return kernels_where([](const tm_kernel& k) { return std::string(k.law) == "hooke"; });
}

INSTANTIATE_TEST_SUITE_P(Hooke, MacNealHarderPatch, testing::ValuesIn(patch_kernels()), KernelParamName());
// Empty for a registry without such kernels (a scratch project).
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(MacNealHarderPatch);

}  // namespace
}  // namespace tmtest
