/// \file test_surfaces.hpp
/// Helpers of the surface tests (surface reader, checks, distance): the
/// committed test surfaces (tests/data/surfaces), closed test surfaces built
/// in memory (subdivided box, icosphere, torus, tetrahedra), STL writers,
/// InputError matchers and a brute-force point-triangle distance.
#ifndef TENSORMASS_TESTS_SUPPORT_TEST_SURFACES_HPP
#define TENSORMASS_TESTS_SUPPORT_TEST_SURFACES_HPP

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/surface_reader.hpp"
#include "tensormass/surface/surface.hpp"

namespace surfacetest {

namespace fs = std::filesystem;
using tensormass::TriangleSurface;
using Vec = std::array<double, 3>;

inline std::string data_file(const std::string& name) {
  return std::string(TENSORMASS_SOURCE_DIR) + "/tests/data/surfaces/" + name;
}

/// Expects read_surface(path) to throw InputError whose message contains every part.
inline void expect_read_error(const std::string& path, const std::vector<std::string>& parts) {
  try {
    (void)tensormass::read_surface(path);
    ADD_FAILURE() << "no InputError for " << path;
  } catch (const tensormass::InputError& error) {
    test_support::expect_contains(error.what(), parts);
  }
}

/// Expects check_closed_surface to throw InputError whose message contains every part.
inline void expect_check_error(TriangleSurface surface, const std::vector<std::string>& parts) {
  try {
    (void)tensormass::check_closed_surface(surface);
    ADD_FAILURE() << "no InputError";
  } catch (const tensormass::InputError& error) {
    test_support::expect_contains(error.what(), parts);
  }
}

/// Builds surfaces point by point (exact-coordinate sharing) and triangle by triangle.
class SurfaceMaker {
 public:
  int point(const Vec& p) {
    const auto [it, added] = index_.try_emplace(p, surface_.point_count());
    if (added) surface_.points.insert(surface_.points.end(), p.begin(), p.end());
    return it->second;
  }
  void triangle(int a, int b, int c, int patch = 0) {
    surface_.triangles.insert(surface_.triangles.end(), {a, b, c});
    surface_.patches.push_back(patch);
    if (surface_.patch_names.size() <= static_cast<std::size_t>(patch)) surface_.patch_names.resize(patch + 1);
  }
  Vec at(int p) const { return {surface_.points[3 * p], surface_.points[3 * p + 1], surface_.points[3 * p + 2]}; }
  /// The four faces of the tetrahedron abcd, each oriented away from its centroid.
  void tetrahedron(const Vec& a, const Vec& b, const Vec& c, const Vec& d) {
    const Vec corners[4] = {a, b, c, d};
    Vec centre{0, 0, 0};
    for (const Vec& p : corners)
      for (int i = 0; i < 3; ++i) centre[i] += p[i] / 4;
    const int faces[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
    for (const auto& f : faces) {
      const Vec &p = corners[f[0]], &q = corners[f[1]], &r = corners[f[2]];
      const Vec u{q[0] - p[0], q[1] - p[1], q[2] - p[2]}, v{r[0] - p[0], r[1] - p[1], r[2] - p[2]};
      const Vec n{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
      const double out = n[0] * (p[0] - centre[0]) + n[1] * (p[1] - centre[1]) + n[2] * (p[2] - centre[2]);
      if (out > 0) triangle(point(p), point(q), point(r));
      else triangle(point(p), point(r), point(q));
    }
  }
  TriangleSurface& surface() { return surface_; }

 private:
  TriangleSurface surface_;
  std::map<Vec, int> index_;
};

/// The unit corner tetrahedron, faces outward; triangles 0-1 in patch 0, 2-3 in patch 1.
inline TriangleSurface unit_tetrahedron() {
  TriangleSurface s;
  s.points = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  s.triangles = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  s.patches = {0, 0, 1, 1};
  s.patch_names = {"bottom", "sides"};
  return s;
}

/// The box [lo, hi], each face an n by n grid of squares cut in two triangles, outward.
inline TriangleSurface make_box(const Vec& lo, const Vec& hi, int n) {
  SurfaceMaker maker;
  auto grid_point = [&](int i, int j, int k) {
    const int ijk[3] = {i, j, k};
    Vec p;
    for (int a = 0; a < 3; ++a) p[a] = lo[a] + (hi[a] - lo[a]) * ijk[a] / n;
    return maker.point(p);
  };
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;  // e_b x e_c = e_a
    for (const int side : {0, n}) {
      for (int u = 0; u < n; ++u)
        for (int v = 0; v < n; ++v) {
          auto at = [&](int du, int dv) {
            int ijk[3];
            ijk[a] = side;
            ijk[b] = u + du;
            ijk[c] = v + dv;
            return grid_point(ijk[0], ijk[1], ijk[2]);
          };
          const int p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
          if (side == n) {
            maker.triangle(p00, p10, p11);
            maker.triangle(p00, p11, p01);
          } else {
            maker.triangle(p00, p11, p10);
            maker.triangle(p00, p01, p11);
          }
        }
    }
  }
  maker.surface().patch_names = {""};
  return std::move(maker.surface());
}

/// Icosphere: an icosahedron subdivided `levels` times (20 * 4^levels triangles), points on the sphere.
inline TriangleSurface make_icosphere(double radius, int levels, const Vec& centre = {0, 0, 0}) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Vec> points = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                             {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec& p : points) {
    const double length = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (double& x : p) x /= length;
  }
  std::vector<std::array<int, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                           {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                           {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                           {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> middle;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto found = middle.find(key);
      if (found != middle.end()) return found->second;
      Vec m;
      for (int i = 0; i < 3; ++i) m[i] = (points[a][i] + points[b][i]) / 2;
      const double length = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
      for (double& x : m) x /= length;
      points.push_back(m);
      return middle[key] = static_cast<int>(points.size()) - 1;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& f : faces) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    faces = std::move(finer);
  }
  TriangleSurface surface;
  for (const Vec& p : points)
    for (int i = 0; i < 3; ++i) surface.points.push_back(centre[i] + radius * p[i]);
  for (const auto& f : faces) surface.triangles.insert(surface.triangles.end(), f.begin(), f.end());
  surface.patches.assign(faces.size(), 0);
  surface.patch_names = {""};
  return surface;
}

/// Torus around z: radii big (centre circle) and small (tube), nu by nv quads, outward.
inline TriangleSurface make_torus(double big, double small, int nu, int nv) {
  TriangleSurface surface;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * std::numbers::pi * i / nu, v = 2 * std::numbers::pi * j / nv;
      const double r = big + small * std::cos(v);
      surface.points.insert(surface.points.end(), {r * std::cos(u), r * std::sin(u), small * std::sin(v)});
    }
  auto id = [&](int i, int j) { return (i % nu) * nv + (j % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      surface.triangles.insert(surface.triangles.end(), {a, b, c, a, c, d});
    }
  surface.patches.assign(surface.triangles.size() / 3, 0);
  surface.patch_names = {""};
  return surface;
}

/// Reverses every triangle (or only triangle `only` when given).
inline void flip(TriangleSurface& surface, int only = -1) {
  for (int t = 0; t < surface.triangle_count(); ++t)
    if (only < 0 || t == only) std::swap(surface.triangles[3 * t + 1], surface.triangles[3 * t + 2]);
}

/// Appends `other` (points and triangles) to `surface`.
inline void append(TriangleSurface& surface, const TriangleSurface& other) {
  const int offset = surface.point_count();
  surface.points.insert(surface.points.end(), other.points.begin(), other.points.end());
  for (const int p : other.triangles) surface.triangles.push_back(p + offset);
  surface.patches.insert(surface.patches.end(), other.patches.begin(), other.patches.end());
}

// ---------------------------------------------------------------- file writers

inline std::string format(double x) {
  std::ostringstream out;
  out.precision(17);
  out << x;
  return out.str();
}

/// ASCII STL: one solid per patch name.
inline std::string ascii_stl(const TriangleSurface& surface) {
  std::string text;
  for (std::size_t patch = 0; patch < std::max<std::size_t>(1, surface.patch_names.size()); ++patch) {
    const std::string name = patch < surface.patch_names.size() ? surface.patch_names[patch] : "";
    text += "solid " + name + "\n";
    for (int t = 0; t < surface.triangle_count(); ++t) {
      if (!surface.patches.empty() && surface.patches[t] != static_cast<int>(patch)) continue;
      text += "  facet normal 0 0 0\n    outer loop\n";
      for (int c = 0; c < 3; ++c) {
        const int p = surface.triangles[3 * t + c];
        text += "      vertex " + format(surface.points[3 * p]) + " " + format(surface.points[3 * p + 1]) + " " +
                format(surface.points[3 * p + 2]) + "\n";
      }
      text += "    endloop\n  endfacet\n";
    }
    text += "endsolid " + name + "\n";
  }
  return text;
}

/// Binary STL with the given 80-byte header text.
inline std::string binary_stl(const TriangleSurface& surface, const std::string& header) {
  std::string data(80, ' ');
  std::copy_n(header.begin(), std::min<std::size_t>(80, header.size()), data.begin());
  auto put32 = [&](std::uint32_t value) {
    char bytes[4];
    std::memcpy(bytes, &value, 4);
    data.append(bytes, 4);
  };
  auto put_float = [&](float value) {
    std::uint32_t bits;
    std::memcpy(&bits, &value, 4);
    put32(bits);
  };
  put32(static_cast<std::uint32_t>(surface.triangle_count()));
  for (int t = 0; t < surface.triangle_count(); ++t) {
    for (int i = 0; i < 3; ++i) put_float(0);
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < 3; ++i) put_float(static_cast<float>(surface.points[3 * surface.triangles[3 * t + c] + i]));
    data.append(2, '\0');
  }
  return data;
}

// ---------------------------------------------------------------- brute force

inline double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec minus(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// Distance from p to segment ab.
inline double segment_distance(const Vec& p, const Vec& a, const Vec& b) {
  const Vec ab = minus(b, a);
  const double s = std::clamp(dot(minus(p, a), ab) / dot(ab, ab), 0.0, 1.0);
  const Vec q{a[0] + s * ab[0], a[1] + s * ab[1], a[2] + s * ab[2]};
  return std::sqrt(dot(minus(p, q), minus(p, q)));
}

/// Distance from p to triangle abc: the plane when the projection falls inside, else the nearest edge.
inline double triangle_distance(const Vec& p, const Vec& a, const Vec& b, const Vec& c) {
  const Vec n = cross(minus(b, a), minus(c, a));
  const double n2 = dot(n, n);
  const double h = dot(minus(p, a), n) / n2;
  const Vec q{p[0] - h * n[0], p[1] - h * n[1], p[2] - h * n[2]};
  const bool inside = dot(cross(minus(b, a), minus(q, a)), n) >= 0 && dot(cross(minus(c, b), minus(q, b)), n) >= 0 &&
                      dot(cross(minus(a, c), minus(q, c)), n) >= 0;
  if (inside) return std::abs(h) * std::sqrt(n2);
  return std::min({segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
}

inline Vec corner(const TriangleSurface& s, int t, int c) {
  const int p = s.triangles[3 * t + c];
  return {s.points[3 * p], s.points[3 * p + 1], s.points[3 * p + 2]};
}

inline double brute_force_distance(const TriangleSurface& s, const Vec& p) {
  double best = INFINITY;
  for (int t = 0; t < s.triangle_count(); ++t)
    best = std::min(best, triangle_distance(p, corner(s, t, 0), corner(s, t, 1), corner(s, t, 2)));
  return best;
}

}  // namespace surfacetest

#endif
