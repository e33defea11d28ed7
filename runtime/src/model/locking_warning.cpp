#include "tensormass/model/locking_warning.hpp"

#include <cstdio>
#include <set>
#include <string>
#include <utility>

namespace tensormass {

namespace {

/// The Poisson's ratio of a material, or a negative value when its law has none.
double poisson_of(const MaterialSpec& material) {
  const auto found = material.constants.find("poisson");
  return found == material.constants.end() ? -1.0 : found->second;
}

std::string warning_text(const MaterialSpec& material, int index, const std::string& element) {
  char text[512];
  std::snprintf(text, sizeof text,
                "material %d (region %s%s%s): its %s cells at poisson = %g are first-order elements, which lock "
                "(answer too stiff) above poisson = %g; quadratic elements lock far less (tensormass raise-order, "
                "tensormass beam --order 2)",
                index, material.region.c_str(), material.line > 0 ? ", scene line " : "",
                material.line > 0 ? std::to_string(material.line).c_str() : "", element.c_str(), poisson_of(material),
                kLockingPoisson);
  return text;
}

}  // namespace

std::vector<std::string> locking_warnings(const Model& model, const ModelSpec& spec) {
  std::set<std::pair<int, std::string>> locking;  // (material, element)
  const Mesh& mesh = model.mesh();
  for (const ElementBlock& block : mesh.blocks) {
    if (block.element->order != 1) continue;
    for (int cell = block.first_cell; cell < block.first_cell + block.count(); ++cell) {
      const int material = model.material(cell);
      if (material >= 0 && material < static_cast<int>(spec.materials.size()) &&
          poisson_of(spec.materials[material]) > kLockingPoisson)
        locking.insert({material, block.element->name});
    }
  }
  std::vector<std::string> warnings;
  for (const auto& [material, element] : locking)
    warnings.push_back(warning_text(spec.materials[material], material, element));
  return warnings;
}

}  // namespace tensormass
