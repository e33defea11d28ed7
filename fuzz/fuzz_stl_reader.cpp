// Fuzz target: the STL surface reader (ASCII and binary) and the surface check.
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return tensormass::fuzz::read_surface("fuzz.stl", data, size);
}
