/// \file registry.hpp
/// The kernel registry: every generated LES triple (law, element, split),
/// looked up in O(1). Switching an element's law is replacing the
/// `const tm_kernel*` it holds.
#ifndef TENSORMASS_REGISTRY_HPP
#define TENSORMASS_REGISTRY_HPP

#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "tensormass/kernels/kernel_abi.h"

namespace tensormass {

/// The most nodes a cell may have: the runtime's per-cell stack buffers
/// (assembly, criteria, inversion checks, refinement) hold this many. The
/// registry refuses at start an element with more.
inline constexpr int kMaxCellNodes = 27;
inline constexpr int kMaxCellDofs = 3 * kMaxCellNodes;

/// How many corners face `face` of a 3D element has: its leading nodes below
/// corner_count (a face lists its corners first).
int face_corner_count(const tm_element_info& element, int face);

/// The registry's first-order element whose nodes are the corners of
/// `element` (same dimension, same reference coordinates): tet4 for tet10,
/// quad4 for quad8 and quad9; `element` itself when it is of order 1;
/// nullptr when there is none.
const tm_element_info* linear_version(const tm_element_info& element);

class Registry {
 public:
  /// The registry of the generated kernels linked into this program.
  static const Registry& instance();

  /// The kernel for (law, element, split), or nullptr when there is none.
  const tm_kernel* find(std::string_view law, std::string_view element, std::string_view split) const;
  /// Like find, but throws std::invalid_argument naming what exists.
  const tm_kernel& get(std::string_view law, std::string_view element, std::string_view split) const;
  /// A kernel of `law`, or nullptr: its `param_names` and `param_limits` are
  /// the law's (every kernel of a law has the same, checked at start).
  const tm_kernel* law_kernel(std::string_view law) const;
  /// The reference element named `name`, or nullptr.
  const tm_element_info* element(std::string_view name) const;

  std::span<const tm_kernel* const> kernels() const { return kernels_; }
  std::span<const tm_element_info* const> elements() const { return elements_; }
  /// Distinct law, element and split names, sorted.
  std::vector<std::string> laws() const;
  std::vector<std::string> splits() const;

 private:
  Registry();
  static std::string key(std::string_view law, std::string_view element, std::string_view split);
  std::vector<const tm_kernel*> kernels_;
  std::vector<const tm_element_info*> elements_;
  std::unordered_map<std::string, const tm_kernel*> by_key_;
  std::unordered_map<std::string, const tm_element_info*> elements_by_name_;
  std::unordered_map<std::string, const tm_kernel*> laws_by_name_;
};

/// True for a kernel of the anp split: its law's bulk part is integrated at
/// the nodes (assembly/nodal_pressure.hpp), not over the cell.
inline bool nodal_pressure_split(const tm_kernel& kernel) {
  return kernel.bulk != nullptr && std::string_view(kernel.split) == "anp";
}
/// True for the splits that keep a cell free of volumetric locking (fbar,
/// anp): a law switch keeps them, the locking warning skips them.
bool locking_free_split(const tm_kernel& kernel);

}  // namespace tensormass

#endif
