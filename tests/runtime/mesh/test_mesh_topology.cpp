// cells_around_nodes, is_load_facet, facet_corners and facet_owner on beams.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "tensormass/kernels/registry.hpp"
#include "tensormass/mesh/mesh_topology.hpp"
#include "tensormass/meshing/beam.hpp"

namespace {

using tensormass::Mesh;

Mesh quad_beam(int order) {
  tensormass::BeamSpec spec;
  spec.cells = {3, 2, 1};
  spec.order = order;
  return tensormass::make_beam(spec);
}

TEST(MeshTopology, CellsAroundNodesListsEveryUseOnceAscending) {
  const Mesh mesh = quad_beam(1);
  const auto node_cells = tensormass::cells_around_nodes(mesh);
  ASSERT_EQ(static_cast<int>(node_cells.size()), mesh.node_count());
  std::size_t uses = 0;
  for (const auto& cells : node_cells) {
    EXPECT_TRUE(std::is_sorted(cells.begin(), cells.end()));
    EXPECT_TRUE(std::adjacent_find(cells.begin(), cells.end()) == cells.end());
    EXPECT_GE(cells.size(), 1u);
    EXPECT_LE(cells.size(), 4u);  // a structured quad grid
    uses += cells.size();
  }
  EXPECT_EQ(uses, 4u * mesh.cell_count());
}

TEST(MeshTopology, LoadFacetsPerDimension) {
  EXPECT_TRUE(tensormass::is_load_facet(2, 2));
  EXPECT_TRUE(tensormass::is_load_facet(2, 3));
  EXPECT_FALSE(tensormass::is_load_facet(2, 4));
  // In 3D: the node counts of the registry's 2D elements.
  for (const tm_element_info* element : tensormass::Registry::instance().elements())
    if (element->dim == 2) EXPECT_TRUE(tensormass::is_load_facet(3, element->nodes)) << element->name;
  for (int nodes : {2, 5, 7}) EXPECT_FALSE(tensormass::is_load_facet(3, nodes)) << nodes;
  EXPECT_EQ(tensormass::facet_corners(2, 3), 2);
  EXPECT_EQ(tensormass::facet_corners(3, 6), 3);
  EXPECT_EQ(tensormass::facet_corners(3, 8), 4);
}

TEST(MeshTopology, EveryBoundaryFacetOfTheBeamHasAnOwnerThatHoldsIt) {
  for (int order : {1, 2}) {
    const Mesh mesh = quad_beam(order);
    const auto node_cells = tensormass::cells_around_nodes(mesh);
    for (const char* name : {"clamp", "tip"}) {
      const tensormass::FacetSet& facets = mesh.group(name)->facets;
      ASSERT_GT(facets.count(), 0) << name;
      for (int f = 0; f < facets.count(); ++f) {
        const std::span<const int> facet(facets.nodes.data() + facets.offsets[f],
                                         static_cast<std::size_t>(facets.offsets[f + 1] - facets.offsets[f]));
        const int owner = tensormass::facet_owner(mesh, node_cells, facet);
        ASSERT_GE(owner, 0) << name << " facet " << f;
        const auto [block, local] = mesh.locate(owner);
        const auto cell = mesh.blocks[block].cell_nodes(local);
        for (int node : facet) EXPECT_NE(std::find(cell.begin(), cell.end(), node), cell.end());
      }
    }
  }
}

TEST(MeshTopology, TwoFarCornersHaveNoOwner) {
  const Mesh mesh = quad_beam(1);
  const auto node_cells = tensormass::cells_around_nodes(mesh);
  const std::vector<int> diagonal{0, mesh.node_count() - 1};
  EXPECT_EQ(tensormass::facet_owner(mesh, node_cells, diagonal), -1);
}

}  // namespace
