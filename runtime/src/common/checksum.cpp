#include "common/checksum.hpp"

// GCC 12 reports the deliberately undefined vectors of its AVX-512
// intrinsics, inlined into xxHash's accumulators, as uninitialised.
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#define XXH_INLINE_ALL
#include <xxhash.h>

namespace tensormass::detail {

struct Checksum::State {
  XXH3_state_t hash;
};

std::uint64_t checksum(const void* data, std::size_t size) { return XXH3_64bits(data, size); }

Checksum::Checksum() : state_(std::make_unique<State>()) { XXH3_64bits_reset(&state_->hash); }
Checksum::~Checksum() = default;

void Checksum::update(const void* data, std::size_t size) { XXH3_64bits_update(&state_->hash, data, size); }

std::uint64_t Checksum::value() const { return XXH3_64bits_digest(&state_->hash); }

}  // namespace tensormass::detail
