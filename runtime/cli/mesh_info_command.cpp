// `tensormass mesh-info FILE [--json]`: what a mesh file holds (dimension,
// nodes, cells per element type, groups) and its shape quality (scaled
// Jacobian and edge ratio per type, inverted elements). Bad input throws
// InputError (exit 2); inverted elements are reported with a warning on
// stderr, exit 0.
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
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

using Json = nlohmann::ordered_json;

/// A number, or null where it is not finite (JSON has no NaN or infinity).
Json number(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

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
  Json types = Json::object();
  for (const ElementBlock& block : mesh.blocks) types[block.element->name] = block.count();
  Json groups = Json::array();
  for (const Group& g : mesh.groups)
    groups.push_back({{"name", g.name},
                      {"dim", g.dim},
                      {"nodes", g.nodes.size()},
                      {"cells", g.cells.size()},
                      {"facets", g.facets.count()}});
  Json per_type = Json::object();
  for (const ElementTypeQuality& t : quality.types)
    per_type[t.element->name] = {{"count", t.count},
                                 {"min_scaled_jacobian", number(t.min_scaled_jacobian)},
                                 {"max_scaled_jacobian", number(t.max_scaled_jacobian)},
                                 {"max_edge_ratio", number(t.max_edge_ratio)},
                                 {"inverted", t.inverted},
                                 {"volume", number(t.volume)}};
  Json inverted = Json::array();
  for (const int cell : quality.inverted_cells)
    inverted.push_back({{"cell", cell}, {"element", element_name(mesh, cell)}, {"source_id", source_id(mesh, cell)}});
  const Json info{{"file", mesh.source},
                  {"dimension", mesh.dim},
                  {"nodes", mesh.node_count()},
                  {"cells", mesh.cell_count()},
                  {"element_types", types},
                  {"groups", groups},
                  {"quality", per_type},
                  {"max_edge_ratio", number(quality.max_edge_ratio)},
                  {"volume", number(quality.volume)},
                  {"inverted", inverted}};
  std::printf("%s\n", info.dump(2, ' ', false, Json::error_handler_t::replace).c_str());
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
