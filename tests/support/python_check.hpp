/// \file python_check.hpp
/// Helpers of the io and beam tests: scratch directories, exact JSON numbers,
/// and running the meshio/Gmsh checking scripts (check_vtu.py, check_msh.py)
/// with /usr/bin/python3.
#ifndef TENSORMASS_TESTS_IO_PYTHON_CHECK_HPP
#define TENSORMASS_TESTS_IO_PYTHON_CHECK_HPP

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <type_traits>
#include <string>
#include <vector>

#include "tensormass/mesh/mesh.hpp"

namespace tmtest {

/// A fresh empty directory, removed with its content on destruction.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag) {
    static int counter = 0;
    path_ = std::filesystem::temp_directory_path() /
            ("tensormass_" + tag + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  /// Names of the files in the directory, sorted.
  std::vector<std::string> files() const {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(path_)) names.push_back(entry.path().filename());
    std::sort(names.begin(), names.end());
    return names;
  }

 private:
  std::filesystem::path path_;
};

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

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

inline std::string script(const std::string& name) {
  return std::string(TENSORMASS_SOURCE_DIR) + "/tests/support/" + name;
}

/// Exit status of a shell command (-1 when it did not exit normally).
inline int run_command(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Runs /usr/bin/python3 SCRIPT FILE EXPECTED; 0 when the script is satisfied.
inline int run_check(const std::string& script_name, const std::string& file, const std::string& expected_json) {
  return run_command("/usr/bin/python3 '" + script(script_name) + "' '" + file + "' '" + expected_json + "'");
}

/// The meshio name of a reference element (as check_msh.py counts cells).
inline std::string meshio_name(const std::string& element) {
  static const std::map<std::string, std::string> names{
      {"tri3", "triangle"}, {"tri6", "triangle6"}, {"quad4", "quad"},     {"quad8", "quad8"},
      {"tet4", "tetra"},    {"tet10", "tetra10"},  {"hex8", "hexahedron"}, {"hex20", "hexahedron20"},
      {"prism6", "wedge"},  {"pyramid5", "pyramid"}};
  return names.at(element);
}

/// Cells per reference element name.
inline std::map<std::string, int> element_counts(const tensormass::Mesh& mesh) {
  std::map<std::string, int> counts;
  for (const tensormass::ElementBlock& block : mesh.blocks) counts[block.element->name] += block.count();
  return counts;
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
