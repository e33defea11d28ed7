// Placeholder until the command lands.
#include <cstdio>

#include "commands.hpp"

namespace tensormass::cli {

int beam_command(const Arguments&) {
  std::fputs("tensormass: beam is not built yet\n", stderr);
  return 2;
}

}  // namespace tensormass::cli
