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
#include "tensormass/parallel/rank_errors.hpp"

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

constexpr std::uint32_t kPartMagic = 0x544d5031;  // "TMP1"

void pack_into(Packer& out, const Mesh& mesh) {
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
  out.array(mesh.cell_numbers);
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
}

Mesh unpack_from(Unpacker& in) {
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
  mesh.cell_numbers = in.array<int>();
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
  return mesh;
}

/// Checks the magic number that starts `bytes`.
void expect_magic(Unpacker& in, std::span<const char> bytes, std::uint32_t magic) {
  if (bytes.size() < sizeof magic || in.value<std::uint32_t>() != magic)
    throw std::invalid_argument("unpack_mesh: bytes that pack_mesh did not make");
}

}  // namespace

std::vector<char> pack_mesh(const Mesh& mesh) {
  Packer out;
  out.value(kMagic);
  pack_into(out, mesh);
  return std::move(out.bytes);
}

Mesh unpack_mesh(std::span<const char> bytes) {
  Unpacker in(bytes);
  expect_magic(in, bytes, kMagic);
  Mesh mesh = unpack_from(in);
  if (!in.done()) throw std::invalid_argument("unpack_mesh: bytes left after the mesh");
  return mesh;
}

std::vector<char> pack_mesh_part(const MeshPart& part) {
  Packer out;
  out.value(kPartMagic);
  pack_into(out, part.mesh);
  out.array(part.cut.global_cell);
  out.array(part.cut.cell_owner);
  out.array(part.cut.global_node);
  out.array(part.cut.node_owner);
  out.value(part.cut.whole_cell_count);
  out.value(part.cut.whole_node_count);
  return std::move(out.bytes);
}

MeshPart unpack_mesh_part(std::span<const char> bytes) {
  Unpacker in(bytes);
  expect_magic(in, bytes, kPartMagic);
  MeshPart part{unpack_from(in), {}};
  part.cut.global_cell = in.array<int>();
  part.cut.cell_owner = in.array<int>();
  part.cut.global_node = in.array<int>();
  part.cut.node_owner = in.array<int>();
  part.cut.whole_cell_count = in.value<int>();
  part.cut.whole_node_count = in.value<int>();
  if (!in.done()) throw std::invalid_argument("unpack_mesh: bytes left after the mesh part");
  return part;
}

MeshPart send_mesh_parts(const Mesh& whole, std::span<const int> cell_owner) {
  const int ranks = world_size();
  const std::vector<int> node_owner = node_owners(whole, cell_owner, ranks);
  for (int rank = 1; rank < ranks; ++rank)  // one part packed at a time: rank 0 never holds them all
    send_bytes_from_root(rank, pack_mesh_part(cut_mesh(whole, cell_owner, node_owner, rank)));
  return cut_mesh(whole, cell_owner, node_owner, 0);
}

MeshPart receive_mesh_part() { return unpack_mesh_part(receive_bytes_from_root()); }

Mesh read_mesh_on_root(const std::string& path) {
  if (world_size() == 1) return read_mesh(path);
  Mesh mesh;
  std::vector<char> bytes;
  on_root([&] {
    mesh = read_mesh(path);
    bytes = pack_mesh(mesh);
  });
  broadcast_bytes_from_root(bytes);
  return world_rank() == 0 ? std::move(mesh) : unpack_mesh(bytes);
}

}  // namespace tensormass::parallel
