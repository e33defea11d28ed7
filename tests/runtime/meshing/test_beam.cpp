// make_beam: conformity, positive volumes, groups and counts for every cut,
// mixes and order 2; spec errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "beam_checks.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/meshing/beam.hpp"

namespace {

using tensormass::BeamSpec;
using tensormass::Group;
using tensormass::InputError;
using tensormass::Mesh;

struct BeamCase {
  std::string name;
  int dim;
  std::array<int, 3> cells;
  std::array<double, 3> size;
  std::string mix;
  int order;
};

void PrintTo(const BeamCase& c, std::ostream* out) {
  *out << c.name << " (" << c.dim << "D " << c.cells[0] << "x" << c.cells[1] << "x" << c.cells[2] << " " << c.mix
       << " order " << c.order << ")";
}

BeamSpec spec_of(const BeamCase& c) {
  BeamSpec spec;
  spec.dim = c.dim;
  spec.cells = c.cells;
  spec.size = c.size;
  spec.phases = tensormass::parse_beam_mix(c.mix);
  spec.order = c.order;
  return spec;
}

std::vector<BeamCase> cases() {
  const std::array<double, 3> box{3.0, 1.0, 0.7};
  return {
      {"quad4", 2, {7, 3, 0}, box, "quad4:1", 1},
      {"tri3", 2, {7, 3, 0}, box, "tri3:1", 1},
      {"quad8", 2, {5, 2, 0}, box, "quad4:1", 2},
      {"tri6", 2, {5, 2, 0}, box, "tri3:1", 2},
      {"tri3_quad4", 2, {10, 3, 0}, box, "tri3:0.3,quad4:0.7", 1},
      {"tri6_quad8", 2, {10, 3, 0}, box, "tri3:0.3,quad4:0.7", 2},
      {"hex8", 3, {5, 3, 2}, box, "hex8:1", 1},
      {"tet5", 3, {5, 3, 2}, box, "tet5:1", 1},
      {"tet6", 3, {5, 3, 2}, box, "tet6:1", 1},
      {"prism6", 3, {5, 3, 2}, box, "prism6:1", 1},
      {"pyramid5", 3, {5, 3, 2}, box, "pyramid5:1", 1},
      {"hex20", 3, {3, 2, 2}, box, "hex8:1", 2},
      {"hex27", 3, {3, 2, 2}, box, "hex27:1", 2},
      {"quad9", 2, {5, 2, 0}, box, "quad9:1", 2},
      {"tri6_quad9", 2, {10, 3, 0}, box, "tri3:0.3,quad9:0.7", 2},
      {"tet10_5", 3, {3, 2, 2}, box, "tet5:1", 2},
      {"tet10_6", 3, {3, 2, 2}, box, "tet6:1", 2},
      {"hex8_tet5", 3, {6, 3, 3}, box, "hex8:0.5,tet5:0.5", 1},
      {"tet5_hex8", 3, {6, 3, 3}, box, "tet5:0.5,hex8:0.5", 1},
      {"four_phases", 3, {8, 3, 3}, box, "tet6:0.25,pyramid5:0.25,prism6:0.25,hex8:0.25", 1},
      {"four_phases_back", 3, {8, 3, 3}, box, "hex8:0.25,prism6:0.25,pyramid5:0.25,tet6:0.25", 1},
      {"four_phases_order2", 3, {8, 3, 3}, box, "tet6:0.25,pyramid5:0.25,prism6:0.25,hex8:0.25", 2},
      {"hex20_tet10_transitions", 3, {6, 3, 3}, box, "hex8:0.5,tet5:0.5", 2},
      {"tet5_tet6", 3, {6, 3, 3}, box, "tet5:0.5,tet6:0.5", 1},
      {"tet6_tet5", 3, {5, 3, 3}, box, "tet6:0.4,tet5:0.6", 1},
      {"tet5_tet6_order2", 3, {4, 2, 3}, box, "tet5:0.5,tet6:0.5", 2},
      {"prism6_tet5_pyramid5", 3, {6, 3, 2}, box, "prism6:0.33,tet5:0.34,pyramid5:0.33", 1},
      {"tet5_prism6_tet6", 3, {6, 3, 2}, box, "tet5:0.33,prism6:0.34,tet6:0.33", 1},
      {"hex8_tet6_order1_odd", 3, {5, 3, 3}, box, "hex8:0.4,tet6:0.6", 1},
      {"single_column_phases", 3, {3, 1, 1}, box, "tet5:0.34,hex8:0.33,tet6:0.33", 1},
  };
}

class BeamTest : public testing::TestWithParam<BeamCase> {};

TEST_P(BeamTest, IsConformingWithUniqueSharedNodes) {
  const BeamCase& c = GetParam();
  const Mesh mesh = tensormass::make_beam(spec_of(c));
  tmtest::expect_conforming(mesh, c.size);
  tmtest::expect_nodes_unique_and_used(mesh);
  if (c.order == 2) tmtest::expect_mid_edge_nodes(mesh);
  for (const tensormass::ElementBlock& block : mesh.blocks) EXPECT_EQ(block.element->order, c.order);
}

TEST_P(BeamTest, CellsHavePositiveVolumesFillingTheBox) {
  const BeamCase& c = GetParam();
  const Mesh mesh = tensormass::make_beam(spec_of(c));
  const std::vector<double> volumes = tmtest::cell_volumes(mesh);
  ASSERT_EQ(static_cast<int>(volumes.size()), mesh.cell_count());
  EXPECT_GT(*std::min_element(volumes.begin(), volumes.end()), 0.0);
  const double box = c.dim == 2 ? c.size[0] * c.size[1] : c.size[0] * c.size[1] * c.size[2];
  EXPECT_NEAR(std::accumulate(volumes.begin(), volumes.end(), 0.0), box, 1e-12 * box);
}

void expect_end_group(const Mesh& mesh, const Group& group, double x, int order, double area) {
  EXPECT_EQ(group.dim, mesh.dim - 1);
  std::vector<int> expected_nodes;
  for (int node = 0; node < mesh.node_count(); ++node)
    if (mesh.rest_positions[3 * node] == x) expected_nodes.push_back(node);
  EXPECT_EQ(group.nodes, expected_nodes) << group.name;
  double total = 0;
  for (int f = 0; f < group.facets.count(); ++f) {
    const std::vector<int> facet(group.facets.nodes.begin() + group.facets.offsets[f],
                                 group.facets.nodes.begin() + group.facets.offsets[f + 1]);
    for (int node : facet) EXPECT_EQ(mesh.rest_positions[3 * node], x) << group.name;
    EXPECT_EQ(group.facets.orders[f], order);
    total += tmtest::facet_measure(mesh, tmtest::facet_corners(facet, order, mesh.dim));
  }
  EXPECT_NEAR(total, area, 1e-12 * area) << group.name;
}

TEST_P(BeamTest, HasClampTipBodyAndPhaseGroups) {
  const BeamCase& c = GetParam();
  const BeamSpec spec = spec_of(c);
  const Mesh mesh = tensormass::make_beam(spec);
  const double end_area = c.dim == 2 ? c.size[1] : c.size[1] * c.size[2];
  ASSERT_EQ(mesh.groups.size(), 3 + (spec.phases.size() > 1 ? spec.phases.size() : 0));
  EXPECT_EQ(mesh.groups[0].name, "clamp");
  EXPECT_EQ(mesh.groups[1].name, "tip");
  expect_end_group(mesh, mesh.groups[0], 0.0, c.order, end_area);
  expect_end_group(mesh, mesh.groups[1], c.size[0], c.order, end_area);
  const Group& body = mesh.groups[2];
  EXPECT_EQ(body.name, "body");
  EXPECT_EQ(body.dim, mesh.dim);
  EXPECT_EQ(static_cast<int>(body.cells.size()), mesh.cell_count());
  EXPECT_EQ(static_cast<int>(body.nodes.size()), mesh.node_count());
}

class BeamMixTest : public BeamTest {};

/// Phase groups partition the cells, each within its columns.
TEST_P(BeamMixTest, PhasesPartitionTheCellsAlongX) {
  const BeamCase& c = GetParam();
  const BeamSpec spec = spec_of(c);
  const Mesh mesh = tensormass::make_beam(spec);
  const std::vector<int> bounds = tensormass::beam_phase_bounds(spec);
  std::vector<int> owner(mesh.cell_count(), -1);
  for (std::size_t p = 0; p < spec.phases.size(); ++p) {
    const Group* group = mesh.group("phase_" + spec.phases[p].cut);
    ASSERT_NE(group, nullptr) << spec.phases[p].cut;
    EXPECT_EQ(group->dim, mesh.dim);
    const double x0 = c.size[0] * bounds[p] / c.cells[0], x1 = c.size[0] * bounds[p + 1] / c.cells[0];
    for (int cell : group->cells) {
      EXPECT_EQ(owner[cell], -1) << "cell in two phases";
      owner[cell] = static_cast<int>(p);
      const auto [b, local] = mesh.locate(cell);
      for (int node : mesh.blocks[b].cell_nodes(local)) {
        EXPECT_GE(mesh.rest_positions[3 * node], x0 - 1e-12);
        EXPECT_LE(mesh.rest_positions[3 * node], x1 + 1e-12);
      }
    }
  }
  EXPECT_EQ(std::count(owner.begin(), owner.end(), -1), 0) << "cells in no phase";
}

std::vector<BeamCase> mixes() {
  std::vector<BeamCase> result;
  for (const BeamCase& c : cases())
    if (c.mix.find(',') != std::string::npos) result.push_back(c);
  return result;
}

std::string case_name(const testing::TestParamInfo<BeamCase>& info) { return info.param.name; }

INSTANTIATE_TEST_SUITE_P(Cuts, BeamTest, testing::ValuesIn(cases()), case_name);
INSTANTIATE_TEST_SUITE_P(Mixes, BeamMixTest, testing::ValuesIn(mixes()), case_name);

// --- Counts --------------------------------------------------------------------------

std::map<std::string, int> counts(int dim, std::array<int, 3> cells, const std::string& mix, int order = 1) {
  return tmtest::cells_per_type(tensormass::make_beam(spec_of({"", dim, cells, {1, 1, 1}, mix, order})));
}

TEST(BeamCounts, OriginDefaultIs600Quads) {
  const Mesh mesh = tensormass::make_beam(BeamSpec{});
  EXPECT_EQ(tmtest::cells_per_type(mesh), (std::map<std::string, int>{{"quad4", 600}}));
  EXPECT_EQ(mesh.node_count(), 61 * 11);
  EXPECT_EQ(mesh.rest_positions[3 * (mesh.node_count() - 1)], 6.0);
}

TEST(BeamCounts, EachCutGivesItsCells) {
  using Counts = std::map<std::string, int>;
  EXPECT_EQ(counts(2, {4, 3, 0}, "tri3:1"), (Counts{{"tri3", 24}}));
  EXPECT_EQ(counts(2, {4, 3, 0}, "tri3:1", 2), (Counts{{"tri6", 24}}));
  EXPECT_EQ(counts(2, {4, 3, 0}, "quad4:1", 2), (Counts{{"quad8", 12}}));
  EXPECT_EQ(counts(3, {3, 2, 2}, "hex8:1"), (Counts{{"hex8", 12}}));
  EXPECT_EQ(counts(3, {3, 2, 2}, "tet5:1"), (Counts{{"tet4", 60}}));
  EXPECT_EQ(counts(3, {3, 2, 2}, "tet6:1"), (Counts{{"tet4", 72}}));
  EXPECT_EQ(counts(3, {3, 2, 2}, "prism6:1"), (Counts{{"prism6", 24}}));
  EXPECT_EQ(counts(3, {3, 2, 2}, "pyramid5:1"), (Counts{{"pyramid5", 72}}));
  EXPECT_EQ(counts(3, {3, 2, 2}, "hex8:1", 2), (Counts{{"hex20", 12}}));
  EXPECT_EQ(counts(3, {3, 2, 2}, "tet6:1", 2), (Counts{{"tet10", 72}}));
}

TEST(BeamCounts, HexNextToTetsGetsPyramidTransitions) {
  // 4 columns: 2 of hexes, then 2 of tet5 whose first column touches the hexes:
  // each of its 4 cubes is a centre node with 1 pyramid and 5 x 2 tets.
  using Counts = std::map<std::string, int>;
  EXPECT_EQ(counts(3, {4, 2, 2}, "hex8:0.5,tet5:0.5"),
            (Counts{{"hex8", 8}, {"pyramid5", 4}, {"tet4", 4 * 10 + 4 * 5}}));
  const Mesh mesh = tensormass::make_beam(spec_of({"", 3, {4, 2, 2}, {1, 1, 1}, "hex8:0.5,tet5:0.5", 1}));
  EXPECT_EQ(mesh.node_count(), 5 * 3 * 3 + 4);  // grid + 4 centres
}

TEST(BeamCounts, MixSplitsColumnsByFraction) {
  using Counts = std::map<std::string, int>;
  EXPECT_EQ(counts(2, {10, 2, 0}, "tri3:0.3,quad4:0.7"), (Counts{{"quad4", 14}, {"tri3", 12}}));
  const BeamSpec spec = spec_of({"", 2, {10, 2, 0}, {1, 1, 1}, "tri3:0.3,quad4:0.7", 1});
  EXPECT_EQ(tensormass::beam_phase_bounds(spec), (std::vector<int>{0, 3, 10}));
}

TEST(BeamCounts, PositionsAreExactAtBothEnds) {
  const Mesh mesh = tensormass::make_beam(spec_of({"", 3, {7, 3, 3}, {0.7, 0.3, 0.1}, "hex8:1", 1}));
  double max_x = 0, max_y = 0, max_z = 0;
  for (int n = 0; n < mesh.node_count(); ++n) {
    max_x = std::max(max_x, mesh.rest_positions[3 * n]);
    max_y = std::max(max_y, mesh.rest_positions[3 * n + 1]);
    max_z = std::max(max_z, mesh.rest_positions[3 * n + 2]);
  }
  EXPECT_EQ(max_x, 0.7);
  EXPECT_EQ(max_y, 0.3);
  EXPECT_EQ(max_z, 0.1);
}

// --- Errors --------------------------------------------------------------------------

void expect_input_error(BeamSpec spec, const std::string& phrase) {
  try {
    tensormass::make_beam(spec);
    ADD_FAILURE() << "no error; expected one mentioning '" << phrase << "'";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(phrase), std::string::npos) << error.what();
  }
}

BeamSpec spec_with(int dim, const std::string& mix, int order = 1) {
  return spec_of({"", dim, {10, 2, 2}, {1, 1, 1}, mix, order});
}

TEST(BeamErrors, RejectBadSpecsWithClearMessages) {
  expect_input_error(spec_with(2, "hex9:1"), "unknown cell type 'hex9'");
  expect_input_error(spec_with(2, "tet5:1"), "'tet5' is a 3D cell type");
  expect_input_error(spec_with(3, "quad4:1"), "'quad4' is a 2D cell type");
  expect_input_error(spec_with(3, "tet10:1"), "use tet5 or tet6 with --order 2");
  expect_input_error(spec_with(2, "tri3:0.3,quad4:0.6"), "sum to");
  expect_input_error(spec_with(2, "tri3:0.5,tri3:0.5"), "appears twice");
  expect_input_error(spec_with(2, "tri3:-0.5,quad4:1.5"), "fraction");
  expect_input_error(spec_with(2, "tri3:0.01,quad4:0.99"), "gets no column");
  expect_input_error(spec_with(3, "hex27:0.5,tet5:0.5"), "hex27 has face-centre nodes");
  BeamSpec linear_hex27 = spec_with(3, "hex8:1");
  linear_hex27.quadratic = {"hex27"};
  expect_input_error(linear_hex27, "hex27 needs order 2");
  BeamSpec tet_hex27 = spec_with(3, "tet5:1", 2);
  tet_hex27.quadratic = {"hex27"};
  expect_input_error(tet_hex27, "hex27 is not a quadratic version of a cell this beam makes");
  expect_input_error(spec_with(2, "quad4:1", 3), "order must be 1 or 2");
  BeamSpec zero = spec_with(3, "hex8:1");
  zero.cells[2] = 0;
  expect_input_error(zero, "at least 1");
  BeamSpec flat = spec_with(2, "quad4:1");
  flat.size[1] = 0;
  expect_input_error(flat, "positive");
  BeamSpec four = spec_with(2, "quad4:1");
  four.dim = 4;
  expect_input_error(four, "dimension");
}

TEST(BeamErrors, MixParsing) {
  const std::vector<tensormass::BeamPhase> phases = tensormass::parse_beam_mix("tri3:0.3,quad4:0.7");
  ASSERT_EQ(phases.size(), 2u);
  EXPECT_EQ(phases[0].cut, "tri3");
  EXPECT_EQ(phases[0].fraction, 0.3);
  EXPECT_EQ(phases[1].cut, "quad4");
  EXPECT_THROW(tensormass::parse_beam_mix("tri3"), InputError);
  EXPECT_THROW(tensormass::parse_beam_mix("tri3:abc"), InputError);
  EXPECT_THROW(tensormass::parse_beam_mix("tri3:0.5x"), InputError);
  EXPECT_THROW(tensormass::parse_beam_mix(":0.5"), InputError);
  EXPECT_THROW(tensormass::parse_beam_mix(""), InputError);
}

}  // namespace
