// Fuzz target: the legacy VTK unstructured grid reader (.vtk, ASCII and BINARY).
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return tensormass::fuzz::read_mesh("fuzz.vtk", data, size);
}
