/// \file fuzz_support.hpp
/// What the fuzz targets share (docs/sanitizers-and-fuzzing.md). A reader
/// given bad bytes must throw InputError whose message names the file; any
/// other exception escapes the target and aborts, and a message without the
/// file name aborts too: libFuzzer keeps both as findings, like crashes,
/// sanitizer reports and hangs.
#ifndef TENSORMASS_FUZZ_SUPPORT_HPP
#define TENSORMASS_FUZZ_SUPPORT_HPP

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "io/mesh_readers.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/surface/surface.hpp"

namespace tensormass::fuzz {

/// The fuzzer's bytes as a string.
inline std::string bytes(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// Runs `read`, accepting only an InputError that names `file`.
template <class Read>
int expect_input_errors_only(const std::string& file, Read&& read) {
  try {
    read();
  } catch (const InputError& error) {
    const std::string message = error.what();
    if (message.find(file) == std::string::npos) {
      std::fprintf(stderr, "InputError without the file name '%s': %s\n", file.c_str(), message.c_str());
      std::abort();
    }
  }
  return 0;
}

/// One input read as the mesh format `file`'s extension names.
inline int read_mesh(const std::string& file, const std::uint8_t* data, std::size_t size) {
  return expect_input_errors_only(file, [&] { detail::read_mesh_data(file, bytes(data, size)); });
}

/// One input read as the surface format `file`'s extension names, then the
/// closed-surface check that `tensormass mesh` runs on what it read.
inline int read_surface(const std::string& file, const std::uint8_t* data, std::size_t size) {
  return expect_input_errors_only(file, [&] {
    TriangleSurface surface = detail::read_surface_data(file, bytes(data, size));
    check_closed_surface(surface);
  });
}

}  // namespace tensormass::fuzz

#endif
