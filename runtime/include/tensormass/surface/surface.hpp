/// \file surface.hpp
/// Closed triangle surfaces: the boundary the octree volume mesher fills.
/// The data structure, checking that the surface
/// bounds a volume (closed, manifold, consistently oriented, not
/// self-intersecting), enclosed volume, and fast distance queries through an
/// axis-aligned bounding box tree (BVH). Reading: io/surface_reader.hpp.
///
/// Glossary:
///   point     a surface vertex; index 0 .. point_count()-1
///   triangle  index 0 .. triangle_count()-1; its corners counter-clockwise
///             seen from outside, so that the right-hand normal points out
///   patch     a named part of the surface (STL solid, OBJ group, Gmsh
///             physical group)
#ifndef TENSORMASS_SURFACE_HPP
#define TENSORMASS_SURFACE_HPP

#include <array>
#include <string>
#include <vector>

namespace tensormass {

/// A triangulated surface, as read from a file.
struct TriangleSurface {
  std::vector<double> points;            ///< #P by 3
  std::vector<int> triangles;            ///< #T by 3, counter-clockwise seen from outside
  std::vector<int> patches;              ///< #T: index into patch_names
  std::vector<std::string> patch_names;  ///< named parts ("" when the file names none)
  std::vector<long> source_ids;  ///< #T (or empty): facet number (STL, from 1), line (OBJ) or element tag (Gmsh)
  std::string source_label;      ///< what source_ids count: "facet", "face at line" or "element"
  std::string source;            ///< file it came from, for messages

  int point_count() const { return static_cast<int>(points.size() / 3); }
  int triangle_count() const { return static_cast<int>(triangles.size() / 3); }
  /// "triangle 57 (facet 58 in liver.stl)": for messages.
  std::string describe_triangle(int triangle) const;
  /// "point 12 (0.5 1 -2)": for messages.
  std::string describe_point(int point) const;
};

/// An axis-aligned box.
struct SurfaceBox {
  std::array<double, 3> min{0, 0, 0};
  std::array<double, 3> max{0, 0, 0};
};

/// Checks that the surface bounds a volume and throws InputError with a
/// precise message (file, triangle numbers, coordinates) for:
/// - degenerate triangles (zero area, or a repeated corner),
/// - an open edge (used by one triangle),
/// - a non-manifold edge (used by more than two triangles),
/// - inconsistent orientation (an edge used twice in the same direction),
/// - a non-manifold point (its triangles form several fans: surfaces touching
///   at a point),
/// - self-intersection: two triangles sharing no point (or one point) whose
///   boxes overlap and where an edge of one crosses the other.
/// Several components are allowed (e.g. a hollow ball: the inner one oriented
/// towards the cavity). A component whose orientation disagrees with its
/// nesting (outermost components must enclose a positive volume, one inside
/// them a negative one, and so on) is flipped in place and a warning returned
/// for it; an inward surface of one component is thus flipped with a warning.
/// Returns the warnings (empty when the surface was fine as it was).
std::vector<std::string> check_closed_surface(TriangleSurface& surface);

/// Signed volume enclosed (divergence theorem), positive for an outward
/// (counter-clockwise seen from outside) closed surface.
double enclosed_volume(const TriangleSurface& surface);

/// Bounding box of the surface's points (zero box when it has none).
SurfaceBox bounding_box(const TriangleSurface& surface);

/// Bounding volume hierarchy over a surface's triangles: a binary tree of
/// axis-aligned boxes, built once top-down by the surface area heuristic
/// (binned triangle centroids; median splits below depth 48, so the depth
/// stays under 80). Read-only after construction: safe to query from several
/// threads at once.
class TriangleBVH {
 public:
  /// Internal node: its first child is the next node, `first` the other, `count` 0.
  /// Leaf: triangles order()[first .. first+count).
  struct Node {
    double min[3];
    double max[3];
    int first = 0;  ///< leaf: offset into order(); internal: index of the second child
    int count = 0;  ///< leaf: number of triangles (> 0); internal: 0
  };

  TriangleBVH() = default;
  /// Builds the tree over all triangles of `surface` (kept by index only).
  explicit TriangleBVH(const TriangleSurface& surface, int leaf_size = 4);

  /// #nodes, root first (empty when the surface has no triangle).
  const std::vector<Node>& nodes() const { return nodes_; }
  /// #T: triangle indices in leaf order.
  const std::vector<int>& order() const { return order_; }
  /// #T by 6, leaf order: each triangle's box (min x y z, max x y z).
  const std::vector<double>& boxes() const { return boxes_; }

  /// Calls visit(triangle) for every triangle whose box overlaps the closed
  /// box [min, max].
  template <class Visit>
  void for_each_overlapping(const double min[3], const double max[3], Visit&& visit) const;
  /// The triangles whose boxes overlap `box`, in leaf order.
  std::vector<int> overlapping(const SurfaceBox& box) const;

 private:
  std::vector<Node> nodes_;
  std::vector<int> order_;
  std::vector<double> boxes_;
};

/// Distance queries against a surface: a BVH over its triangles, built once,
/// with nearest-first traversal and box-distance pruning. The surface's
/// geometry is copied: the object does not refer to the surface after
/// construction. All queries are const and use no shared scratch, so they
/// may run from several (OpenMP) threads at once.
class SurfaceDistance {
 public:
  explicit SurfaceDistance(const TriangleSurface& surface);

  /// Closest point on the surface and the triangle it lies on;
  /// `distance` is unsigned in closest(), signed in signed_closest().
  /// For a surface without triangles: distance +infinity, triangle -1.
  struct Closest {
    double distance;
    std::array<double, 3> point;
    int triangle;
  };

  /// Signed distance: negative inside, positive outside, 0 on the surface.
  /// The sign comes from the angle-weighted pseudonormal of the closest
  /// feature (face, edge or vertex; Baerentzen and Aanaes 2005): exact on a
  /// closed, manifold, outward-oriented surface (see check_closed_surface).
  double signed_distance(const double point[3]) const { return signed_closest(point).distance; }
  /// Closest point, its triangle and the unsigned distance.
  Closest closest(const double point[3]) const;
  /// As closest(), with the signed distance.
  Closest signed_closest(const double point[3]) const;
  bool inside(const double point[3]) const { return signed_distance(point) < 0; }

  const TriangleBVH& tree() const { return tree_; }
  int triangle_count() const { return static_cast<int>(triangle_ids_.size()); }

 private:
  struct Hit {
    double distance2;
    double point[3];
    int slot;     ///< triangle position in leaf order
    int feature;  ///< closest feature: face, a vertex or an edge (surface_distance.cpp)
  };
  Hit nearest(const double point[3]) const;

  TriangleBVH tree_;
  std::vector<double> corners_;       ///< #T by 9: the three corners of each triangle, leaf order
  std::vector<int> triangle_ids_;     ///< #T: surface triangle of each leaf-order slot
  std::vector<double> face_normals_;  ///< #T by 3, leaf order: unit face normals
  std::vector<double> edge_normals_;  ///< #T by 9, leaf order: edges 01, 12, 20: sum of the adjacent unit face normals
  std::vector<double> vertex_normals_;  ///< #T by 9, leaf order: angle-weighted pseudonormal at each corner
};

// --- template implementation --------------------------------------------------

template <class Visit>
void TriangleBVH::for_each_overlapping(const double min[3], const double max[3], Visit&& visit) const {
  if (nodes_.empty()) return;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node* node = &nodes_[static_cast<std::size_t>(stack[--top])];
    for (;;) {
      if (node->min[0] > max[0] || node->max[0] < min[0] || node->min[1] > max[1] || node->max[1] < min[1] ||
          node->min[2] > max[2] || node->max[2] < min[2])
        break;
      if (node->count > 0) {
        for (int k = node->first; k < node->first + node->count; ++k) {
          const double* box = &boxes_[6 * static_cast<std::size_t>(k)];
          if (box[0] <= max[0] && box[3] >= min[0] && box[1] <= max[1] && box[4] >= min[1] && box[2] <= max[2] &&
              box[5] >= min[2])
            visit(order_[static_cast<std::size_t>(k)]);
        }
        break;
      }
      const int self = static_cast<int>(node - nodes_.data());
      stack[top++] = node->first;
      node = &nodes_[static_cast<std::size_t>(self + 1)];
    }
  }
}

}  // namespace tensormass

#endif
