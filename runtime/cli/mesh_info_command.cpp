// Placeholder until the command lands.
#include <cstdio>

#include "commands.hpp"

namespace tensormass::cli {

int mesh_info_command(const Arguments&) {
  std::fputs("tensormass: mesh-info is not built yet\n", stderr);
  return 2;
}

}  // namespace tensormass::cli
