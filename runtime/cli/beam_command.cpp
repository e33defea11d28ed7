// `tensormass beam`: writes a test beam mesh (.msh) with groups clamp, tip, body.
#include <array>
#include <cstdio>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "arguments.hpp"
#include "commands.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/gmsh_writer.hpp"
#include "tensormass/meshing/beam.hpp"

namespace tensormass::cli {
namespace {

constexpr const char* kBeamUsage =
    "usage: tensormass beam [OPTIONS] -o OUT.msh\n"
    "\n"
    "Writes a cantilever test beam: a box [0,L]x[0,H] (2D, z = 0) or [0,L]x[0,H]x[0,W]\n"
    "cut into NX by NY (by NZ) squares or cubes, each cut into cells of one type.\n"
    "\n"
    "options:\n"
    "  --dim 2|3                 dimension (default 2)\n"
    "  --cells NX,NY[,NZ]        squares/cubes per axis (default 60,10 in 2D, 60,10,10 in 3D)\n"
    "  --size L,H[,W]            box size in metres (default 6,1 in 2D, 6,1,1 in 3D)\n"
    "  --type TYPE               how each square/cube is cut (default quad4 in 2D, hex8 in 3D):\n"
    "                              2D: quad4 (1 quad), tri3 (2 triangles)\n"
    "                              3D: hex8 (1 hex), tet5 (5 tets), tet6 (6 tets, Kuhn),\n"
    "                                  prism6 (2 prisms along z), pyramid5 (6 pyramids, centre node)\n"
    "                            or a quadratic element with the corners of one of these\n"
    "                            (quad8, quad9, tri6, hex20, hex27, prism15, pyramid13, ...):\n"
    "                            that cut at order 2, making this element\n"
    "  --mix TYPE:F,TYPE:F,...   consecutive phases along x, F = share of the columns (sum 1),\n"
    "                            e.g. tri3:0.3,quad4:0.7; each phase is a group phase_TYPE\n"
    "  --order 1|2               2: each cell becomes the quadratic element with its corners\n"
    "                            with the fewest nodes (tri6, quad8, tet10, hex20, ...; default 1)\n"
    "  --format 4.1|2.2          Gmsh file format (default 4.1)\n"
    "  -o, --output FILE         the .msh file to write (required)\n"
    "  -h, --help                this text\n"
    "\n"
    "groups: clamp (x = 0: facets and nodes), tip (x = L), body (all cells),\n"
    "        phase_TYPE (the cells of each phase, with --mix of two types or more)\n"
    "meshes are conforming; between phases, cubes get pyramid/tet transitions where needed.\n";

struct BeamOptions {
  BeamSpec spec;
  std::string output;
  io::MshFormat format = io::MshFormat::v41;
  bool type_given = false;      ///< --type or --mix seen
  std::size_t cells_count = 0;  ///< values given to --cells (0: default)
  std::size_t size_count = 0;   ///< values given to --size (0: default)
};

template <class T>
T parse_number(const std::string& option, const std::string& text) {
  std::size_t used = 0;
  T value{};
  try {
    if constexpr (std::is_same_v<T, int>) value = std::stoi(text, &used);
    else value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) throw InputError(option + ": '" + text + "' is not a number");
  return value;
}

/// "a,b[,c]" into the first 2 or 3 entries of `out`; returns how many were given.
template <class T>
std::size_t parse_list(const std::string& option, const std::string& text, std::array<T, 3>& out) {
  const std::vector<std::string> parts = split_commas(text);
  if (parts.size() < 2 || parts.size() > 3)
    throw InputError(option + ": expected 2 or 3 comma-separated values, got '" + text + "'");
  for (std::size_t a = 0; a < parts.size(); ++a) out[a] = parse_number<T>(option, parts[a]);
  return parts.size();
}

/// Applies one option; `value` is its argument.
void apply_option(BeamOptions& options, const std::string& name, const std::string& value) {
  if (name == "--dim") options.spec.dim = parse_number<int>(name, value);
  else if (name == "--cells") options.cells_count = parse_list(name, value, options.spec.cells);
  else if (name == "--size") options.size_count = parse_list(name, value, options.spec.size);
  else if (name == "--type" || name == "--mix") {
    if (options.type_given) throw InputError("beam: give one of --type or --mix, once");
    options.type_given = true;
    options.spec.phases = name == "--type" ? std::vector<BeamPhase>{{value, 1.0}} : parse_beam_mix(value);
  } else if (name == "--order") options.spec.order = parse_number<int>(name, value);
  else if (name == "--format") options.format = io::parse_msh_format(value);
  else options.output = value;  // -o, --output
}

bool known_option(const std::string& name) {
  for (const char* known : {"--dim", "--cells", "--size", "--type", "--mix", "--order", "--format", "-o", "--output"})
    if (name == known) return true;
  return false;
}

/// Splits "--name=value" in place, or takes the value from the next argument.
std::string option_value(const Arguments& args, std::size_t& a, std::string& name) {
  const std::size_t equals = name.find('=');
  std::string value;
  if (name.starts_with("--") && equals != std::string::npos) {
    value = name.substr(equals + 1);
    name.resize(equals);
  } else if (a + 1 < args.size()) {
    value = args[++a];
  }
  if (!name.starts_with("-")) throw InputError("beam: unexpected argument '" + name + "' (the output is -o FILE)");
  if (!known_option(name)) throw InputError("beam: unknown option '" + name + "' (see tensormass beam --help)");
  if (value.empty()) throw InputError("beam: option '" + name + "' needs a value");
  return value;
}

/// Fills defaults that depend on the dimension and checks list lengths.
void finish_options(BeamOptions& options) {
  BeamSpec& spec = options.spec;
  if (spec.dim != 2 && spec.dim != 3) throw InputError("--dim: expected 2 or 3, got " + std::to_string(spec.dim));
  const std::size_t dim = static_cast<std::size_t>(spec.dim);
  if (options.cells_count && options.cells_count != dim)
    throw InputError("--cells: a " + std::to_string(dim) + "D beam needs " + std::to_string(dim) + " counts");
  if (options.size_count && options.size_count != dim)
    throw InputError("--size: a " + std::to_string(dim) + "D beam needs " + std::to_string(dim) + " lengths");
  if (!options.type_given && spec.dim == 3) spec.phases = {{"hex8", 1.0}};
  if (options.output.empty()) throw InputError("beam: missing -o OUT.msh");
}

std::string summary(const std::string& path, const Mesh& mesh) {
  std::string text = path + ": " + std::to_string(mesh.dim) + "D, " + std::to_string(mesh.node_count()) + " nodes, " +
                     std::to_string(mesh.cell_count()) + " cells (";
  for (std::size_t b = 0; b < mesh.blocks.size(); ++b)
    text += (b ? ", " : "") + std::to_string(mesh.blocks[b].count()) + " " + mesh.blocks[b].element->name;
  text += "), groups ";
  for (std::size_t g = 0; g < mesh.groups.size(); ++g) {
    const Group& group = mesh.groups[g];
    text += (g ? ", " : "") + group.name + " (";
    text += group.dim == mesh.dim
                ? std::to_string(group.cells.size()) + " cells"
                : std::to_string(group.facets.count()) + " facets, " + std::to_string(group.nodes.size()) + " nodes";
    text += ")";
  }
  return text;
}

}  // namespace

int beam_command(const Arguments& args) {
  BeamOptions options;
  for (std::size_t a = 0; a < args.size(); ++a) {
    std::string name = args[a];
    if (name == "-h" || name == "--help") {
      std::fputs(kBeamUsage, stdout);
      return 0;
    }
    const std::string value = option_value(args, a, name);
    apply_option(options, name, value);
  }
  finish_options(options);
  const Mesh mesh = make_beam(options.spec);
  io::write_msh(options.output, mesh, options.format);
  std::printf("%s\n", summary(options.output, mesh).c_str());
  return 0;
}

}  // namespace tensormass::cli
