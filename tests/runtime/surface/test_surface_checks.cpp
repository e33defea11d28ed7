// check_closed_surface and enclosed_volume: closed surfaces pass; degenerate
// triangles, open, non-manifold and flipped edges, non-manifold points and
// self-intersections are refused; inward components are flipped with a warning.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <string>

#include "support/test_surfaces.hpp"
#include "tensormass/surface/surface.hpp"

namespace {

using namespace surfacetest;
using tensormass::check_closed_surface;
using tensormass::enclosed_volume;

/// Index of the point at p in the surface (-1 if none).
int find_point(const TriangleSurface& surface, const Vec& p) {
  for (int i = 0; i < surface.point_count(); ++i)
    if (surface.points[3 * i] == p[0] && surface.points[3 * i + 1] == p[1] && surface.points[3 * i + 2] == p[2])
      return i;
  return -1;
}

TEST(SurfaceChecks, ClosedBoxPassesAndItsVolumeIsExact) {
  TriangleSurface box = make_box({-1, -1, -1}, {1, 1, 1}, 4);
  EXPECT_EQ(box.triangle_count(), 6 * 4 * 4 * 2);
  EXPECT_TRUE(check_closed_surface(box).empty());
  EXPECT_EQ(enclosed_volume(box), 8.0);
  TriangleSurface shifted = make_box({10, 20, 30}, {12, 21, 34}, 2);
  EXPECT_TRUE(check_closed_surface(shifted).empty());
  EXPECT_EQ(enclosed_volume(shifted), 8.0);
  const tensormass::SurfaceBox bounds = tensormass::bounding_box(shifted);
  EXPECT_EQ(bounds.min, (std::array<double, 3>{10, 20, 30}));
  EXPECT_EQ(bounds.max, (std::array<double, 3>{12, 21, 34}));
}

TEST(SurfaceChecks, IcosphereVolumeWithinDiscretisationError) {
  const double r = 1.5, exact = 4 * std::numbers::pi * r * r * r / 3;
  double previous_error = INFINITY;
  for (int levels = 2; levels <= 5; ++levels) {
    TriangleSurface ball = make_icosphere(r, levels, {0.3, -2, 7});
    EXPECT_TRUE(check_closed_surface(ball).empty());
    const double volume = enclosed_volume(ball);
    const double error = (exact - volume) / exact;
    EXPECT_GT(error, 0) << "an inscribed polyhedron encloses less";
    // Second order: each subdivision divides the error by about 4.
    EXPECT_LT(error, 2.0 / std::pow(4.0, levels)) << levels;
    EXPECT_LT(error, previous_error / 3.5) << levels;
    previous_error = error;
  }
}

TEST(SurfaceChecks, DegenerateTriangles) {
  TriangleSurface repeated = make_box({0, 0, 0}, {1, 1, 1}, 1);
  repeated.triangles[3 * 5 + 2] = repeated.triangles[3 * 5 + 1];
  expect_check_error(repeated, {"1 degenerate triangle", "triangle 5", "repeated"});

  SurfaceMaker maker;
  maker.triangle(maker.point({0, 0, 0}), maker.point({1, 1, 1}), maker.point({3, 3, 3}));
  maker.triangle(maker.point({0, 0, 0}), maker.point({1, 0, 0}), maker.point({0, 1, 0}));
  expect_check_error(maker.surface(), {"degenerate", "triangle 0", "(3 3 3)", "one line"});
}

TEST(SurfaceChecks, OpenBox) {
  TriangleSurface box = make_box({0, 0, 0}, {2, 2, 2}, 2);
  box.source = "box.stl";
  box.triangles.erase(box.triangles.begin() + 3 * 7, box.triangles.begin() + 3 * 8);
  box.patches.pop_back();
  expect_check_error(box, {"box.stl", "not closed", "3 open edges", "used by one triangle"});
}

TEST(SurfaceChecks, NonManifoldEdge) {
  // Two tetrahedra sharing only the edge (0 0 0)-(1 0 0): it is used by four triangles.
  SurfaceMaker maker;
  maker.tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  maker.tetrahedron({0, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 0, -1});
  expect_check_error(maker.surface(), {"non-manifold edge", "(0 0 0)", "(1 0 0)", "used by 4 triangles"});
}

TEST(SurfaceChecks, NonManifoldPoint) {
  // Two tetrahedra touching at the origin only.
  SurfaceMaker maker;
  maker.tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  maker.tetrahedron({0, 0, 0}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1});
  expect_check_error(maker.surface(), {"non-manifold point", "(0 0 0)", "separate fans"});
}

TEST(SurfaceChecks, FlippedTriangle) {
  TriangleSurface box = make_box({0, 0, 0}, {1, 1, 1}, 3);
  flip(box, 40);
  expect_check_error(box, {"inconsistent orientation", "triangle 40", "3 such edges"});
}

TEST(SurfaceChecks, OverlappingTetrahedra) {
  SurfaceMaker maker;
  maker.tetrahedron({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1});
  maker.tetrahedron({0.2, 0.2, 0.2}, {1.2, 0.2, 0.2}, {0.2, 1.2, 0.2}, {0.2, 0.2, 1.2});
  expect_check_error(maker.surface(), {"intersects itself", "pairs of triangles cross", "near ("});
}

TEST(SurfaceChecks, BoxWithAPushedThroughVertex) {
  TriangleSurface box = make_box({-1, -1, -1}, {1, 1, 1}, 4);
  const int top = find_point(box, {0, 0, 1});
  ASSERT_GE(top, 0);
  box.points[3 * top + 2] = -1.5;  // through the bottom face
  expect_check_error(box, {"intersects itself", "triangle", "(0 0 -1.5)"});
  box.points[3 * top + 2] = 0.5;  // pushed in, not through: still a valid (non-convex) surface
  EXPECT_TRUE(check_closed_surface(box).empty());
}

TEST(SurfaceChecks, TouchingComponentsAreNotSelfIntersecting) {
  // Two separate boxes whose faces are 1e-3 apart, and a tiny box next to a big one.
  TriangleSurface surface = make_box({0, 0, 0}, {1, 1, 1}, 3);
  append(surface, make_box({1.001, 0.2, 0.2}, {2, 0.8, 0.8}, 3));
  EXPECT_TRUE(check_closed_surface(surface).empty());
  EXPECT_NEAR(enclosed_volume(surface), 1 + 0.999 * 0.36, 1e-12);
}

TEST(SurfaceChecks, InwardSurfaceIsFlippedWithAWarning) {
  TriangleSurface ball = make_icosphere(1, 3);
  ball.source = "ball.stl";
  flip(ball);
  EXPECT_LT(enclosed_volume(ball), 0);
  const auto warnings = check_closed_surface(ball);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("ball.stl"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("inward"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("1280 triangles"), std::string::npos) << warnings[0];
  EXPECT_GT(enclosed_volume(ball), 0);
  EXPECT_TRUE(check_closed_surface(ball).empty());
}

TEST(SurfaceChecks, HollowBallAndSeparateBodies) {
  // Outer sphere outward, inner sphere facing its cavity: a valid shell.
  TriangleSurface shell = make_icosphere(2, 3);
  TriangleSurface cavity = make_icosphere(1, 3);
  flip(cavity);
  append(shell, cavity);
  const double volume = enclosed_volume(shell);
  EXPECT_NEAR(volume, 4 * std::numbers::pi / 3 * 7, 0.03 * volume);
  TriangleSurface copy = shell;
  EXPECT_TRUE(check_closed_surface(copy).empty());

  // The cavity facing outward: flipped, with a warning naming it.
  TriangleSurface wrong = make_icosphere(2, 3);
  append(wrong, make_icosphere(1, 3));
  auto warnings = check_closed_surface(wrong);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("component 2 of 2"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("inside 1 other"), std::string::npos) << warnings[0];
  EXPECT_NEAR(enclosed_volume(wrong), volume, 1e-9 * volume);

  // Everything inward: both flipped.
  TriangleSurface inverted = shell;
  flip(inverted);
  warnings = check_closed_surface(inverted);
  EXPECT_EQ(warnings.size(), 2u);
  EXPECT_NEAR(enclosed_volume(inverted), volume, 1e-9 * volume);

  // Two separate balls, one inward: only that one is flipped.
  TriangleSurface pair = make_icosphere(1, 2);
  TriangleSurface second = make_icosphere(1, 2, {3, 0, 0});
  flip(second);
  append(pair, second);
  warnings = check_closed_surface(pair);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("inside 0 other"), std::string::npos) << warnings[0];
  EXPECT_GT(enclosed_volume(pair), 0);
}

TEST(SurfaceChecks, FlatDoubleSidedSurfaceEnclosesNoVolume) {
  SurfaceMaker maker;
  const int a = maker.point({0, 0, 0}), b = maker.point({1, 0, 0}), c = maker.point({0, 1, 0});
  maker.triangle(a, b, c);
  maker.triangle(a, c, b);
  expect_check_error(maker.surface(), {"encloses no volume"});
}

TEST(SurfaceChecks, LargeSurfaceIsCheckedQuickly) {
  TriangleSurface torus = make_torus(1, 0.4, 250, 100);  // 50,000 triangles
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(check_closed_surface(torus).empty());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 2.0);  // about 0.05 s in Release; generous for Debug and sanitizers
}

}  // namespace
