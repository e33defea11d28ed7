// check_closed_surface, enclosed_volume, bounding_box: is a triangle surface
// the boundary of a volume? Degenerate triangles, open, non-manifold and
// inconsistently oriented edges, non-manifold points and self-intersections
// are refused; components oriented against their nesting are flipped.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "common/vector3.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/surface/surface.hpp"

namespace tensormass {

namespace {

using detail::cross;
using detail::dot;
using detail::norm;
using detail::sub;

std::string file_of(const TriangleSurface& surface) { return surface.source.empty() ? "surface" : surface.source; }

std::string plural(long n, const std::string& word) { return std::to_string(n) + " " + word + (n == 1 ? "" : "s"); }

std::string format_point(const double* xyz) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.9g %.9g %.9g)", xyz[0], xyz[1], xyz[2]);
  return buffer;
}

const double* point_of(const TriangleSurface& surface, int index) {
  return &surface.points[3 * static_cast<std::size_t>(index)];
}
const int* corners_of(const TriangleSurface& surface, int triangle) {
  return &surface.triangles[3 * static_cast<std::size_t>(triangle)];
}

std::string describe_with_corners(const TriangleSurface& surface, int triangle) {
  const int* tri = corners_of(surface, triangle);
  return surface.describe_triangle(triangle) + " with corners " + surface.describe_point(tri[0]) + ", " +
         surface.describe_point(tri[1]) + ", " + surface.describe_point(tri[2]);
}

// ------------------------------------------------------------ basic checks

void check_indices_and_points(const TriangleSurface& surface) {
  const std::string file = file_of(surface);
  if (surface.points.size() % 3 != 0) throw InputError(file + ": the point array is not #P by 3");
  if (surface.triangles.size() % 3 != 0) throw InputError(file + ": the triangle array is not #T by 3");
  if (surface.triangle_count() == 0) throw InputError(file + ": the surface has no triangles");
  const int points = surface.point_count();
  for (int t = 0; t < surface.triangle_count(); ++t)
    for (int c = 0; c < 3; ++c) {
      const int p = corners_of(surface, t)[c];
      if (p < 0 || p >= points)
        throw InputError(file + ": " + surface.describe_triangle(t) + " refers to point " + std::to_string(p) +
                         ", out of range (" + plural(points, "point") + ")");
    }
  for (int p = 0; p < points; ++p)
    for (int a = 0; a < 3; ++a)
      if (!std::isfinite(point_of(surface, p)[a]))
        throw InputError(file + ": point " + std::to_string(p) + " has a non-finite coordinate");
}

void check_degenerate(const TriangleSurface& surface) {
  long count = 0;
  int first = -1;
  bool repeated = false;
  for (int t = 0; t < surface.triangle_count(); ++t) {
    const int* tri = corners_of(surface, t);
    bool bad = tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0];
    const bool same = bad;
    if (!bad) {
      const double *a = point_of(surface, tri[0]), *b = point_of(surface, tri[1]), *c = point_of(surface, tri[2]);
      double ab[3], bc[3], ca[3], n[3];
      sub(b, a, ab);
      sub(c, b, bc);
      sub(a, c, ca);
      cross(ab, bc, n);
      const double longest2 = std::max({dot(ab, ab), dot(bc, bc), dot(ca, ca)});
      bad = !(norm(n) > 1e-12 * longest2);
    }
    if (bad) {
      if (count == 0) {
        first = t;
        repeated = same;
      }
      ++count;
    }
  }
  if (count == 0) return;
  throw InputError(file_of(surface) + ": " + plural(count, "degenerate triangle") + " (zero area), e.g. " +
                   describe_with_corners(surface, first) +
                   (repeated ? " (a point repeated)" : " (corners on one line)"));
}

// ------------------------------------------------------------ edges

struct HalfEdge {
  std::uint64_t key;  // min point << 32 | max point
  int triangle;
  int from, to;  // direction in the triangle
};

std::vector<HalfEdge> sorted_half_edges(const TriangleSurface& surface) {
  std::vector<HalfEdge> edges(surface.triangles.size());
  for (int t = 0; t < surface.triangle_count(); ++t) {
    const int* tri = corners_of(surface, t);
    for (int c = 0; c < 3; ++c) {
      const int a = tri[c], b = tri[(c + 1) % 3];
      const auto lo = static_cast<std::uint64_t>(std::min(a, b)), hi = static_cast<std::uint64_t>(std::max(a, b));
      edges[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(c)] = {(lo << 32) | hi, t, a, b};
    }
  }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.key != y.key ? x.key < y.key : x.triangle < y.triangle;
  });
  return edges;
}

void check_edges(const TriangleSurface& surface, const std::vector<HalfEdge>& edges) {
  const std::string file = file_of(surface);
  long open = 0, non_manifold = 0, flipped = 0;
  std::size_t first_open = 0, first_non_manifold = 0, first_flipped = 0;
  std::size_t non_manifold_size = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    const std::size_t size = j - i;
    if (size == 1) {
      if (open++ == 0) first_open = i;
    } else if (size > 2) {
      if (non_manifold++ == 0) {
        first_non_manifold = i;
        non_manifold_size = size;
      }
    } else if (edges[i].from == edges[i + 1].from) {
      if (flipped++ == 0) first_flipped = i;
    }
    i = j;
  }
  if (open > 0) {
    const HalfEdge& e = edges[first_open];
    throw InputError(file + ": the surface is not closed: " + plural(open, "open edge") +
                     " (used by one triangle only), e.g. the edge from " + surface.describe_point(e.from) + " to " +
                     surface.describe_point(e.to) + " of " + surface.describe_triangle(e.triangle));
  }
  if (non_manifold > 0) {
    const HalfEdge& e = edges[first_non_manifold];
    std::string users;
    for (std::size_t k = 0; k < std::min<std::size_t>(non_manifold_size, 4); ++k)
      users += (k ? ", " : "") + surface.describe_triangle(edges[first_non_manifold + k].triangle);
    if (non_manifold_size > 4) users += ", ...";
    throw InputError(file + ": non-manifold edge from " + surface.describe_point(e.from) + " to " +
                     surface.describe_point(e.to) + ": used by " + std::to_string(non_manifold_size) + " triangles (" +
                     users + "); a closed surface uses each edge twice" +
                     (non_manifold > 1 ? " (" + plural(non_manifold, "such edge") + ")" : std::string()));
  }
  if (flipped > 0) {
    const HalfEdge& e = edges[first_flipped];
    throw InputError(file + ": inconsistent orientation: " + surface.describe_triangle(e.triangle) + " and " +
                     surface.describe_triangle(edges[first_flipped + 1].triangle) + " both run from " +
                     surface.describe_point(e.from) + " to " + surface.describe_point(e.to) +
                     " (neighbours must use their shared edge in opposite directions: one of them is flipped; " +
                     plural(flipped, "such edge") + ")");
  }
}

/// With every edge shared by two consistently oriented triangles, the
/// triangles around each point must form a single fan.
void check_points_manifold(const TriangleSurface& surface) {
  const auto points = static_cast<std::size_t>(surface.point_count());
  std::vector<int> offsets(points + 1, 0);
  for (const int p : surface.triangles) ++offsets[static_cast<std::size_t>(p) + 1];
  for (std::size_t p = 0; p < points; ++p) offsets[p + 1] += offsets[p];
  struct Link {
    int from, to, triangle;
  };
  std::vector<Link> links(surface.triangles.size());
  std::vector<int> fill(offsets.begin(), offsets.end() - 1);
  for (int t = 0; t < surface.triangle_count(); ++t) {
    const int* tri = corners_of(surface, t);
    for (int c = 0; c < 3; ++c)
      links[static_cast<std::size_t>(fill[static_cast<std::size_t>(tri[c])]++)] = {tri[(c + 1) % 3], tri[(c + 2) % 3],
                                                                                   t};
  }
  std::vector<char> visited;
  for (std::size_t p = 0; p < points; ++p) {
    const auto begin = links.begin() + offsets[p], end = links.begin() + offsets[p + 1];
    const auto size = static_cast<std::size_t>(end - begin);
    if (size == 0) continue;
    std::sort(begin, end, [](const Link& x, const Link& y) { return x.from < y.from; });
    // Walk the cycle from the first link: from -> to -> (the link starting at to) ...
    visited.assign(size, 0);
    std::size_t walked = 0, at = 0;
    while (!visited[at]) {
      visited[at] = 1;
      ++walked;
      const int next = begin[static_cast<long>(at)].to;
      const auto found = std::lower_bound(begin, end, next, [](const Link& x, int value) { return x.from < value; });
      if (found == end || found->from != next) break;  // cannot happen on a closed, oriented surface
      at = static_cast<std::size_t>(found - begin);
    }
    if (walked == size) continue;
    std::size_t other = 0;
    while (visited[other]) ++other;
    throw InputError(file_of(surface) + ": non-manifold point: " + surface.describe_point(static_cast<int>(p)) +
                     " joins separate fans of triangles (the surface touches itself there), e.g. " +
                     surface.describe_triangle(begin->triangle) + " and " +
                     surface.describe_triangle(begin[static_cast<long>(other)].triangle));
  }
}

// ------------------------------------------------------------ self-intersection

struct TriangleGeometry {
  const double* v[3];
  double normal[3];  // unit
};

TriangleGeometry geometry(const TriangleSurface& surface, int t) {
  TriangleGeometry g;
  const int* tri = corners_of(surface, t);
  for (int c = 0; c < 3; ++c) g.v[c] = point_of(surface, tri[c]);
  double e1[3], e2[3];
  sub(g.v[1], g.v[0], e1);
  sub(g.v[2], g.v[0], e2);
  cross(e1, e2, g.normal);
  const double length = norm(g.normal);
  for (double& x : g.normal) x /= length;
  return g;
}

/// Signed in-plane distance of x from the line u->v (positive on the left, seen along `normal`).
double side(const double* x, const double* u, const double* v, const double* normal) {
  double e[3], w[3], c[3];
  sub(v, u, e);
  sub(x, u, w);
  cross(e, w, c);
  return dot(c, normal) / norm(e);
}

bool strictly_inside(const double* x, const TriangleGeometry& g, double eps) {
  for (int c = 0; c < 3; ++c)
    if (side(x, g.v[c], g.v[(c + 1) % 3], g.normal) <= eps) return false;
  return true;
}

/// x (in the triangle's plane) inside or on the boundary, within eps.
bool inside_or_on(const double* x, const TriangleGeometry& g, double eps) {
  for (int c = 0; c < 3; ++c)
    if (side(x, g.v[c], g.v[(c + 1) % 3], g.normal) < -eps) return false;
  return true;
}

/// Segment p-q and the triangle, both in the triangle's plane: proper crossing
/// of one of its edges, or p strictly inside.
bool coplanar_cross(const double* p, const double* q, const TriangleGeometry& g, double eps, double* x) {
  if (strictly_inside(p, g, eps)) {
    std::copy_n(p, 3, x);
    return true;
  }
  for (int c = 0; c < 3; ++c) {
    const double *u = g.v[c], *v = g.v[(c + 1) % 3];
    const double s1 = side(p, u, v, g.normal), s2 = side(q, u, v, g.normal);
    if (!((s1 > eps && s2 < -eps) || (s1 < -eps && s2 > eps))) continue;
    const double s3 = side(u, p, q, g.normal), s4 = side(v, p, q, g.normal);
    if (!((s3 > eps && s4 < -eps) || (s3 < -eps && s4 > eps))) continue;
    const double t = s1 / (s1 - s2);
    for (int a = 0; a < 3; ++a) x[a] = p[a] + t * (q[a] - p[a]);
    return true;
  }
  return false;
}

/// Does segment p-q cross the triangle: its ends strictly on both sides of the
/// plane (beyond the tolerance eps), through the triangle or its boundary
/// (an edge through an edge of another triangle also makes the surface cross itself)?
bool segment_crosses(const double* p, const double* q, const TriangleGeometry& g, double eps, double* x) {
  double dp[3], dq[3];
  sub(p, g.v[0], dp);
  sub(q, g.v[0], dq);
  const double hp = dot(dp, g.normal), hq = dot(dq, g.normal);
  if (std::abs(hp) <= eps && std::abs(hq) <= eps) return coplanar_cross(p, q, g, eps, x);
  if (!((hp > eps && hq < -eps) || (hp < -eps && hq > eps))) return false;
  const double t = hp / (hp - hq);
  for (int a = 0; a < 3; ++a) x[a] = p[a] + t * (q[a] - p[a]);
  return inside_or_on(x, g, eps);
}

double longest_edge(const TriangleGeometry& g) {
  double longest = 0;
  for (int c = 0; c < 3; ++c) {
    double e[3];
    sub(g.v[(c + 1) % 3], g.v[c], e);
    longest = std::max(longest, norm(e));
  }
  return longest;
}

/// Triangles t and u (sharing at most one point): does an edge of one cross the other?
bool triangles_cross(const TriangleSurface& surface, int t, int u, double* x) {
  const int* a = corners_of(surface, t);
  const int* b = corners_of(surface, u);
  int shared_a = -1, shared_b = -1, shared = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[i] == b[j]) {
        ++shared;
        shared_a = i;
        shared_b = j;
      }
  if (shared >= 2) return false;
  const TriangleGeometry ga = geometry(surface, t), gb = geometry(surface, u);
  const double eps = 1e-9 * std::max(longest_edge(ga), longest_edge(gb));
  for (int c = 0; c < 3; ++c) {
    // With a shared point, only the edge opposite it can cross the other triangle away from that point.
    if (shared == 1 && c != (shared_a + 1) % 3) continue;
    if (segment_crosses(ga.v[c], ga.v[(c + 1) % 3], gb, eps, x)) return true;
  }
  for (int c = 0; c < 3; ++c) {
    if (shared == 1 && c != (shared_b + 1) % 3) continue;
    if (segment_crosses(gb.v[c], gb.v[(c + 1) % 3], ga, eps, x)) return true;
  }
  return false;
}

void check_self_intersection(const TriangleSurface& surface) {
  const TriangleBVH tree(surface);
  const int count = surface.triangle_count();
  long pairs = 0;
  int first_t = -1, first_u = -1;
  double first_x[3] = {0, 0, 0};
#pragma omp parallel
  {
    long my_pairs = 0;
    int my_t = -1, my_u = -1;
    double my_x[3] = {0, 0, 0};
#pragma omp for schedule(dynamic, 512) nowait
    for (int t = 0; t < count; ++t) {
      const int* tri = corners_of(surface, t);
      double lo[3], hi[3];
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min({point_of(surface, tri[0])[a], point_of(surface, tri[1])[a], point_of(surface, tri[2])[a]});
        hi[a] = std::max({point_of(surface, tri[0])[a], point_of(surface, tri[1])[a], point_of(surface, tri[2])[a]});
      }
      tree.for_each_overlapping(lo, hi, [&](int u) {
        if (u <= t) return;
        double x[3];
        if (!triangles_cross(surface, t, u, x)) return;
        if (my_pairs++ == 0 || t < my_t || (t == my_t && u < my_u)) {
          my_t = t;
          my_u = u;
          std::copy_n(x, 3, my_x);
        }
      });
    }
#pragma omp critical(tensormass_surface_self_intersection)
    {
      pairs += my_pairs;
      if (my_pairs > 0 && (first_t < 0 || my_t < first_t || (my_t == first_t && my_u < first_u))) {
        first_t = my_t;
        first_u = my_u;
        std::copy_n(my_x, 3, first_x);
      }
    }
  }
  if (pairs == 0) return;
  throw InputError(file_of(surface) + ": the surface intersects itself: " + plural(pairs, "pair") +
                   " of triangles cross, e.g. " + describe_with_corners(surface, first_t) + " and " +
                   describe_with_corners(surface, first_u) + ", near " + format_point(first_x));
}

// ------------------------------------------------------------ orientation

/// Six times the signed volume of the tetrahedron (origin, triangle t).
double triangle_volume6(const TriangleSurface& surface, int t, const double* origin) {
  const int* tri = corners_of(surface, t);
  double a[3], b[3], c[3], bc[3];
  sub(point_of(surface, tri[0]), origin, a);
  sub(point_of(surface, tri[1]), origin, b);
  sub(point_of(surface, tri[2]), origin, c);
  cross(b, c, bc);
  return dot(a, bc);
}

int find_root(std::vector<int>& parent, int x) {
  while (parent[static_cast<std::size_t>(x)] != x) {
    parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    x = parent[static_cast<std::size_t>(x)];
  }
  return x;
}

/// Solid angle of triangle abc seen from p (Van Oosterom and Strackee 1983).
double solid_angle(const double* p, const double* a, const double* b, const double* c) {
  double x[3], y[3], z[3], yz[3];
  sub(a, p, x);
  sub(b, p, y);
  sub(c, p, z);
  cross(y, z, yz);
  const double lx = norm(x), ly = norm(y), lz = norm(z);
  const double numerator = dot(x, yz);
  const double denominator = lx * ly * lz + dot(x, y) * lz + dot(x, z) * ly + dot(y, z) * lx;
  return 2 * std::atan2(numerator, denominator);
}

std::vector<std::string> fix_orientation(TriangleSurface& surface, const std::vector<HalfEdge>& edges) {
  const int count = surface.triangle_count();
  std::vector<int> parent(static_cast<std::size_t>(count));
  for (int t = 0; t < count; ++t) parent[static_cast<std::size_t>(t)] = t;
  for (std::size_t i = 0; i + 1 < edges.size(); i += 2) {  // every edge is a pair here
    const int x = find_root(parent, edges[i].triangle), y = find_root(parent, edges[i + 1].triangle);
    if (x != y) parent[static_cast<std::size_t>(std::max(x, y))] = std::min(x, y);
  }
  std::vector<int> component(static_cast<std::size_t>(count), -1), root_component(static_cast<std::size_t>(count), -1);
  int components = 0;
  for (int t = 0; t < count; ++t) {
    int& id = root_component[static_cast<std::size_t>(find_root(parent, t))];
    if (id < 0) id = components++;
    component[static_cast<std::size_t>(t)] = id;
  }
  const SurfaceBox box = bounding_box(surface);
  const double origin[3] = {(box.min[0] + box.max[0]) / 2, (box.min[1] + box.max[1]) / 2,
                            (box.min[2] + box.max[2]) / 2};
  const auto k = static_cast<std::size_t>(components);
  std::vector<double> volume(k, 0.0);
  std::vector<int> size(k, 0), first(k, -1);
  std::vector<SurfaceBox> boxes(k);
  for (auto& b : boxes) {
    b.min.fill(std::numeric_limits<double>::infinity());
    b.max.fill(-std::numeric_limits<double>::infinity());
  }
  for (int t = 0; t < count; ++t) {
    const auto c = static_cast<std::size_t>(component[static_cast<std::size_t>(t)]);
    volume[c] += triangle_volume6(surface, t, origin) / 6;
    if (size[c]++ == 0) first[c] = t;
    for (int corner = 0; corner < 3; ++corner) {
      const double* p = point_of(surface, corners_of(surface, t)[corner]);
      for (int a = 0; a < 3; ++a) {
        boxes[c].min[static_cast<std::size_t>(a)] = std::min(boxes[c].min[static_cast<std::size_t>(a)], p[a]);
        boxes[c].max[static_cast<std::size_t>(a)] = std::max(boxes[c].max[static_cast<std::size_t>(a)], p[a]);
      }
    }
  }
  // Nesting depth: how many other components enclose a point of this one.
  std::vector<int> depth(k, 0);
  if (k > 1) {
    std::vector<std::vector<int>> members(k);
    for (int t = 0; t < count; ++t)
      members[static_cast<std::size_t>(component[static_cast<std::size_t>(t)])].push_back(t);
    for (std::size_t c = 0; c < k; ++c) {
      const int* tri = corners_of(surface, first[c]);
      double probe[3];
      for (int a = 0; a < 3; ++a)
        probe[a] = (point_of(surface, tri[0])[a] + point_of(surface, tri[1])[a] + point_of(surface, tri[2])[a]) / 3;
      for (std::size_t d = 0; d < k; ++d) {
        if (d == c) continue;
        bool contained = true;
        for (std::size_t a = 0; a < 3; ++a)
          contained = contained && boxes[d].min[a] <= boxes[c].min[a] && boxes[c].max[a] <= boxes[d].max[a];
        if (!contained) continue;
        double angle = 0;
        for (const int t : members[d]) {
          const int* other = corners_of(surface, t);
          angle +=
              solid_angle(probe, point_of(surface, other[0]), point_of(surface, other[1]), point_of(surface, other[2]));
        }
        if (std::abs(angle) > 2 * std::numbers::pi) ++depth[c];
      }
    }
  }
  for (std::size_t c = 0; c < k; ++c) {
    double diagonal2 = 0;
    for (std::size_t a = 0; a < 3; ++a)
      diagonal2 += (boxes[c].max[a] - boxes[c].min[a]) * (boxes[c].max[a] - boxes[c].min[a]);
    if (!(std::abs(volume[c]) > 1e-12 * diagonal2 * std::sqrt(diagonal2)))
      throw InputError(
          file_of(surface) + ": " +
          (k == 1 ? std::string("the surface") : "component " + std::to_string(c + 1) + " of " + std::to_string(k)) +
          " (" + plural(size[c], "triangle") + ", e.g. " + surface.describe_triangle(first[c]) +
          ") encloses no volume (flat, or folded onto itself)");
  }
  std::vector<std::string> warnings;
  std::vector<char> flip(k, 0);
  for (std::size_t c = 0; c < k; ++c) {
    const bool want_positive = depth[c] % 2 == 0;
    if ((volume[c] > 0) == want_positive) continue;
    flip[c] = 1;
    char number[32];
    std::snprintf(number, sizeof number, "%.6g", volume[c]);
    if (k == 1) {
      warnings.push_back(file_of(surface) + ": the surface was oriented inward (enclosed volume " + number + "); its " +
                         plural(size[c], "triangle") + " were flipped to face outward");
    } else {
      warnings.push_back(file_of(surface) + ": component " + std::to_string(c + 1) + " of " + std::to_string(k) + " (" +
                         plural(size[c], "triangle") + ", e.g. " + surface.describe_triangle(first[c]) + "), inside " +
                         std::to_string(depth[c]) + " other component" + (depth[c] == 1 ? "" : "s") +
                         ", enclosed volume " + number + ": should face " +
                         (want_positive ? "outward" : "into its cavity") + "; its triangles were flipped");
    }
  }
  for (int t = 0; t < count; ++t)
    if (flip[static_cast<std::size_t>(component[static_cast<std::size_t>(t)])])
      std::swap(surface.triangles[3 * static_cast<std::size_t>(t) + 1],
                surface.triangles[3 * static_cast<std::size_t>(t) + 2]);
  return warnings;
}

}  // namespace

double enclosed_volume(const TriangleSurface& surface) {
  if (surface.triangle_count() == 0) return 0;
  const SurfaceBox box = bounding_box(surface);
  const double origin[3] = {(box.min[0] + box.max[0]) / 2, (box.min[1] + box.max[1]) / 2,
                            (box.min[2] + box.max[2]) / 2};
  double volume = 0;
  for (int t = 0; t < surface.triangle_count(); ++t) volume += triangle_volume6(surface, t, origin);
  return volume / 6;
}

SurfaceBox bounding_box(const TriangleSurface& surface) {
  SurfaceBox box;
  if (surface.point_count() == 0) return box;
  box.min.fill(std::numeric_limits<double>::infinity());
  box.max.fill(-std::numeric_limits<double>::infinity());
  for (int p = 0; p < surface.point_count(); ++p)
    for (std::size_t a = 0; a < 3; ++a) {
      box.min[a] = std::min(box.min[a], surface.points[3 * static_cast<std::size_t>(p) + a]);
      box.max[a] = std::max(box.max[a], surface.points[3 * static_cast<std::size_t>(p) + a]);
    }
  return box;
}

std::vector<std::string> check_closed_surface(TriangleSurface& surface) {
  check_indices_and_points(surface);
  check_degenerate(surface);
  const std::vector<HalfEdge> edges = sorted_half_edges(surface);
  check_edges(surface, edges);
  check_points_manifold(surface);
  check_self_intersection(surface);
  return fix_orientation(surface, edges);
}

}  // namespace tensormass
