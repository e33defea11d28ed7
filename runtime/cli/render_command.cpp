// `tensormass render FRAME.vtu -o IMAGE.png [...]`: draws a result with
// scripts/render.py (matplotlib, meshio) under the Debian interpreter. This
// side checks the command line, finds the script and writes the image
// atomically: the script renders to a temporary name in the output's
// directory, renamed onto the output only when it succeeded. Exit codes are
// the script's: 0 written, 2 bad input, 1 anything else.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "commands.hpp"
#include "tensormass/common/errors.hpp"

extern char** environ;

namespace tensormass::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kRenderUsage =
    "usage: tensormass render FRAME.vtu -o IMAGE.png [--field NAME] [--deformed | --rest]\n"
    "                         [--width PX] [--title TEXT]\n"
    "\n"
    "Draws a result of `tensormass run` to a PNG: a 2D mesh cell by cell, a 3D mesh by its\n"
    "boundary surface, at the deformed positions (rest + displacement) by default.\n"
    "\n"
    "options:\n"
    "  -o, --output FILE   the PNG to write (required; written only on success)\n"
    "  --field NAME        colour by this cell array (state, law_id, R_EL, ...) or point array\n"
    "                      (displacement: its magnitude). Default: state when present\n"
    "                      (criterion / threshold from green to red, switched elements in blue),\n"
    "                      else law_id (law names from the summary.json next to FRAME)\n"
    "  --deformed, --rest  draw at rest + displacement (default) or at the rest positions\n"
    "  --width PX          image width in pixels (default 1600)\n"
    "  --title TEXT        replaces the generated title (file, field, counts)\n"
    "  -h, --help          this text\n"
    "\n"
    "Needs python3 with matplotlib and meshio (/usr/bin/python3 when present). The script is\n"
    "$TENSORMASS_RENDER_SCRIPT if set, else scripts/render.py of the source tree, else the\n"
    "installed share/tensormass/render.py. Exit 0 written, 2 bad input, 1 other failure.\n";

struct Options {
  std::string frame;
  std::string output;
  std::vector<std::string> script_arguments;  ///< passed through, output excluded
  bool help = false;
};

Options parse_options(const Arguments& args) {
  Options options;
  const auto value = [&](std::size_t& i) -> const std::string& {
    if (i + 1 >= args.size()) throw InputError("render: " + args[i] + " needs a value (tensormass render --help)");
    return args[++i];
  };
  bool shape_given = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "-h" || arg == "--help") {
      options.help = true;
    } else if (arg == "-o" || arg == "--output") {
      options.output = value(i);
    } else if (arg == "--field" || arg == "--title") {
      options.script_arguments.insert(options.script_arguments.end(), {arg, value(i)});
    } else if (arg == "--width") {
      const std::string& width = value(i);
      char* end = nullptr;
      const long pixels = std::strtol(width.c_str(), &end, 10);
      if (width.empty() || *end != '\0' || pixels < 100 || pixels > 20000)
        throw InputError("render: --width '" + width + "': expected 100 to 20000 pixels");
      options.script_arguments.insert(options.script_arguments.end(), {arg, width});
    } else if (arg == "--deformed" || arg == "--rest") {
      if (shape_given) throw InputError("render: give one of --deformed and --rest");
      shape_given = true;
      options.script_arguments.push_back(arg);
    } else if (!arg.empty() && arg[0] == '-') {
      throw InputError("render: unknown option '" + arg + "' (tensormass render --help)");
    } else if (options.frame.empty()) {
      options.frame = arg;
    } else {
      throw InputError("render: more than one FRAME ('" + options.frame + "', '" + arg + "')");
    }
  }
  if (options.help) return options;
  if (options.frame.empty()) throw InputError("render: missing FRAME.vtu (tensormass render --help)");
  if (options.output.empty()) throw InputError("render: missing -o IMAGE.png (tensormass render --help)");
  std::error_code error;
  if (!fs::is_regular_file(options.frame, error)) throw InputError("render: " + options.frame + ": no such file");
  const fs::path directory = fs::absolute(options.output, error).parent_path();
  if (!fs::is_directory(directory, error))
    throw InputError("render: " + options.output + ": directory " + directory.string() + " does not exist");
  return options;
}

/// The script: $TENSORMASS_RENDER_SCRIPT, the source tree's, or the installed one; empty if none
/// (a message on stderr when the variable names no file).
std::string find_script() {
  std::error_code error;
  if (const char* path = std::getenv("TENSORMASS_RENDER_SCRIPT"); path && *path) {
    if (fs::is_regular_file(path, error)) return path;
    std::fprintf(stderr, "tensormass: render: TENSORMASS_RENDER_SCRIPT=%s: no such file\n", path);
    return {};
  }
  if (fs::is_regular_file(TENSORMASS_RENDER_SOURCE_SCRIPT, error)) return TENSORMASS_RENDER_SOURCE_SCRIPT;
  const fs::path binary = fs::read_symlink("/proc/self/exe", error);  // PREFIX/bin/tensormass
  if (!error) {
    const fs::path installed =
        binary.parent_path().parent_path() / TENSORMASS_INSTALL_DATADIR / "tensormass" / "render.py";
    if (fs::is_regular_file(installed, error)) return installed.string();
  }
  return {};
}

/// Runs `python script arguments...`, returns its exit code (1 when it could not run or died).
int run_python(const std::string& script, const std::vector<std::string>& arguments) {
  const std::string python = access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
  std::vector<std::string> words = {python, script};
  words.insert(words.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  pid_t child = 0;
  if (const int error = posix_spawnp(&child, python.c_str(), nullptr, nullptr, argv.data(), environ); error != 0) {
    std::fprintf(stderr, "tensormass: render: cannot run %s: %s\n", python.c_str(), std::strerror(error));
    return 1;
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) return 1;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  std::fprintf(stderr, "tensormass: render: %s stopped by signal %d\n", python.c_str(), WTERMSIG(status));
  return 1;
}

}  // namespace

int render_command(const Arguments& args) {
  Options options = parse_options(args);
  if (options.help) {
    std::fputs(kRenderUsage, stdout);
    return 0;
  }
  const std::string script = find_script();
  if (script.empty()) {
    if (!std::getenv("TENSORMASS_RENDER_SCRIPT"))
      std::fprintf(stderr,
                   "tensormass: render: render.py not found (neither %s nor the installed share/tensormass/render.py);"
                   " set TENSORMASS_RENDER_SCRIPT\n",
                   TENSORMASS_RENDER_SOURCE_SCRIPT);
    return 1;
  }
  const std::string temporary = options.output + ".tmp-" + std::to_string(getpid());
  std::vector<std::string> arguments = {options.frame, "-o", temporary};
  arguments.insert(arguments.end(), options.script_arguments.begin(), options.script_arguments.end());
  const int code = run_python(script, arguments);
  std::error_code error;
  if (code == 0) {
    fs::rename(temporary, options.output, error);
    if (!error) return 0;
    std::fprintf(stderr, "tensormass: render: cannot write %s: %s\n", options.output.c_str(), error.message().c_str());
  }
  fs::remove(temporary, error);
  return code == 0 ? 1 : code;
}

}  // namespace tensormass::cli
