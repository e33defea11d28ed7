// The registry (which LES triples exist, lookups) and the reference-element
// facts exposed at runtime (tm_element_info: shape functions, quadrature).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernel_test_support.hpp"
#include "tensormass/kernels/law_parameters.hpp"

namespace tmtest {
namespace {

const std::vector<std::string> kSplits = {"anp", "fbar", "tensor", "terms", "whole"};

struct ExpectedElement {
  int dim, order, nodes, vtk_type;
};

/// Facts of well-known elements from the VTK file-format documentation;
/// an element file of another name is checked against itself only.
const std::map<std::string, ExpectedElement>& known_elements() {
  static const std::map<std::string, ExpectedElement> table = {
      {"tri3", {2, 1, 3, 5}},      {"quad4", {2, 1, 4, 9}},       {"tet4", {3, 1, 4, 10}},  {"hex8", {3, 1, 8, 12}},
      {"prism6", {3, 1, 6, 13}},   {"pyramid5", {3, 1, 5, 14}},   {"tri6", {2, 2, 6, 22}},  {"quad8", {2, 2, 8, 23}},
      {"tet10", {3, 2, 10, 24}},   {"hex20", {3, 2, 20, 25}},     {"quad9", {2, 2, 9, 28}}, {"hex27", {3, 2, 27, 29}},
      {"prism15", {3, 2, 15, 26}}, {"pyramid13", {3, 2, 13, 27}},
  };
  return table;
}

/// The project whose elements/ and laws/ the registry was generated from:
/// $TENSORMASS_INPUTS_DIR when set (a scratch project linked into these
/// tests, tests/examples/run_adding_files.sh), else the source tree.
std::filesystem::path inputs_dir() {
  const char* scratch = std::getenv("TENSORMASS_INPUTS_DIR");
  return scratch && *scratch ? std::filesystem::path(scratch) : std::filesystem::path(TENSORMASS_SOURCE_DIR);
}

/// The stems of the *.toml files of the project's `folder`, sorted.
std::vector<std::string> description_files(const std::string& folder) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(inputs_dir() / folder))
    if (entry.path().extension() == ".toml") names.insert(entry.path().stem().string());
  return {names.begin(), names.end()};
}

/// One element per file of elements/ and one law per file of laws/.
TEST(Registry, HoldsEveryElementAndLawFile) {
  std::vector<std::string> names;
  for (const tm_element_info* info : registry().elements()) names.push_back(info->name);
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, description_files("elements"));
  EXPECT_EQ(registry().laws(), description_files("laws"));
  for (const std::string& split : registry().splits())
    EXPECT_NE(std::find(kSplits.begin(), kSplits.end(), split), kSplits.end()) << "unknown split " << split;
}

/// whole for every (law, element) pair, terms for every pair or for none
/// (the build's TENSORMASS_TERMS_SPLIT); tensor on first-order elements
/// only, for hooke and stvk at least; fbar for every law on exactly the
/// first-order elements with more than one quadrature point but prism6
/// (which it does not free); nothing else. Prony series on the
/// viscoelastic law only, its weights named g1, g2.
TEST(Registry, OffersTheExpectedTriples) {
  const bool with_terms = registry().find("hooke", "tet4", "terms") != nullptr;
  int count = 0;
  for (const tm_element_info* element : registry().elements())
    for (const std::string& law : registry().laws())
      for (const std::string& split : kSplits) {
        const tm_kernel* kernel = registry().find(law, element->name, split);
        if (split == "whole" || (split == "terms" && with_terms))
          EXPECT_NE(kernel, nullptr) << law << "/" << element->name << "/" << split;
        if (split == "terms" && !with_terms) EXPECT_EQ(kernel, nullptr) << law << "/" << element->name;
        if (split == "tensor" && element->order != 1) EXPECT_EQ(kernel, nullptr) << law << "/" << element->name;
        if (split == "tensor" && element->order == 1 && (law == "hooke" || law == "stvk"))
          EXPECT_NE(kernel, nullptr) << law << "/" << element->name << "/tensor";
        if (split == "fbar")
          EXPECT_EQ(kernel != nullptr,
                    element->order == 1 && element->quadrature_points > 1 && std::string(element->name) != "prism6")
              << law << "/" << element->name << "/fbar";
        // anp: the one-point elements and prism6, under the laws with a bulk part.
        const bool anp_element =
            (element->quadrature_points == 1 && element->order == 1) || std::string(element->name) == "prism6";
        if (split == "anp")
          EXPECT_EQ(kernel != nullptr, anp_element && law != "stvk" && law != "corotational")
              << law << "/" << element->name << "/anp";
        if (kernel == nullptr) continue;
        // The bulk part: in anp, and in whole for a viscoelastic law (its viscous part relaxes the rest).
        EXPECT_EQ(kernel->bulk != nullptr, split == "anp" || (split == "whole" && kernel->prony_terms > 0));
        EXPECT_EQ(kernel->prony_terms > 0, law == "viscoelastic_neohookean");
        for (int i = 0; i < kernel->prony_terms; ++i)
          EXPECT_EQ(std::string(kernel->param_names[kernel->prony_weights[i]]), "g" + std::to_string(i + 1));
        ++count;
        EXPECT_EQ(kernel->law, law);
        EXPECT_EQ(kernel->element, std::string(element->name));
        EXPECT_EQ(kernel->split, split);
      }
  EXPECT_EQ(registry().kernels().size(), static_cast<std::size_t>(count));
  EXPECT_EQ(tm_kernel_count(), count);
}

TEST(Registry, KernelsAreUniqueAndComplete) {
  std::set<std::string> names;
  for (const tm_kernel* kernel : registry().kernels()) {
    SCOPED_TRACE(kernel_name(*kernel));
    EXPECT_TRUE(names.insert(kernel_name(*kernel)).second) << "duplicate triple";
    const tm_element_info* info = registry().element(kernel->element);
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(kernel->dim, info->dim);
    EXPECT_EQ(kernel->nodes, info->nodes);
    EXPECT_EQ(kernel->dofs, kernel->nodes * kernel->dim);
    EXPECT_EQ(kernel->quadrature_points, info->quadrature_points);
    EXPECT_GE(kernel->params, 1);
    ASSERT_NE(kernel->param_names, nullptr);
    ASSERT_NE(kernel->param_limits, nullptr);
    std::set<std::string> parameters;
    for (int p = 0; p < kernel->params; ++p) {
      EXPECT_TRUE(parameters.insert(kernel->param_names[p]).second) << "parameter named twice";
      EXPECT_LE(kernel->param_limits[p].lower, kernel->param_limits[p].upper) << kernel->param_names[p];
    }
    const tm_kernel& first = *registry().law_kernel(kernel->law);
    EXPECT_EQ(tensormass::parameter_names(*kernel), tensormass::parameter_names(first)) << "the law's parameters";
    EXPECT_GE(kernel->derived_params, 1);
    EXPECT_GE(kernel->consts, kernel->derived_params + kernel->quadrature_points * (1 + kernel->dim * kernel->nodes));
    EXPECT_NE(kernel->precompute, nullptr);
    EXPECT_NE(kernel->energy, nullptr);
    EXPECT_NE(kernel->gradient, nullptr);
    EXPECT_NE(kernel->hessian, nullptr);
    EXPECT_NE(kernel->gradient_hessian, nullptr);
    EXPECT_NE(kernel->stress, nullptr);
    EXPECT_GT(kernel->flops_energy, 0);
    EXPECT_GT(kernel->flops_gradient, 0);
    EXPECT_GE(kernel->flops_hessian, 0);
    EXPECT_EQ(registry().find(kernel->law, kernel->element, kernel->split), kernel);
    EXPECT_EQ(&registry().get(kernel->law, kernel->element, kernel->split), kernel);
  }
  for (int i = 0; i < tm_kernel_count(); ++i)
    EXPECT_EQ(tm_kernel_at(i), registry().kernels()[static_cast<std::size_t>(i)]);
  EXPECT_EQ(tm_kernel_at(-1), nullptr);
  EXPECT_EQ(tm_kernel_at(tm_kernel_count()), nullptr);
}

/// The generator flags a kernel linear when its law's energy is quadratic
/// in u (Hooke; not St Venant-Kirchhoff), the same on every kernel of a law
/// (Hooke's fbar kernels are B-bar, quadratic too).
TEST(Registry, LinearFlagMarksQuadraticEnergies) {
  for (const tm_kernel* kernel : registry().kernels()) {
    SCOPED_TRACE(kernel_name(*kernel));
    EXPECT_EQ(kernel->linear, registry().law_kernel(kernel->law)->linear);
    if (std::string(kernel->law) == "hooke") EXPECT_EQ(kernel->linear, 1);
    if (std::string(kernel->law) == "stvk") EXPECT_EQ(kernel->linear, 0);
  }
}

/// The flag follows the law file's `invertible` (stable neo-Hookean sets it),
/// except on fbar kernels: F̄ takes a root of J̄/J, which inversion makes negative.
TEST(Registry, InvertibleFlagFollowsTheLaw) {
  for (const tm_kernel* kernel : registry().kernels()) {
    SCOPED_TRACE(kernel_name(*kernel));
    // fbar, and anp on its fbar base (prism6), take a root of J̄/J.
    const bool fbar =
        std::string(kernel->split) == "fbar" || (std::string(kernel->split) == "anp" && kernel->quadrature_points > 1);
    EXPECT_EQ(kernel->invertible, fbar ? 0 : registry().law_kernel(kernel->law)->invertible);
    if (std::string(kernel->law) == "stable_neohookean") EXPECT_EQ(kernel->invertible, fbar ? 0 : 1);
    if (std::string(kernel->law) == "hooke") EXPECT_EQ(kernel->invertible, 0);
  }
}

TEST(Registry, FindReturnsNullForUnknownNames) {
  EXPECT_EQ(registry().find("hooke", "tet4", "nope"), nullptr);
  EXPECT_EQ(registry().find("nope", "tet4", "whole"), nullptr);
  EXPECT_EQ(registry().find("hooke", "tet5", "whole"), nullptr);
  EXPECT_EQ(registry().find("", "", ""), nullptr);
  EXPECT_EQ(registry().find("Hooke", "tet4", "whole"), nullptr);
  EXPECT_EQ(registry().find("hooke/tet4", "", "whole"), nullptr);
  EXPECT_EQ(registry().find("neohookean", "tet4", "tensor"), nullptr);
  EXPECT_EQ(registry().find("hooke", "hex20", "tensor"), nullptr);
  EXPECT_EQ(registry().element("nope"), nullptr);
  EXPECT_EQ(registry().element(""), nullptr);
}

TEST(Registry, GetThrowsInvalidArgumentForUnknownNames) {
  EXPECT_THROW(registry().get("hooke", "tet4", "nope"), std::invalid_argument);
  EXPECT_THROW(registry().get("nope", "tet4", "whole"), std::invalid_argument);
  EXPECT_THROW(registry().get("hooke", "tet5", "whole"), std::invalid_argument);
  EXPECT_THROW(registry().get("neohookean", "hex8", "tensor"), std::invalid_argument);
  EXPECT_THROW(registry().get("", "", ""), std::invalid_argument);
  try {
    registry().get("neohookean", "hex8", "tensor");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("neohookean"), std::string::npos) << message;
    EXPECT_NE(message.find("hex8"), std::string::npos) << message;
  }
  EXPECT_NO_THROW(registry().get("stvk", "tet4", "tensor"));
}

// --- Reference elements at runtime -------------------------------------------

class ElementInfo : public testing::TestWithParam<std::string> {};

TEST_P(ElementInfo, FactsMatchTheElement) {
  const tm_element_info* info = registry().element(GetParam());
  ASSERT_NE(info, nullptr);
  EXPECT_STREQ(info->name, GetParam().c_str());
  const auto known = known_elements().find(GetParam());
  if (known != known_elements().end()) {
    EXPECT_EQ(info->dim, known->second.dim);
    EXPECT_EQ(info->order, known->second.order);
    EXPECT_EQ(info->nodes, known->second.nodes);
    EXPECT_EQ(info->vtk_type, known->second.vtk_type);
  }
  // tensormass node order = VTK order.
  for (int k = 0; k < info->nodes; ++k) EXPECT_EQ(info->vtk_order[k], k);
  std::vector<int> gmsh(info->gmsh_order, info->gmsh_order + info->nodes);
  std::sort(gmsh.begin(), gmsh.end());
  for (int k = 0; k < info->nodes; ++k)
    EXPECT_EQ(gmsh[static_cast<std::size_t>(k)], k) << "gmsh_order is a permutation";
  EXPECT_EQ(info->edge_size, info->order == 1 ? 2 : 3);
  for (int i = 0; i < info->edge_count * info->edge_size; ++i) {
    EXPECT_GE(info->edges[i], 0);
    EXPECT_LT(info->edges[i], info->nodes);
  }
  EXPECT_GT(info->quadrature_points, 0);
}

/// At every quadrature point the shape functions sum to 1 (partition of
/// unity), the weights sum to the reference volume (tri 1/2, quad 4, tet
/// 1/6, hex 8, prism 1, pyramid 4/3), and sum_j N_j(q) r_j lies inside the
/// reference element's bounding box.
TEST_P(ElementInfo, ShapeFunctionsAndWeights) {
  const tm_element_info& info = *registry().element(GetParam());
  const int points = info.quadrature_points, nodes = info.nodes, dim = info.dim;
  double weights = 0.0;
  for (int q = 0; q < points; ++q) {
    EXPECT_GT(info.weights[q], 0.0) << "weight " << q;
    weights += info.weights[q];
    double sum = 0.0;
    for (int j = 0; j < nodes; ++j) sum += info.shape_values[q * nodes + j];
    EXPECT_NEAR(sum, 1.0, 1e-14) << "partition of unity at point " << q;
    for (int a = 0; a < dim; ++a) {
      double x = 0.0, low = 1e300, high = -1e300;
      for (int j = 0; j < nodes; ++j) {
        x += info.shape_values[q * nodes + j] * info.reference_nodes[j * dim + a];
        low = std::min(low, info.reference_nodes[j * dim + a]);
        high = std::max(high, info.reference_nodes[j * dim + a]);
      }
      EXPECT_GT(x, low) << "point " << q << " coordinate " << a;
      EXPECT_LT(x, high) << "point " << q << " coordinate " << a;
    }
  }
  EXPECT_NEAR(weights, reference_volume(info.name), 1e-14 * reference_volume(info.name));
}

INSTANTIATE_TEST_SUITE_P(AllElements, ElementInfo, testing::ValuesIn(element_names()), ElementParamName());

}  // namespace
}  // namespace tmtest
