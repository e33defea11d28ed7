#include "mesh_builder.hpp"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <map>
#include <memory>
#include <unordered_map>

#include "tensormass/errors.hpp"
#include "tensormass/registry.hpp"

namespace tensormass::detail {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

std::string quoted(std::string_view text) {
  std::string shown(text.substr(0, 40));
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return "'" + shown + (text.size() > 40 ? "...'" : "'");
}

}  // namespace

std::string format_location(const std::string& file, Location where) {
  if (where.byte) return file + ": byte " + std::to_string(where.value);
  return file + ":" + std::to_string(where.value);
}

// ---------------------------------------------------------------- cursor

bool InputCursor::at_end() {
  while (pos_ < data_.size() && is_space(data_[pos_])) {
    if (data_[pos_] == '\n') ++line_;
    ++pos_;
  }
  return pos_ >= data_.size();
}

std::string_view InputCursor::token(std::string_view what) {
  if (at_end()) fail("unexpected end of file, expected " + std::string(what));
  const std::size_t begin = pos_;
  while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
  return std::string_view(data_).substr(begin, pos_ - begin);
}

std::string_view InputCursor::peek_token() {
  if (at_end()) return {};
  std::size_t end = pos_;
  while (end < data_.size() && !is_space(data_[end])) ++end;
  return std::string_view(data_).substr(pos_, end - pos_);
}

std::string_view InputCursor::rest_of_line() {
  const std::size_t begin = pos_;
  std::size_t end = data_.find('\n', pos_);
  if (end == std::string::npos) end = data_.size();
  pos_ = end < data_.size() ? end + 1 : end;
  if (end < data_.size()) ++line_;
  std::string_view text = std::string_view(data_).substr(begin, end - begin);
  while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
  return text;
}

void InputCursor::skip_line_end() {
  while (pos_ < data_.size() && (data_[pos_] == ' ' || data_[pos_] == '\t' || data_[pos_] == '\r')) ++pos_;
  if (pos_ < data_.size() && data_[pos_] == '\n') {
    ++pos_;
    ++line_;
  }
}

void InputCursor::expect(std::string_view keyword) {
  const std::string_view found = token(keyword);
  if (found != keyword) fail("expected " + std::string(keyword) + ", found " + quoted(found));
}

void InputCursor::skip_past(std::string_view marker, std::string_view what) {
  const std::size_t found = data_.find(marker, pos_);
  if (found == std::string::npos) fail("missing " + std::string(what) + " (end of file reached)");
  line_ += static_cast<long>(std::count(data_.begin() + static_cast<std::ptrdiff_t>(pos_),
                                        data_.begin() + static_cast<std::ptrdiff_t>(found), '\n'));
  pos_ = found + marker.size();
}

long InputCursor::integer(std::string_view what) {
  const std::string_view text = token(what);
  long value = 0;
  if (!parse_integer(text, value)) fail("expected an integer (" + std::string(what) + "), found " + quoted(text));
  return value;
}

double InputCursor::real(std::string_view what) {
  const std::string_view text = token(what);
  double value = 0;
  if (!parse_real(text, value)) fail("expected a number (" + std::string(what) + "), found " + quoted(text));
  return value;
}

long InputCursor::count(std::string_view what, std::size_t min_bytes_each) {
  const Location where = location();
  const long n = integer(what);
  if (n < 0) fail_at(where, "negative " + std::string(what) + " " + std::to_string(n));
  return checked_count(static_cast<unsigned long long>(n), what, min_bytes_each, where);
}

long InputCursor::checked_count(unsigned long long n, std::string_view what, std::size_t min_bytes_each,
                                Location where) const {
  if (n > static_cast<unsigned long long>(INT_MAX))
    fail_at(where, std::to_string(n) + " " + std::string(what) + " is more than this program supports (" +
                       std::to_string(INT_MAX) + ")");
  if (min_bytes_each > 0 && n > remaining() / min_bytes_each)
    fail_at(where, "the file declares " + std::to_string(n) + " " + std::string(what) + " but only " +
                       std::to_string(remaining()) + " bytes are left: truncated file or bad count");
  return static_cast<long>(n);
}

std::span<const unsigned char> InputCursor::bytes(std::size_t n, std::string_view what) {
  if (n > remaining())
    fail("unexpected end of file reading " + std::string(what) + " (" + std::to_string(n) + " bytes needed, " +
         std::to_string(remaining()) + " left)");
  const auto* begin = reinterpret_cast<const unsigned char*>(data_.data()) + pos_;
  pos_ += n;
  return {begin, n};
}

long InputCursor::line_at(std::size_t offset) const {
  offset = std::min(offset, data_.size());
  return 1 + static_cast<long>(std::count(data_.begin(), data_.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
}

void InputCursor::fail(const std::string& message) const { fail_at(location(), message); }

void InputCursor::fail_at(Location where, const std::string& message) const {
  throw InputError(format_location(path_, where) + ": " + message);
}

bool parse_integer(std::string_view text, long& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size() && !text.empty();
}

bool parse_real(std::string_view text, double& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size() && !text.empty();
}

// ---------------------------------------------------------------- shapes

namespace {

const std::vector<Shape>& shapes() {
  static const std::vector<Shape> table = [] {
    std::vector<Shape> result{{"point", 0, 1, 1, nullptr}, {"line2", 1, 2, 1, nullptr}, {"line3", 1, 3, 2, nullptr}};
    for (const tm_element_info* e : Registry::instance().elements())
      result.push_back({e->name, e->dim, e->nodes, e->order, e});
    return result;
  }();
  return table;
}

}  // namespace

const Shape* find_shape(std::string_view name) {
  for (const Shape& shape : shapes())
    if (shape.name == name) return &shape;
  return nullptr;
}

const Shape* shape_of(const tm_element_info* element) {
  for (const Shape& shape : shapes())
    if (shape.element == element) return &shape;
  return nullptr;
}

// ---------------------------------------------------------------- builder

/// File node id -> raw node index: a dense table when ids are compact, a hash map otherwise.
struct MeshBuilder::NodeIndex {
  long min_id = 0;
  std::vector<int> dense;
  std::unordered_map<long, int> sparse;
  bool use_dense = true;

  int find(long id) const {
    if (use_dense) {
      const long k = id - min_id;
      return k >= 0 && k < static_cast<long>(dense.size()) ? dense[static_cast<std::size_t>(k)] : -1;
    }
    const auto found = sparse.find(id);
    return found == sparse.end() ? -1 : found->second;
  }
};

MeshBuilder::MeshBuilder(std::string source, std::string element_word)
    : source_(std::move(source)), element_word_(std::move(element_word)) {}

void MeshBuilder::reserve_nodes(std::size_t count) {
  node_ids_.reserve(count);
  xyz_.reserve(3 * count);
  node_where_.reserve(count);
}

void MeshBuilder::add_node(long id, const double xyz[3], Location where) {
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(xyz[c]))
      throw InputError(format_location(source_, where) + ": node " + std::to_string(id) +
                       " has a non-finite coordinate (" + "xyz"[c] + " = " + std::to_string(xyz[c]) + ")");
  node_ids_.push_back(id);
  xyz_.insert(xyz_.end(), xyz, xyz + 3);
  node_where_.push_back(where);
}

void MeshBuilder::add_element(const Shape& shape, long id, std::span<const long> nodes, std::span<const long> groups,
                              Location where) {
  shapes_.push_back(&shape);
  element_ids_.push_back(id);
  element_nodes_.insert(element_nodes_.end(), nodes.begin(), nodes.end());
  node_offsets_.push_back(element_nodes_.size());
  element_groups_.insert(element_groups_.end(), groups.begin(), groups.end());
  group_offsets_.push_back(element_groups_.size());
  element_where_.push_back(where);
}

void MeshBuilder::fail_element(std::size_t e, const std::string& message) const {
  throw InputError(format_location(source_, element_where_[e]) + ": " + element_word_ + " " +
                   std::to_string(element_ids_[e]) + " (" + shapes_[e]->name + ") " + message);
}

int MeshBuilder::mesh_dimension() const {
  if (shapes_.empty()) throw InputError(source_ + ": the file has no elements");
  int dim = 0;
  for (const Shape* shape : shapes_) dim = std::max(dim, shape->dim);
  if (dim < 2)
    throw InputError(source_ + ": no 2D or 3D elements (the highest element dimension is " + std::to_string(dim) + ")");
  return dim;
}

namespace {

/// Builds the id -> index table; throws on a duplicate id.
void index_nodes(const std::string& source, const std::vector<long>& ids, const std::vector<Location>& where,
                 long& min_id, std::vector<int>& dense, std::unordered_map<long, int>& sparse, bool& use_dense) {
  if (ids.empty()) throw InputError(source + ": the file has no nodes");
  const auto [lo, hi] = std::minmax_element(ids.begin(), ids.end());
  min_id = *lo;
  const unsigned long long span = static_cast<unsigned long long>(*hi - *lo) + 1;
  use_dense = span <= 4 * ids.size() + 1024;
  if (use_dense) dense.assign(span, -1);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    int* slot = nullptr;
    if (use_dense) {
      slot = &dense[static_cast<std::size_t>(ids[i] - min_id)];
    } else {
      slot = &sparse.try_emplace(ids[i], -1).first->second;
    }
    if (*slot >= 0)
      throw InputError(format_location(source, where[i]) + ": duplicate node id " + std::to_string(ids[i]) +
                       " (first defined at " + format_location(source, where[static_cast<std::size_t>(*slot)]) + ")");
    *slot = static_cast<int>(i);
  }
}

/// Index of the first element with the same shape and nodes, for each element.
std::vector<int> find_duplicates(const std::vector<const Shape*>& shapes, const std::vector<std::size_t>& offsets,
                                 const std::vector<int>& nodes) {
  std::vector<int> first(shapes.size());
  std::unordered_multimap<std::size_t, int> seen;
  seen.reserve(shapes.size());
  for (std::size_t e = 0; e < shapes.size(); ++e) {
    std::size_t h = std::hash<const void*>()(shapes[e]);
    for (std::size_t k = offsets[e]; k < offsets[e + 1]; ++k) h = h * 1000003u ^ static_cast<std::size_t>(nodes[k]);
    first[e] = static_cast<int>(e);
    const auto [begin, end] = seen.equal_range(h);
    for (auto it = begin; it != end; ++it) {
      const auto other = static_cast<std::size_t>(it->second);
      if (shapes[other] == shapes[e] &&
          std::equal(nodes.begin() + static_cast<std::ptrdiff_t>(offsets[e]),
                     nodes.begin() + static_cast<std::ptrdiff_t>(offsets[e + 1]),
                     nodes.begin() + static_cast<std::ptrdiff_t>(offsets[other]))) {
        first[e] = it->second;
        break;
      }
    }
    if (first[e] == static_cast<int>(e)) seen.emplace(h, static_cast<int>(e));
  }
  return first;
}

struct GroupParts {
  Group group;
  bool dim_given = false;
};

void sort_unique(std::vector<int>& values) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
}

}  // namespace

std::vector<int> MeshBuilder::map_nodes(const NodeIndex& index, int dim, std::vector<int>& renumber) const {
  std::vector<int> raw(element_nodes_.size());
  for (std::size_t e = 0; e < shapes_.size(); ++e)
    for (std::size_t k = node_offsets_[e]; k < node_offsets_[e + 1]; ++k) {
      raw[k] = index.find(element_nodes_[k]);
      if (raw[k] < 0) fail_element(e, "refers to node " + std::to_string(element_nodes_[k]) + ", which the file does not define");
    }
  renumber.assign(node_ids_.size(), -1);
  for (std::size_t e = 0; e < shapes_.size(); ++e)
    if (shapes_[e]->dim == dim)
      for (std::size_t k = node_offsets_[e]; k < node_offsets_[e + 1]; ++k) renumber[static_cast<std::size_t>(raw[k])] = 0;
  int next = 0;
  for (int& number : renumber)
    if (number == 0) number = next++;
  return raw;
}

Mesh MeshBuilder::build(const std::function<GroupInfo(long key)>& describe) {
  const int dim = mesh_dimension();
  NodeIndex index;
  index_nodes(source_, node_ids_, node_where_, index.min_id, index.dense, index.sparse, index.use_dense);
  std::vector<int> renumber;
  const std::vector<int> raw = map_nodes(index, dim, renumber);
  const std::vector<int> first = find_duplicates(shapes_, node_offsets_, raw);

  Mesh mesh;
  mesh.dim = dim;
  mesh.source = source_;
  const int node_count = static_cast<int>(std::count_if(renumber.begin(), renumber.end(), [](int n) { return n >= 0; }));
  mesh.rest_positions.resize(3 * static_cast<std::size_t>(node_count));
  mesh.node_source_ids.resize(static_cast<std::size_t>(node_count));
  for (std::size_t i = 0; i < renumber.size(); ++i) {
    if (renumber[i] < 0) continue;
    const auto n = static_cast<std::size_t>(renumber[i]);
    mesh.node_source_ids[n] = node_ids_[i];
    std::copy_n(xyz_.begin() + static_cast<std::ptrdiff_t>(3 * i), 3, mesh.rest_positions.begin() + static_cast<std::ptrdiff_t>(3 * n));
  }

  // Cells, block by block in registry order, file order inside a block.
  std::vector<int> cell_of(shapes_.size(), -1);
  int next_cell = 0;
  for (const tm_element_info* element : Registry::instance().elements()) {
    if (element->dim != dim) continue;
    ElementBlock block;
    block.element = element;
    block.first_cell = next_cell;
    for (std::size_t e = 0; e < shapes_.size(); ++e) {
      if (shapes_[e]->element != element || first[e] != static_cast<int>(e)) continue;
      for (std::size_t k = node_offsets_[e]; k < node_offsets_[e + 1]; ++k)
        block.connectivity.push_back(renumber[static_cast<std::size_t>(raw[k])]);
      block.source_ids.push_back(element_ids_[e]);
      cell_of[e] = next_cell++;
    }
    if (block.count() > 0) mesh.blocks.push_back(std::move(block));
  }

  // Groups: (key, first element) pairs in key order, then file order.
  std::vector<std::pair<long, int>> members;
  for (std::size_t e = 0; e < shapes_.size(); ++e)
    for (std::size_t k = group_offsets_[e]; k < group_offsets_[e + 1]; ++k) members.emplace_back(element_groups_[k], first[e]);
  std::sort(members.begin(), members.end());
  members.erase(std::unique(members.begin(), members.end()), members.end());

  std::vector<GroupParts> parts;
  std::map<std::string, std::size_t> by_name;
  long current_key = 0;
  GroupParts* target = nullptr;
  for (const auto& [key, e_int] : members) {
    if (!target || key != current_key) {
      const GroupInfo info = describe(key);
      auto [it, added] = by_name.try_emplace(info.name, parts.size());
      if (added) {
        parts.emplace_back();
        parts.back().group.name = info.name;
        parts.back().group.dim = -1;
      }
      target = &parts[it->second];
      if (info.dim >= 0) target->group.dim = std::max(target->group.dim, info.dim);
      current_key = key;
    }
    const auto e = static_cast<std::size_t>(e_int);
    const Shape& shape = *shapes_[e];
    target->group.dim = std::max(target->group.dim, shape.dim);
    for (std::size_t k = node_offsets_[e]; k < node_offsets_[e + 1]; ++k) {
      const int node = renumber[static_cast<std::size_t>(raw[k])];
      if (node < 0)
        fail_element(e, "of group '" + target->group.name + "' uses node " + std::to_string(element_nodes_[k]) +
                            ", which belongs to no " + std::to_string(dim) + "D element");
      target->group.nodes.push_back(node);
      if (shape.dim == dim - 1) target->group.facets.nodes.push_back(node);
    }
    if (shape.dim == dim) target->group.cells.push_back(cell_of[e]);
    if (shape.dim == dim - 1) {
      target->group.facets.offsets.push_back(static_cast<int>(target->group.facets.nodes.size()));
      target->group.facets.orders.push_back(shape.order);
    }
  }
  for (GroupParts& part : parts) {
    sort_unique(part.group.nodes);
    sort_unique(part.group.cells);
    mesh.groups.push_back(std::move(part.group));
  }

  if (dim == 2) flatten_2d(mesh);
  mesh.validate();
  return mesh;
}

void MeshBuilder::flatten_2d(Mesh& mesh) const {
  double extent = 0;
  for (double x : mesh.rest_positions) extent = std::max(extent, std::abs(x));
  const double tolerance = 1e-9 * std::max(1.0, extent);
  for (int n = 0; n < mesh.node_count(); ++n) {
    double& z = mesh.rest_positions[3 * static_cast<std::size_t>(n) + 2];
    if (std::abs(z) > tolerance)
      throw InputError(source_ + ": 2D mesh with node " + std::to_string(mesh.node_source_ids[static_cast<std::size_t>(n)]) +
                       " at z = " + std::to_string(z) + "; 2D meshes must lie in the plane z = 0");
    z = 0;
  }
}

}  // namespace tensormass::detail
