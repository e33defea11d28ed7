#include "allocation_counter.hpp"

#include <cstdlib>
#include <new>

std::atomic<long> test_support::allocation_count{0};

// Not inlined: GCC would otherwise pair malloc/free across the inlined
// operators and warn (-Wmismatched-new-delete).
[[gnu::noinline]] void* operator new(std::size_t size) {
  ++test_support::allocation_count;
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  throw std::bad_alloc();
}
[[gnu::noinline]] void operator delete(void* memory) noexcept { std::free(memory); }
[[gnu::noinline]] void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }
// The nothrow pair too, so that every new these deletes may free comes from
// malloc: AddressSanitizer's own nothrow new, freed here, is an
// alloc-dealloc mismatch (libfreeimage, loaded by Gmsh, uses it).
[[gnu::noinline]] void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  ++test_support::allocation_count;
  return std::malloc(size == 0 ? 1 : size);
}
[[gnu::noinline]] void operator delete(void* memory, const std::nothrow_t&) noexcept { std::free(memory); }
