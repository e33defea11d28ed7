/// \file vtk_writer.hpp
/// VTK XML unstructured-grid output (.vtu), its parallel form (one .vtu
/// piece per MPI rank named by a .pvtu) and ParaView collections (.pvd).
#ifndef TENSORMASS_IO_VTU_WRITER_HPP
#define TENSORMASS_IO_VTU_WRITER_HPP

#include <span>
#include <string>
#include <vector>

#include "tensormass/io/field.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace tensormass::io {

/// Writes the mesh's cells (all blocks, VTK node order, positions = rest +
/// displacement when `displacement` is non-empty (node_count by 3)) with
/// point and cell data, atomically. Cell data are in mesh-wide cell order.
void write_vtu(const std::string& path, const Mesh& mesh, const std::vector<double>& displacement,
               const std::vector<Field>& point_data, const std::vector<Field>& cell_data);

/// One piece of a parallel dataset: the cells of `mesh` where `cells`
/// (cell_count) is true and the points they use, renumbered in mesh order.
/// Point and cell data are given for the whole mesh, as for write_vtu, and
/// cut the same way; each piece also holds `global_node` (point data) and
/// `global_cell` (cell data), the whole mesh's numbers: a node's or cell's
/// index in `mesh`, or `node_numbers[node]` and `cell_numbers[cell]` when
/// given (a mesh that is part of a larger one; node_count and cell_count long).
void write_vtu_piece(const std::string& path, const Mesh& mesh, const std::vector<bool>& cells,
                     const std::vector<double>& displacement, const std::vector<Field>& point_data,
                     const std::vector<Field>& cell_data, std::span<const int> cell_numbers = {},
                     std::span<const int> node_numbers = {});
/// The .pvtu that joins `pieces` (file names relative to it) written by
/// write_vtu_piece with these fields (only their names and components are read).
void write_pvtu(const std::string& path, const std::vector<std::string>& pieces, const std::vector<Field>& point_data,
                const std::vector<Field>& cell_data);

/// One entry of a ParaView collection: time and file name relative to the .pvd.
struct SeriesEntry {
  double time;
  std::string file;
};
void write_pvd(const std::string& path, const std::vector<SeriesEntry>& entries);

}  // namespace tensormass::io

#endif
