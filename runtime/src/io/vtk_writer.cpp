// VTK XML writers: .vtu as version 1.0 with UInt64 block headers and raw
// appended binary data (exact doubles, compact, read by ParaView and meshio),
// and .pvd collections.
#include "tensormass/io/vtk_writer.hpp"

#include <bit>
#include <charconv>
#include <cstdint>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "tensormass/io/atomic_file.hpp"

namespace tensormass::io {
namespace {

const char* byte_order() { return std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian"; }

std::string xml_escape(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

/// Shortest text that reads back as exactly `value`.
std::string exact(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

/// The appended-data section: each array is a UInt64 byte count then its
/// bytes. The arrays are written last first: meshio 5.0 (Debian 12) reads
/// them in data order, finding each one's DataArray tag by its offset and
/// rewriting that offset as it goes; a rewritten offset can equal a later
/// array's, and meshio then took the wrong tag (a piece's global_cell read
/// as its law_id). Written last first, each array's tag comes before every
/// tag already rewritten, so meshio's first match is the right one. VTK and
/// ParaView follow the offsets and do not mind the order.
class AppendedData {
 public:
  /// Adds a view of `values`, which must outlive write(); returns the
  /// array's index, for offset(). Nothing is copied: a piece's arrays go
  /// from their vectors to the file.
  template <class T>
  int add(const std::vector<T>& values) {
    arrays_.push_back({reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T)});
    return static_cast<int>(arrays_.size()) - 1;
  }
  /// Where array `index` starts in the section.
  std::size_t offset(int index) const {
    std::size_t offset = 0;
    for (std::size_t later = static_cast<std::size_t>(index) + 1; later < arrays_.size(); ++later)
      offset += sizeof(std::uint64_t) + arrays_[later].size;
    return offset;
  }
  void write(std::ostream& out) const {
    for (auto array = arrays_.rbegin(); array != arrays_.rend(); ++array) {
      out.write(reinterpret_cast<const char*>(&array->size), sizeof array->size);
      out.write(array->bytes, static_cast<std::streamsize>(array->size));
    }
  }

 private:
  struct Array {
    const char* bytes;
    std::uint64_t size;
  };
  std::vector<Array> arrays_;
};

void data_array(std::ostream& xml, const char* type, const std::string& name, int components, std::size_t offset) {
  xml << "        <DataArray type=\"" << type << "\" Name=\"" << xml_escape(name) << "\"";
  if (components > 0) xml << " NumberOfComponents=\"" << components << "\"";
  xml << " format=\"appended\" offset=\"" << offset << "\"/>\n";
}

void check_field(const Field& field, int count, const std::string& path, const char* kind) {
  if (field.components < 1 || field.values.size() != static_cast<std::size_t>(count) * field.components)
    throw std::invalid_argument(path + ": " + kind + " field '" + field.name + "' has " +
                                std::to_string(field.values.size()) + " values, expected " + std::to_string(count) +
                                " by " + std::to_string(field.components));
}

/// Adds the fields' values to `data`; returns their indices.
std::vector<int> add_fields(AppendedData& data, const std::vector<Field>& fields) {
  std::vector<int> indices;
  for (const Field& field : fields) indices.push_back(data.add(field.values));
  return indices;
}

void write_fields(std::ostream& xml, const AppendedData& data, const char* section, const std::vector<Field>& fields,
                  const std::vector<int>& indices) {
  xml << "      <" << section << ">\n";
  for (std::size_t f = 0; f < fields.size(); ++f)
    data_array(xml, "Float64", fields[f].name, fields[f].components, data.offset(indices[f]));
  xml << "      </" << section << ">\n";
}

std::vector<double> current_positions(const Mesh& mesh, const std::vector<double>& displacement,
                                      const std::string& path) {
  std::vector<double> points = mesh.rest_positions;
  if (displacement.empty()) return points;
  if (displacement.size() != points.size())
    throw std::invalid_argument(path + ": displacement has " + std::to_string(displacement.size()) +
                                " values, expected " + std::to_string(points.size()) + " (nodes by 3)");
  for (std::size_t i = 0; i < points.size(); ++i) points[i] += displacement[i];
  return points;
}

struct CellArrays {
  std::vector<std::int64_t> connectivity;
  std::vector<std::int64_t> offsets;
  std::vector<std::uint8_t> types;
};

/// Connectivity in VTK node order (the k-th VTK node is our node
/// vtk_order[k]) of the cells where `keep` is true (every cell when empty),
/// with node numbers through `node_number` (identity when empty).
CellArrays cell_arrays(const Mesh& mesh, const std::vector<bool>& keep = {},
                       const std::vector<std::int64_t>& node_number = {}) {
  CellArrays cells;
  for (const ElementBlock& block : mesh.blocks) {
    const tm_element_info& element = *block.element;
    for (int local = 0; local < block.count(); ++local) {
      if (!keep.empty() && !keep[block.first_cell + local]) continue;
      const std::span<const int> nodes = block.cell_nodes(local);
      for (int k = 0; k < element.nodes; ++k) {
        const int node = nodes[element.vtk_order[k]];
        cells.connectivity.push_back(node_number.empty() ? node : node_number[node]);
      }
      cells.offsets.push_back(static_cast<std::int64_t>(cells.connectivity.size()));
      cells.types.push_back(static_cast<std::uint8_t>(element.vtk_type));
    }
  }
  return cells;
}

/// The entries of `values` (count by components) where `keep` is true, in order.
std::vector<double> kept(const std::vector<double>& values, int components, const std::vector<bool>& keep) {
  std::vector<double> out;
  for (std::size_t i = 0; i < keep.size(); ++i)
    if (keep[i]) out.insert(out.end(), values.begin() + i * components, values.begin() + (i + 1) * components);
  return out;
}

/// One piece: points (by 3), cells, point and cell data (already cut to them).
void write_piece(const std::string& path, const std::vector<double>& points, const CellArrays& cells,
                 const std::vector<Field>& point_data, const std::vector<Field>& cell_data) {
  AppendedData data;  // in the order of the tags below
  const std::vector<int> point_fields = add_fields(data, point_data), cell_fields = add_fields(data, cell_data);
  const int points_array = data.add(points), connectivity_array = data.add(cells.connectivity),
            offsets_array = data.add(cells.offsets), types_array = data.add(cells.types);
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"" << byte_order()
      << "\" header_type=\"UInt64\">\n"
      << "  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << points.size() / 3 << "\" NumberOfCells=\"" << cells.types.size() << "\">\n";
  write_fields(xml, data, "PointData", point_data, point_fields);
  write_fields(xml, data, "CellData", cell_data, cell_fields);
  xml << "      <Points>\n";
  data_array(xml, "Float64", "Points", 3, data.offset(points_array));
  xml << "      </Points>\n      <Cells>\n";
  data_array(xml, "Int64", "connectivity", 0, data.offset(connectivity_array));
  data_array(xml, "Int64", "offsets", 0, data.offset(offsets_array));
  data_array(xml, "UInt8", "types", 0, data.offset(types_array));
  xml << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";
  write_atomically(path, [&](std::ostream& out) {
    out << xml.str();
    data.write(out);
    out << "\n  </AppendedData>\n</VTKFile>\n";
  });
}

}  // namespace

void write_vtu(const std::string& path, const Mesh& mesh, const std::vector<double>& displacement,
               const std::vector<Field>& point_data, const std::vector<Field>& cell_data) {
  for (const Field& field : point_data) check_field(field, mesh.node_count(), path, "point");
  for (const Field& field : cell_data) check_field(field, mesh.cell_count(), path, "cell");
  write_piece(path, current_positions(mesh, displacement, path), cell_arrays(mesh), point_data, cell_data);
}

void write_vtu_piece(const std::string& path, const Mesh& mesh, const std::vector<bool>& cells,
                     const std::vector<double>& displacement, const std::vector<Field>& point_data,
                     const std::vector<Field>& cell_data, std::span<const int> cell_numbers,
                     std::span<const int> node_numbers) {
  if (cells.size() != static_cast<std::size_t>(mesh.cell_count()))
    throw std::invalid_argument(path + ": the piece's cell mask has " + std::to_string(cells.size()) + " entries for " +
                                std::to_string(mesh.cell_count()) + " cells");
  if (!cell_numbers.empty() && cell_numbers.size() != cells.size())
    throw std::invalid_argument(path + ": " + std::to_string(cell_numbers.size()) + " cell numbers for " +
                                std::to_string(cells.size()) + " cells");
  if (!node_numbers.empty() && node_numbers.size() != static_cast<std::size_t>(mesh.node_count()))
    throw std::invalid_argument(path + ": " + std::to_string(node_numbers.size()) + " node numbers for " +
                                std::to_string(mesh.node_count()) + " nodes");
  for (const Field& field : point_data) check_field(field, mesh.node_count(), path, "point");
  for (const Field& field : cell_data) check_field(field, mesh.cell_count(), path, "cell");
  // The points the piece's cells use, numbered in mesh order.
  std::vector<bool> used(mesh.node_count(), false);
  for (const ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local)
      if (cells[block.first_cell + local])
        for (int node : block.cell_nodes(local)) used[node] = true;
  std::vector<std::int64_t> number(mesh.node_count(), -1);
  Field global_node{"global_node", 1, {}}, global_cell{"global_cell", 1, {}};
  for (int node = 0; node < mesh.node_count(); ++node)
    if (used[node])
      number[node] = static_cast<std::int64_t>(global_node.values.size()),
      global_node.values.push_back(node_numbers.empty() ? node : node_numbers[node]);
  for (int cell = 0; cell < mesh.cell_count(); ++cell)
    if (cells[cell]) global_cell.values.push_back(cell_numbers.empty() ? cell : cell_numbers[cell]);
  std::vector<Field> piece_points{global_node}, piece_cells{global_cell};
  for (const Field& field : point_data)
    piece_points.push_back({field.name, field.components, kept(field.values, field.components, used)});
  for (const Field& field : cell_data)
    piece_cells.push_back({field.name, field.components, kept(field.values, field.components, cells)});
  write_piece(path, kept(current_positions(mesh, displacement, path), 3, used), cell_arrays(mesh, cells, number),
              piece_points, piece_cells);
}

void write_pvtu(const std::string& path, const std::vector<std::string>& pieces, const std::vector<Field>& point_data,
                const std::vector<Field>& cell_data) {
  const auto declare = [](std::ostream& xml, const char* section, const std::string& ids,
                          const std::vector<Field>& fields) {
    xml << "    <" << section << ">\n      <PDataArray type=\"Float64\" Name=\"" << ids << "\"/>\n";
    for (const Field& field : fields)
      xml << "      <PDataArray type=\"Float64\" Name=\"" << xml_escape(field.name) << "\" NumberOfComponents=\""
          << field.components << "\"/>\n";
    xml << "    </" << section << ">\n";
  };
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"" << byte_order()
      << "\" header_type=\"UInt64\">\n"
      << "  <PUnstructuredGrid GhostLevel=\"0\">\n";
  declare(xml, "PPointData", "global_node", point_data);
  declare(xml, "PCellData", "global_cell", cell_data);
  xml << "    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n    "
         "</PPoints>\n";
  for (const std::string& piece : pieces) xml << "    <Piece Source=\"" << xml_escape(piece) << "\"/>\n";
  xml << "  </PUnstructuredGrid>\n</VTKFile>\n";
  write_atomically(path, [&](std::ostream& out) { out << xml.str(); });
}

void write_pvd(const std::string& path, const std::vector<SeriesEntry>& entries) {
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"" << byte_order() << "\">\n"
      << "  <Collection>\n";
  for (const SeriesEntry& entry : entries)
    xml << "    <DataSet timestep=\"" << exact(entry.time) << "\" group=\"\" part=\"0\" file=\""
        << xml_escape(entry.file) << "\"/>\n";
  xml << "  </Collection>\n</VTKFile>\n";
  write_atomically(path, [&](std::ostream& out) { out << xml.str(); });
}

}  // namespace tensormass::io
