// read_mesh: opens a file and hands it to the reader its extension names.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "mesh_builder.hpp"
#include "tensormass/errors.hpp"
#include "tensormass/mesh.hpp"

namespace tensormass {

namespace {

std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

std::string read_whole_file(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) throw InputError(path + ": is a directory, not a mesh file");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError(path + ": cannot open mesh file (" + std::strerror(errno) + ")");
  std::ostringstream content;
  content << file.rdbuf();
  if (file.bad()) throw InputError(path + ": read error");
  return std::move(content).str();
}

}  // namespace

Mesh read_mesh(const std::string& path) {
  const std::string extension = lower_extension(path);
  if (extension != ".msh" && extension != ".vtu" && extension != ".vtk")
    throw InputError(path + ": unknown mesh format '" + extension + "' (expected .msh, .vtu or .vtk)");
  detail::InputCursor input(path, read_whole_file(path));
  if (input.at_end()) throw InputError(path + ": the file is empty");
  if (extension == ".msh") return detail::read_gmsh(input);
  if (extension == ".vtu") return detail::read_vtu(input);
  return detail::read_legacy_vtk(input);
}

}  // namespace tensormass
