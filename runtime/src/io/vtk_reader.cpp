// VTK readers: XML unstructured grids (.vtu; DataArrays in ascii, inline
// base64 or appended raw/base64 form, UInt32 or UInt64 headers, no
// compression) and legacy files (.vtk; ASCII or big-endian BINARY,
// DATASET UNSTRUCTURED_GRID, both the classic CELLS layout and the
// OFFSETS/CONNECTIVITY layout of version 5). The XML is read by a tiny
// tokenizer: elements, attributes and content ranges, nothing more.
#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "io/mesh_readers.hpp"
#include "mesh/mesh_builder.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass::detail {

namespace {

// ---------------------------------------------------------------- cells

struct VtkType {
  long id;
  const char* name;
};

constexpr VtkType kVtkTypes[] = {
    {1, "VTK_VERTEX"},
    {2, "VTK_POLY_VERTEX"},
    {3, "VTK_LINE"},
    {4, "VTK_POLY_LINE"},
    {5, "VTK_TRIANGLE"},
    {6, "VTK_TRIANGLE_STRIP"},
    {7, "VTK_POLYGON"},
    {8, "VTK_PIXEL"},
    {9, "VTK_QUAD"},
    {10, "VTK_TETRA"},
    {11, "VTK_VOXEL"},
    {12, "VTK_HEXAHEDRON"},
    {13, "VTK_WEDGE"},
    {14, "VTK_PYRAMID"},
    {15, "VTK_PENTAGONAL_PRISM"},
    {16, "VTK_HEXAGONAL_PRISM"},
    {21, "VTK_QUADRATIC_EDGE"},
    {22, "VTK_QUADRATIC_TRIANGLE"},
    {23, "VTK_QUADRATIC_QUAD"},
    {24, "VTK_QUADRATIC_TETRA"},
    {25, "VTK_QUADRATIC_HEXAHEDRON"},
    {26, "VTK_QUADRATIC_WEDGE"},
    {27, "VTK_QUADRATIC_PYRAMID"},
    {28, "VTK_BIQUADRATIC_QUAD"},
    {29, "VTK_TRIQUADRATIC_HEXAHEDRON"},
    {42, "VTK_POLYHEDRON"},
    {68, "VTK_LAGRANGE_CURVE"},
    {69, "VTK_LAGRANGE_TRIANGLE"},
    {70, "VTK_LAGRANGE_QUADRILATERAL"},
    {71, "VTK_LAGRANGE_TETRAHEDRON"},
    {72, "VTK_LAGRANGE_HEXAHEDRON"},
};

std::string vtk_type_name(long id) {
  for (const VtkType& type : kVtkTypes)
    if (type.id == id) return type.name;
  return "unknown";
}

/// Our shape of a VTK cell type and order[k] = our index of the k-th VTK node (nullptr: same).
struct Mapping {
  const Shape* shape = nullptr;
  const int* order = nullptr;
};

Mapping vtk_mapping(long id) {
  if (id == 1) return {find_shape("point"), nullptr};
  if (id == 3) return {find_shape("line2"), nullptr};
  if (id == 21) return {find_shape("line3"), nullptr};
  for (const tm_element_info* element : Registry::instance().elements())
    if (element->vtk_type == id) return {shape_of(element), element->vtk_order};
  return {};
}

std::string supported_list() {
  std::string text = "VTK_VERTEX (1), VTK_LINE (3), VTK_QUADRATIC_EDGE (21)";
  for (const tm_element_info* element : Registry::instance().elements())
    text += ", " + vtk_type_name(element->vtk_type) + " (" + std::to_string(element->vtk_type) + ")";
  return text;
}

/// Cell data arrays that define groups, best first.
int region_priority(std::string_view name) {
  if (name == "gmsh:physical") return 0;
  if (name == "region") return 1;
  if (name == "group") return 2;
  return -1;
}

/// An unstructured grid as read, before mapping to our elements.
struct Grid {
  std::vector<double> points;    ///< point count by 3
  std::vector<long> offsets{0};  ///< cells + 1: cell c's nodes are connectivity[offsets[c] .. offsets[c+1])
  std::vector<long> connectivity;
  std::vector<long> types;    ///< VTK cell type per cell
  std::vector<long> regions;  ///< group value per cell; empty when the file has none
  std::vector<Location> cell_where;
  Location points_where;
};

Mesh build_mesh(const InputCursor& in, const Grid& grid) {
  MeshBuilder builder(in.path(), "cell");
  const std::size_t point_count = grid.points.size() / 3;
  builder.reserve_nodes(point_count);
  for (std::size_t i = 0; i < point_count; ++i)
    builder.add_node(static_cast<long>(i), &grid.points[3 * i], grid.points_where);
  std::vector<long> ours;
  for (std::size_t c = 0; c + 1 < grid.offsets.size(); ++c) {
    const Mapping mapping = vtk_mapping(grid.types[c]);
    const std::string cell = "cell " + std::to_string(c);
    if (!mapping.shape)
      in.fail_at(grid.cell_where[c], cell + " has VTK type " + std::to_string(grid.types[c]) + " (" +
                                         vtk_type_name(grid.types[c]) +
                                         "), which is not supported; supported: " + supported_list());
    const long count = grid.offsets[c + 1] - grid.offsets[c];
    if (count != mapping.shape->nodes)
      in.fail_at(grid.cell_where[c], cell + " (" + vtk_type_name(grid.types[c]) + ") has " + std::to_string(count) +
                                         " nodes, expected " + std::to_string(mapping.shape->nodes));
    const auto first = grid.connectivity.begin() + grid.offsets[c];
    ours.assign(first, first + count);
    if (mapping.order)
      for (long k = 0; k < count; ++k) ours[static_cast<std::size_t>(mapping.order[k])] = first[k];
    const std::span<const long> groups =
        grid.regions.empty() ? std::span<const long>() : std::span<const long>(&grid.regions[c], 1);
    builder.add_element(*mapping.shape, static_cast<long>(c), ours, groups, grid.cell_where[c]);
  }
  return builder.build([](long key) { return GroupInfo{"region_" + std::to_string(key), -1}; });
}

/// Checks offsets (leading 0, non-decreasing, ending at the connectivity size)
/// from cell `first_cell` on (the cells before it were checked already).
void check_offsets(const InputCursor& in, const Grid& grid, Location where, std::size_t first_cell = 0) {
  for (std::size_t c = first_cell; c + 1 < grid.offsets.size(); ++c)
    if (grid.offsets[c + 1] < grid.offsets[c] || grid.offsets[c + 1] > static_cast<long>(grid.connectivity.size()))
      in.fail_at(where,
                 "cell offsets are not increasing within the connectivity size (cell " + std::to_string(c) + ")");
  if (grid.offsets.back() != static_cast<long>(grid.connectivity.size()))
    in.fail_at(where, "the offsets end at " + std::to_string(grid.offsets.back()) + " but the connectivity has " +
                          std::to_string(grid.connectivity.size()) + " entries");
}

bool is_integer_value(double value) {
  return std::isfinite(value) && value == std::floor(value) && std::abs(value) < 9.0e15;
}

std::vector<long> to_integers(const InputCursor& in, const std::vector<double>& values, Location where,
                              std::string_view what) {
  std::vector<long> result(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!is_integer_value(values[i]))
      in.fail_at(where, std::string(what) + " value " + std::to_string(i) + " is not an integer");
    result[i] = static_cast<long>(values[i]);
  }
  return result;
}

std::string lower(std::string_view text) {
  std::string result(text);
  for (char& c : result) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return result;
}

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > begin) words.push_back(line.substr(begin, i - begin));
  }
  return words;
}

// ---------------------------------------------------------------- legacy

/// Size in bytes of a legacy data type, 0 when unsupported.
std::size_t legacy_type_size(std::string_view type) {
  const std::string name = lower(type);
  if (name == "unsigned_char" || name == "char" || name == "vtktypeint8" || name == "vtktypeuint8") return 1;
  if (name == "unsigned_short" || name == "short" || name == "vtktypeint16" || name == "vtktypeuint16") return 2;
  if (name == "unsigned_int" || name == "int" || name == "float" || name == "vtktypeint32" || name == "vtktypeuint32")
    return 4;
  if (name == "unsigned_long" || name == "long" || name == "double" || name == "vtktypeint64" ||
      name == "vtktypeuint64")
    return 8;
  return 0;
}

bool legacy_integer_type(std::string_view type) { return lower(type) != "float" && lower(type) != "double"; }

class LegacyReader {
 public:
  explicit LegacyReader(InputCursor& in) : in_(in) {}
  Mesh read();

 private:
  bool header(std::vector<std::string_view>& words);
  long word_count(std::size_t index, std::string_view what, std::size_t min_bytes_each);
  std::size_t checked_type(std::string_view type);
  double value(std::string_view type, std::size_t size);
  std::vector<double> values(long count, std::string_view type, std::vector<Location>* where = nullptr);
  void read_points();
  void read_cells();
  void read_cells_classic(long cells, long size);
  void read_cells_split(long offsets, long size);
  void read_cell_types();
  void read_scalars();
  void read_field();
  void read_attribute(long values_per_item, std::size_t type_word);
  void skip_metadata();
  void offer_region(std::string_view name, std::string_view type, long components, long tuples);

  InputCursor& in_;
  bool binary_ = false;
  Grid grid_;
  std::vector<std::string_view> words_;
  Location where_;
  bool have_points_ = false;
  bool have_cells_ = false;
  bool have_types_ = false;
  bool in_cell_data_ = false;
  long data_count_ = 0;
  int region_priority_ = 99;
};

bool LegacyReader::header(std::vector<std::string_view>& words) {
  if (in_.at_end()) return false;
  where_ = in_.location();
  words = split_words(in_.rest_of_line());
  return true;
}

long LegacyReader::word_count(std::size_t index, std::string_view what, std::size_t min_bytes_each) {
  long n = 0;
  if (index >= words_.size() || !parse_integer(words_[index], n) || n < 0)
    in_.fail_at(where_, std::string(words_[0]) + ": expected " + std::string(what) + " (a count)");
  return in_.checked_count(static_cast<unsigned long long>(n), what, min_bytes_each, where_);
}

std::size_t LegacyReader::checked_type(std::string_view type) {
  const std::size_t size = legacy_type_size(type);
  if (size == 0) in_.fail_at(where_, "data type '" + std::string(type) + "' is not supported");
  return size;
}

double LegacyReader::value(std::string_view type, std::size_t size) {
  if (!binary_) return in_.real("a value");
  const std::string name = lower(type);
  const bool is_unsigned = name.starts_with("unsigned") || name.starts_with("vtktypeuint");
  if (name == "float") return in_.value<float>("a float", std::endian::big);
  if (name == "double") return in_.value<double>("a double", std::endian::big);
  switch (size) {
    case 1:
      return is_unsigned ? in_.value<std::uint8_t>("a byte", std::endian::big)
                         : in_.value<std::int8_t>("a byte", std::endian::big);
    case 2:
      return is_unsigned ? in_.value<std::uint16_t>("a short", std::endian::big)
                         : in_.value<std::int16_t>("a short", std::endian::big);
    case 4:
      return is_unsigned ? in_.value<std::uint32_t>("an int", std::endian::big)
                         : in_.value<std::int32_t>("an int", std::endian::big);
    default:
      return is_unsigned ? static_cast<double>(in_.value<std::uint64_t>("a long", std::endian::big))
                         : static_cast<double>(in_.value<std::int64_t>("a long", std::endian::big));
  }
}

std::vector<double> LegacyReader::values(long count, std::string_view type, std::vector<Location>* where) {
  const std::size_t size = checked_type(type);
  in_.checked_count(static_cast<unsigned long long>(count), "values", binary_ ? size : 1, where_);
  std::vector<double> result(static_cast<std::size_t>(count));
  if (where) where->resize(result.size());
  for (std::size_t i = 0; i < result.size(); ++i) {
    if (where) (*where)[i] = in_.here();
    result[i] = value(type, size);
  }
  return result;
}

Mesh LegacyReader::read() {
  const std::string_view first = in_.rest_of_line();
  if (!lower(first).starts_with("# vtk datafile version"))
    in_.fail_at({1, false}, "not a legacy VTK file (the first line must be '# vtk DataFile Version x.y')");
  in_.rest_of_line();  // title
  const std::string format = lower(in_.rest_of_line());
  if (format != "ascii" && format != "binary")
    in_.fail_at({3, false}, "expected ASCII or BINARY on line 3, found '" + format.substr(0, 40) + "'");
  binary_ = format == "binary";
  in_.set_binary(binary_);
  while (header(words_)) {
    if (words_.empty()) continue;
    const std::string keyword = lower(words_[0]);
    if (keyword == "dataset") {
      if (words_.size() < 2 || lower(words_[1]) != "unstructured_grid")
        in_.fail_at(where_, "only DATASET UNSTRUCTURED_GRID is supported, found '" +
                                std::string(words_.size() > 1 ? words_[1] : "") + "'");
    } else if (keyword == "points") read_points();
    else if (keyword == "cells") read_cells();
    else if (keyword == "cell_types") read_cell_types();
    else if (keyword == "cell_data" || keyword == "point_data") {
      in_cell_data_ = keyword == "cell_data";
      data_count_ = word_count(1, "data tuples", 1);
    } else if (keyword == "scalars") read_scalars();
    else if (keyword == "field") read_field();
    else if (keyword == "vectors" || keyword == "normals") read_attribute(3, 2);
    else if (keyword == "tensors") read_attribute(9, 2);
    else if (keyword == "tensors6") read_attribute(6, 2);
    else if (keyword == "metadata") skip_metadata();
    else
      in_.fail_at(where_, "unsupported keyword '" + std::string(words_[0].substr(0, 40)) +
                              "' (unstructured grids with POINTS, CELLS, CELL_TYPES and cell data)");
  }
  if (!have_points_) throw InputError(in_.path() + ": no POINTS section");
  if (!have_cells_ || !have_types_) throw InputError(in_.path() + ": no CELLS or CELL_TYPES section");
  if (grid_.types.size() + 1 != grid_.offsets.size())
    throw InputError(in_.path() + ": CELL_TYPES has " + std::to_string(grid_.types.size()) + " entries for " +
                     std::to_string(grid_.offsets.size() - 1) + " cells");
  if (!grid_.regions.empty() && grid_.regions.size() != grid_.types.size()) grid_.regions.clear();
  return build_mesh(in_, grid_);
}

void LegacyReader::read_points() {
  const long count = word_count(1, "points", 1);
  if (words_.size() < 3) in_.fail_at(where_, "POINTS: expected a data type");
  grid_.points_where = where_;
  grid_.points = values(3 * count, words_[2]);
  have_points_ = true;
}

void LegacyReader::read_cells() {
  const long first = word_count(1, "cells", 1);
  const long second = word_count(2, "cell list entries", 1);
  if (in_.data().substr(in_.position()).starts_with("OFFSETS")) read_cells_split(first, second);
  else read_cells_classic(first, second);
  check_offsets(in_, grid_, where_);
  have_cells_ = true;
}

void LegacyReader::read_cells_classic(long cells, long size) {
  in_.checked_count(static_cast<unsigned long long>(size), "cell list entries", binary_ ? 4 : 2, where_);
  if (cells > size) in_.fail_at(where_, "CELLS: more cells (" + std::to_string(cells) + ") than list entries");
  long used = 0;
  for (long c = 0; c < cells; ++c) {
    grid_.cell_where.push_back(in_.here());
    const double n = value("int", 4);
    if (!is_integer_value(n) || n < 0 || used + 1 + static_cast<long>(n) > size)
      in_.fail_at(grid_.cell_where.back(), "cell " + std::to_string(c) + ": bad node count " + std::to_string(n));
    for (long k = 0; k < static_cast<long>(n); ++k) {
      const double node = value("int", 4);
      if (!is_integer_value(node))
        in_.fail_at(grid_.cell_where.back(), "cell " + std::to_string(c) + ": bad node index");
      grid_.connectivity.push_back(static_cast<long>(node));
    }
    used += 1 + static_cast<long>(n);
    grid_.offsets.push_back(static_cast<long>(grid_.connectivity.size()));
  }
  if (used != size)
    in_.fail_at(where_,
                "CELLS declares " + std::to_string(size) + " list entries but the cells use " + std::to_string(used));
}

void LegacyReader::read_cells_split(long offsets, long size) {
  if (offsets < 1) in_.fail_at(where_, "CELLS: the offsets array needs at least one entry");
  const Location cells_where = where_;
  if (!header(words_) || lower(words_[0]) != "offsets" || words_.size() < 2)
    in_.fail_at(where_, "expected OFFSETS TYPE");
  grid_.offsets = to_integers(in_, values(offsets, words_[1]), where_, "OFFSETS");
  if (grid_.offsets.front() != 0) in_.fail_at(where_, "OFFSETS must start at 0");
  if (!header(words_) || lower(words_[0]) != "connectivity" || words_.size() < 2)
    in_.fail_at(where_, "expected CONNECTIVITY TYPE");
  std::vector<Location> value_where;
  grid_.connectivity = to_integers(in_, values(size, words_[1], &value_where), where_, "CONNECTIVITY");
  for (std::size_t c = 0; c + 1 < grid_.offsets.size(); ++c) {
    const auto at = static_cast<std::size_t>(std::clamp(grid_.offsets[c], 0L, static_cast<long>(value_where.size())));
    grid_.cell_where.push_back(at < value_where.size() ? value_where[at] : cells_where);
  }
  where_ = cells_where;
}

void LegacyReader::read_cell_types() {
  const long count = word_count(1, "cell types", 1);
  grid_.types = to_integers(in_, values(count, "int"), where_, "CELL_TYPES");
  have_types_ = true;
}

void LegacyReader::offer_region(std::string_view name, std::string_view type, long components, long tuples) {
  const int priority = region_priority(name);
  const bool usable = in_cell_data_ && priority >= 0 && priority < region_priority_ && components == 1 &&
                      legacy_integer_type(type) && tuples == static_cast<long>(grid_.types.size());
  const Location where = where_;
  std::vector<double> data = values(components * tuples, type);
  if (!usable) return;
  grid_.regions = to_integers(in_, data, where, name);
  region_priority_ = priority;
}

void LegacyReader::read_scalars() {
  if (words_.size() < 3) in_.fail_at(where_, "SCALARS: expected a name and a data type");
  const std::string name(words_[1]);
  const std::string type(words_[2]);
  long components = 1;
  if (words_.size() > 3 && (!parse_integer(words_[3], components) || components < 1 || components > 4))
    in_.fail_at(where_, "SCALARS: bad component count");
  const Location where = where_;
  if (in_.data().substr(in_.position()).starts_with("LOOKUP_TABLE")) in_.rest_of_line();
  where_ = where;
  offer_region(name, type, components, data_count_);
}

void LegacyReader::read_field() {
  const long arrays = word_count(2, "field arrays", 4);
  for (long a = 0; a < arrays; ++a) {
    if (!header(words_) || words_.size() < 4) in_.fail_at(where_, "FIELD: expected NAME COMPONENTS TUPLES TYPE");
    const std::string name(words_[0]);
    const std::string type(words_[3]);
    const long components = word_count(1, "components", 1);
    const long tuples = word_count(2, "tuples", 1);
    if (components > 0 && tuples > static_cast<long>(in_.remaining()) / components)
      in_.fail_at(where_, "FIELD array '" + name + "' is larger than the rest of the file");
    offer_region(name, type, components, tuples);
  }
}

void LegacyReader::read_attribute(long values_per_item, std::size_t type_word) {
  if (words_.size() <= type_word) in_.fail_at(where_, std::string(words_[0]) + ": expected a data type");
  if (data_count_ > static_cast<long>(in_.remaining()) / values_per_item)
    in_.fail_at(where_, "attribute larger than the rest of the file");
  values(values_per_item * data_count_, words_[type_word]);
}

void LegacyReader::skip_metadata() {
  while (in_.remaining() > 0 && !in_.rest_of_line().empty()) {
  }
}

// ---------------------------------------------------------------- XML

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;
  std::size_t begin = 0;  ///< offset of '<'
  std::size_t content_begin = 0;
  std::size_t content_end = 0;
  long line = 1;  ///< line of '<'
  int parent = -1;
  std::vector<int> children;  ///< indices into XmlDocument::elements, in file order

  std::string attribute(std::string_view key, std::string fallback = {}) const {
    for (const auto& [k, v] : attributes)
      if (k == key) return v;
    return fallback;
  }
};

std::string decode_entities(std::string_view text) {
  std::string result;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '&') {
      result += text[i];
      continue;
    }
    const std::size_t end = text.find(';', i);
    const std::string_view entity = end == std::string_view::npos ? std::string_view() : text.substr(i, end - i + 1);
    if (entity == "&lt;") result += '<';
    else if (entity == "&gt;") result += '>';
    else if (entity == "&amp;") result += '&';
    else if (entity == "&quot;") result += '"';
    else if (entity == "&apos;") result += '\'';
    else {
      result += '&';
      continue;
    }
    i = end;
  }
  return result;
}

/// A flat list of elements parsed up to <AppendedData> (whose content is binary).
class XmlDocument {
 public:
  explicit XmlDocument(const InputCursor& in) : in_(in), text_(in.data()) { parse(); }

  std::vector<XmlElement> elements;
  std::size_t appended_begin = std::string::npos;  ///< first byte after '_'
  std::string appended_encoding = "raw";

  /// The children of `parent` (nullptr: the top level) named `name`; only
  /// the parent's own children are looked at, so reading a file stays linear.
  std::vector<const XmlElement*> children(const XmlElement* parent, std::string_view name) const {
    std::vector<const XmlElement*> result;
    for (const int index : parent ? parent->children : top_level_)
      if (elements[static_cast<std::size_t>(index)].name == name)
        result.push_back(&elements[static_cast<std::size_t>(index)]);
    return result;
  }
  const XmlElement* child(const XmlElement* parent, std::string_view name) const {
    const auto found = children(parent, name);
    return found.empty() ? nullptr : found.front();
  }

 private:
  [[noreturn]] void fail(std::size_t offset, const std::string& message) const {
    in_.fail_at({in_.line_at(offset), false}, message);
  }
  void parse();
  std::size_t start_tag(std::size_t lt, std::vector<int>& open);
  std::size_t end_tag(std::size_t lt, std::vector<int>& open);
  std::size_t skip_to(std::size_t from, std::string_view marker, std::string_view what) const {
    const std::size_t found = text_.find(marker, from);
    if (found == std::string_view::npos) fail(from, "unterminated " + std::string(what));
    return found + marker.size();
  }

  /// Line of `offset`, counted on from the previous call (offsets only grow).
  long line_of(std::size_t offset) {
    for (; counted_to_ < offset; ++counted_to_)
      if (text_[counted_to_] == '\n') ++counted_line_;
    return counted_line_;
  }

  const InputCursor& in_;
  std::string_view text_;
  std::vector<int> top_level_;
  std::size_t counted_to_ = 0;
  long counted_line_ = 1;
};

void XmlDocument::parse() {
  std::vector<int> open;
  std::size_t pos = 0;
  while (appended_begin == std::string::npos) {
    const std::size_t lt = text_.find('<', pos);
    if (lt == std::string_view::npos) break;
    const std::string_view rest = text_.substr(lt);
    if (rest.starts_with("<!--")) pos = skip_to(lt, "-->", "comment");
    else if (rest.starts_with("<?")) pos = skip_to(lt, "?>", "processing instruction");
    else if (rest.starts_with("<!")) pos = skip_to(lt, ">", "declaration");
    else if (rest.starts_with("</")) pos = end_tag(lt, open);
    else pos = start_tag(lt, open);
  }
  if (appended_begin == std::string::npos && !open.empty())
    fail(text_.size(), "unexpected end of file (truncated file?) inside <" +
                           elements[static_cast<std::size_t>(open.back())].name + ">");
  if (elements.empty()) fail(0, "not an XML VTK file (no elements)");
}

std::size_t XmlDocument::start_tag(std::size_t lt, std::vector<int>& open) {
  XmlElement element;
  element.begin = lt;
  element.line = line_of(lt);
  element.parent = open.empty() ? -1 : open.back();
  std::size_t i = lt + 1;
  auto is_name_char = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '-' || c == '.';
  };
  auto skip_space = [&] {
    while (i < text_.size() && std::isspace(static_cast<unsigned char>(text_[i]))) ++i;
  };
  while (i < text_.size() && is_name_char(text_[i])) element.name += text_[i++];
  if (element.name.empty()) fail(lt, "malformed XML tag");
  for (;;) {
    skip_space();
    if (i >= text_.size()) fail(lt, "unterminated tag <" + element.name + ">");
    if (text_[i] == '>' || text_.substr(i).starts_with("/>")) break;
    std::string key;
    while (i < text_.size() && is_name_char(text_[i])) key += text_[i++];
    skip_space();
    if (key.empty() || i >= text_.size() || text_[i] != '=') fail(i, "malformed attribute in <" + element.name + ">");
    ++i;
    skip_space();
    if (i >= text_.size() || (text_[i] != '"' && text_[i] != '\''))
      fail(i, "attribute " + key + " of <" + element.name + "> is not quoted");
    const char quote = text_[i++];
    const std::size_t end = text_.find(quote, i);
    if (end == std::string_view::npos) fail(i, "unterminated attribute " + key);
    element.attributes.emplace_back(key, decode_entities(text_.substr(i, end - i)));
    i = end + 1;
  }
  const bool self_closing = text_[i] == '/';
  i += self_closing ? 2 : 1;
  element.content_begin = element.content_end = i;
  const int index = static_cast<int>(elements.size());
  (element.parent < 0 ? top_level_ : elements[static_cast<std::size_t>(element.parent)].children).push_back(index);
  elements.push_back(std::move(element));
  if (elements.back().name == "AppendedData" && !self_closing) {
    appended_encoding = elements.back().attribute("encoding", "raw");
    const std::size_t underscore = text_.find('_', i);
    if (underscore == std::string_view::npos) fail(i, "<AppendedData> without the '_' that starts the data");
    appended_begin = underscore + 1;
  } else if (!self_closing) {
    open.push_back(static_cast<int>(elements.size()) - 1);
  }
  return i;
}

std::size_t XmlDocument::end_tag(std::size_t lt, std::vector<int>& open) {
  const std::size_t gt = text_.find('>', lt);
  if (gt == std::string_view::npos) fail(lt, "unterminated end tag");
  std::string_view name = text_.substr(lt + 2, gt - lt - 2);
  while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.remove_suffix(1);
  if (open.empty() || elements[static_cast<std::size_t>(open.back())].name != name)
    fail(lt, "unexpected </" + std::string(name.substr(0, 40)) + ">" +
                 (open.empty() ? std::string()
                               : " (open: <" + elements[static_cast<std::size_t>(open.back())].name + ">)"));
  elements[static_cast<std::size_t>(open.back())].content_end = lt;
  open.pop_back();
  return gt + 1;
}

// ---------------------------------------------------------------- VTU

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

/// Decodes base64 text (no whitespace); false on a bad character.
bool base64_decode(std::string_view text, std::vector<unsigned char>& out) {
  out.clear();
  out.reserve(text.size() / 4 * 3 + 3);
  unsigned int buffer = 0;
  int bits = 0;
  for (char c : text) {
    if (c == '=') break;
    const int v = base64_value(c);
    if (v < 0) return false;
    buffer = (buffer << 6) | static_cast<unsigned int>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((buffer >> bits) & 0xffu));
    }
  }
  return true;
}

std::size_t base64_length(std::size_t bytes) { return (bytes + 2) / 3 * 4; }

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

Mesh read_vtu(InputCursor& input) { return VtuReader(input).read(); }

Mesh read_legacy_vtk(InputCursor& input) { return LegacyReader(input).read(); }

}  // namespace tensormass::detail
