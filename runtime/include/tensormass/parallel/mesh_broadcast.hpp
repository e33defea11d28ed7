/// \file mesh_broadcast.hpp
/// The mesh read once for all MPI ranks: rank 0 reads the file and sends
/// the mesh to the others, which never open it (nor hold the reader's
/// working memory, several times the mesh's own at a million cells).
#ifndef TENSORMASS_PARALLEL_MESH_BROADCAST_HPP
#define TENSORMASS_PARALLEL_MESH_BROADCAST_HPP

#include <span>
#include <string>
#include <vector>

#include "tensormass/mesh/mesh.hpp"
#include "tensormass/parallel/mesh_cut.hpp"

namespace tensormass::parallel {

/// read_mesh(path) on rank 0, its mesh sent to every other rank; on one
/// rank, read_mesh(path). An error reading it on rank 0 is thrown on every
/// rank with the same message (an InputError as an InputError), so no rank
/// waits for a mesh that does not come.
Mesh read_mesh_on_root(const std::string& path);

/// `mesh` as bytes, and back: the same mesh, exactly (element types go by
/// name and come back from the kernel registry).
std::vector<char> pack_mesh(const Mesh& mesh);
/// Throws std::invalid_argument on bytes that pack_mesh did not make.
Mesh unpack_mesh(std::span<const char> bytes);
/// A mesh part as bytes, and back (unpack_mesh_part throws as unpack_mesh).
std::vector<char> pack_mesh_part(const MeshPart& part);
MeshPart unpack_mesh_part(std::span<const char> bytes);

/// On rank 0 of several: cuts `whole` (cell_owner: per cell, its rank),
/// sends every other rank its part (cut_mesh) and returns rank 0's. Every
/// other rank calls receive_mesh_part() at the same time.
MeshPart send_mesh_parts(const Mesh& whole, std::span<const int> cell_owner);
MeshPart receive_mesh_part();

}  // namespace tensormass::parallel

#endif
