// Legacy VTK reader (.vtk): ASCII or big-endian BINARY, DATASET
// UNSTRUCTURED_GRID, both the classic CELLS layout and the
// OFFSETS/CONNECTIVITY layout of version 5; cell data arrays named
// gmsh:physical, region or group make the groups.
#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_readers.hpp"
#include "io/vtk_cells.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::detail {

namespace vtk {
namespace {

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

}  // namespace
}  // namespace vtk

Mesh read_legacy_vtk(InputCursor& input) { return vtk::LegacyReader(input).read(); }

}  // namespace tensormass::detail
