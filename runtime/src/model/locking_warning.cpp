#include "tensormass/model/locking_warning.hpp"

#include <cstdio>
#include <set>
#include <string>
#include <utility>

#include "tensormass/kernels/registry.hpp"

namespace tensormass {

namespace {

/// The Poisson's ratio of a material, or a negative value when its law has none.
double poisson_of(const MaterialSpec& material) {
  const auto found = material.constants.find("poisson");
  return found == material.constants.end() ? -1.0 : found->second;
}

/// The remedy the registry offers for `element`: its anp kernels (averaged
/// nodal pressure) or fbar kernels (mean dilatation) where the material's law
/// has them, else a quadratic mesh.
std::string remedy(const MaterialSpec& material, const std::string& element) {
  if (Registry::instance().find(material.law, element, "anp"))
    return "set `split: anp` on the material (averaged nodal pressure, docs/formulations.md)";
  if (Registry::instance().find(material.law, element, "fbar"))
    return "set `split: fbar` (or `anp`) on the material (mean dilatation, docs/formulations.md)";
  return "quadratic elements lock far less (tensormass raise-order, tensormass beam --order 2)";
}

std::string warning_text(const MaterialSpec& material, int index, const std::string& element) {
  char text[640];
  std::snprintf(text, sizeof text,
                "material %d (region %s%s%s): its %s cells at poisson = %g are first-order elements, which lock "
                "(answer too stiff) above poisson = %g; %s",
                index, material.region.c_str(), material.line > 0 ? ", scene line " : "",
                material.line > 0 ? std::to_string(material.line).c_str() : "", element.c_str(), poisson_of(material),
                kLockingPoisson, remedy(material, element).c_str());
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
      if (locking_free_split(model.kernel(cell))) continue;
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
