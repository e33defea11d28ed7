// VTK XML unstructured grid reader (.vtu): DataArrays in ascii, inline
// base64 or appended raw/base64 form, UInt32 or UInt64 headers, either byte
// order, no compression; several pieces are concatenated. The XML is read
// by XmlDocument (io/xml_document.hpp).
#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_readers.hpp"
#include "io/vtk_cells.hpp"
#include "io/xml_document.hpp"

namespace tensormass::detail {

namespace vtk {
namespace {

std::size_t vtu_type_size(std::string_view type) {
  if (type == "Int8" || type == "UInt8") return 1;
  if (type == "Int16" || type == "UInt16") return 2;
  if (type == "Int32" || type == "UInt32" || type == "Float32") return 4;
  if (type == "Int64" || type == "UInt64" || type == "Float64") return 8;
  return 0;
}

/// The value of type T stored at `bytes` in byte order `order`.
template <class T>
T load_raw(const unsigned char* bytes, std::endian order) {
  unsigned char buffer[sizeof(T)];
  std::copy_n(bytes, sizeof(T), buffer);
  if (order != std::endian::native) std::reverse(buffer, buffer + sizeof(T));
  T value;
  std::memcpy(&value, buffer, sizeof(T));
  return value;
}

template <class T>
double load(const unsigned char* bytes, std::endian order) {
  return static_cast<double>(load_raw<T>(bytes, order));
}

double load_value(const unsigned char* bytes, std::string_view type, std::endian order) {
  if (type == "Int8") return load<std::int8_t>(bytes, order);
  if (type == "UInt8") return load<std::uint8_t>(bytes, order);
  if (type == "Int16") return load<std::int16_t>(bytes, order);
  if (type == "UInt16") return load<std::uint16_t>(bytes, order);
  if (type == "Int32") return load<std::int32_t>(bytes, order);
  if (type == "UInt32") return load<std::uint32_t>(bytes, order);
  if (type == "Int64") return load<std::int64_t>(bytes, order);
  if (type == "UInt64") return load<std::uint64_t>(bytes, order);
  if (type == "Float32") return load<float>(bytes, order);
  return load<double>(bytes, order);
}

class VtuReader {
 public:
  explicit VtuReader(InputCursor& in) : in_(in), xml_(in), data_bytes_left_(in.data().size()) {}
  Mesh read();

 private:
  struct Array {
    const XmlElement* element;
    std::string name;
    std::string type;
    std::size_t size;
  };
  Location where(const XmlElement& e) const { return {e.line, false}; }
  [[noreturn]] void fail(const XmlElement& e, const std::string& message) const { in_.fail_at(where(e), message); }
  void read_piece(const XmlElement& piece);
  long count_attribute(const XmlElement& e, std::string_view key, std::size_t min_bytes_each) const;
  std::vector<double> read_array(const XmlElement& e, long expected, long components);
  std::vector<double> ascii_values(const Array& array);
  std::vector<double> inline_values(const Array& array);
  std::vector<double> appended_values(const Array& array);
  std::vector<double> convert(const Array& array, std::span<const unsigned char> bytes) const;
  void take_data_bytes(const Array& array, std::size_t bytes, Location at);
  std::size_t header_value(const Array& array, std::span<const unsigned char> bytes, Location at) const;
  const XmlElement* data_array(const XmlElement* parent, std::string_view name) const;

  InputCursor& in_;
  XmlDocument xml_;
  std::endian order_ = std::endian::little;
  std::size_t header_size_ = 4;
  Grid grid_;
  bool every_piece_has_regions_ = true;
  /// What the arrays may still decode, in bytes: each byte of the file holds
  /// at most one byte of array data (or one ASCII value), so arrays that
  /// share appended data, or declare more than they hold, are refused
  /// before their memory is taken.
  std::size_t data_bytes_left_;
};

Mesh VtuReader::read() {
  const XmlElement& root = xml_.elements.front();
  if (root.name != "VTKFile") fail(root, "not a VTK XML file (root element <" + root.name + ">)");
  if (root.attribute("type") != "UnstructuredGrid")
    fail(root, "VTK XML file of type '" + root.attribute("type") + "': only UnstructuredGrid (.vtu) is supported");
  if (!root.attribute("compressor").empty())
    fail(root, "compressed data (" + root.attribute("compressor") +
                   ") is not supported; write the file without compression (ParaView: Data Mode 'Binary' or 'Ascii' "
                   "with compressor 'None'; meshio: compression=None)");
  const std::string byte_order = root.attribute("byte_order", "LittleEndian");
  if (byte_order != "LittleEndian" && byte_order != "BigEndian") fail(root, "unknown byte_order '" + byte_order + "'");
  order_ = byte_order == "BigEndian" ? std::endian::big : std::endian::little;
  const std::string header_type = root.attribute("header_type", "UInt32");
  if (header_type != "UInt32" && header_type != "UInt64")
    fail(root, "header_type '" + header_type + "' is not UInt32 or UInt64");
  header_size_ = header_type == "UInt64" ? 8 : 4;
  const XmlElement* grid = xml_.child(&root, "UnstructuredGrid");
  if (!grid) fail(root, "no <UnstructuredGrid> element");
  const auto pieces = xml_.children(grid, "Piece");
  if (pieces.empty()) fail(*grid, "no <Piece> element");
  for (const XmlElement* piece : pieces) read_piece(*piece);
  if (!every_piece_has_regions_) grid_.regions.clear();
  return build_mesh(in_, grid_);
}

long VtuReader::count_attribute(const XmlElement& e, std::string_view key, std::size_t min_bytes_each) const {
  long n = 0;
  if (!parse_integer(e.attribute(key), n) || n < 0) fail(e, "<" + e.name + "> needs a count " + std::string(key));
  if (static_cast<std::size_t>(n) > in_.data().size() / min_bytes_each)
    fail(e, std::string(key) + "=" + std::to_string(n) + " is more than the file (" +
                std::to_string(in_.data().size()) + " bytes) can hold: truncated file or bad count");
  return in_.checked_count(static_cast<unsigned long long>(n), key, 0, where(e));
}

const XmlElement* VtuReader::data_array(const XmlElement* parent, std::string_view name) const {
  for (const XmlElement* array : xml_.children(parent, "DataArray"))
    if (array->attribute("Name") == name) return array;
  return nullptr;
}

void VtuReader::read_piece(const XmlElement& piece) {
  const long points = count_attribute(piece, "NumberOfPoints", 3);
  const long cells = count_attribute(piece, "NumberOfCells", 1);
  const long base = static_cast<long>(grid_.points.size() / 3);
  const XmlElement* points_element = xml_.child(&piece, "Points");
  const XmlElement* point_array = points_element ? xml_.child(points_element, "DataArray") : nullptr;
  if (!point_array) fail(piece, "<Piece> without <Points><DataArray>");
  grid_.points_where = where(*point_array);
  const std::vector<double> xyz = read_array(*point_array, 3 * points, 3);
  grid_.points.insert(grid_.points.end(), xyz.begin(), xyz.end());

  const XmlElement* cells_element = xml_.child(&piece, "Cells");
  if (!cells_element) fail(piece, "<Piece> without <Cells>");
  const XmlElement* connectivity = data_array(cells_element, "connectivity");
  const XmlElement* offsets = data_array(cells_element, "offsets");
  const XmlElement* types = data_array(cells_element, "types");
  if (!connectivity || !offsets || !types)
    fail(*cells_element, "<Cells> needs DataArrays connectivity, offsets and types");
  const std::vector<long> ends = to_integers(in_, read_array(*offsets, cells, 1), where(*offsets), "offsets");
  const std::vector<long> nodes = to_integers(in_, read_array(*connectivity, ends.empty() ? 0 : ends.back(), 1),
                                              where(*connectivity), "connectivity");
  const std::vector<long> cell_types = to_integers(in_, read_array(*types, cells, 1), where(*types), "types");
  const long first = grid_.offsets.back();
  const std::size_t first_cell = grid_.offsets.size() - 1;
  for (long end : ends) grid_.offsets.push_back(first + end);
  for (long node : nodes) grid_.connectivity.push_back(node + base);
  grid_.types.insert(grid_.types.end(), cell_types.begin(), cell_types.end());
  grid_.cell_where.insert(grid_.cell_where.end(), static_cast<std::size_t>(cells), where(*connectivity));
  check_offsets(in_, grid_, where(*offsets), first_cell);

  std::vector<long> regions;
  int priority = 99;
  if (const XmlElement* cell_data = xml_.child(&piece, "CellData"))
    for (const XmlElement* array : xml_.children(cell_data, "DataArray")) {
      const int p = region_priority(array->attribute("Name"));
      if (p < 0 || p >= priority || array->attribute("type").starts_with("Float")) continue;
      if (array->attribute("NumberOfComponents", "1") != "1") continue;
      regions = to_integers(in_, read_array(*array, cells, 1), where(*array), array->attribute("Name"));
      priority = p;
    }
  if (regions.empty() && cells > 0) every_piece_has_regions_ = false;
  grid_.regions.insert(grid_.regions.end(), regions.begin(), regions.end());
}

std::vector<double> VtuReader::read_array(const XmlElement& e, long expected, long components) {
  Array array{&e, e.attribute("Name"), e.attribute("type"), vtu_type_size(e.attribute("type"))};
  if (array.size == 0) fail(e, "DataArray '" + array.name + "' has unsupported type '" + array.type + "'");
  long found_components = 1;
  if (!parse_integer(e.attribute("NumberOfComponents", "1"), found_components) || found_components != components)
    fail(e, "DataArray '" + array.name + "' must have " + std::to_string(components) + " component(s)");
  const std::string format = e.attribute("format", "ascii");
  std::vector<double> values;
  if (format == "ascii") values = ascii_values(array);
  else if (format == "binary") values = inline_values(array);
  else if (format == "appended") values = appended_values(array);
  else fail(e, "DataArray '" + array.name + "' has unknown format '" + format + "'");
  if (static_cast<long>(values.size()) != expected)
    fail(e, "DataArray '" + array.name + "' has " + std::to_string(values.size()) + " values, expected " +
                std::to_string(expected));
  return values;
}

void VtuReader::take_data_bytes(const Array& array, std::size_t bytes, Location at) {
  if (bytes > data_bytes_left_)
    in_.fail_at(at, "DataArray '" + array.name + "' brings the arrays to more data in total than the file's " +
                        std::to_string(in_.data().size()) +
                        " bytes hold (arrays sharing appended data, or a bad size)");
  data_bytes_left_ -= bytes;
}

std::vector<double> VtuReader::ascii_values(const Array& array) {
  std::vector<double> values;
  const std::string_view text =
      in_.data().substr(array.element->content_begin, array.element->content_end - array.element->content_begin);
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    const std::size_t begin = i;
    while (i < text.size() && !std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    if (i == begin) break;
    double value = 0;
    if (!parse_real(text.substr(begin, i - begin), value))
      in_.fail_at({in_.line_at(array.element->content_begin + begin), false},
                  "bad number '" + std::string(text.substr(begin, std::min<std::size_t>(i - begin, 40))) +
                      "' in DataArray '" + array.name + "'");
    values.push_back(value);
  }
  take_data_bytes(array, values.size(), where(*array.element));
  return values;
}

/// Read as an integer, not through a double (2^64 - 1 would round to 2^64,
/// which no size_t holds), and refused when larger than the whole file, so
/// that the sizes computed from it cannot overflow. `at`: where it was read.
std::size_t VtuReader::header_value(const Array& array, std::span<const unsigned char> bytes, Location at) const {
  const std::uint64_t value =
      header_size_ == 8 ? load_raw<std::uint64_t>(bytes.data(), order_) : load_raw<std::uint32_t>(bytes.data(), order_);
  if (value > in_.data().size())
    in_.fail_at(at, "DataArray '" + array.name + "' declares " + std::to_string(value) +
                        " bytes, more than the whole file holds (" + std::to_string(in_.data().size()) + ")");
  return static_cast<std::size_t>(value);
}

std::vector<double> VtuReader::convert(const Array& array, std::span<const unsigned char> bytes) const {
  if (bytes.size() % array.size != 0)
    fail(*array.element, "DataArray '" + array.name + "' holds " + std::to_string(bytes.size()) +
                             " bytes, not a multiple of its type size");
  std::vector<double> values(bytes.size() / array.size);
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i] = load_value(bytes.data() + i * array.size, array.type, order_);
  return values;
}

std::vector<double> VtuReader::inline_values(const Array& array) {
  std::string text;
  for (std::size_t i = array.element->content_begin; i < array.element->content_end; ++i)
    if (!std::isspace(static_cast<unsigned char>(in_.data()[i]))) text += in_.data()[i];
  const std::size_t header_chars = base64_length(header_size_);
  std::vector<unsigned char> header;
  std::vector<unsigned char> data;
  const std::string bad = "DataArray '" + array.name + "': invalid or truncated base64 data";
  if (text.size() < header_chars || !base64_decode(std::string_view(text).substr(0, header_chars), header) ||
      header.size() < header_size_)
    fail(*array.element, bad);
  const std::size_t bytes = header_value(array, header, where(*array.element));
  take_data_bytes(array, bytes, where(*array.element));
  if (text[header_chars - 1] == '=') {  // header and data encoded separately (VTK)
    if (base64_length(bytes) > text.size() - header_chars)
      fail(*array.element, bad + " (" + std::to_string(bytes) + " bytes declared)");
    if (!base64_decode(std::string_view(text).substr(header_chars, base64_length(bytes)), data))
      fail(*array.element, bad);
    data.resize(std::min(data.size(), bytes));
  } else {  // header and data encoded together (meshio)
    if (base64_length(header_size_ + bytes) > text.size())
      fail(*array.element, bad + " (" + std::to_string(bytes) + " bytes declared)");
    if (!base64_decode(std::string_view(text).substr(0, base64_length(header_size_ + bytes)), data))
      fail(*array.element, bad);
    data.erase(data.begin(), data.begin() + static_cast<std::ptrdiff_t>(header_size_));
    data.resize(std::min(data.size(), bytes));
  }
  if (data.size() < bytes) fail(*array.element, bad);
  return convert(array, data);
}

std::vector<double> VtuReader::appended_values(const Array& array) {
  if (xml_.appended_begin == std::string::npos)
    fail(*array.element, "DataArray '" + array.name + "' is appended but the file has no <AppendedData>");
  long offset = 0;
  if (!parse_integer(array.element->attribute("offset"), offset) || offset < 0)
    fail(*array.element, "DataArray '" + array.name + "' needs an offset");
  const std::string_view data = in_.data();
  const std::size_t start = xml_.appended_begin + static_cast<std::size_t>(offset);
  const Location at{static_cast<long>(start), true};
  if (start > data.size()) in_.fail_at(at, "appended data of '" + array.name + "' starts past the end of the file");
  if (xml_.appended_encoding == "raw") {
    if (data.size() - start < header_size_) in_.fail_at(at, "truncated appended data of '" + array.name + "'");
    const auto* bytes = reinterpret_cast<const unsigned char*>(data.data()) + start;
    const std::size_t size = header_value(array, {bytes, header_size_}, at);
    if (size > data.size() - start - header_size_)
      in_.fail_at(at, "appended array '" + array.name + "' declares " + std::to_string(size) + " bytes but only " +
                          std::to_string(data.size() - start - header_size_) + " are left");
    take_data_bytes(array, size, at);
    return convert(array, {bytes + header_size_, size});
  }
  if (xml_.appended_encoding != "base64")
    fail(*array.element, "unknown AppendedData encoding '" + xml_.appended_encoding + "'");
  const std::string_view text = data.substr(start);
  const std::size_t header_chars = base64_length(header_size_);
  std::vector<unsigned char> header;
  std::vector<unsigned char> bytes;
  const std::string bad = "invalid or truncated base64 appended data of '" + array.name + "'";
  if (text.size() < header_chars || !base64_decode(text.substr(0, header_chars), header) ||
      header.size() < header_size_)
    in_.fail_at(at, bad);
  const std::size_t size = header_value(array, header, at);
  take_data_bytes(array, size, at);
  const bool separate = text[header_chars - 1] == '=';
  const std::size_t first = separate ? header_chars : 0;
  const std::size_t length = separate ? base64_length(size) : base64_length(header_size_ + size);
  if (length > text.size() - first || !base64_decode(text.substr(first, length), bytes)) in_.fail_at(at, bad);
  if (!separate)
    bytes.erase(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(std::min(bytes.size(), header_size_)));
  if (bytes.size() < size) in_.fail_at(at, bad);
  bytes.resize(size);
  return convert(array, bytes);
}

}  // namespace
}  // namespace vtk

Mesh read_vtu(InputCursor& input) { return vtk::VtuReader(input).read(); }

}  // namespace tensormass::detail
