/// \file msh_writer.hpp
/// Gmsh mesh output (.msh), ASCII, in format 4.1 (default) or 2.2.
///
/// What is written:
///   nodes     tags 1 .. node_count(), coordinates exact (shortest text
///             that reads back as the same double)
///   cells     tags 1 .. cell_count() in mesh-wide cell order, Gmsh node order
///             (element->gmsh_order)
///   facets    every group's facets as elements of dimension dim-1 (a facet
///             shared by several groups is written once in 4.1), tags after
///             the cells
///   points    group nodes not covered by the group's cells or facets, as
///             point elements (type 15) of a dimension-0 physical group
///   groups    physical tag = index in mesh.groups + 1, named in $PhysicalNames
///             for every dimension the group uses
/// Format 4.1: one entity per distinct set of physical tags (so a cell in
/// `body` and `phase_tet5` lies in one entity carrying both tags), one point
/// entity per point element. Format 2.2: an element in several physical
/// groups is written once per group (as Gmsh itself does), the elementary
/// tag being the 4.1 entity tag.
#ifndef TENSORMASS_IO_MSH_WRITER_HPP
#define TENSORMASS_IO_MSH_WRITER_HPP

#include <string>
#include <string_view>

#include "tensormass/mesh/mesh.hpp"

namespace tensormass::io {

enum class MshFormat { v41, v22 };

/// "4.1" or "2.2"; throws InputError naming the accepted values otherwise.
MshFormat parse_msh_format(std::string_view text);

/// Writes `mesh` to `path` atomically (never a partial file).
/// Throws std::invalid_argument for a facet shape Gmsh cannot name and
/// std::runtime_error when the file cannot be written.
void write_msh(const std::string& path, const Mesh& mesh, MshFormat format = MshFormat::v41);

}  // namespace tensormass::io

#endif
