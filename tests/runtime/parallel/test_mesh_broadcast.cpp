// The mesh sent from rank 0 to the others (mesh_broadcast.cpp): packed and
// unpacked, a mixed mesh read from a file, with its groups' nodes, cells
// and facets, comes back identical; bytes that are not a packed mesh are
// refused; on one rank read_mesh_on_root is read_mesh, errors included.
// (Several ranks: ctest parallel.mpirun runs every scene through it.)
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "support/test_meshes.hpp"
#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/read_mesh.hpp"
#include "tensormass/parallel/mesh_broadcast.hpp"

namespace tensormass::parallel {
namespace {

TEST(MeshBroadcast, PackedMeshesComeBackIdentical) {
  for (const char* name : {"hybrid_o1.msh41b.msh", "box_tet_o2.msh22.msh"}) {
    SCOPED_TRACE(name);
    const Mesh mesh = read_mesh(meshtest::data_dir() + name);
    ASSERT_FALSE(mesh.groups.empty());
    const std::vector<char> bytes = pack_mesh(mesh);
    const Mesh back = unpack_mesh(bytes);
    meshtest::expect_identical(mesh, back, true);
    EXPECT_EQ(back.source, mesh.source);
    EXPECT_NO_THROW(back.validate());
    EXPECT_EQ(pack_mesh(back), bytes);
  }
}

TEST(MeshBroadcast, RefusesBytesItDidNotPack) {
  const Mesh mesh = read_mesh(meshtest::data_dir() + "hybrid_o1.msh41b.msh");
  std::vector<char> bytes = pack_mesh(mesh);
  EXPECT_THROW(unpack_mesh(std::vector<char>(bytes.begin(), bytes.end() - 1)), std::invalid_argument);
  std::vector<char> longer = bytes;
  longer.push_back(0);
  EXPECT_THROW(unpack_mesh(longer), std::invalid_argument);
  bytes[0] ^= 1;
  EXPECT_THROW(unpack_mesh(bytes), std::invalid_argument);
  EXPECT_THROW(unpack_mesh(std::vector<char>{}), std::invalid_argument);
}

TEST(MeshBroadcast, OnOneRankReadsTheFileItself) {
  const std::string path = meshtest::data_dir() + "box_tet_o1.msh41.msh";
  meshtest::expect_identical(read_mesh_on_root(path), read_mesh(path), true);
  EXPECT_THROW(read_mesh_on_root(meshtest::data_dir() + "no_such_mesh.msh"), InputError);
}

}  // namespace
}  // namespace tensormass::parallel
