/// \file mesh_readers.hpp
/// Internal (not installed): the format readers behind read_mesh
/// (tensormass/io/read_mesh.hpp), each on a file held in an InputCursor.
#ifndef TENSORMASS_IO_MESH_READERS_HPP
#define TENSORMASS_IO_MESH_READERS_HPP

#include "io/input_cursor.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace tensormass::detail {

/// Reads a Gmsh .msh file (2.2 or 4.1, ASCII or binary) held in `input`.
Mesh read_gmsh(InputCursor& input);
/// Reads a VTK XML unstructured grid (.vtu).
Mesh read_vtu(InputCursor& input);
/// Reads a legacy VTK unstructured grid (.vtk, ASCII or BINARY).
Mesh read_legacy_vtk(InputCursor& input);

}  // namespace tensormass::detail

#endif
