/// \file commands.hpp
/// The subcommands of the `tensormass` command line. Each takes the
/// arguments after its name and returns the process exit code
/// (0 success, 2 bad input, 3 numerical failure).
#ifndef TENSORMASS_CLI_COMMANDS_HPP
#define TENSORMASS_CLI_COMMANDS_HPP

#include <string>
#include <vector>

namespace tensormass::cli {

using Arguments = std::vector<std::string>;

int kernels_command(const Arguments& args);
int demo_command(const Arguments& args);
int run_command(const Arguments& args);
int beam_command(const Arguments& args);
int mesh_info_command(const Arguments& args);
int render_command(const Arguments& args);
int mesh_command(const Arguments& args);
int raise_order_command(const Arguments& args);
/// Runs tensormass-bench (beside this binary, else in the install bindir)
/// with `args` in place of this process: returns only when it cannot (exit
/// 2, with a message).
int bench_command(const Arguments& args);

}  // namespace tensormass::cli

#endif
