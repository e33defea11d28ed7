// Placeholder until the command lands.
#include <cstdio>

#include "commands.hpp"

namespace tensormass::cli {

int render_command(const Arguments&) {
  std::fputs("tensormass: render is not built yet\n", stderr);
  return 2;
}

}  // namespace tensormass::cli
