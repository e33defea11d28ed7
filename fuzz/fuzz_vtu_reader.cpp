// Fuzz target: the VTK XML unstructured grid reader (.vtu: ASCII, base64, appended raw or base64).
#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return tensormass::fuzz::read_mesh("fuzz.vtu", data, size);
}
