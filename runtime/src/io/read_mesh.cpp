// read_mesh: opens a file and hands it to the reader its extension names.
#include "tensormass/io/read_mesh.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/input_cursor.hpp"
#include "io/mesh_readers.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass {

namespace {

std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

}  // namespace

Mesh read_mesh(const std::string& path) {
  const std::string extension = lower_extension(path);
  if (extension != ".msh" && extension != ".vtu" && extension != ".vtk")
    throw InputError(path + ": unknown mesh format '" + extension + "' (expected .msh, .vtu or .vtk)");
  detail::InputCursor input(path, detail::read_whole_file(path, "mesh"));
  if (input.at_end()) throw InputError(path + ": the file is empty");
  if (extension == ".msh") return detail::read_gmsh(input);
  if (extension == ".vtu") return detail::read_vtu(input);
  return detail::read_legacy_vtk(input);
}

}  // namespace tensormass
