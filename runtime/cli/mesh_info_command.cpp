// `tensormass mesh-info FILE [--json]`: what a mesh file holds (dimension,
// nodes, cells per element type, groups) and its shape quality (scaled
// Jacobian and edge ratio per type, inverted elements). Bad input throws
// InputError (exit 2); inverted elements are reported with a warning on
// stderr, exit 0.
#include <cmath>
#include <cstdio>
#include <string>

#include "commands.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/mesh/mesh.hpp"
#include "tensormass/mesh/mesh_quality.hpp"

namespace tensormass::cli {
namespace {

constexpr const char* kMeshInfoUsage =
    "usage: tensormass mesh-info FILE [--json]\n"
    "\n"
    "Reads a mesh (.msh Gmsh 2.2/4.1, .vtu, legacy .vtk) and prints its dimension,\n"
    "node count, cells per element type, groups (name, dim, nodes, cells, facets),\n"
    "the scaled Jacobian (1 = ideal shape, <= 0 = inverted) and edge ratio per type,\n"
    "and the inverted elements. Exit 0 (a warning on stderr when elements are\n"
    "inverted), 2 on bad input.\n";

constexpr int kTextListLimit = 50;

struct Options {
  std::string path;
  bool json = false;
};

Options parse_options(const Arguments& args) {
  Options options;
  for (const std::string& arg : args) {
    if (arg == "--json") options.json = true;
    else if (!arg.empty() && arg[0] == '-')
      throw InputError("mesh-info: unknown option '" + arg + "' (usage: tensormass mesh-info FILE [--json])");
    else if (options.path.empty()) options.path = arg;
    else throw InputError("mesh-info: more than one FILE ('" + options.path + "', '" + arg + "')");
  }
  if (options.path.empty()) throw InputError("mesh-info: missing FILE (usage: tensormass mesh-info FILE [--json])");
  return options;
}

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += std::string("\\") + c;
    else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += buffer;
    } else out += c;
  }
  return out + "\"";
}

std::string json_number(double value) {
  if (!std::isfinite(value)) return "null";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

long source_id(const Mesh& mesh, int cell) {
  const auto [b, local] = mesh.locate(cell);
  return mesh.blocks[static_cast<std::size_t>(b)].source_ids[static_cast<std::size_t>(local)];
}

const char* element_name(const Mesh& mesh, int cell) {
  return mesh.blocks[static_cast<std::size_t>(mesh.locate(cell).first)].element->name;
}

void print_text(const Mesh& mesh, const MeshQuality& quality) {
  std::printf("mesh            %s\n", mesh.source.c_str());
  std::printf("dimension       %d\n", mesh.dim);
  std::printf("nodes           %d\n", mesh.node_count());
  std::printf("cells           %d\n", mesh.cell_count());
  for (const ElementBlock& block : mesh.blocks) std::printf("  %-12s %8d\n", block.element->name, block.count());
  std::printf("groups          %zu\n", mesh.groups.size());
  if (!mesh.groups.empty()) std::printf("  %-20s %4s %8s %8s %8s\n", "name", "dim", "nodes", "cells", "facets");
  for (const Group& g : mesh.groups)
    std::printf("  %-20s %4d %8zu %8zu %8d\n", g.name.c_str(), g.dim, g.nodes.size(), g.cells.size(), g.facets.count());
  std::printf("quality         scaled Jacobian: 1 = ideal shape, <= 0 = inverted\n");
  std::printf("  %-10s %8s %10s %10s %14s %9s\n", "type", "count", "min_sj", "max_sj", "max_edge_ratio", "inverted");
  for (const ElementTypeQuality& t : quality.types)
    std::printf("  %-10s %8d %10.4g %10.4g %14.4g %9d\n", t.element->name, t.count, t.min_scaled_jacobian,
                t.max_scaled_jacobian, t.max_edge_ratio, t.inverted);
  std::printf("max edge ratio  %.4g\n", quality.max_edge_ratio);
  std::printf("%-15s %.10g\n", mesh.dim == 2 ? "area" : "volume", quality.volume);
  std::printf("inverted        %zu\n", quality.inverted_cells.size());
  int shown = 0;
  for (const int cell : quality.inverted_cells) {
    if (shown++ == kTextListLimit) {
      std::printf("  ... %zu more (--json lists all)\n", quality.inverted_cells.size() - kTextListLimit);
      break;
    }
    std::printf("  %s\n", mesh.describe_cell(cell).c_str());
  }
}

void print_json(const Mesh& mesh, const MeshQuality& quality) {
  std::printf("{\n  \"file\": %s,\n  \"dimension\": %d,\n  \"nodes\": %d,\n  \"cells\": %d,\n",
              json_string(mesh.source).c_str(), mesh.dim, mesh.node_count(), mesh.cell_count());
  std::printf("  \"element_types\": {");
  for (std::size_t b = 0; b < mesh.blocks.size(); ++b)
    std::printf("%s\"%s\": %d", b ? ", " : "", mesh.blocks[b].element->name, mesh.blocks[b].count());
  std::printf("},\n  \"groups\": [");
  for (std::size_t i = 0; i < mesh.groups.size(); ++i) {
    const Group& g = mesh.groups[i];
    std::printf("%s\n    {\"name\": %s, \"dim\": %d, \"nodes\": %zu, \"cells\": %zu, \"facets\": %d}", i ? "," : "",
                json_string(g.name).c_str(), g.dim, g.nodes.size(), g.cells.size(), g.facets.count());
  }
  std::printf("%s],\n  \"quality\": {", mesh.groups.empty() ? "" : "\n  ");
  for (std::size_t i = 0; i < quality.types.size(); ++i) {
    const ElementTypeQuality& t = quality.types[i];
    std::printf(
        "%s\n    \"%s\": {\"count\": %d, \"min_scaled_jacobian\": %s, \"max_scaled_jacobian\": %s, "
        "\"max_edge_ratio\": %s, \"inverted\": %d, \"volume\": %s}",
        i ? "," : "", t.element->name, t.count, json_number(t.min_scaled_jacobian).c_str(),
        json_number(t.max_scaled_jacobian).c_str(), json_number(t.max_edge_ratio).c_str(), t.inverted,
        json_number(t.volume).c_str());
  }
  std::printf("\n  },\n  \"max_edge_ratio\": %s,\n  \"volume\": %s,\n  \"inverted\": [",
              json_number(quality.max_edge_ratio).c_str(), json_number(quality.volume).c_str());
  for (std::size_t i = 0; i < quality.inverted_cells.size(); ++i) {
    const int cell = quality.inverted_cells[i];
    std::printf("%s\n    {\"cell\": %d, \"element\": \"%s\", \"source_id\": %ld}", i ? "," : "", cell,
                element_name(mesh, cell), source_id(mesh, cell));
  }
  std::printf("%s]\n}\n", quality.inverted_cells.empty() ? "" : "\n  ");
}

}  // namespace

int mesh_info_command(const Arguments& args) {
  for (const std::string& arg : args)
    if (arg == "-h" || arg == "--help") {
      std::fputs(kMeshInfoUsage, stdout);
      return 0;
    }
  const Options options = parse_options(args);
  const Mesh mesh = read_mesh(options.path);
  const MeshQuality quality = mesh_quality(mesh);
  options.json ? print_json(mesh, quality) : print_text(mesh, quality);
  std::fflush(stdout);
  if (!quality.inverted_cells.empty())
    std::fprintf(stderr, "tensormass: warning: %zu inverted element(s) in %s (first: %s); a simulation rejects them\n",
                 quality.inverted_cells.size(), mesh.source.c_str(),
                 mesh.describe_cell(quality.inverted_cells.front()).c_str());
  return 0;
}

}  // namespace tensormass::cli
