#include "tensormass/kernels/registry.hpp"

#include <algorithm>
#include <cstring>
#include <set>
#include <stdexcept>

namespace tensormass {

namespace {

bool same_limit(const tm_param_limit& a, const tm_param_limit& b) {
  return a.lower == b.lower && a.upper == b.upper && a.lower_inclusive == b.lower_inclusive &&
         a.upper_inclusive == b.upper_inclusive;
}

bool same_parameters(const tm_kernel& a, const tm_kernel& b) {
  if (a.params != b.params) return false;
  for (int p = 0; p < a.params; ++p)
    if (std::strcmp(a.param_names[p], b.param_names[p]) != 0 || !same_limit(a.param_limits[p], b.param_limits[p]))
      return false;
  return true;
}

}  // namespace

int face_corner_count(const tm_element_info& element, int face) {
  const int* nodes = element.faces + element.face_offsets[face];
  int corners = 0;
  while (corners < element.face_sizes[face] && nodes[corners] < element.corner_count) ++corners;
  return corners;
}

const tm_element_info* linear_version(const tm_element_info& element) {
  if (element.order == 1) return &element;
  for (const tm_element_info* linear : Registry::instance().elements())
    if (linear->order == 1 && linear->dim == element.dim && linear->nodes == element.corner_count &&
        std::equal(linear->reference_nodes, linear->reference_nodes + linear->nodes * linear->dim,
                   element.reference_nodes))
      return linear;
  return nullptr;
}

const Registry& Registry::instance() {
  static const Registry registry;
  return registry;
}

Registry::Registry() {
  for (int i = 0; i < tm_kernel_count(); ++i) {
    const tm_kernel* kernel = tm_kernel_at(i);
    kernels_.push_back(kernel);
    by_key_.emplace(key(kernel->law, kernel->element, kernel->split), kernel);
    const tm_kernel* first = laws_by_name_.emplace(kernel->law, kernel).first->second;
    if (!same_parameters(*first, *kernel))
      throw std::logic_error(std::string("kernels of law ") + kernel->law + " differ in their parameters (" +
                             first->element + " and " + kernel->element + "): regenerate the kernels");
  }
  for (int i = 0; i < tm_element_count(); ++i) {
    const tm_element_info* info = tm_element_at(i);
    if (info->nodes > kMaxCellNodes)
      throw std::logic_error(std::string("element ") + info->name + " has " + std::to_string(info->nodes) +
                             " nodes, more than the runtime's per-cell buffers hold (kMaxCellNodes = " +
                             std::to_string(kMaxCellNodes) + " in tensormass/kernels/registry.hpp)");
    elements_.push_back(info);
    elements_by_name_.emplace(info->name, info);
  }
}

std::string Registry::key(std::string_view law, std::string_view element, std::string_view split) {
  std::string result;
  result.reserve(law.size() + element.size() + split.size() + 2);
  result.append(law).append("/").append(element).append("/").append(split);
  return result;
}

const tm_kernel* Registry::find(std::string_view law, std::string_view element, std::string_view split) const {
  const auto found = by_key_.find(key(law, element, split));
  return found == by_key_.end() ? nullptr : found->second;
}

const tm_kernel& Registry::get(std::string_view law, std::string_view element, std::string_view split) const {
  if (const tm_kernel* kernel = find(law, element, split)) return *kernel;
  std::string available;
  for (const tm_kernel* kernel : kernels_)
    if (kernel->element == element || kernel->law == law)
      available +=
          std::string(available.empty() ? "" : ", ") + kernel->law + "/" + kernel->element + "/" + kernel->split;
  throw std::invalid_argument("no kernel for law '" + std::string(law) + "', element '" + std::string(element) +
                              "', split '" + std::string(split) + "'" +
                              (available.empty() ? std::string() : " (related: " + available + ")"));
}

const tm_kernel* Registry::law_kernel(std::string_view law) const {
  const auto found = laws_by_name_.find(std::string(law));
  return found == laws_by_name_.end() ? nullptr : found->second;
}

const tm_element_info* Registry::element(std::string_view name) const {
  const auto found = elements_by_name_.find(std::string(name));
  return found == elements_by_name_.end() ? nullptr : found->second;
}

std::vector<std::string> Registry::laws() const {
  std::set<std::string> names;
  for (const tm_kernel* kernel : kernels_) names.insert(kernel->law);
  return {names.begin(), names.end()};
}

std::vector<std::string> Registry::splits() const {
  std::set<std::string> names;
  for (const tm_kernel* kernel : kernels_) names.insert(kernel->split);
  return {names.begin(), names.end()};
}

bool locking_free_split(const tm_kernel& kernel) {
  return nodal_pressure_split(kernel) || std::string_view(kernel.split) == "fbar";
}

}  // namespace tensormass
