// Locking warnings (model/locking_warning.hpp): first-order cells under a
// material whose Poisson's ratio passes 0.45 are named, per material and
// element type, with the fbar split as the remedy where the element has it;
// quadratic cells, fbar cells, laws without a Poisson's ratio and ratios up
// to 0.45 give none.
#include <gtest/gtest.h>

#include <utility>

#include "support/cantilever.hpp"
#include "support/test_support.hpp"
#include "tensormass/model/locking_warning.hpp"

namespace tensormass {
namespace {

using test_support::expect_contains;

std::vector<std::string> warnings_of(const Mesh& mesh, double poisson, const std::string& law = "stvk",
                                     const std::string& split = "") {
  Scene scene = test::cantilever(law);
  scene.model.materials[0].constants = elastic_constants(1e6, poisson);
  scene.model.materials[0].split = split;
  scene.model.materials[0].line = 7;
  const Model model(mesh, scene.model);
  return locking_warnings(model, scene.model);
}

TEST(LockingWarning, FirstOrderCellsNearIncompressibilityAreNamed) {
  for (const auto& [cut, element] :
       {std::pair{"tet6", "tet4"}, {"hex8", "hex8"}, {"prism6", "prism6"}, {"pyramid5", "pyramid5"}}) {
    const std::vector<std::string> warnings = warnings_of(test::beam(3, cut, {4, 2, 2}), 0.49);
    ASSERT_EQ(warnings.size(), 1u) << element;
    const bool fbar = std::string(element) == "hex8" || std::string(element) == "pyramid5";
    expect_contains(warnings[0], {"material 0 (region all, scene line 7)", std::string("its ") + element + " cells",
                                  "poisson = 0.49", "first-order", fbar ? "split: fbar" : "raise-order"});
  }
  const std::vector<std::string> plane = warnings_of(test::beam(2, "quad4", {4, 2, 1}), 0.499);
  ASSERT_EQ(plane.size(), 1u);
  expect_contains(plane[0], {"quad4", "poisson = 0.499"});
}

TEST(LockingWarning, NoneAtOrBelowTheThreshold) {
  EXPECT_TRUE(warnings_of(test::beam(3, "tet6", {4, 2, 2}), 0.45).empty());
  EXPECT_TRUE(warnings_of(test::beam(3, "tet6", {4, 2, 2}), 0.3).empty());
}

TEST(LockingWarning, NoneForFbarCells) {
  for (const char* cut : {"hex8", "pyramid5"})
    EXPECT_TRUE(warnings_of(test::beam(3, cut, {4, 2, 2}), 0.499, "stvk", "fbar").empty()) << cut;
  EXPECT_TRUE(warnings_of(test::beam(2, "quad4", {4, 2, 1}), 0.499, "stvk", "fbar").empty());
  // prism6 has no fbar kernels: its cells keep `whole` and are named.
  EXPECT_EQ(warnings_of(test::beam(3, "prism6", {4, 2, 2}), 0.499, "stvk", "fbar").size(), 1u);
}

/// tet4 under a law with a bulk part is offered `split: anp`, and its anp
/// cells are not named; under stvk (no bulk part) anp keeps `whole`.
TEST(LockingWarning, NamesAnpForTet4AndNoneForAnpCells) {
  const Mesh tets = test::beam(3, "tet6", {4, 2, 2});
  const std::vector<std::string> plain = warnings_of(tets, 0.499, "neohookean");
  ASSERT_EQ(plain.size(), 1u);
  expect_contains(plain[0], {"tet4", "split: anp"});
  EXPECT_TRUE(warnings_of(tets, 0.499, "neohookean", "anp").empty());
  EXPECT_TRUE(warnings_of(test::beam(2, "tri3", {4, 2, 1}), 0.499, "hooke", "anp").empty());
  EXPECT_EQ(warnings_of(tets, 0.499, "stvk", "anp").size(), 1u);
  // anp on hexahedra is their mean dilatation.
  EXPECT_TRUE(warnings_of(test::beam(3, "hex8", {4, 2, 2}), 0.499, "neohookean", "anp").empty());
}

TEST(LockingWarning, NoneForQuadraticElements) {
  EXPECT_TRUE(warnings_of(test::beam(3, "tet6", {4, 2, 2}, 2), 0.49).empty());
  EXPECT_TRUE(warnings_of(test::beam(3, "hex8", {4, 2, 2}, 2), 0.49).empty());
}

TEST(LockingWarning, NoneForALawWithoutAPoissonsRatio) {
  Scene scene = test::cantilever("stvk");
  scene.model.materials[0].law = "mooney_rivlin";
  scene.model.materials[0].constants = {{"c10", 1e5}, {"c01", 2e4}, {"kappa", 1e8}};
  const Mesh mesh = test::beam(3, "tet6", {4, 2, 2});
  const Model model(mesh, scene.model);
  EXPECT_TRUE(locking_warnings(model, scene.model).empty());
}

}  // namespace
}  // namespace tensormass
