/// \file gmsh_order.hpp
/// Second-order meshes from first-order ones by Gmsh's own high-order
/// meshing (gmsh::model::mesh::setOrder): a .msh file raised to order 2,
/// the groups kept, the new nodes placed by Gmsh at edge midpoints (and, for
/// its complete elements, at face and cell centres).
#ifndef TENSORMASS_MESHING_GMSH_ORDER_HPP
#define TENSORMASS_MESHING_GMSH_ORDER_HPP

#include <string>

#include "tensormass/io/gmsh_writer.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace tensormass {

struct RaiseOrderSpec {
  std::string input;   ///< a first-order Gmsh .msh file (2.2 or 4.1)
  std::string output;  ///< the .msh file to write
  /// Gmsh's complete elements (quad9, hex27; prism18 and pyramid14, which the
  /// registry lacks); else its serendipity ones (tri6, quad8, tet10, hex20,
  /// prism15, pyramid13).
  bool complete = false;
  io::MshFormat format = io::MshFormat::v41;
};

/// Reads `input` with the project's reader first (bad input: InputError
/// naming the file and line; a mesh that is not first order is refused), has
/// Gmsh raise it to order 2, checks that the project reads Gmsh's result
/// (every element in the registry), writes it to `output` atomically and
/// returns it. InputError, and nothing written, when Gmsh fails or makes an
/// element the registry lacks (naming it).
Mesh raise_order_with_gmsh(const RaiseOrderSpec& spec);

}  // namespace tensormass

#endif
