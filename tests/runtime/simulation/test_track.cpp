// GroupTrack: the rest-volume-weighted centroid of a group (track.hpp)
// against independent computations, rigid translations, the recorded rows
// and the CSV format.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

#include "tensormass/common/errors.hpp"
#include "tensormass/io/streamed_file.hpp"
#include "tensormass/mesh/mesh_quality.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/simulation/track.hpp"
#include "track_test_support.hpp"

namespace {

using tensormass::BeamSpec;
using tensormass::GroupTrack;
using tensormass::Mesh;

Mesh beam(int dim, std::vector<tensormass::BeamPhase> phases, int order = 1, std::array<int, 3> cells = {6, 2, 2}) {
  BeamSpec spec;
  spec.dim = dim;
  spec.cells = cells;
  spec.size = {3.0, 1.0, 0.5};
  spec.phases = std::move(phases);
  spec.order = order;
  return tensormass::make_beam(spec);
}

std::vector<int> all_cells(const Mesh& mesh) {
  std::vector<int> cells(static_cast<std::size_t>(mesh.cell_count()));
  for (int c = 0; c < mesh.cell_count(); ++c) cells[static_cast<std::size_t>(c)] = c;
  return cells;
}

void expect_near3(const std::array<double, 3>& got, const std::array<double, 3>& want, double tolerance) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], tolerance) << "component " << c;
}

/// The box [0,3]x[0,1]x[0,0.5] (z = 0 in 2D): its volume centroid.
std::array<double, 3> box_centre(int dim) { return {1.5, 0.5, dim == 3 ? 0.25 : 0.0}; }

struct MixedCase {
  const char* name;
  int dim;
  std::vector<tensormass::BeamPhase> phases;
  int order;
  std::size_t element_types;
};

class WholeBody : public ::testing::TestWithParam<MixedCase> {};

// Cells whose node mean is their volume centroid (simplices, squares, cubes,
// right prisms, the symmetric pyramid5 cut; no transition cubes between these
// phases): the body's centroid is the box centre.
TEST_P(WholeBody, CentroidIsTheBoxCentre) {
  const MixedCase c = GetParam();
  const Mesh mesh = beam(c.dim, c.phases, c.order);
  ASSERT_EQ(mesh.blocks.size(), c.element_types);
  const GroupTrack track(mesh, *mesh.group("body"));
  expect_near3(track.rest_centroid(), box_centre(c.dim), 1e-14);
  EXPECT_NEAR(track.rest_volume(), c.dim == 3 ? 1.5 : 3.0, 1e-13);
  const std::vector<double> zero(static_cast<std::size_t>(mesh.node_count() * mesh.dim), 0.0);
  expect_near3(track.centroid(zero), box_centre(c.dim), 1e-14);
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, WholeBody,
    ::testing::Values(MixedCase{"tri3_quad4", 2, {{"tri3", 0.5}, {"quad4", 0.5}}, 1, 2},
                      MixedCase{"tri6_quad8", 2, {{"tri3", 0.5}, {"quad4", 0.5}}, 2, 2},
                      MixedCase{"hex8_prism6_pyramid5", 3, {{"hex8", 0.4}, {"prism6", 0.3}, {"pyramid5", 0.3}}, 1, 3},
                      MixedCase{"tet5_tet6", 3, {{"tet5", 0.5}, {"tet6", 0.5}}, 1, 1},
                      MixedCase{"tet10_tet5_tet6", 3, {{"tet5", 0.5}, {"tet6", 0.5}}, 2, 1}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(Centroid, PhaseGroupIsItsHalfOfTheBox) {
  const Mesh mesh = beam(2, {{"tri3", 0.5}, {"quad4", 0.5}});
  expect_near3(GroupTrack(mesh, *mesh.group("phase_quad4")).rest_centroid(), {2.25, 0.5, 0.0}, 1e-14);
  expect_near3(GroupTrack(mesh, *mesh.group("phase_tri3")).rest_centroid(), {0.75, 0.5, 0.0}, 1e-14);
}

/// Tet volume by the determinant and vertex mean: independent of the kernels.
std::array<double, 4> tet_volume_and_centre(const Mesh& mesh, std::span<const int> nodes) {
  auto x = [&](int k, int c) { return mesh.rest_positions[3 * static_cast<std::size_t>(nodes[k]) + c]; };
  double e[3][3];
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 3; ++c) e[k][c] = x(k + 1, c) - x(0, c);
  const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                     e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                     e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
  std::array<double, 4> out{std::abs(det) / 6, 0, 0, 0};
  for (int c = 0; c < 3; ++c) out[1 + c] = (x(0, c) + x(1, c) + x(2, c) + x(3, c)) / 4;
  return out;
}

// Irregular tets (interior nodes moved at random): the volume centroid of
// the polyhedral body, summed tet by tet with the determinant formula.
TEST(Centroid, IrregularTetMeshMatchesTheDeterminantFormula) {
  Mesh mesh = beam(3, {{"tet5", 0.5}, {"tet6", 0.5}}, 1, {6, 3, 3});
  std::mt19937 random(7);
  std::uniform_real_distribution<double> shift(-0.04, 0.04);
  for (int i = 0; i < mesh.node_count(); ++i) {
    double* x = &mesh.rest_positions[3 * static_cast<std::size_t>(i)];
    if (x[0] > 0 && x[0] < 3 && x[1] > 0 && x[1] < 1 && x[2] > 0 && x[2] < 0.5)
      for (int c = 0; c < 3; ++c) x[c] += shift(random);
  }
  double volume = 0;
  std::array<double, 3> moment{};
  for (const tensormass::ElementBlock& block : mesh.blocks) {
    ASSERT_EQ(block.nodes_per_cell(), 4);
    for (int local = 0; local < block.count(); ++local) {
      const auto v = tet_volume_and_centre(mesh, block.cell_nodes(local));
      volume += v[0];
      for (int c = 0; c < 3; ++c) moment[c] += v[0] * v[1 + c];
    }
  }
  const GroupTrack track(mesh, "body", all_cells(mesh));
  EXPECT_NEAR(track.rest_volume(), volume, 1e-13);
  expect_near3(track.rest_centroid(), {moment[0] / volume, moment[1] / volume, moment[2] / volume}, 1e-14);
  EXPECT_NEAR(volume, 1.5, 1e-13);  // interior nodes moved: same box
}

// Transition cubes (pyramids between hexes and tets): the documented
// formula, evaluated cell by cell.
TEST(Centroid, TransitionMeshMatchesTheDocumentedFormula) {
  const Mesh mesh = beam(3, {{"hex8", 0.5}, {"tet6", 0.5}});
  double volume = 0;
  std::array<double, 3> moment{};
  for (const tensormass::ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local) {
      const double v = tensormass::cell_volume(*block.element, 3, tensormass::cell_coordinates(mesh, block, local));
      for (int node : block.cell_nodes(local))
        for (int c = 0; c < 3; ++c)
          moment[c] += v * mesh.rest_positions[3 * static_cast<std::size_t>(node) + c] / block.nodes_per_cell();
      volume += v;
    }
  const GroupTrack track(mesh, *mesh.group("body"));
  EXPECT_NEAR(track.rest_volume(), 1.5, 1e-13);
  expect_near3(track.rest_centroid(), {moment[0] / volume, moment[1] / volume, moment[2] / volume}, 1e-14);
}

// Exactly: the weighted sum is evaluated as u_0 + sum_i W_i (u_i - u_0).
TEST(Centroid, RigidTranslationMovesItByTheTranslation) {
  for (const int dim : {2, 3}) {
    const Mesh mesh = dim == 2 ? beam(2, {{"tri3", 0.3}, {"quad4", 0.7}}) : beam(3, {{"hex8", 0.5}, {"tet6", 0.5}});
    const std::array<double, 3> t{0.125, -0.3, dim == 3 ? 0.07 : 0.0};
    std::vector<double> u(static_cast<std::size_t>(mesh.node_count() * dim));
    for (std::size_t i = 0; i < u.size(); ++i) u[i] = t[i % static_cast<std::size_t>(dim)];
    GroupTrack track(mesh, *mesh.group("body"));
    track.record(0.0, std::vector<double>(u.size(), 0.0));
    const tensormass::TrackRow row = track.record(1.0, u);
    const auto rest = track.rest_centroid();
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(row.displacement[c], t[c]) << "dim " << dim << " component " << c;
      EXPECT_EQ(row.position[c], rest[c] + t[c]) << "dim " << dim << " component " << c;
      EXPECT_EQ(track.centroid(u)[c], row.position[c]);
    }
  }
}

TEST(Centroid, FirstRowHasExactlyZeroDisplacement) {
  const Mesh mesh = beam(2, {{"quad4", 1.0}});
  std::vector<double> u(static_cast<std::size_t>(mesh.node_count() * 2));
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = 1e-3 * std::sin(0.37 * static_cast<double>(i));
  GroupTrack track(mesh, *mesh.group("body"));
  const tensormass::TrackRow first = track.record(0.5, u);
  const tensormass::TrackRow second = track.record(0.75, std::vector<double>(u.size(), 0.0));
  for (int c = 0; c < 3; ++c) EXPECT_EQ(first.displacement[c], 0.0);
  expect_near3(second.position, track.rest_centroid(), 0);
  for (int c = 0; c < 3; ++c)  // measured from the first row, not from rest
    EXPECT_NEAR(second.displacement[c], track.rest_centroid()[c] - first.position[c], 1e-15);
}

TEST(Centroid, CsvHasTheHeaderAndRoundTripPrecision) {
  track_test::TempDir dir;
  const Mesh mesh = beam(2, {{"quad4", 1.0}});
  GroupTrack track(mesh, *mesh.group("body"));
  std::vector<double> u(static_cast<std::size_t>(mesh.node_count() * 2), 0.0);
  tensormass::io::StreamedFile file(dir.file("track_body.csv"), tensormass::track_csv_header());
  file.append(tensormass::track_csv_row(track.record(0.0, u)));
  for (std::size_t i = 1; i < u.size(); i += 2) u[i] = -1.0 / 3.0;
  const tensormass::TrackRow recorded = track.record(0.1, u);
  file.append(tensormass::track_csv_row(recorded));
  file.finish();
  const auto lines = track_test::read_lines(dir.path() / "track_body.csv");
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "time,x,y,z,ux,uy,uz");
  EXPECT_EQ(lines[1].substr(lines[1].size() - 6), ",0,0,0");
  const std::vector<double> row = track_test::numbers(lines[2]);
  ASSERT_EQ(row.size(), 7u);
  EXPECT_EQ(row[0], 0.1);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(row[1 + c], recorded.position[c]);  // bit for bit
    EXPECT_EQ(row[4 + c], recorded.displacement[c]);
  }
  EXPECT_NEAR(row[5], -1.0 / 3.0, 1e-15);
  for (const auto& entry : std::filesystem::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().filename(), "track_body.csv");
}

TEST(Centroid, NoCellsIsAnInputError) {
  const Mesh mesh = beam(2, {{"quad4", 1.0}});
  EXPECT_THROW(GroupTrack(mesh, *mesh.group("clamp")), tensormass::InputError);
}

}  // namespace
