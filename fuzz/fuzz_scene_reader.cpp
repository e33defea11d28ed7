// Fuzz target: the YAML scene reader (load_scene: keys, types, ranges and
// names, without the mesh). load_scene reads a path, so each input is
// written to a file of this process's own temporary directory first.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "fuzz_support.hpp"
#include "tensormass/scene/scene.hpp"

namespace {

/// A directory of this process (in /dev/shm when there is one, so that the
/// per-input write stays in memory), removed when the fuzzer exits.
class ScratchDirectory {
 public:
  ScratchDirectory() {
    namespace fs = std::filesystem;
    const fs::path base = fs::is_directory("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
    path_ = base / ("tensormass-fuzz-scene-" + std::to_string(getpid()));
    fs::create_directories(path_);
  }
  ~ScratchDirectory() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const ScratchDirectory scratch;
  const std::string file = scratch.file("scene.yaml");
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return tensormass::fuzz::expect_input_errors_only(file, [&] { tensormass::load_scene(file); });
}
