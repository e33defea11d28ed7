// The mesh read on rank 0 and sent to the other ranks as bytes: dimension,
// nodes, blocks (element type by name), groups; each array as its length
// then its values.
#include "tensormass/parallel/mesh_broadcast.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>

#include "tensormass/common/errors.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/parallel/mpi_world.hpp"

namespace tensormass::parallel {

namespace {

class Packer {
 public:
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const char* p = reinterpret_cast<const char*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof v);
  }
  template <class T>
  void array(const std::vector<T>& values) {
    value(static_cast<std::uint64_t>(values.size()));
    const char* p = reinterpret_cast<const char*>(values.data());
    bytes.insert(bytes.end(), p, p + values.size() * sizeof(T));
  }
  void text(const std::string& s) { array(std::vector<char>(s.begin(), s.end())); }
  std::vector<char> bytes;
};

class Unpacker {
 public:
  explicit Unpacker(std::span<const char> bytes) : bytes_(bytes) {}
  template <class T>
  T value() {
    T v;
    take(&v, sizeof v);
    return v;
  }
  template <class T>
  std::vector<T> array() {
    const auto count = value<std::uint64_t>();
    if (count > (bytes_.size() - at_) / sizeof(T)) fail();
    std::vector<T> values(count);
    take(values.data(), count * sizeof(T));
    return values;
  }
  std::string text() {
    const std::vector<char> chars = array<char>();
    return {chars.begin(), chars.end()};
  }
  bool done() const { return at_ == bytes_.size(); }

 private:
  [[noreturn]] static void fail() { throw std::invalid_argument("unpack_mesh: bytes that pack_mesh did not make"); }
  void take(void* out, std::size_t size) {
    if (size > bytes_.size() - at_) fail();
    if (size > 0) std::memcpy(out, bytes_.data() + at_, size);
    at_ += size;
  }
  std::span<const char> bytes_;
  std::size_t at_ = 0;
};

constexpr std::uint32_t kMagic = 0x544d4d31;  // "TMM1"

}  // namespace

std::vector<char> pack_mesh(const Mesh& mesh) {
  Packer out;
  out.value(kMagic);
  out.value(mesh.dim);
  out.text(mesh.source);
  out.array(mesh.rest_positions);
  out.array(mesh.node_source_ids);
  out.value(static_cast<std::uint64_t>(mesh.blocks.size()));
  for (const ElementBlock& block : mesh.blocks) {
    out.text(block.element->name);
    out.array(block.connectivity);
    out.array(block.source_ids);
    out.value(block.first_cell);
  }
  out.value(static_cast<std::uint64_t>(mesh.groups.size()));
  for (const Group& group : mesh.groups) {
    out.text(group.name);
    out.value(group.dim);
    out.array(group.nodes);
    out.array(group.cells);
    out.array(group.facets.offsets);
    out.array(group.facets.nodes);
    out.array(group.facets.orders);
  }
  return std::move(out.bytes);
}

Mesh unpack_mesh(std::span<const char> bytes) {
  Unpacker in(bytes);
  if (bytes.size() < sizeof kMagic || in.value<std::uint32_t>() != kMagic)
    throw std::invalid_argument("unpack_mesh: bytes that pack_mesh did not make");
  Mesh mesh;
  mesh.dim = in.value<int>();
  mesh.source = in.text();
  mesh.rest_positions = in.array<double>();
  mesh.node_source_ids = in.array<long>();
  mesh.blocks.resize(in.value<std::uint64_t>());
  for (ElementBlock& block : mesh.blocks) {
    const std::string name = in.text();
    block.element = Registry::instance().element(name);
    if (!block.element) throw std::invalid_argument("unpack_mesh: no element type '" + name + "' in the registry");
    block.connectivity = in.array<int>();
    block.source_ids = in.array<long>();
    block.first_cell = in.value<int>();
  }
  mesh.groups.resize(in.value<std::uint64_t>());
  for (Group& group : mesh.groups) {
    group.name = in.text();
    group.dim = in.value<int>();
    group.nodes = in.array<int>();
    group.cells = in.array<int>();
    group.facets.offsets = in.array<int>();
    group.facets.nodes = in.array<int>();
    group.facets.orders = in.array<int>();
  }
  if (!in.done()) throw std::invalid_argument("unpack_mesh: bytes left after the mesh");
  return mesh;
}

Mesh read_mesh_on_root(const std::string& path) {
  if (world_size() == 1) return read_mesh(path);
  // Rank 0 sends what it met, then the mesh's bytes or the error's message.
  enum Status : int { kMesh, kInputError, kOtherError };
  int status = kMesh;
  std::vector<char> bytes;
  Mesh mesh;
  if (world_rank() == 0) {
    try {
      mesh = read_mesh(path);
      bytes = pack_mesh(mesh);
    } catch (const InputError& e) {
      status = kInputError, bytes.assign(e.what(), e.what() + std::strlen(e.what()));
    } catch (const std::exception& e) {
      status = kOtherError, bytes.assign(e.what(), e.what() + std::strlen(e.what()));
    }
  }
  broadcast_from_root(std::span<int>(&status, 1));
  broadcast_bytes_from_root(bytes);
  if (status == kMesh) return world_rank() == 0 ? std::move(mesh) : unpack_mesh(bytes);
  const std::string message(bytes.begin(), bytes.end());
  if (status == kInputError) throw InputError(message);
  throw std::runtime_error(message);
}

}  // namespace tensormass::parallel
