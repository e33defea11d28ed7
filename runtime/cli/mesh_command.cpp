// `tensormass mesh SURFACE --size H ...`: a hex-dominant mixed volume mesh
// of a closed triangle surface (octree core + Gmsh tetrahedra in the gap).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "arguments.hpp"
#include "commands.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/gmsh_writer.hpp"
#include "tensormass/io/surface_reader.hpp"
#include "tensormass/mesh/mesh_conformity.hpp"
#include "tensormass/mesh/mesh_quality.hpp"
#include "tensormass/meshing/octree_mesher.hpp"
#include "tensormass/surface/surface.hpp"

namespace tensormass::cli {
namespace {

constexpr const char* kMeshUsage =
    "usage: tensormass mesh SURFACE --size H [OPTIONS] -o OUT.msh\n"
    "\n"
    "Fills a closed, outward-oriented triangle surface (.stl ASCII or binary, .obj,\n"
    "or a Gmsh .msh surface) with a hex-dominant mixed mesh: an octree of hexahedra\n"
    "inside, pyramid/tetrahedron transitions where the octree changes level, and\n"
    "a layer of prisms on the surface triangles, and Gmsh tetrahedra in between. The mesh's boundary is the\n"
    "input triangulation itself, so surface triangles should be about the size of\n"
    "the cells near the surface (H / 2^levels).\n"
    "\n"
    "options:\n"
    "  --size H                   edge of the interior hexahedra (required)\n"
    "  --levels K                 halvings of H near the surface (default 1, 0..8)\n"
    "  --roi X,Y,Z,R[,H_ROI]      refine the ball of centre X,Y,Z and radius R to cells\n"
    "                             of edge H_ROI or less (default H/2); repeatable\n"
    "  --region NAME=FILE         cells whose centroid lies inside the closed surface\n"
    "                             FILE join the cell group NAME (first match wins); repeatable\n"
    "  --layer T                  prism layer on the surface, T edges of the cells near the\n"
    "                             surface thick (default 0.25; 0: none; thinner when needed)\n"
    "  --margin M                 core cells stay M of their edge inside the surface (default 0.35)\n"
    "  --format 4.1|2.2           Gmsh file format (default 4.1)\n"
    "  -o, --output FILE          the .msh file to write (required)\n"
    "  -h, --help                 this text\n"
    "\n"
    "groups: body (all cells), surface (the input triangles), one facet group per\n"
    "named patch of the input (STL solid, OBJ group, Gmsh physical surface), and one\n"
    "cell group per --region. Exit 2 on bad input (open, non-manifold, inconsistently\n"
    "oriented or self-intersecting surfaces included), 3 when the gap cannot be filled.\n";

struct MeshOptions {
  std::string surface, output;
  OctreeMeshOptions octree;
  std::vector<std::pair<std::string, std::string>> regions;  // name, file
  io::MshFormat format = io::MshFormat::v41;
  bool size_given = false;
};

double parse_real(const std::string& option, const std::string& text) {
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(value))
    throw InputError("mesh: " + option + ": '" + text + "' is not a number");
  return value;
}

RegionOfInterest parse_roi(const std::string& text, double size) {
  const std::vector<std::string> parts = split_commas(text);
  if (parts.size() != 4 && parts.size() != 5)
    throw InputError("mesh: --roi: expected X,Y,Z,R or X,Y,Z,R,H_ROI, got '" + text + "'");
  RegionOfInterest roi;
  for (int a = 0; a < 3; ++a) roi.centre[a] = parse_real("--roi", parts[a]);
  roi.radius = parse_real("--roi", parts[3]);
  roi.size = parts.size() == 5 ? parse_real("--roi", parts[4]) : size / 2;
  if (roi.radius <= 0 || roi.size <= 0)
    throw InputError("mesh: --roi: radius and size must be positive, got '" + text + "'");
  return roi;
}

MeshOptions parse_options(const Arguments& args) {
  MeshOptions options;
  std::vector<std::string> rois;
  for (std::size_t a = 0; a < args.size(); ++a) {
    std::string name = args[a];
    if (name.empty() || name[0] != '-') {
      if (!options.surface.empty())
        throw InputError("mesh: more than one SURFACE ('" + options.surface + "', '" + name + "')");
      options.surface = name;
      continue;
    }
    std::string value;
    const std::size_t equals = name.find('=');
    if (name.starts_with("--") && equals != std::string::npos) {
      value = name.substr(equals + 1);
      name.resize(equals);
    } else if (a + 1 < args.size()) {
      value = args[++a];
    }
    if (value.empty()) throw InputError("mesh: option '" + name + "' needs a value (see tensormass mesh --help)");
    if (name == "--size") {
      options.octree.size = parse_real(name, value);
      options.size_given = true;
    } else if (name == "--levels") {
      const double levels = parse_real(name, value);
      if (levels != std::floor(levels) || levels < 0 || levels > 8)
        throw InputError("mesh: --levels: expected an integer in 0..8, got '" + value + "'");
      options.octree.surface_levels = static_cast<int>(levels);
    } else if (name == "--roi") {
      rois.push_back(value);
    } else if (name == "--region") {
      const std::size_t split = value.find('=');
      if (split == std::string::npos || split == 0 || split + 1 == value.size())
        throw InputError("mesh: --region: expected NAME=FILE, got '" + value + "'");
      options.regions.emplace_back(value.substr(0, split), value.substr(split + 1));
    } else if (name == "--layer") {
      options.octree.boundary_layer = parse_real(name, value);
    } else if (name == "--margin") {
      options.octree.margin = parse_real(name, value);
    } else if (name == "--format") {
      options.format = io::parse_msh_format(value);
    } else if (name == "-o" || name == "--output") {
      options.output = value;
    } else {
      throw InputError("mesh: unknown option '" + name + "' (see tensormass mesh --help)");
    }
  }
  if (options.surface.empty()) throw InputError("mesh: missing SURFACE (see tensormass mesh --help)");
  if (!options.size_given) throw InputError("mesh: missing --size H");
  if (options.output.empty()) throw InputError("mesh: missing -o OUT.msh");
  if (!(options.octree.size > 0)) throw InputError("mesh: --size must be positive");
  for (const std::string& roi : rois) options.octree.regions_of_interest.push_back(parse_roi(roi, options.octree.size));
  return options;
}

TriangleSurface read_checked(const std::string& path) {
  TriangleSurface surface = read_surface(path);
  for (const std::string& warning : check_closed_surface(surface))
    std::fprintf(stderr, "tensormass mesh: warning: %s\n", warning.c_str());
  return surface;
}

void print_report(const MeshOptions& options, const Mesh& mesh, const OctreeMeshReport& report,
                  const ConformityReport& conformity) {
  const MeshQuality quality = mesh_quality(mesh);
  std::printf("mesh            %s\n", options.output.c_str());
  std::printf("nodes           %d\n", mesh.node_count());
  std::printf("cells           %d\n", mesh.cell_count());
  std::printf("  %-10s %8s %8s %10s %10s %9s\n", "type", "count", "volume", "min SJ", "max ratio", "inverted");
  for (const ElementTypeQuality& type : quality.types)
    std::printf("  %-10s %8d %7.1f%% %10.4f %10.2f %9d\n", type.element->name, type.count,
                100 * type.volume / quality.volume, type.min_scaled_jacobian, type.max_edge_ratio, type.inverted);
  std::printf(
      "octree          %d leaves, core %d cells (%d hexahedra, %d transitions, %d removed), %d caps, %d gap tets\n",
      report.leaves, report.core_cells, report.core_hexahedra, report.transition_cells, report.removed_for_conformity,
      report.caps, report.gap_tetrahedra);
  std::printf("boundary layer  %d prisms, %.4g thick\n", report.boundary_prisms, report.boundary_layer_thickness);
  const double error =
      report.surface_volume != 0 ? (report.mesh_volume - report.surface_volume) / report.surface_volume : 0;
  std::printf("volume          %.9g (surface %.9g, relative difference %.2e)\n", report.mesh_volume,
              report.surface_volume, error);
  std::printf("conformity      %d interior faces, %zu boundary faces, %d faces used more than twice\n",
              conformity.interior_faces, conformity.boundary_faces.size(), conformity.overused_faces);
  std::printf("groups          ");
  for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
    const Group& group = mesh.groups[g];
    std::printf("%s%s (%zu %s)", g ? ", " : "", group.name.c_str(),
                group.dim == 3 ? group.cells.size() : static_cast<std::size_t>(group.facets.count()),
                group.dim == 3 ? "cells" : "facets");
  }
  std::printf("\ntimes (s)       ");
  double total = 0;
  for (const auto& [stage, seconds] : report.stage_seconds) {
    std::printf("%s %.2f  ", stage.c_str(), seconds);
    total += seconds;
  }
  std::printf("total %.2f\n", total);
  for (const std::string& warning : report.warnings)
    std::fprintf(stderr, "tensormass mesh: warning: %s\n", warning.c_str());
}

}  // namespace

int mesh_command(const Arguments& args) {
  for (const std::string& arg : args)
    if (arg == "-h" || arg == "--help") {
      std::fputs(kMeshUsage, stdout);
      return 0;
    }
  MeshOptions options = parse_options(args);
  const TriangleSurface surface = read_checked(options.surface);
  for (const auto& [name, file] : options.regions) options.octree.regions.push_back({name, read_checked(file)});
  const auto start = std::chrono::steady_clock::now();
  options.octree.on_stage = [&](const std::string& stage) {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "[%6.2f s] %s\n", t, stage.c_str());
  };
  OctreeMeshReport report;
  const Mesh mesh = mesh_surface_volume(surface, options.octree, &report);
  const MeshQuality quality = mesh_quality(mesh);
  if (!quality.inverted_cells.empty())
    throw NumericalError("the mesh has " + std::to_string(quality.inverted_cells.size()) + " inverted cells, first " +
                         mesh.describe_cell(quality.inverted_cells.front()) + "; nothing written");
  const ConformityReport conformity = check_conformity(mesh);
  if (conformity.overused_faces > 0 ||
      conformity.boundary_faces.size() != static_cast<std::size_t>(surface.triangle_count()))
    throw NumericalError("the mesh is not conforming (" + std::to_string(conformity.boundary_faces.size()) +
                         " boundary faces for " + std::to_string(surface.triangle_count()) + " surface triangles, " +
                         std::to_string(conformity.overused_faces) + " faces used more than twice); nothing written");
  io::write_msh(options.output, mesh, options.format);
  print_report(options, mesh, report, conformity);
  return 0;
}

}  // namespace tensormass::cli
