#include "tensormass/kernels/registry.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>

namespace tensormass {

const Registry& Registry::instance() {
  static const Registry registry;
  return registry;
}

Registry::Registry() {
  for (int i = 0; i < tm_kernel_count(); ++i) {
    const tm_kernel* kernel = tm_kernel_at(i);
    kernels_.push_back(kernel);
    by_key_.emplace(key(kernel->law, kernel->element, kernel->split), kernel);
  }
  for (int i = 0; i < tm_element_count(); ++i) {
    const tm_element_info* info = tm_element_at(i);
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

}  // namespace tensormass
