// SurfaceDistance: signed distance against analytic distances (box, sphere,
// torus, hollow ball), closest() against brute force over all triangles,
// the BVH box query, concurrent queries, and a speed benchmark (disabled).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <thread>
#include <vector>

#include "support/test_surfaces.hpp"
#include "tensormass/io/surface_reader.hpp"
#include "tensormass/surface/surface.hpp"

namespace {

using namespace surfacetest;
using tensormass::SurfaceDistance;

/// Exact signed distance to the box [-h, h].
double box_sdf(const Vec& p, const Vec& h) {
  double outside2 = 0, inside = -INFINITY;
  for (int a = 0; a < 3; ++a) {
    const double q = std::abs(p[a]) - h[a];
    outside2 += std::max(q, 0.0) * std::max(q, 0.0);
    inside = std::max(inside, q);
  }
  return outside2 > 0 ? std::sqrt(outside2) : inside;
}

double torus_sdf(const Vec& p, double big, double small) {
  const double ring = std::hypot(p[0], p[1]) - big;
  return std::hypot(ring, p[2]) - small;
}

std::vector<Vec> random_points(int count, double lo, double hi, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(lo, hi);
  std::vector<Vec> points(count);
  for (Vec& p : points) p = {uniform(random), uniform(random), uniform(random)};
  return points;
}

TEST(SurfaceDistance, BoxMatchesAnalyticEverywhere) {
  const Vec h{1, 0.5, 2};
  const TriangleSurface box = make_box({-h[0], -h[1], -h[2]}, h, 4);
  const SurfaceDistance distance(box);
  std::vector<Vec> points = random_points(2000, -3, 3, 1);
  // Near faces, edges and corners, inside and outside.
  for (const double e : {1e-9, 1e-6, 1e-3, 0.1}) {
    points.push_back({h[0] + e, 0.1, 0.2});
    points.push_back({h[0] - e, 0.1, 0.2});
    points.push_back({h[0] + e, h[1] + e, 0.3});
    points.push_back({h[0] - e, h[1] - e, 0.3});
    points.push_back({h[0] + e, h[1] - e, 0.3});
    points.push_back({h[0] + e, h[1] + e, h[2] + e});
    points.push_back({h[0] - e, h[1] - e, h[2] - e});
    points.push_back({-h[0] - e, -h[1] + e, -h[2] - e});
    points.push_back({0, 0, h[2] + e});
    points.push_back({0.25, 0, -h[2] + e});     // above a grid point of the bottom face
    points.push_back({-0.5, -0.25, h[2] - e});  // below a face vertex shared by six triangles
  }
  points.push_back({0, 0, 0});
  for (const Vec& p : points) {
    const double expected = box_sdf(p, h);
    const double got = distance.signed_distance(p.data());
    EXPECT_NEAR(got, expected, 1e-12) << p[0] << " " << p[1] << " " << p[2];
    EXPECT_EQ(distance.inside(p.data()), expected < 0);
  }
  // On the surface: zero, not inside.
  const Vec on{h[0], 0.1, 0.2};
  EXPECT_EQ(distance.signed_distance(on.data()), 0.0);
  EXPECT_FALSE(distance.inside(on.data()));
}

TEST(SurfaceDistance, IcosphereMatchesRadiusDistance) {
  const double r = 1.0;
  const TriangleSurface ball = make_icosphere(r, 5);  // 20,480 triangles, edge about 0.03
  const SurfaceDistance distance(ball);
  EXPECT_EQ(distance.triangle_count(), 20480);
  // Largest gap between the sphere and the inscribed triangles: r minus the
  // smallest distance from the centre to a triangle's plane (about 3e-4).
  double sagitta = 0;
  for (int t = 0; t < ball.triangle_count(); ++t) {
    const Vec a = corner(ball, t, 0);
    Vec n = cross(minus(corner(ball, t, 1), a), minus(corner(ball, t, 2), a));
    sagitta = std::max(sagitta, r - dot(a, n) / std::sqrt(dot(n, n)));
  }
  EXPECT_LT(sagitta, 4e-4);
  sagitta *= 1 + 1e-9;
  for (const Vec& p : random_points(5000, -1.6, 1.6, 2)) {
    const double radius = std::sqrt(dot(p, p));
    const double got = distance.signed_distance(p.data());
    EXPECT_NEAR(got, radius - r, sagitta) << radius;
    if (std::abs(radius - r) > sagitta) {
      EXPECT_EQ(got < 0, radius < r) << radius;
    }
  }
  // Points on rays through vertices, edge midpoints and face centres, just inside and outside.
  for (int t = 0; t < 200; ++t) {
    const Vec a = corner(ball, t, 0), b = corner(ball, t, 1), c = corner(ball, t, 2);
    const Vec targets[3] = {a,
                            {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2},
                            {(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3, (a[2] + b[2] + c[2]) / 3}};
    for (const Vec& target : targets)
      for (const double scale : {1 - 1e-7, 1 + 1e-7, 0.9, 1.1}) {
        const Vec p{target[0] * scale, target[1] * scale, target[2] * scale};
        EXPECT_EQ(distance.signed_distance(p.data()) < 0, scale < 1) << t << " " << scale;
      }
  }
}

TEST(SurfaceDistance, TorusSignsAndDistances) {
  const TriangleSurface torus = make_torus(1, 0.4, 120, 48);
  const SurfaceDistance distance(torus);
  for (const Vec& p : random_points(4000, -1.6, 1.6, 3)) {
    const double expected = torus_sdf(p, 1, 0.4);
    const double got = distance.signed_distance(p.data());
    EXPECT_NEAR(got, expected, 5e-3);
    if (std::abs(expected) > 5e-3) {
      EXPECT_EQ(got < 0, expected < 0);
    }
  }
}

TEST(SurfaceDistance, CommittedCutBallSigns) {
  // Ball of radius 1 cut flat at z = 0.4 (sharp rim): inside where max(|p| - 1, z - 0.4) < 0.
  if (!fs::exists(data_file("cut_ball.stl"))) GTEST_SKIP() << "cut_ball.stl not present";
  TriangleSurface surface = tensormass::read_surface(data_file("cut_ball.stl"));
  ASSERT_TRUE(tensormass::check_closed_surface(surface).empty());
  const SurfaceDistance distance(surface);
  int tested = 0;
  for (const Vec& p : random_points(4000, -1.3, 1.3, 6)) {
    const double level = std::max(std::sqrt(dot(p, p)) - 1, p[2] - 0.4);
    if (std::abs(level) < 0.02) continue;  // within the discretisation of the sphere
    EXPECT_EQ(distance.inside(p.data()), level < 0) << p[0] << " " << p[1] << " " << p[2];
    ++tested;
  }
  EXPECT_GT(tested, 3000);
  // Near the rim (the circle of radius sqrt(1 - 0.16) at z = 0.4), outside along the bisector.
  const double rim = std::sqrt(1 - 0.16);
  for (int k = 0; k < 36; ++k) {
    const double angle = 2 * std::numbers::pi * k / 36;
    const Vec out{(rim + 0.03) * std::cos(angle), (rim + 0.03) * std::sin(angle), 0.43};
    const Vec in{(rim - 0.05) * std::cos(angle), (rim - 0.05) * std::sin(angle), 0.37};
    EXPECT_FALSE(distance.inside(out.data())) << k;
    EXPECT_TRUE(distance.inside(in.data())) << k;
  }
}

TEST(SurfaceDistance, HollowBallCavityIsOutside) {
  TriangleSurface shell = make_icosphere(2, 4);
  TriangleSurface cavity = make_icosphere(1, 4);
  flip(cavity);
  append(shell, cavity);
  ASSERT_TRUE(tensormass::check_closed_surface(shell).empty());
  const SurfaceDistance distance(shell);
  const Vec in_wall{1.5, 0, 0}, in_cavity{0.2, 0.1, 0}, beyond{0, 2.5, 0};
  EXPECT_NEAR(distance.signed_distance(in_wall.data()), -0.5, 2e-3);
  EXPECT_NEAR(distance.signed_distance(in_cavity.data()), 1 - std::sqrt(0.05), 2e-3);
  EXPECT_NEAR(distance.signed_distance(beyond.data()), 0.5, 2e-3);
}

TEST(SurfaceDistance, ClosestMatchesBruteForce) {
  for (int shape = 0; shape < 3; ++shape) {
    const TriangleSurface surface = shape == 0   ? make_icosphere(1, 3)
                                    : shape == 1 ? make_torus(1, 0.3, 40, 16)
                                                 : make_box({-1, -2, -0.5}, {1, 0, 0.5}, 5);
    const SurfaceDistance distance(surface);
    for (const Vec& p : random_points(400, -2.5, 2.5, 10 + shape)) {
      const auto closest = distance.closest(p.data());
      const double brute = brute_force_distance(surface, p);
      EXPECT_NEAR(closest.distance, brute, 1e-12) << shape;
      // The point lies on the triangle named, at the distance given.
      ASSERT_GE(closest.triangle, 0);
      ASSERT_LT(closest.triangle, surface.triangle_count());
      const Vec q{closest.point[0], closest.point[1], closest.point[2]};
      EXPECT_NEAR(std::sqrt(dot(minus(p, q), minus(p, q))), closest.distance, 1e-12);
      EXPECT_NEAR(triangle_distance(q, corner(surface, closest.triangle, 0), corner(surface, closest.triangle, 1),
                                    corner(surface, closest.triangle, 2)),
                  0, 1e-12);
      const auto signed_closest = distance.signed_closest(p.data());
      EXPECT_EQ(std::abs(signed_closest.distance), closest.distance);
      EXPECT_EQ(signed_closest.triangle, closest.triangle);
    }
  }
}

TEST(SurfaceDistance, BvhBoxQueryMatchesBruteForce) {
  const TriangleSurface torus = make_torus(1, 0.4, 60, 24);
  const tensormass::TriangleBVH tree(torus);
  EXPECT_EQ(tree.order().size(), static_cast<std::size_t>(torus.triangle_count()));
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(-1.5, 1.5), size(0, 0.5);
  for (int q = 0; q < 100; ++q) {
    tensormass::SurfaceBox box;
    for (int a = 0; a < 3; ++a) {
      box.min[a] = uniform(random);
      box.max[a] = box.min[a] + size(random);
    }
    std::vector<int> got = tree.overlapping(box);
    std::sort(got.begin(), got.end());
    std::vector<int> expected;
    for (int t = 0; t < torus.triangle_count(); ++t) {
      bool overlap = true;
      for (int a = 0; a < 3; ++a) {
        const double lo = std::min({corner(torus, t, 0)[a], corner(torus, t, 1)[a], corner(torus, t, 2)[a]});
        const double hi = std::max({corner(torus, t, 0)[a], corner(torus, t, 1)[a], corner(torus, t, 2)[a]});
        overlap = overlap && lo <= box.max[a] && hi >= box.min[a];
      }
      if (overlap) expected.push_back(t);
    }
    EXPECT_EQ(got, expected);
  }
}

TEST(SurfaceDistance, ConcurrentQueriesAgreeWithSerial) {
  const TriangleSurface ball = make_icosphere(1, 4);
  const SurfaceDistance distance(ball);
  const std::vector<Vec> points = random_points(20000, -1.5, 1.5, 4);
  std::vector<double> serial(points.size()), parallel(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) serial[i] = distance.signed_distance(points[i].data());
  std::vector<std::thread> threads;
  const int count = 4;
  for (int k = 0; k < count; ++k)
    threads.emplace_back([&, k] {
      for (std::size_t i = static_cast<std::size_t>(k); i < points.size(); i += count)
        parallel[i] = distance.signed_distance(points[i].data());
    });
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(serial, parallel);
}

TEST(SurfaceDistance, EmptySurfaceAndCopiedGeometry) {
  const TriangleSurface empty;
  const SurfaceDistance none(empty);
  const Vec p{0, 0, 0};
  EXPECT_EQ(none.closest(p.data()).triangle, -1);
  EXPECT_TRUE(std::isinf(none.signed_distance(p.data())));

  // The geometry is copied: the surface may go away.
  auto* box = new TriangleSurface(make_box({-1, -1, -1}, {1, 1, 1}, 2));
  const SurfaceDistance distance(*box);
  delete box;
  EXPECT_DOUBLE_EQ(distance.signed_distance(p.data()), -1.0);
}

// Speed: run with --gtest_also_run_disabled_tests --gtest_filter='*Speed*'.
TEST(SurfaceDistance, DISABLED_Speed) {
  using clock = std::chrono::steady_clock;
  auto seconds = [](clock::time_point start) { return std::chrono::duration<double>(clock::now() - start).count(); };
  {
    TriangleSurface torus = make_torus(1, 0.4, 250, 100);  // 50,000 triangles
    auto start = clock::now();
    const SurfaceDistance distance(torus);
    const double build = seconds(start);
    const std::vector<Vec> points = random_points(1000000, -1.5, 1.5, 7);
    start = clock::now();
    double sum = 0;
    for (const Vec& p : points) sum += distance.signed_distance(p.data());
    const double query = seconds(start);
    // Points within 0.05 of the surface (the octree's refinement band).
    std::vector<Vec> near;
    for (const Vec& p : points)
      if (std::abs(torus_sdf(p, 1, 0.4)) < 0.05) near.push_back(p);
    start = clock::now();
    for (const Vec& p : near) sum += distance.signed_distance(p.data());
    const double near_query = seconds(start);
    std::cout << "torus " << torus.triangle_count() << " triangles: build " << build * 1e3 << " ms; "
              << points.size() / query << " queries/s (uniform in the box), " << near.size() / near_query
              << " queries/s (within 0.05 of the surface); checksum " << sum << "\n";
  }
  for (const int nu : {250, 500}) {
    TriangleSurface torus = make_torus(1, 0.4, nu, 200);
    const auto start = clock::now();
    const auto warnings = tensormass::check_closed_surface(torus);
    std::cout << "check_closed_surface on " << torus.triangle_count() << " triangles: " << seconds(start) * 1e3
              << " ms\n";
    EXPECT_TRUE(warnings.empty());
  }
}

}  // namespace
