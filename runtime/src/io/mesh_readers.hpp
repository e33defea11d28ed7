/// \file mesh_readers.hpp
/// Internal (not installed): the format readers behind read_mesh
/// (tensormass/io/read_mesh.hpp) and read_surface
/// (tensormass/io/surface_reader.hpp), on bytes already in memory. The
/// fuzzers (fuzz/) call the *_data entry points directly.
#ifndef TENSORMASS_IO_MESH_READERS_HPP
#define TENSORMASS_IO_MESH_READERS_HPP

#include <string>
#include <string_view>

#include "common/input_cursor.hpp"
#include "tensormass/mesh/mesh.hpp"
#include "tensormass/surface/surface.hpp"

namespace tensormass::detail {

/// What read_mesh does once the file is read: `data` is read as the format
/// `path`'s extension names (.msh, .vtu, .vtk); `path` names it in messages.
Mesh read_mesh_data(const std::string& path, std::string data);
/// Reads a Gmsh .msh file (2.2 or 4.1, ASCII or binary) held in `input`.
Mesh read_gmsh(InputCursor& input);
/// Reads a VTK XML unstructured grid (.vtu).
Mesh read_vtu(InputCursor& input);
/// Reads a legacy VTK unstructured grid (.vtk, ASCII or BINARY).
Mesh read_legacy_vtk(InputCursor& input);

/// What read_surface does once an .stl or .obj file is read (a Gmsh .msh
/// surface is read by the Gmsh API from its path, so not from memory).
TriangleSurface read_surface_data(const std::string& path, std::string_view data);

}  // namespace tensormass::detail

#endif
