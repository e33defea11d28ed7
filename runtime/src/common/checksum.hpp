// XXH3-64 checksums of bytes, at once or fed piece by piece (xxHash,
// header-only in checksum.cpp). Internal header.
#ifndef TENSORMASS_COMMON_CHECKSUM_HPP
#define TENSORMASS_COMMON_CHECKSUM_HPP

#include <cstddef>
#include <cstdint>
#include <memory>

namespace tensormass::detail {

/// XXH3-64 of `size` bytes at `data`.
std::uint64_t checksum(const void* data, std::size_t size);

/// XXH3-64 of everything given to update(), in order: equal to checksum()
/// of the concatenated bytes.
class Checksum {
 public:
  Checksum();
  ~Checksum();
  Checksum(const Checksum&) = delete;
  Checksum& operator=(const Checksum&) = delete;
  void update(const void* data, std::size_t size);
  std::uint64_t value() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace tensormass::detail

#endif
