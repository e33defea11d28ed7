/// \file read_mesh.hpp
/// Volume mesh input: the reader is chosen by the file's extension (the
/// writers of the same formats are gmsh_writer.hpp and vtk_writer.hpp).
#ifndef TENSORMASS_IO_READ_MESH_HPP
#define TENSORMASS_IO_READ_MESH_HPP

#include <string>

#include "tensormass/mesh/mesh.hpp"

namespace tensormass {

/// Reads a mesh by extension: .msh (Gmsh 2.2 or 4.1, ASCII or binary),
/// .vtu (XML, ASCII/base64 appended or inline, no compression) or .vtk
/// (legacy ASCII/binary unstructured grid). Throws InputError naming the file
/// and line (or byte offset) on any bad input, before allocating for absurd counts.
Mesh read_mesh(const std::string& path);

}  // namespace tensormass

#endif
