// Face matching of a mesh's cells (see mesh_conformity.hpp).
#include "tensormass/mesh/mesh_conformity.hpp"

#include <algorithm>
#include <map>
#include <span>

#include "tensormass/kernels/registry.hpp"

namespace tensormass {
namespace {

using FaceUses = std::map<std::vector<int>, int>;

/// Counts the faces of a 3D cell (corner nodes only: quadratic faces list their corners first).
void count_faces(const tm_element_info& element, std::span<const int> nodes, FaceUses& uses) {
  for (int f = 0; f < element.face_count; ++f) {
    std::vector<int> face;
    const int corners = face_corner_count(element, f);
    for (int n = 0; n < corners; ++n) face.push_back(nodes[element.faces[element.face_offsets[f] + n]]);
    std::sort(face.begin(), face.end());
    ++uses[face];
  }
}

/// Counts the edges of a 2D cell by their two end nodes (a mid-edge node comes after them).
void count_edges(const tm_element_info& element, std::span<const int> nodes, FaceUses& uses) {
  for (int e = 0; e < element.edge_count; ++e) {
    const int* edge = element.edges + e * element.edge_size;
    std::vector<int> ends{nodes[edge[0]], nodes[edge[1]]};
    std::sort(ends.begin(), ends.end());
    ++uses[ends];
  }
}

}  // namespace

ConformityReport check_conformity(const Mesh& mesh) {
  FaceUses uses;
  for (const ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local) {
      if (mesh.dim == 2) count_edges(*block.element, block.cell_nodes(local), uses);
      else count_faces(*block.element, block.cell_nodes(local), uses);
    }
  ConformityReport report;
  for (const auto& [face, count] : uses) {
    if (count == 1) report.boundary_faces.push_back(face);
    else if (count == 2) ++report.interior_faces;
    else ++report.overused_faces;
  }
  return report;
}

}  // namespace tensormass
