// Face matching of a mesh's cells (see mesh_conformity.hpp).
#include "tensormass/mesh/mesh_conformity.hpp"

#include <algorithm>
#include <map>

namespace tensormass {

ConformityReport check_conformity(const Mesh& mesh) {
  std::map<std::vector<int>, int> uses;
  for (const ElementBlock& block : mesh.blocks) {
    const tm_element_info& element = *block.element;
    for (int local = 0; local < block.count(); ++local) {
      const auto nodes = block.cell_nodes(local);
      for (int f = 0; f < element.face_count; ++f) {
        std::vector<int> face;
        // Corner nodes only: quadratic faces list their corners first.
        const int corners = element.face_sizes[f] == 6 || element.face_sizes[f] == 3 ? 3 : 4;
        for (int n = 0; n < corners; ++n) face.push_back(nodes[element.faces[element.face_offsets[f] + n]]);
        std::sort(face.begin(), face.end());
        ++uses[face];
      }
    }
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
