// `tensormass raise-order IN.msh -o OUT.msh [--complete] [--format 4.1|2.2]`:
// a first-order Gmsh mesh raised to order 2 by Gmsh (meshing/gmsh_order.hpp).
#include <cstdio>
#include <map>
#include <string>

#include "commands.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/meshing/gmsh_order.hpp"

namespace tensormass::cli {
namespace {

constexpr const char* kRaiseOrderUsage =
    "usage: tensormass raise-order IN.msh -o OUT.msh [--complete] [--format 4.1|2.2]\n"
    "\n"
    "Has Gmsh raise a first-order mesh to order 2 (its groups kept): tri6, quad8, tet10,\n"
    "hex20, prism15, pyramid13; with --complete Gmsh's complete elements (quad9, hex27;\n"
    "its 18-node prisms and 14-node pyramids have no element file and are refused).\n"
    "Nothing is written when the input is bad or Gmsh's result cannot be read.\n";

RaiseOrderSpec parse(const Arguments& args) {
  RaiseOrderSpec spec;
  for (std::size_t a = 0; a < args.size(); ++a) {
    const std::string& arg = args[a];
    const bool takes_value = arg == "-o" || arg == "--output" || arg == "--format";
    if (takes_value && a + 1 == args.size()) throw InputError("raise-order: " + arg + " needs a value");
    if (arg == "-o" || arg == "--output") spec.output = args[++a];
    else if (arg == "--format") spec.format = io::parse_msh_format(args[++a]);
    else if (arg == "--complete") spec.complete = true;
    else if (!arg.empty() && arg[0] == '-')
      throw InputError("raise-order: unknown option '" + arg + "' (see tensormass raise-order --help)");
    else if (spec.input.empty()) spec.input = arg;
    else throw InputError("raise-order: more than one input ('" + spec.input + "', '" + arg + "')");
  }
  if (spec.input.empty()) throw InputError("raise-order: missing IN.msh (see tensormass raise-order --help)");
  if (spec.output.empty()) throw InputError("raise-order: missing -o OUT.msh");
  return spec;
}

}  // namespace

int raise_order_command(const Arguments& args) {
  for (const std::string& arg : args)
    if (arg == "-h" || arg == "--help") {
      std::fputs(kRaiseOrderUsage, stdout);
      return 0;
    }
  const Mesh mesh = raise_order_with_gmsh(parse(args));
  std::map<std::string, int> cells;
  for (const ElementBlock& block : mesh.blocks) cells[block.element->name] += block.count();
  std::string types;
  for (const auto& [name, count] : cells) types += (types.empty() ? "" : ", ") + std::to_string(count) + " " + name;
  std::printf("%s: %dD, %d nodes, %d cells (%s), %zu groups\n", mesh.source.c_str(), mesh.dim, mesh.node_count(),
              mesh.cell_count(), types.c_str(), mesh.groups.size());
  return 0;
}

}  // namespace tensormass::cli
