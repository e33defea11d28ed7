// Batched entry points (kernel_abi.h): for every kernel that has them, each
// element of a batch gets the per-element kernel's results, full and partial
// batches alike, with and without the gradient.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "kernel_test_support.hpp"

namespace tmtest {
namespace {

/// The registry's per-element results differ from the batched ones by the
/// order of a few roundings (contractions into FMAs may differ).
constexpr double kTolerance = 1e-12;

class KernelBatch : public testing::TestWithParam<const tm_kernel*> {};

/// Width elements (or fewer, the rest of the lanes copies of the first) with
/// their displacements, and the batch built from them.
struct Batch {
  std::vector<Element> elements;
  std::vector<Vector> displacements;
  Vector u, consts;  ///< dofs by W and consts by W
};

Batch make_batch(const tm_kernel& kernel, int used, double strain) {
  const int width = kernel.batch_width;
  Batch batch;
  for (int lane = 0; lane < used; ++lane) {
    batch.elements.push_back(make_element(kernel, 40 + lane));
    batch.displacements.push_back(random_displacement(batch.elements.back(), 140 + lane, strain, strain / 5));
  }
  batch.u.assign(static_cast<std::size_t>(kernel.dofs) * width, 0.0);
  batch.consts.assign(static_cast<std::size_t>(kernel.consts) * width, 0.0);
  for (int lane = 0; lane < width; ++lane) {
    const int source = lane < used ? lane : 0;
    for (int i = 0; i < kernel.dofs; ++i) batch.u[i * width + lane] = batch.displacements[source][i];
    for (int i = 0; i < kernel.consts; ++i) batch.consts[i * width + lane] = batch.elements[source].consts[i];
  }
  return batch;
}

/// Element `lane`'s output from a batched output (element by element).
Vector lane_of(const Vector& batched, int width, int lane) {
  const std::size_t size = batched.size() / width;
  return Vector(batched.begin() + lane * size, batched.begin() + (lane + 1) * size);
}

/// Every lane of a full and of a one-element batch matches the per-element
/// gradient_hessian and stress, at small and large strains.
TEST_P(KernelBatch, EveryLaneEqualsTheElementKernel) {
  const tm_kernel& kernel = *GetParam();
  const int width = kernel.batch_width;
  const auto dofs = static_cast<std::size_t>(kernel.dofs);
  for (const int used : {width, 1})
    for (const double strain : {0.05, 0.2}) {
      Batch batch = make_batch(kernel, used, strain);
      for (const Element& e : batch.elements) ASSERT_EQ(e.status, 0);
      const auto stresses = static_cast<std::size_t>(kernel.quadrature_points * kernel.dim * kernel.dim);
      Vector g(dofs * width), K(dofs * dofs * width), g_only(dofs * width), P(stresses * width);
      kernel.gradient_hessian_batch(batch.u.data(), batch.consts.data(), g.data(), K.data());
      kernel.gradient_batch(batch.u.data(), batch.consts.data(), g_only.data());
      kernel.stress_batch(batch.u.data(), batch.consts.data(), P.data());
      for (int lane = 0; lane < width; ++lane) {
        const int source = lane < used ? lane : 0;
        const Element& e = batch.elements[source];
        const Vector& u = batch.displacements[source];
        Vector expected_g(dofs), expected_K(dofs * dofs), expected_P(stresses);
        kernel.gradient_hessian(u.data(), e.consts.data(), expected_g.data(), expected_K.data());
        kernel.stress(u.data(), e.consts.data(), expected_P.data());
        EXPECT_LE(relative_error(lane_of(g, width, lane), expected_g), kTolerance) << "lane " << lane;
        EXPECT_LE(relative_error(lane_of(g_only, width, lane), expected_g), kTolerance) << "lane " << lane;
        EXPECT_LE(relative_error(lane_of(K, width, lane), expected_K), kTolerance) << "lane " << lane;
        EXPECT_LE(relative_error(lane_of(P, width, lane), expected_P), kTolerance) << "lane " << lane;
      }
    }
}

/// A null gradient leaves the Hessian unchanged (the assembler's K-only path).
TEST_P(KernelBatch, HessianDoesNotDependOnAskingForTheGradient) {
  const tm_kernel& kernel = *GetParam();
  const int width = kernel.batch_width;
  const auto dofs = static_cast<std::size_t>(kernel.dofs);
  const Batch batch = make_batch(kernel, width, 0.1);
  Vector g(dofs * width), with_gradient(dofs * dofs * width), without(dofs * dofs * width);
  kernel.gradient_hessian_batch(batch.u.data(), batch.consts.data(), g.data(), with_gradient.data());
  kernel.gradient_hessian_batch(batch.u.data(), batch.consts.data(), nullptr, without.data());
  EXPECT_EQ(0, std::memcmp(with_gradient.data(), without.data(), without.size() * sizeof(double)));
}

INSTANTIATE_TEST_SUITE_P(BatchedKernels, KernelBatch,
                         testing::ValuesIn(kernels_where([](const tm_kernel& k) { return k.batch_width > 0; })),
                         KernelParamName());
// Empty for a registry without such kernels (a scratch project).
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(KernelBatch);

/// The `whole` split is batched, with a SIMD width, where batches pay
/// (generator/splits/whole.py): small elements, under laws whose block has
/// no library calls but log, exp and powers (vectorised) and the polar
/// rotation (computed for the batch). A kernel has its three batched entry
/// points exactly when it has a width; no other split has them. The shipped
/// small elements under the shipped elastic laws stay batched, and the
/// large ones (hex8, tet10, hex20) stay unbatched.
TEST(KernelBatch, BatchesWhereTheyPayAndTheOthersSayTheyDoNot) {
  const std::set<std::string> batched_elements = {"tri3", "quad4", "tri6", "quad8", "tet4", "prism6", "pyramid5"};
  const std::set<std::string> unbatched_elements = {"hex8", "tet10", "hex20"};
  const std::set<std::string> batched_laws = {"hooke", "stvk", "stable_neohookean", "neohookean", "corotational"};
  for (const tm_kernel* kernel : registry().kernels()) {
    SCOPED_TRACE(kernel_name(*kernel));
    const bool batched = kernel->batch_width > 0;
    if (batched) EXPECT_TRUE(kernel->batch_width == 2 || kernel->batch_width == 4 || kernel->batch_width == 8);
    // anp kernels are the whole kernels' entry points with a bulk part.
    const std::string split = kernel->split;
    EXPECT_TRUE(!batched || split == "whole" || split == "anp");
    if (split == "anp") {  // the whole kernel's batches on one-point elements, none on an fbar base
      const int whole = registry().get(kernel->law, kernel->element, "whole").batch_width;
      EXPECT_EQ(kernel->batch_width, kernel->quadrature_points == 1 ? whole : 0);
    }
    EXPECT_EQ(kernel->gradient_batch != nullptr, batched);
    EXPECT_EQ(kernel->gradient_hessian_batch != nullptr, batched);
    EXPECT_EQ(kernel->stress_batch != nullptr, batched);
    if (std::string(kernel->split) == "whole" && batched_elements.count(kernel->element) &&
        batched_laws.count(kernel->law))
      EXPECT_TRUE(batched);
    if (unbatched_elements.count(kernel->element)) EXPECT_FALSE(batched);
  }
}

}  // namespace
}  // namespace tmtest
