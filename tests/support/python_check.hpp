/// \file python_check.hpp
/// Checks of written mesh files by independent readers: the expectations
/// (exact JSON numbers, meshio cell names) and the checking scripts beside
/// this header, check_msh.py (meshio and the Gmsh API) and check_vtu.py
/// (meshio), run with /usr/bin/python3. For the io writer and beam command tests.
#ifndef TENSORMASS_TESTS_SUPPORT_PYTHON_CHECK_HPP
#define TENSORMASS_TESTS_SUPPORT_PYTHON_CHECK_HPP

#include <charconv>
#include <map>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "support/test_support.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace tmtest {

/// Shortest text that reads back as exactly `value` (Python's float() included).
inline std::string exact(double value) {
  char buffer[32];
  return std::string(buffer, std::to_chars(buffer, buffer + sizeof buffer, value).ptr);
}

template <class T>
std::string json_list(const std::vector<T>& values) {
  std::string text = "[";
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) text += ",";
    if constexpr (std::is_floating_point_v<T>) text += exact(values[i]);
    else text += std::to_string(values[i]);
  }
  return text + "]";
}

/// Runs /usr/bin/python3 tests/support/SCRIPT FILE EXPECTED; 0 when the script is satisfied.
inline int run_check(const std::string& script_name, const std::string& file, const std::string& expected_json) {
  const std::string script = test_support::source_path("tests/support/" + script_name);
  return test_support::python("'" + script + "' '" + file + "' '" + expected_json + "'").exit_code;
}

/// The meshio name of a reference element (as check_msh.py counts cells).
inline std::string meshio_name(const std::string& element) {
  static const std::map<std::string, std::string> names{
      {"tri3", "triangle"}, {"tri6", "triangle6"},  {"quad4", "quad"},      {"quad8", "quad8"},
      {"tet4", "tetra"},    {"tet10", "tetra10"},   {"hex8", "hexahedron"}, {"hex20", "hexahedron20"},
      {"prism6", "wedge"},  {"pyramid5", "pyramid"}};
  return names.at(element);
}

/// check_msh.py's expected JSON for `mesh` written as .msh: points, cell counts and groups.
inline std::string msh_expectation(const tensormass::Mesh& mesh) {
  std::map<std::string, int> cells;
  for (const tensormass::ElementBlock& block : mesh.blocks) cells[meshio_name(block.element->name)] += block.count();
  std::ostringstream json;
  json << "{\"dim\":" << mesh.dim << ",\"points\":" << json_list(mesh.rest_positions) << ",\"cells\":{";
  const char* separator = "";
  for (const auto& [name, count] : cells) {
    json << separator << '"' << name << "\":" << count;
    separator = ",";
  }
  json << "},\"groups\":{";
  separator = "";
  for (const tensormass::Group& group : mesh.groups) {
    const std::size_t count = group.dim == mesh.dim       ? group.cells.size()
                              : group.dim == mesh.dim - 1 ? static_cast<std::size_t>(group.facets.count())
                                                          : group.nodes.size();
    json << separator << '"' << group.name << "\":{\"dim\":" << group.dim << ",\"count\":" << count << "}";
    separator = ",";
  }
  json << "}}";
  return json.str();
}

}  // namespace tmtest

#endif
