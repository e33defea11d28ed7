// Tetrahedra between the octree core and the input surface, by Gmsh.
#include "meshing/gap_mesher.hpp"

#include <algorithm>
#include <exception>
#include <string>
#include <unordered_map>

#include "io/gmsh_session.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::detail {
namespace {

/// Compact Gmsh node tags (1..M) for the nodes of the surfaces: Gmsh may
/// renumber sparse tags when it meshes.
struct SurfaceNodes {
  std::unordered_map<int, std::size_t> tag_of_node;
  std::vector<int> node_of_tag{-1};  ///< index 0 unused
  std::size_t tag(int node) {
    const auto [where, inserted] = tag_of_node.emplace(node, node_of_tag.size());
    if (inserted) node_of_tag.push_back(node);
    return where->second;
  }
};

/// Adds a discrete surface holding `triangles`; returns its tag.
int add_discrete_surface(int tag, const std::vector<double>& positions,
                         const std::vector<std::array<int, 3>>& triangles, SurfaceNodes& nodes) {
  std::vector<std::size_t> node_tags, unique;
  std::vector<double> coordinates;
  for (const auto& t : triangles)
    for (int node : t) {
      const std::size_t before = nodes.node_of_tag.size();
      node_tags.push_back(nodes.tag(node));
      if (nodes.node_of_tag.size() != before) {
        unique.push_back(node_tags.back());
        for (int a = 0; a < 3; ++a) coordinates.push_back(positions[3 * static_cast<std::size_t>(node) + a]);
      }
    }
  gmsh::model::addDiscreteEntity(2, tag);
  gmsh::model::mesh::addNodes(2, tag, unique, coordinates);
  gmsh::model::mesh::addElementsByType(tag, 2, {}, node_tags);
  return tag;
}

/// Throws unless the surfaces still hold exactly the nodes given, where given.
void check_surfaces_kept(const std::vector<double>& positions, const SurfaceNodes& nodes, int surfaces) {
  for (int surface = 1; surface <= surfaces; ++surface) {
    std::vector<std::size_t> tags;
    std::vector<double> coordinates, parametric;
    gmsh::model::mesh::getNodes(tags, coordinates, parametric, 2, surface, true, false);
    for (std::size_t n = 0; n < tags.size(); ++n) {
      const bool known = tags[n] >= 1 && tags[n] < nodes.node_of_tag.size();
      const std::size_t node = known ? static_cast<std::size_t>(nodes.node_of_tag[tags[n]]) : 0;
      if (!known || coordinates[3 * n] != positions[3 * node] || coordinates[3 * n + 1] != positions[3 * node + 1] ||
          coordinates[3 * n + 2] != positions[3 * node + 2])
        throw NumericalError("Gmsh changed a boundary surface (node " + std::to_string(tags[n]) +
                             "): the gap's triangulations were not kept");
    }
  }
}

}  // namespace

GapMesh fill_gap(const std::vector<double>& positions, const std::vector<std::array<int, 3>>& outer,
                 const std::vector<std::array<int, 3>>& inner, int threads) {
  const std::size_t known = positions.size() / 3;
  GapMesh gap;
  try {
    GmshSession session;
    gmsh::option::setNumber("General.Verbosity", 1);
    gmsh::option::setNumber("General.NumThreads", threads);
    gmsh::option::setNumber("Mesh.Algorithm3D", 1);  // Delaunay
    gmsh::option::setNumber("Mesh.Optimize", 1);
    gmsh::model::add("gap");
    SurfaceNodes surface_nodes;
    std::vector<int> loops{
        gmsh::model::geo::addSurfaceLoop({add_discrete_surface(1, positions, outer, surface_nodes)})};
    if (!inner.empty())
      loops.push_back(gmsh::model::geo::addSurfaceLoop({add_discrete_surface(2, positions, inner, surface_nodes)}));
    const std::size_t surface_tags = surface_nodes.node_of_tag.size() - 1;
    const int volume = gmsh::model::geo::addVolume(loops);
    gmsh::model::geo::synchronize();
    gmsh::model::mesh::generate(3);

    check_surfaces_kept(positions, surface_nodes, inner.empty() ? 1 : 2);
    std::vector<std::size_t> new_tags;
    std::vector<double> coordinates, parametric;
    gmsh::model::mesh::getNodes(new_tags, coordinates, parametric, 3, volume, false, false);
    std::unordered_map<std::size_t, int> new_index;
    for (std::size_t n = 0; n < new_tags.size(); ++n) {
      new_index[new_tags[n]] = static_cast<int>(known + n);
      gap.new_positions.insert(gap.new_positions.end(), coordinates.begin() + 3 * n, coordinates.begin() + 3 * n + 3);
    }
    std::vector<std::size_t> element_tags, element_nodes;
    gmsh::model::mesh::getElementsByType(4, element_tags, element_nodes, volume);
    for (std::size_t e = 0; 4 * e < element_nodes.size(); ++e) {
      std::array<int, 4> tet{};
      for (int c = 0; c < 4; ++c) {
        const std::size_t tag = element_nodes[4 * e + c];
        if (tag >= 1 && tag <= surface_tags) {
          tet[c] = surface_nodes.node_of_tag[tag];
        } else {
          const auto where = new_index.find(tag);
          if (where == new_index.end())
            throw NumericalError("Gmsh added node " + std::to_string(tag) +
                                 " on a boundary surface: the gap's triangulations were not kept");
          tet[c] = where->second;
        }
      }
      gap.tets.push_back(tet);
    }
    if (gap.tets.empty()) throw NumericalError("Gmsh produced no tetrahedra in the gap");
  } catch (const NumericalError&) {
    throw;
  } catch (const std::exception& error) {
    throw NumericalError(std::string("Gmsh could not fill the gap between the octree core and the surface: ") +
                         error.what());
  } catch (...) {
    throw NumericalError("Gmsh could not fill the gap between the octree core and the surface");
  }
  return gap;
}

}  // namespace tensormass::detail
