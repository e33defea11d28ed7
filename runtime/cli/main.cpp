// tensormass: the command line. `tensormass help` lists the subcommands.
#include <cstdio>
#include <exception>
#include <string>

#include "commands.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/common/thread_defaults.hpp"
#include "tensormass/common/version.hpp"
#include "tensormass/parallel/mpi_world.hpp"

namespace {

constexpr const char* kUsage =
    "usage: tensormass COMMAND [ARGS]\n"
    "\n"
    "commands:\n"
    "  kernels [--json]                 list the kernel registry (one row per law/element/split)\n"
    "  demo [LAW [ELEMENT [SPLIT]]]     evaluate one element's energy, force and stiffness\n"
    "  bench kernels [--json FILE] [--quick]\n"
    "                                   time every kernel (median ns per element)\n"
    "  bench runtime [--quick] [--json FILE] [--only NAME]\n"
    "                                   whole-solver timings, against CalculiX (docs/results/runtime.md)\n"
    "  bench paper [--quick | --smoke] [--json FILE] [--out DIR]\n"
    "                                   the origin report's Table 1 and Figure 12 (docs/results/paper.md)\n"
    "                                   (bench runs the tensormass-bench program, built with\n"
    "                                   -DTENSORMASS_BUILD_BENCH=ON)\n"
    "  run SCENE.yaml [--set a.b=VALUE ...]\n"
    "                                   run a scene (exit 2: bad input, 3: numerical failure);\n"
    "                                   mpirun -n N tensormass run ... --set solver.backend=petsc\n"
    "                                   shares it among N MPI ranks\n"
    "  beam [OPTIONS] -o OUT.msh        write a test beam (tensormass beam --help)\n"
    "  mesh SURFACE --size H [OPTIONS] -o OUT.msh\n"
    "                                   hex-dominant volume mesh of a closed surface (tensormass mesh --help)\n"
    "  mesh-info FILE                   element counts per type, quality, inverted elements\n"
    "  raise-order IN.msh -o OUT.msh    the mesh at order 2, by Gmsh (tensormass raise-order --help)\n"
    "  render FRAME.vtu -o IMAGE.png    draw a result coloured by criterion state or law\n"
    "  version, --version               the version\n"
    "  help                             this text\n";

int usage_error(const std::string& message) {
  std::fprintf(stderr, "tensormass: %s\n\n%s", message.c_str(), kUsage);
  return 2;
}

/// The command's exit code; errors are thrown.
int run(const std::string& command, const tensormass::cli::Arguments& args) {
  if (command == "help" || command == "--help" || command == "-h") {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (command == "version" || command == "--version") {
    std::printf("tensormass %s\n", tensormass::kVersion);
    return 0;
  }
  if (command == "kernels") return tensormass::cli::kernels_command(args);
  if (command == "demo") return tensormass::cli::demo_command(args);
  if (command == "run") return tensormass::cli::run_command(args);
  if (command == "beam") return tensormass::cli::beam_command(args);
  if (command == "mesh") return tensormass::cli::mesh_command(args);
  if (command == "mesh-info") return tensormass::cli::mesh_info_command(args);
  if (command == "raise-order") return tensormass::cli::raise_order_command(args);
  if (command == "render") return tensormass::cli::render_command(args);
  if (command == "bench") return tensormass::cli::bench_command(args);
  return usage_error("unknown command '" + command + "'");
}

}  // namespace

int main(int argc, char** argv) {
  namespace parallel = tensormass::parallel;
  tensormass::apply_default_wait_policy(argv);
  if (argc < 2) return usage_error("missing command");
  const std::string command = argv[1];
  tensormass::cli::Arguments args(argv + 2, argv + argc);
  // Under mpirun every rank runs this program; errors end all ranks together.
  try {
    parallel::start_world();
    const int code = run(command, args);
    parallel::finish_world();
    return code;
  } catch (const tensormass::NumericalError& error) {
    return parallel::end_after_error(std::string("tensormass: numerical failure: ") + error.what(), 3);
  } catch (const tensormass::OutputError& error) {
    return parallel::end_after_error(std::string("tensormass: output failure: ") + error.what(), 4);
  } catch (const std::exception& error) {
    return parallel::end_after_error(std::string("tensormass: error: ") + error.what(), 2);
  }
}
