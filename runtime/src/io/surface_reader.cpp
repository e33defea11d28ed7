// read_surface: triangle surfaces from STL (ASCII or binary), OBJ and Gmsh
// .msh files; coincident points merged, unused points and patches dropped.
#include "tensormass/io/surface_reader.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <new>
#include <sstream>
#include <string_view>
#include <unordered_map>

#include "common/input_cursor.hpp"
#include "common/regular_file.hpp"
#include "io/gmsh_session.hpp"
#include "io/mesh_readers.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass {

namespace {

using detail::quoted;

std::string format_number(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string file_name(const std::string& path) { return std::filesystem::path(path).filename().string(); }

std::string lower(std::string_view text) {
  std::string result(text);
  std::transform(result.begin(), result.end(), result.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return result;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::string_view trim(std::string_view text) {
  while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
  return text;
}

/// Splits a line into whitespace-separated tokens (at most `max` kept; the count is exact).
struct Tokens {
  static constexpr int kMax = 16;
  std::string_view items[kMax];
  int count = 0;

  explicit Tokens(std::string_view line) {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && is_space(line[i])) ++i;
      if (i >= line.size()) break;
      const std::size_t start = i;
      while (i < line.size() && !is_space(line[i])) ++i;
      if (count < kMax) items[count] = line.substr(start, i - start);
      ++count;
    }
  }
};

/// Iterates over the lines of a buffer with their numbers (from 1).
class LineReader {
 public:
  explicit LineReader(std::string_view data) : data_(data) {}
  bool next(std::string_view& line) {
    if (pos_ >= data_.size()) return false;
    const std::size_t end = data_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? data_.size() : end;
    line = data_.substr(pos_, stop - pos_);
    pos_ = stop + 1;
    ++number_;
    return true;
  }
  long number() const { return number_; }

 private:
  std::string_view data_;
  std::size_t pos_ = 0;
  long number_ = 0;
};

bool parse_double(std::string_view text, double& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return false;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

bool parse_long(std::string_view text, long& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return false;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

/// Builds a surface: points, triangles with their patch and source id.
class SurfaceBuilder {
 public:
  SurfaceBuilder(const std::string& path, std::string label) {
    surface_.source = path;
    surface_.source_label = std::move(label);
  }

  int patch(const std::string& name) {
    const auto [it, added] = patch_index_.try_emplace(name, static_cast<int>(surface_.patch_names.size()));
    if (added) surface_.patch_names.push_back(name);
    return it->second;
  }
  int add_point(double x, double y, double z) {
    surface_.points.insert(surface_.points.end(), {x, y, z});
    return surface_.point_count() - 1;
  }
  void add_triangle(int a, int b, int c, int patch, long source_id) {
    surface_.triangles.insert(surface_.triangles.end(), {a, b, c});
    surface_.patches.push_back(patch);
    surface_.source_ids.push_back(source_id);
  }
  TriangleSurface& surface() { return surface_; }

 private:
  TriangleSurface surface_;
  std::map<std::string, int> patch_index_;
};

// ------------------------------------------------------------------ STL

bool starts_with_solid(std::string_view data) {
  std::size_t i = 0;
  while (i < data.size() && (is_space(data[i]) || data[i] == '\n')) ++i;
  return lower(data.substr(i, 5)) == "solid" &&
         (i + 5 == data.size() || std::isspace(static_cast<unsigned char>(data[i + 5])));
}

bool looks_like_text(std::string_view data) {
  for (const char ch : data) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 9 || (c > 13 && c < 32) || c == 127) return false;
  }
  return true;
}

void read_binary_stl(const std::string& path, std::string_view data, SurfaceBuilder& builder) {
  if (data.size() < 84)
    throw InputError(path + ": " + std::to_string(data.size()) +
                     " bytes is too short for a binary STL (80-byte header and a 4-byte triangle count) "
                     "and the file is not ASCII STL (which starts with 'solid')");
  std::uint32_t count = 0;
  std::memcpy(&count, data.data() + 80, 4);
  if constexpr (std::endian::native == std::endian::big) count = __builtin_bswap32(count);
  const unsigned long long needed = 84ULL + 50ULL * count;
  if (needed != data.size()) {
    if (needed > data.size())
      throw InputError(path + ": byte 80: truncated binary STL: the header counts " + std::to_string(count) +
                       " triangles, which need " + std::to_string(needed) + " bytes, but the file has " +
                       std::to_string(data.size()) + " (facet " + std::to_string((data.size() - 84) / 50 + 1) +
                       " is cut at byte " + std::to_string(84 + ((data.size() - 84) / 50) * 50) + ")");
    throw InputError(path + ": byte " + std::to_string(needed) + ": binary STL: the header (byte 80) counts " +
                     std::to_string(count) + " triangles, which end at byte " + std::to_string(needed) +
                     ", but the file has " + std::to_string(data.size() - needed) + " more bytes");
  }
  const int patch = builder.patch("");
  for (std::uint32_t f = 0; f < count; ++f) {
    const std::size_t offset = 84 + 50 * static_cast<std::size_t>(f);
    int corners[3];
    for (int k = 0; k < 3; ++k) {
      double xyz[3];
      for (int a = 0; a < 3; ++a) {
        const std::size_t at = offset + 12 + 12 * static_cast<std::size_t>(k) + 4 * static_cast<std::size_t>(a);
        std::uint32_t bits = 0;
        std::memcpy(&bits, data.data() + at, 4);
        if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
        const float value = std::bit_cast<float>(bits);
        if (!std::isfinite(value))
          throw InputError(path + ": byte " + std::to_string(at) + ": facet " + std::to_string(f + 1) + ", vertex " +
                           std::to_string(k + 1) + ": coordinate " + "xyz"[a] + " is not a finite number (" +
                           format_number(value) + ")");
        xyz[a] = value;
      }
      corners[k] = builder.add_point(xyz[0], xyz[1], xyz[2]);
    }
    builder.add_triangle(corners[0], corners[1], corners[2], patch, static_cast<long>(f) + 1);
  }
}

void read_ascii_stl(const std::string& path, std::string_view data, SurfaceBuilder& builder) {
  enum class State { kOutside, kSolid, kFacet, kLoop, kEndLoop };
  State state = State::kOutside;
  LineReader lines(data);
  std::string_view line;
  std::string solid_name;
  long solid_line = 0, facet_line = 0;
  long facet_number = 0;
  int patch = -1;
  std::vector<int> corners;
  auto fail = [&](const std::string& message) -> void {
    throw InputError(path + ":" + std::to_string(lines.number()) + ": " + message);
  };
  auto number = [&](std::string_view token, const char* what, bool finite) {
    double value = 0;
    if (!parse_double(token, value)) fail(std::string("expected a number (") + what + "), found " + quoted(token));
    if (finite && !std::isfinite(value)) fail(std::string(what) + " is not a finite number: " + quoted(token));
    return value;
  };
  while (lines.next(line)) {
    const Tokens tokens(line);
    if (tokens.count == 0) continue;
    const std::string keyword = lower(tokens.items[0]);
    auto expect_count = [&](int n, const char* form) {
      if (tokens.count != n) fail("expected '" + std::string(form) + "', found " + quoted(trim(line)));
    };
    if (keyword == "solid") {
      if (state != State::kOutside)
        fail("'solid' inside solid '" + solid_name + "' (started at line " + std::to_string(solid_line) +
             "): missing 'endsolid'");
      const std::string_view rest = trim(trim(line).substr(tokens.items[0].size()));
      solid_name = std::string(rest);
      solid_line = lines.number();
      patch = builder.patch(solid_name);
      state = State::kSolid;
    } else if (keyword == "endsolid") {
      if (state != State::kSolid) {
        if (state == State::kOutside) fail("'endsolid' without 'solid'");
        fail("'endsolid' inside the facet started at line " + std::to_string(facet_line));
      }
      state = State::kOutside;
    } else if (keyword == "facet") {
      if (state != State::kSolid) {
        if (state == State::kOutside) fail("'facet' outside a solid (expected 'solid NAME' first)");
        fail("'facet' inside the facet started at line " + std::to_string(facet_line) + " (missing 'endfacet')");
      }
      if (tokens.count >= 2 && lower(tokens.items[1]) == "normal") {
        expect_count(5, "facet normal NX NY NZ");
        for (int a = 0; a < 3; ++a) number(tokens.items[2 + a], "facet normal", false);
      } else {
        expect_count(1, "facet normal NX NY NZ");
      }
      facet_line = lines.number();
      ++facet_number;
      state = State::kFacet;
    } else if (keyword == "outer") {
      if (state != State::kFacet) fail("'outer loop' outside a facet");
      expect_count(2, "outer loop");
      if (lower(tokens.items[1]) != "loop") fail("expected 'outer loop', found " + quoted(trim(line)));
      corners.clear();
      state = State::kLoop;
    } else if (keyword == "vertex") {
      if (state != State::kLoop) fail("'vertex' outside 'outer loop'");
      expect_count(4, "vertex X Y Z");
      const double x = number(tokens.items[1], "vertex x", true);
      const double y = number(tokens.items[2], "vertex y", true);
      const double z = number(tokens.items[3], "vertex z", true);
      corners.push_back(builder.add_point(x, y, z));
    } else if (keyword == "endloop") {
      if (state != State::kLoop) fail("'endloop' without 'outer loop'");
      expect_count(1, "endloop");
      if (corners.size() < 3)
        fail("the facet started at line " + std::to_string(facet_line) + " has " + std::to_string(corners.size()) +
             " vertices (at least 3 needed)");
      state = State::kEndLoop;
    } else if (keyword == "endfacet") {
      if (state != State::kEndLoop) fail("'endfacet' without a complete 'outer loop ... endloop'");
      expect_count(1, "endfacet");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k)
        builder.add_triangle(corners[0], corners[k], corners[k + 1], patch, facet_number);
      state = State::kSolid;
    } else {
      fail("unexpected " + quoted(tokens.items[0]) + " in ASCII STL");
    }
  }
  if (state == State::kSolid)
    throw InputError(path + ":" + std::to_string(lines.number()) + ": unexpected end of file: solid '" + solid_name +
                     "' started at line " + std::to_string(solid_line) + " has no 'endsolid' (truncated file?)");
  if (state != State::kOutside)
    throw InputError(path + ":" + std::to_string(lines.number()) +
                     ": unexpected end of file inside the facet started at line " + std::to_string(facet_line) +
                     " (truncated file?)");
}

void read_stl(const std::string& path, std::string_view data, SurfaceBuilder& builder) {
  if (data.size() >= 84) {
    std::uint32_t count = 0;
    std::memcpy(&count, data.data() + 80, 4);
    if constexpr (std::endian::native == std::endian::big) count = __builtin_bswap32(count);
    if (84ULL + 50ULL * count == data.size()) return read_binary_stl(path, data, builder);
  }
  std::string_view text = data;
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte order mark
  if (starts_with_solid(text) && looks_like_text(text)) return read_ascii_stl(path, text, builder);
  read_binary_stl(path, data, builder);
}

// ------------------------------------------------------------------ OBJ

void read_obj(const std::string& path, std::string_view data, SurfaceBuilder& builder) {
  struct Corner {
    long index;  // 0-based, may still be >= the vertex count (checked at the end)
    long line;
  };
  LineReader lines(data);
  std::string_view line;
  int patch = -1;
  std::vector<Corner> corners;
  struct Face {
    std::size_t first;
    int count;
    int patch;
    long line;
  };
  std::vector<Face> faces;
  long vertex_count = 0;
  auto fail = [&](const std::string& message) -> void {
    throw InputError(path + ":" + std::to_string(lines.number()) + ": " + message);
  };
  while (lines.next(line)) {
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    const Tokens tokens(line);
    if (tokens.count == 0) continue;
    const std::string_view keyword = tokens.items[0];
    if (keyword == "v") {
      if (tokens.count < 4 || tokens.count > 8)
        fail("expected 'v X Y Z' (optionally W or R G B), found " + quoted(trim(line)));
      double xyz[3];
      for (int i = 1; i < std::min(tokens.count, Tokens::kMax); ++i) {
        double value = 0;
        if (!parse_double(tokens.items[i], value))
          fail("expected a number (vertex coordinate " + std::to_string(i) + "), found " + quoted(tokens.items[i]));
        if (i <= 3) {
          if (!std::isfinite(value))
            fail(std::string("vertex coordinate ") + "xyz"[i - 1] +
                 " is not a finite number: " + quoted(tokens.items[i]));
          xyz[i - 1] = value;
        }
      }
      builder.add_point(xyz[0], xyz[1], xyz[2]);
      ++vertex_count;
    } else if (keyword == "f") {
      if (tokens.count < 4) fail("a face needs at least 3 vertices, found " + quoted(trim(line)));
      std::vector<std::string_view> items;  // all corners (a polygon may have more than Tokens::kMax)
      {
        std::size_t i = 0;
        const std::string_view text = line;
        while (i < text.size()) {
          while (i < text.size() && is_space(text[i])) ++i;
          if (i >= text.size()) break;
          const std::size_t start = i;
          while (i < text.size() && !is_space(text[i])) ++i;
          items.push_back(text.substr(start, i - start));
        }
      }
      if (patch < 0) patch = builder.patch("");
      const std::size_t first = corners.size();
      for (std::size_t k = 1; k < items.size(); ++k) {
        const std::string_view item = items[k];
        const std::string_view index_text = item.substr(0, item.find('/'));
        long index = 0;
        if (!parse_long(index_text, index)) fail("expected a vertex index, found " + quoted(item));
        if (index == 0) fail("vertex index 0 in " + quoted(item) + " (OBJ indices start at 1)");
        if (index < 0) {
          if (index < -vertex_count)  // not -index > vertex_count: -LONG_MIN overflows
            fail("relative vertex index " + std::to_string(index) + " goes before the first vertex (" +
                 std::to_string(vertex_count) + " defined so far)");
          index = vertex_count + index;
        } else {
          index -= 1;
        }
        corners.push_back({index, lines.number()});
      }
      faces.push_back({first, static_cast<int>(items.size() - 1), patch, lines.number()});
    } else if (keyword == "g" || keyword == "o") {
      patch = builder.patch(std::string(trim(trim(line).substr(keyword.size()))));
    }
    // vt, vn, vp, s, usemtl, mtllib, l, p and other statements: not needed.
  }
  for (const Corner& corner : corners)
    if (corner.index >= vertex_count)
      throw InputError(path + ":" + std::to_string(corner.line) + ": vertex index " + std::to_string(corner.index + 1) +
                       " is out of range (the file has " + std::to_string(vertex_count) + " vertices)");
  for (const Face& face : faces)
    for (int k = 1; k + 1 < face.count; ++k)
      builder.add_triangle(static_cast<int>(corners[face.first].index), static_cast<int>(corners[face.first + k].index),
                           static_cast<int>(corners[face.first + k + 1].index), face.patch, face.line);
}

// ------------------------------------------------------------------ Gmsh

void read_msh_with_gmsh(const std::string& path, SurfaceBuilder& builder) {
  const detail::GmshSession session;
  std::string failure;
  try {
    gmsh::open(path);
    std::vector<std::size_t> node_tags;
    std::vector<double> coords, parametric;
    gmsh::model::mesh::getNodes(node_tags, coords, parametric, -1, -1, false, false);
    std::unordered_map<std::size_t, int> node_index;
    node_index.reserve(node_tags.size());
    for (std::size_t i = 0; i < node_tags.size(); ++i) {
      const double* xyz = &coords[3 * i];
      for (int a = 0; a < 3; ++a)
        if (!std::isfinite(xyz[a]))
          throw InputError(path + ": node " + std::to_string(node_tags[i]) + ": coordinate " + "xyz"[a] +
                           " is not a finite number");
      node_index.emplace(node_tags[i], builder.add_point(xyz[0], xyz[1], xyz[2]));
    }
    gmsh::vectorpair entities;
    gmsh::model::getEntities(entities, 2);
    for (const auto& [dim, tag] : entities) {
      std::vector<int> physicals;
      gmsh::model::getPhysicalGroupsForEntity(dim, tag, physicals);
      std::string name;
      if (!physicals.empty()) gmsh::model::getPhysicalName(dim, physicals.front(), name);
      std::vector<int> types;
      std::vector<std::vector<std::size_t>> element_tags, element_nodes;
      gmsh::model::mesh::getElements(types, element_tags, element_nodes, dim, tag);
      for (std::size_t k = 0; k < types.size(); ++k) {
        if (element_tags[k].empty()) continue;
        if (types[k] != 2) {
          std::string type_name;
          int type_dim = 0, order = 0, nodes = 0, primary = 0;
          std::vector<double> local;
          gmsh::model::mesh::getElementProperties(types[k], type_name, type_dim, order, nodes, local, primary);
          throw InputError(path + ": element " + std::to_string(element_tags[k].front()) + " on surface " +
                           std::to_string(tag) + " is a " + type_name + " (Gmsh type " + std::to_string(types[k]) +
                           "): only 3-node triangles (type 2) make a surface");
        }
        const int patch = builder.patch(name);
        for (std::size_t e = 0; e < element_tags[k].size(); ++e) {
          int corners[3];
          for (int c = 0; c < 3; ++c) {
            const auto found = node_index.find(element_nodes[k][3 * e + static_cast<std::size_t>(c)]);
            if (found == node_index.end())
              throw InputError(path + ": element " + std::to_string(element_tags[k][e]) + " refers to node " +
                               std::to_string(element_nodes[k][3 * e + static_cast<std::size_t>(c)]) +
                               ", which does not exist");
            corners[c] = found->second;
          }
          builder.add_triangle(corners[0], corners[1], corners[2], patch, static_cast<long>(element_tags[k][e]));
        }
      }
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::string& message) {
    failure = message;
  } catch (const char* message) {
    failure = message ? message : "unknown error";
  } catch (const std::exception& error) {
    failure = error.what();
  } catch (...) {
    failure = "unknown error";
  }
  if (!failure.empty()) throw InputError(path + ": Gmsh could not read the file: " + failure);
}

// ------------------------------------------------------------------ finishing

/// Merges points with exactly equal coordinates, drops points no triangle uses
/// (keeping first-use order) and patches no triangle uses.
void merge_and_compact(TriangleSurface& surface) {
  struct Key {
    std::uint64_t bits[3];
    bool operator==(const Key& other) const {
      return bits[0] == other.bits[0] && bits[1] == other.bits[1] && bits[2] == other.bits[2];
    }
  };
  struct KeyHash {
    std::size_t operator()(const Key& key) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ULL;
      for (const std::uint64_t b : key.bits) {
        h ^= b + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
        h *= 0xff51afd7ed558ccdULL;
        h ^= h >> 33;
      }
      return static_cast<std::size_t>(h);
    }
  };
  const int old_count = surface.point_count();
  std::vector<int> new_index(static_cast<std::size_t>(old_count), -1);
  std::unordered_map<Key, int, KeyHash> seen;
  seen.reserve(static_cast<std::size_t>(old_count));
  std::vector<double> points;
  points.reserve(surface.points.size());
  for (int& corner : surface.triangles) {
    const auto old = static_cast<std::size_t>(corner);
    if (new_index[old] < 0) {
      Key key;
      for (int a = 0; a < 3; ++a) {
        const double value = surface.points[3 * old + static_cast<std::size_t>(a)] + 0.0;  // -0 -> +0
        key.bits[a] = std::bit_cast<std::uint64_t>(value == 0 ? 0.0 : value);
      }
      const auto [it, added] = seen.try_emplace(key, static_cast<int>(points.size() / 3));
      if (added)
        points.insert(points.end(), surface.points.begin() + static_cast<long>(3 * old),
                      surface.points.begin() + static_cast<long>(3 * old + 3));
      new_index[old] = it->second;
    }
    corner = new_index[old];
  }
  surface.points = std::move(points);

  std::vector<int> patch_index(surface.patch_names.size(), -1);
  std::vector<std::string> names;
  for (int& patch : surface.patches) {
    auto& mapped = patch_index[static_cast<std::size_t>(patch)];
    if (mapped < 0) {
      mapped = static_cast<int>(names.size());
      names.push_back(surface.patch_names[static_cast<std::size_t>(patch)]);
    }
    patch = mapped;
  }
  surface.patch_names = std::move(names);
}

}  // namespace

std::string TriangleSurface::describe_triangle(int triangle) const {
  std::string text = "triangle " + std::to_string(triangle);
  if (triangle >= 0 && static_cast<std::size_t>(triangle) < source_ids.size()) {
    text += " (" + (source_label.empty() ? std::string("number") : source_label) + " " +
            std::to_string(source_ids[static_cast<std::size_t>(triangle)]);
    if (!source.empty()) text += " in " + file_name(source);
    text += ")";
  }
  return text;
}

std::string TriangleSurface::describe_point(int point) const {
  std::string text = "point " + std::to_string(point);
  if (point >= 0 && point < point_count()) {
    const double* xyz = &points[3 * static_cast<std::size_t>(point)];
    text += " (" + format_number(xyz[0]) + " " + format_number(xyz[1]) + " " + format_number(xyz[2]) + ")";
  }
  return text;
}

namespace {

std::string surface_extension(const std::string& path) {
  return lower(std::filesystem::path(path).extension().string());
}

void check_not_empty(const std::string& path, std::string_view data) {
  if (data.find_first_not_of(" \t\r\n\v\f") == std::string_view::npos) throw InputError(path + ": the file is empty");
}

/// The checks and clean-up shared by every format.
TriangleSurface finish(const std::string& path, SurfaceBuilder& builder) {
  TriangleSurface& surface = builder.surface();
  if (surface.triangle_count() == 0) throw InputError(path + ": no triangles (empty surface)");
  merge_and_compact(surface);
  return std::move(surface);
}

}  // namespace

namespace detail {

TriangleSurface read_surface_data(const std::string& path, std::string_view data) {
  const std::string extension = surface_extension(path);
  if (extension != ".stl" && extension != ".obj")
    throw InputError(path + ": surface data in memory must be .stl or .obj, not '" + extension + "'");
  check_not_empty(path, data);
  if (extension == ".stl") {
    SurfaceBuilder builder(path, "facet");
    read_stl(path, data, builder);
    return finish(path, builder);
  }
  SurfaceBuilder builder(path, "face at line");
  read_obj(path, data.starts_with("\xEF\xBB\xBF") ? data.substr(3) : data, builder);
  return finish(path, builder);
}

}  // namespace detail

TriangleSurface read_surface(const std::string& path) {
  const std::string extension = surface_extension(path);
  if (extension != ".stl" && extension != ".obj" && extension != ".msh")
    throw InputError(path + ": unknown surface format '" + extension + "' (expected .stl, .obj or .msh)");
  try {
    const std::string data = detail::read_regular_file(path, "surface");
    if (extension != ".msh") return detail::read_surface_data(path, data);
    check_not_empty(path, data);
    SurfaceBuilder builder(path, "element");
    read_msh_with_gmsh(path, builder);
    return finish(path, builder);
  } catch (const std::bad_alloc&) {  // a surface too large for this machine: say which file
    throw InputError(path + ": not enough memory to read this surface");
  }
}

}  // namespace tensormass
