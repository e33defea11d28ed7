// tensormass run SCENE.yaml [--set a.b=value ...] [--resume] [--quiet]
#include <cstdio>
#include <string>

#include "commands.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/parallel/mpi_world.hpp"
#include "tensormass/scene/scene.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace tensormass::cli {

namespace {

constexpr const char* kRunUsage =
    "usage: tensormass run SCENE.yaml [--set KEY=VALUE ...] [--resume] [--quiet]\n"
    "  --set KEY=VALUE  override a scene key (YAML value), e.g. --set solver.steps=10\n"
    "                   or --set materials.0.young=2e6\n"
    "  --resume         continue from the output directory's checkpoint.bin (written every\n"
    "                   output.checkpoint_every steps), or start afresh when there is none\n"
    "  --quiet          no progress and no summary (errors still go to stderr)\n";

}  // namespace

int run_command(const Arguments& args) {
  std::string scene_path;
  std::vector<std::string> overrides;
  bool quiet = false, resume = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--help" || arg == "-h") {
      std::fputs(kRunUsage, stdout);
      return 0;
    } else if (arg == "--set") {
      if (i + 1 >= args.size()) throw InputError("run: --set needs KEY=VALUE");
      overrides.push_back(args[++i]);
    } else if (arg.rfind("--set=", 0) == 0) {
      overrides.push_back(arg.substr(6));
    } else if (arg == "--resume") {
      resume = true;
    } else if (arg == "--quiet" || arg == "-q") {
      quiet = true;
    } else if (!arg.empty() && arg[0] == '-') {
      throw InputError("run: unknown option '" + arg + "'\n" + kRunUsage);
    } else if (scene_path.empty()) {
      scene_path = arg;
    } else {
      throw InputError("run: more than one scene given ('" + scene_path + "', '" + arg + "')");
    }
  }
  if (scene_path.empty()) throw InputError(std::string("run: missing SCENE.yaml\n") + kRunUsage);
  const Scene scene = load_scene(scene_path, overrides);
  RunOptions options;
  options.progress = !quiet;
  options.resume = resume;
  const RunReport report = run_scene(scene, options);
  if (!quiet && parallel::world_rank() == 0) std::fputs(format_report(scene, report).c_str(), stdout);
  return 0;
}

}  // namespace tensormass::cli
