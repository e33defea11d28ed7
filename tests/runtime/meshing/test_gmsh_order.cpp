// raise_order_with_gmsh: Gmsh's order-2 version of a beam is the beam the
// project makes at order 2 itself (cell by cell, node by node, through the
// element files' Gmsh node orders), errors name what is wrong and write
// nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/gmsh_writer.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/meshing/gmsh_order.hpp"

namespace tensormass {
namespace {

using test_support::TempDir;

BeamSpec beam_spec(int dim, const std::string& mix, int order) {
  BeamSpec spec;
  spec.dim = dim;
  spec.cells = dim == 2 ? std::array<int, 3>{6, 2, 1} : std::array<int, 3>{8, 2, 2};
  spec.size = {3.0, 1.0, 1.0};
  spec.phases = parse_beam_mix(mix);
  spec.order = order;
  return spec;
}

/// Per cell, its element's name and its nodes' positions in local order
/// (rounded to 1e-9), sorted: the mesh up to the numbering of nodes and cells.
std::vector<std::pair<std::string, std::vector<std::array<long, 3>>>> cells_by_position(const Mesh& mesh) {
  std::vector<std::pair<std::string, std::vector<std::array<long, 3>>>> cells;
  for (const ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local) {
      std::vector<std::array<long, 3>> points;
      for (int node : block.cell_nodes(local)) {
        std::array<long, 3> p{};
        for (int a = 0; a < 3; ++a) p[a] = std::lround(mesh.rest_positions[3 * node + a] * 1e9);
        points.push_back(p);
      }
      cells.emplace_back(block.element->name, std::move(points));
    }
  std::sort(cells.begin(), cells.end());
  return cells;
}

/// Gmsh raises `mix` written at order 1; the result equals make_beam at
/// order 2 (with `quadratic` naming the complete elements).
void expect_gmsh_matches_the_beam(int dim, const std::string& mix, bool complete) {
  const TempDir dir;
  io::write_msh(dir.file("linear.msh"), make_beam(beam_spec(dim, mix, 1)));
  RaiseOrderSpec spec{dir.file("linear.msh"), dir.file("quadratic.msh"), complete};
  const Mesh raised = raise_order_with_gmsh(spec);
  BeamSpec ours = beam_spec(dim, mix, 2);
  if (complete) ours.quadratic = {dim == 2 ? "quad9" : "hex27"};
  const Mesh expected = make_beam(ours);
  EXPECT_EQ(raised.node_count(), expected.node_count()) << mix;
  EXPECT_EQ(cells_by_position(raised), cells_by_position(expected)) << mix;
  EXPECT_EQ(raised.groups.size(), expected.groups.size()) << mix;
  EXPECT_EQ(dir.files(), (std::vector<std::string>{"linear.msh", "quadratic.msh"}));
}

TEST(GmshOrder, SerendipityElementsMatchTheBeamsOwn) {
  expect_gmsh_matches_the_beam(3, "hex8:0.25,prism6:0.25,pyramid5:0.25,tet6:0.25", false);
  expect_gmsh_matches_the_beam(2, "tri3:0.5,quad4:0.5", false);
}

TEST(GmshOrder, CompleteElementsMatchTheBeamsOwn) {
  expect_gmsh_matches_the_beam(3, "hex8:1", true);
  expect_gmsh_matches_the_beam(2, "quad4:1", true);
}

TEST(GmshOrder, ElementsTheRegistryLacksAreRefusedAndNothingIsWritten) {
  const TempDir dir;
  io::write_msh(dir.file("prisms.msh"), make_beam(beam_spec(3, "prism6:1", 1)));
  try {
    raise_order_with_gmsh({dir.file("prisms.msh"), dir.file("out.msh"), true});
    FAIL() << "18-node prisms were accepted";
  } catch (const InputError& error) {
    test_support::expect_contains(error.what(), {"18-node prism", "without --complete"});
  }
  EXPECT_EQ(dir.files(), std::vector<std::string>{"prisms.msh"});
}

TEST(GmshOrder, BadInputIsRefusedBeforeGmshRuns) {
  const TempDir dir;
  io::write_msh(dir.file("quadratic.msh"), make_beam(beam_spec(2, "quad4:1", 2)));
  dir.write("broken.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n");
  const std::vector<std::pair<RaiseOrderSpec, std::vector<std::string>>> cases{
      {{dir.file("quadratic.msh"), dir.file("out.msh")}, {"quad8", "order 2 already"}},
      {{dir.file("broken.msh"), dir.file("out.msh")}, {"broken.msh"}},
      {{dir.file("missing.msh"), dir.file("out.msh")}, {"missing.msh"}},
      {{dir.file("quadratic.msh"), dir.file("out.vtu")}, {"must end in .msh"}},
  };
  for (const auto& [spec, parts] : cases) {
    try {
      raise_order_with_gmsh(spec);
      ADD_FAILURE() << spec.input << " was accepted";
    } catch (const InputError& error) {
      test_support::expect_contains(error.what(), parts);
    }
  }
  EXPECT_EQ(dir.files(), (std::vector<std::string>{"broken.msh", "quadratic.msh"}));
}

}  // namespace
}  // namespace tensormass
