/// \file mesh_builder.hpp
/// Internal helpers of the mesh readers (not installed):
///   InputCursor  walks a file held in memory (text tokens with line numbers,
///                binary values with byte offsets) and throws InputError
///                "FILE:LINE: what" or "FILE: byte N: what";
///   MeshBuilder  assembles a Mesh from format-independent raw nodes and
///                elements (file ids, our node order, group keys).
#ifndef TENSORMASS_MESH_BUILDER_HPP
#define TENSORMASS_MESH_BUILDER_HPP

#include <bit>
#include <cstdint>
#include <cstring>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tensormass/mesh.hpp"

namespace tensormass::detail {

/// Where something was read: a line (text) or a byte offset (binary).
struct Location {
  long value = 0;
  bool byte = false;
};

/// "FILE:LINE" or "FILE: byte N".
std::string format_location(const std::string& file, Location where);

/// The whole content of a file and a read position.
/// Text is read as whitespace-separated tokens; each newline passed counts a
/// line. Once `set_binary(true)` is called, errors name byte offsets instead.
class InputCursor {
 public:
  InputCursor(std::string path, std::string data) : path_(std::move(path)), data_(std::move(data)) {}

  const std::string& path() const { return path_; }
  std::string_view data() const { return data_; }
  std::size_t position() const { return pos_; }
  std::size_t remaining() const { return data_.size() - pos_; }
  long line() const { return line_; }
  bool binary() const { return binary_; }
  void set_binary(bool binary) { binary_ = binary; }
  Location location() const { return binary_ ? Location{static_cast<long>(pos_), true} : Location{line_, false}; }
  /// Where the next item starts: skips whitespace first in text mode (so the
  /// line is the item's own), nothing in binary mode.
  Location here() {
    if (!binary_) at_end();
    return location();
  }
  /// The line number of byte `offset` (counted from the start of the file).
  long line_at(std::size_t offset) const;

  /// Skips whitespace; true when nothing but whitespace is left.
  bool at_end();
  /// The next token; throws "unexpected end of file, expected WHAT" at the end.
  std::string_view token(std::string_view what);
  /// The next token without consuming it ("" at the end).
  std::string_view peek_token();
  /// The rest of the current line (trimmed), consuming its newline.
  std::string_view rest_of_line();
  /// Consumes spaces up to and including the end of the current line.
  void skip_line_end();
  /// Consumes the next token and throws unless it equals `keyword`.
  void expect(std::string_view keyword);
  /// Moves past the next occurrence of `marker` (not consumed when absent: throws).
  void skip_past(std::string_view marker, std::string_view what);

  long integer(std::string_view what);
  double real(std::string_view what);
  /// A count in [0, limit]: refuses counts that cannot fit in the bytes left
  /// (min_bytes_each per item) before anything is allocated for them.
  long count(std::string_view what, std::size_t min_bytes_each);
  /// Checks a count read elsewhere (binary) the same way; `where` is where it was read.
  long checked_count(unsigned long long n, std::string_view what, std::size_t min_bytes_each, Location where) const;

  /// `n` raw bytes; throws when fewer are left.
  std::span<const unsigned char> bytes(std::size_t n, std::string_view what);
  /// A binary value of type T stored little- or big-endian.
  template <class T>
  T value(std::string_view what, std::endian order = std::endian::little) {
    const auto raw = bytes(sizeof(T), what);
    unsigned char buffer[sizeof(T)];
    std::memcpy(buffer, raw.data(), sizeof(T));
    if (order != std::endian::native)
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(buffer[i], buffer[sizeof(T) - 1 - i]);
    T result;
    std::memcpy(&result, buffer, sizeof(T));
    return result;
  }

  /// Throws InputError "FILE:LINE: message" (or "FILE: byte N: message").
  [[noreturn]] void fail(const std::string& message) const;
  [[noreturn]] void fail_at(Location where, const std::string& message) const;

 private:
  std::string path_;
  std::string data_;
  std::size_t pos_ = 0;
  long line_ = 1;
  bool binary_ = false;
};

/// Parses a whole token as a number; false on garbage or overflow.
bool parse_integer(std::string_view text, long& value);
bool parse_real(std::string_view text, double& value);

/// An element kind the builder knows: a point, a line (2 or 3 nodes) or a
/// registry reference element.
struct Shape {
  std::string name;
  int dim = 0;
  int nodes = 0;
  int order = 1;
  const tm_element_info* element = nullptr;  ///< null for point and lines
};

/// "point", "line2", "line3" or a registry element name; nullptr otherwise.
const Shape* find_shape(std::string_view name);
/// The shape of a registry element.
const Shape* shape_of(const tm_element_info* element);

/// How a group key is turned into a group: its name and dimension
/// (dim < 0: the highest dimension of its elements).
struct GroupInfo {
  std::string name;
  int dim = -1;
};

/// Collects raw nodes and elements, then builds a Mesh:
///   - the mesh dimension is the highest element dimension (2 or 3); the
///     elements of that dimension are the cells, sorted into blocks in
///     registry order (file order inside a block);
///   - elements of dimension dim-1 are the facets of their groups; a
///     group's nodes are the nodes of its elements of any dimension;
///   - elements repeated with the same shape and nodes are merged (MSH 2.2
///     writes an element once per physical group);
///   - nodes used by no cell are dropped; the others are renumbered
///     0..n-1 in file order (node_source_ids keeps the file ids);
///   - groups sharing a name are merged (dimension: the highest).
class MeshBuilder {
 public:
  /// `element_word` names elements in messages ("element" or "cell").
  MeshBuilder(std::string source, std::string element_word);

  /// Reserves room for `count` nodes (counts already checked by the reader).
  void reserve_nodes(std::size_t count);
  /// Adds node `id`; throws at `where` for a non-finite coordinate.
  void add_node(long id, const double xyz[3], Location where);
  /// Adds an element: `nodes` are file node ids in our node order,
  /// `groups` the keys of the groups it belongs to.
  void add_element(const Shape& shape, long id, std::span<const long> nodes, std::span<const long> groups,
                   Location where);

  /// Builds and validates the mesh; `describe` names each group key.
  Mesh build(const std::function<GroupInfo(long key)>& describe);

 private:
  class NodeIndex;
  struct Resolved;
  int mesh_dimension() const;
  Resolved resolve() const;
  void fill_nodes(Mesh& mesh, const Resolved& r) const;
  void fill_blocks(Mesh& mesh, Resolved& r) const;
  void fill_groups(Mesh& mesh, const Resolved& r, const std::function<GroupInfo(long key)>& describe) const;
  void add_to_group(Group& group, std::size_t e, const Resolved& r) const;
  void flatten_2d(Mesh& mesh) const;
  [[noreturn]] void fail_element(std::size_t e, const std::string& message) const;

  std::string source_;
  std::string element_word_;
  std::vector<long> node_ids_;
  std::vector<double> xyz_;
  std::vector<Location> node_where_;
  std::vector<const Shape*> shapes_;
  std::vector<long> element_ids_;
  std::vector<std::size_t> node_offsets_{0};
  std::vector<long> element_nodes_;
  std::vector<std::size_t> group_offsets_{0};
  std::vector<long> element_groups_;
  std::vector<Location> element_where_;
};

/// Reads a Gmsh .msh file (2.2 or 4.1, ASCII or binary) held in `input`.
Mesh read_gmsh(InputCursor& input);
/// Reads a VTK XML unstructured grid (.vtu).
Mesh read_vtu(InputCursor& input);
/// Reads a legacy VTK unstructured grid (.vtk, ASCII or BINARY).
Mesh read_legacy_vtk(InputCursor& input);

}  // namespace tensormass::detail

#endif
