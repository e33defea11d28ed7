// read_mesh: opens a file and hands it to the reader its extension names.
#include "tensormass/io/read_mesh.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <new>

#include "common/input_cursor.hpp"
#include "common/regular_file.hpp"
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

/// Refuses extensions no reader takes, before the file is opened.
void check_extension(const std::string& path, const std::string& extension) {
  if (extension != ".msh" && extension != ".vtu" && extension != ".vtk")
    throw InputError(path + ": unknown mesh format '" + extension + "' (expected .msh, .vtu or .vtk)");
}

}  // namespace

namespace detail {

Mesh read_mesh_data(const std::string& path, std::string data) {
  const std::string extension = lower_extension(path);
  check_extension(path, extension);
  InputCursor input(path, std::move(data));
  if (input.at_end()) throw InputError(path + ": the file is empty");
  if (extension == ".msh") return read_gmsh(input);
  if (extension == ".vtu") return read_vtu(input);
  return read_legacy_vtk(input);
}

}  // namespace detail

Mesh read_mesh(const std::string& path) {
  check_extension(path, lower_extension(path));
  try {
    return detail::read_mesh_data(path, detail::read_regular_file(path, "mesh"));
  } catch (const std::bad_alloc&) {  // a mesh too large for this machine: say which file
    throw InputError(path + ": not enough memory to read this mesh");
  }
}

}  // namespace tensormass
