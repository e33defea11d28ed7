/// \file vtu_writer.hpp
/// VTK XML unstructured-grid output (.vtu) and ParaView collections (.pvd).
#ifndef TENSORMASS_IO_VTU_WRITER_HPP
#define TENSORMASS_IO_VTU_WRITER_HPP

#include <string>
#include <vector>

#include "tensormass/mesh/mesh.hpp"

namespace tensormass::io {

/// One data array: `components` values per point (or per cell), flattened.
struct Field {
  std::string name;
  int components = 1;
  std::vector<double> values;  ///< count by components
};

/// Writes the mesh's cells (all blocks, VTK node order, positions = rest +
/// displacement when `displacement` is non-empty (node_count by 3)) with
/// point and cell data, atomically. Cell data are in mesh-wide cell order.
void write_vtu(const std::string& path, const Mesh& mesh, const std::vector<double>& displacement,
               const std::vector<Field>& point_data, const std::vector<Field>& cell_data);

/// One entry of a ParaView collection: time and file name relative to the .pvd.
struct SeriesEntry {
  double time;
  std::string file;
};
void write_pvd(const std::string& path, const std::vector<SeriesEntry>& entries);

}  // namespace tensormass::io

#endif
