/// \file surface_reader.hpp
/// Closed triangle surface input (.stl ASCII/binary, .obj, Gmsh .msh); the
/// surface itself and its checks are in surface/surface.hpp.
#ifndef TENSORMASS_IO_SURFACE_READER_HPP
#define TENSORMASS_IO_SURFACE_READER_HPP

#include <string>

#include "tensormass/surface/surface.hpp"

namespace tensormass {

/// Reads a surface by extension (case-insensitive):
/// - .stl, ASCII or binary, told apart by content (a binary file may start
///   with "solid": binary when 84 + 50 n equals the file size, n the count at
///   byte 80). Each `solid NAME ... endsolid` block of an ASCII file is a
///   patch named NAME; a binary file is one patch named "".
/// - .obj: `v` and `f` lines (f corners may be i, i/t, i//n, i/t/n, negative
///   indices count back from the last vertex); polygons are fan-triangulated;
///   `g` and `o` names become patches; other lines are ignored.
/// - .msh: a Gmsh mesh read with the Gmsh API; its 3-node triangles (type 2)
///   are the surface, the physical group names of their entities the
///   patches. Gmsh is initialised and finalised around the read, so it must
///   not be called while another part of the program holds a Gmsh session.
/// Coincident points (exact coordinate match) are merged and points used by
/// no triangle dropped, in every format. Throws InputError naming the file and
/// line (or byte offset) on any bad input: missing file, unknown extension,
/// truncated, garbage or non-finite numbers, empty surface, index out of range.
TriangleSurface read_surface(const std::string& path);

}  // namespace tensormass

#endif
