// Fuzz target: the Gmsh .msh reader (2.2 and 4.1, ASCII and binary).
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return tensormass::fuzz::read_mesh("fuzz.msh", data, size);
}
