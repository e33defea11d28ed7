/// \file mesh_test_support.hpp
/// Helpers of the mesh tests: paths of the committed test meshes, a scratch
/// directory, a minimal JSON reader for expected.json, mesh comparison and
/// an InputError matcher.
#ifndef TENSORMASS_TESTS_MESH_TEST_SUPPORT_HPP
#define TENSORMASS_TESTS_MESH_TEST_SUPPORT_HPP

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include "tensormass/common/errors.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace meshtest {

namespace fs = std::filesystem;

inline std::string data_dir() { return std::string(TENSORMASS_SOURCE_DIR) + "/tests/data/meshes/"; }
inline std::string data_file(const std::string& name) { return data_dir() + name; }

/// The four Gmsh encodings written by make_meshes.py.
inline const std::vector<std::string>& encodings() {
  static const std::vector<std::string> list{"msh22", "msh22b", "msh41", "msh41b"};
  return list;
}

/// A fresh directory under the system temporary directory, removed at exit.
class ScratchDir {
 public:
  ScratchDir() {
    path_ = fs::temp_directory_path() /
            ("tensormass_mesh_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++));
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  /// Writes `content` to NAME in the directory; returns the path.
  std::string write(const std::string& name, const std::string& content) const {
    const std::string file = (path_ / name).string();
    std::ofstream out(file, std::ios::binary);
    out << content;
    return file;
  }
  std::string path(const std::string& name) const { return (path_ / name).string(); }

 private:
  static int& counter() {
    static int value = 0;
    return value;
  }
  fs::path path_;
};

inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Runs read_mesh(path); expects an InputError whose message contains every piece.
inline void expect_input_error(const std::string& path, const std::vector<std::string>& pieces) {
  try {
    tensormass::read_mesh(path);
    ADD_FAILURE() << path << ": read without error";
  } catch (const tensormass::InputError& error) {
    const std::string message = error.what();
    for (const std::string& piece : pieces)
      EXPECT_NE(message.find(piece), std::string::npos) << "message '" << message << "' lacks '" << piece << "'";
  } catch (const std::exception& error) {
    ADD_FAILURE() << path << ": not an InputError: " << error.what();
  }
}

// --- Minimal JSON (objects, arrays, numbers, strings without escapes) ------

struct Json {
  enum class Kind { null, number, string, array, object } kind = Kind::null;
  double number = 0;
  std::string text;
  std::vector<Json> items;
  std::map<std::string, Json> members;

  const Json& operator[](const std::string& key) const {
    static const Json missing;
    const auto found = members.find(key);
    return found == members.end() ? missing : found->second;
  }
  int integer() const { return static_cast<int>(number); }
};

class JsonParser {
 public:
  explicit JsonParser(std::string text) : text_(std::move(text)) {}
  Json parse() {
    Json value = parse_value();
    skip_space();
    if (pos_ != text_.size()) throw std::runtime_error("json: trailing characters");
    return value;
  }

 private:
  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  char next() {
    skip_space();
    if (pos_ >= text_.size()) throw std::runtime_error("json: unexpected end");
    return text_[pos_];
  }
  std::string parse_string() {
    ++pos_;
    const std::size_t end = text_.find('"', pos_);
    if (end == std::string::npos) throw std::runtime_error("json: unterminated string");
    std::string result = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    return result;
  }
  Json parse_value() {
    Json value;
    const char c = next();
    if (c == '{') {
      value.kind = Json::Kind::object;
      ++pos_;
      while (next() != '}') {
        const std::string key = parse_string();
        if (next() != ':') throw std::runtime_error("json: expected ':'");
        ++pos_;
        value.members[key] = parse_value();
        if (next() == ',') ++pos_;
      }
      ++pos_;
    } else if (c == '[') {
      value.kind = Json::Kind::array;
      ++pos_;
      while (next() != ']') {
        value.items.push_back(parse_value());
        if (next() == ',') ++pos_;
      }
      ++pos_;
    } else if (c == '"') {
      value.kind = Json::Kind::string;
      value.text = parse_string();
    } else if (text_.compare(pos_, 4, "null") == 0) {
      pos_ += 4;
    } else {
      value.kind = Json::Kind::number;
      std::size_t used = 0;
      value.number = std::stod(text_.substr(pos_, 40), &used);
      pos_ += used;
    }
    return value;
  }
  std::string text_;
  std::size_t pos_ = 0;
};

inline const Json& expected_meshes() {
  static const Json json = JsonParser(read_file(data_file("expected.json"))).parse();
  return json;
}

// --- Mesh comparison ----------------------------------------------------------

inline std::array<double, 3> position(const tensormass::Mesh& mesh, int node) {
  const auto n = static_cast<std::size_t>(node);
  return {mesh.rest_positions[3 * n], mesh.rest_positions[3 * n + 1], mesh.rest_positions[3 * n + 2]};
}

/// Sorted coordinates of `nodes`.
inline std::vector<std::array<double, 3>> positions(const tensormass::Mesh& mesh, const std::vector<int>& nodes) {
  std::vector<std::array<double, 3>> result;
  for (int node : nodes) result.push_back(position(mesh, node));
  std::sort(result.begin(), result.end());
  return result;
}

/// Same cells (type, order, node coordinates in order), compared by position so
/// that node numbering may differ.
inline void expect_same_cells(const tensormass::Mesh& a, const tensormass::Mesh& b) {
  ASSERT_EQ(a.dim, b.dim);
  ASSERT_EQ(a.node_count(), b.node_count());
  ASSERT_EQ(a.blocks.size(), b.blocks.size());
  for (std::size_t k = 0; k < a.blocks.size(); ++k) {
    const tensormass::ElementBlock& x = a.blocks[k];
    const tensormass::ElementBlock& y = b.blocks[k];
    ASSERT_EQ(x.element, y.element);
    ASSERT_EQ(x.count(), y.count()) << x.element->name;
    EXPECT_EQ(x.first_cell, y.first_cell);
    for (int c = 0; c < x.count(); ++c)
      for (int j = 0; j < x.nodes_per_cell(); ++j)
        ASSERT_EQ(position(a, x.cell_nodes(c)[static_cast<std::size_t>(j)]), position(b, y.cell_nodes(c)[static_cast<std::size_t>(j)]))
            << x.element->name << " cell " << c << " node " << j;
  }
}

/// Identical meshes (same numbering), groups included; source ids optional.
/// Coordinates may differ in the last digit (Gmsh writes ASCII with 16 digits).
inline void expect_identical(const tensormass::Mesh& a, const tensormass::Mesh& b, bool compare_element_ids) {
  EXPECT_EQ(a.dim, b.dim);
  ASSERT_EQ(a.rest_positions.size(), b.rest_positions.size());
  for (std::size_t i = 0; i < a.rest_positions.size(); ++i)
    ASSERT_NEAR(a.rest_positions[i], b.rest_positions[i], 1e-15 * std::max(1.0, std::abs(a.rest_positions[i]))) << "coordinate " << i;
  EXPECT_EQ(a.node_source_ids, b.node_source_ids);
  ASSERT_EQ(a.blocks.size(), b.blocks.size());
  for (std::size_t k = 0; k < a.blocks.size(); ++k) {
    EXPECT_EQ(a.blocks[k].element, b.blocks[k].element);
    EXPECT_EQ(a.blocks[k].connectivity, b.blocks[k].connectivity);
    EXPECT_EQ(a.blocks[k].first_cell, b.blocks[k].first_cell);
    if (compare_element_ids) {
      EXPECT_EQ(a.blocks[k].source_ids, b.blocks[k].source_ids);
    }
  }
  ASSERT_EQ(a.groups.size(), b.groups.size());
  for (std::size_t g = 0; g < a.groups.size(); ++g) {
    EXPECT_EQ(a.groups[g].name, b.groups[g].name);
    EXPECT_EQ(a.groups[g].dim, b.groups[g].dim);
    EXPECT_EQ(a.groups[g].nodes, b.groups[g].nodes);
    EXPECT_EQ(a.groups[g].cells, b.groups[g].cells);
    EXPECT_EQ(a.groups[g].facets.offsets, b.groups[g].facets.offsets);
    EXPECT_EQ(a.groups[g].facets.nodes, b.groups[g].facets.nodes);
    EXPECT_EQ(a.groups[g].facets.orders, b.groups[g].facets.orders);
  }
}

}  // namespace meshtest

#endif
