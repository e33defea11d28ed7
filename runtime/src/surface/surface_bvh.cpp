// TriangleBVH: an axis-aligned box tree over a surface's triangles, built
// top-down by the surface area heuristic over binned centroids (median split
// along the longest axis where that fails, and below depth 48).
#include <algorithm>
#include <limits>
#include <numeric>

#include "tensormass/surface/surface.hpp"

namespace tensormass {

namespace {

struct Builder {
  const std::vector<double>& boxes;      // #T by 6, surface order
  const std::vector<double>& centroids;  // #T by 3
  std::vector<int>& order;
  std::vector<TriangleBVH::Node>& nodes;
  int leaf_size;

  /// Surface area heuristic over binned centroids: partitions order[begin, end)
  /// at the cheapest of 16 bins per axis; returns the split position (begin
  /// or end when no split separates anything).
  int sah_split(int begin, int end, const double* cmin, const double* cmax) {
    constexpr int kBins = 16;
    struct Bin {
      double min[3], max[3];
      int count;
    };
    double best_cost = std::numeric_limits<double>::infinity();
    int best_axis = -1, best_bin = -1;
    for (int axis = 0; axis < 3; ++axis) {
      const double extent = cmax[axis] - cmin[axis];
      if (!(extent > 0)) continue;
      Bin bins[kBins];
      for (Bin& bin : bins) {
        bin.count = 0;
        for (int a = 0; a < 3; ++a) {
          bin.min[a] = std::numeric_limits<double>::infinity();
          bin.max[a] = -std::numeric_limits<double>::infinity();
        }
      }
      const double scale = kBins / extent;
      for (int k = begin; k < end; ++k) {
        const auto t = static_cast<std::size_t>(order[static_cast<std::size_t>(k)]);
        const int b = std::min(
            kBins - 1, static_cast<int>((centroids[3 * t + static_cast<std::size_t>(axis)] - cmin[axis]) * scale));
        Bin& bin = bins[b];
        ++bin.count;
        for (int a = 0; a < 3; ++a) {
          bin.min[a] = std::min(bin.min[a], boxes[6 * t + static_cast<std::size_t>(a)]);
          bin.max[a] = std::max(bin.max[a], boxes[6 * t + 3 + static_cast<std::size_t>(a)]);
        }
      }
      auto area = [](const double* lo, const double* hi) {
        const double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
        return dx * dy + dy * dz + dz * dx;
      };
      // Right-to-left sweep: areas and counts of bins b.. end.
      double right_area[kBins];
      int right_count[kBins];
      double lo[3], hi[3];
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<double>::infinity();
        hi[a] = -std::numeric_limits<double>::infinity();
      }
      int count = 0;
      for (int b = kBins - 1; b > 0; --b) {
        count += bins[b].count;
        for (int a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], bins[b].min[a]);
          hi[a] = std::max(hi[a], bins[b].max[a]);
        }
        right_area[b] = count ? area(lo, hi) : 0;
        right_count[b] = count;
      }
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<double>::infinity();
        hi[a] = -std::numeric_limits<double>::infinity();
      }
      count = 0;
      for (int b = 0; b + 1 < kBins; ++b) {
        count += bins[b].count;
        for (int a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], bins[b].min[a]);
          hi[a] = std::max(hi[a], bins[b].max[a]);
        }
        if (count == 0 || right_count[b + 1] == 0) continue;
        const double cost = area(lo, hi) * count + right_area[b + 1] * right_count[b + 1];
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_bin = b;
        }
      }
    }
    if (best_axis < 0) return begin;
    const double scale = kBins / (cmax[best_axis] - cmin[best_axis]);
    const auto split = std::partition(order.begin() + begin, order.begin() + end, [&](int t) {
      const int b =
          std::min(kBins - 1,
                   static_cast<int>((centroids[3 * static_cast<std::size_t>(t) + static_cast<std::size_t>(best_axis)] -
                                     cmin[best_axis]) *
                                    scale));
      return b <= best_bin;
    });
    return static_cast<int>(split - order.begin());
  }

  /// Builds the subtree of order[begin, end); returns its node index.
  int build(int begin, int end, int depth) {
    const int index = static_cast<int>(nodes.size());
    nodes.emplace_back();
    TriangleBVH::Node node;
    double cmin[3], cmax[3];
    for (int a = 0; a < 3; ++a) {
      node.min[a] = cmin[a] = std::numeric_limits<double>::infinity();
      node.max[a] = cmax[a] = -std::numeric_limits<double>::infinity();
    }
    for (int k = begin; k < end; ++k) {
      const auto t = static_cast<std::size_t>(order[static_cast<std::size_t>(k)]);
      for (int a = 0; a < 3; ++a) {
        node.min[a] = std::min(node.min[a], boxes[6 * t + static_cast<std::size_t>(a)]);
        node.max[a] = std::max(node.max[a], boxes[6 * t + 3 + static_cast<std::size_t>(a)]);
        cmin[a] = std::min(cmin[a], centroids[3 * t + static_cast<std::size_t>(a)]);
        cmax[a] = std::max(cmax[a], centroids[3 * t + static_cast<std::size_t>(a)]);
      }
    }
    if (end - begin <= leaf_size) {
      node.first = begin;
      node.count = end - begin;
      nodes[static_cast<std::size_t>(index)] = node;
      return index;
    }
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (cmax[a] - cmin[a] > cmax[axis] - cmin[axis]) axis = a;
    // Below kMaxSahDepth the surface area heuristic; deeper (pathological
    // inputs only), median splits keep the depth, and the query stacks, bounded.
    constexpr int kMaxSahDepth = 48;
    int middle = depth < kMaxSahDepth ? sah_split(begin, end, cmin, cmax) : begin;
    if (middle <= begin || middle >= end) {
      middle = begin + (end - begin) / 2;
      std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end, [&](int x, int y) {
        return centroids[3 * static_cast<std::size_t>(x) + static_cast<std::size_t>(axis)] <
               centroids[3 * static_cast<std::size_t>(y) + static_cast<std::size_t>(axis)];
      });
    }
    build(begin, middle, depth + 1);  // first child: index + 1
    node.first = build(middle, end, depth + 1);
    node.count = 0;
    nodes[static_cast<std::size_t>(index)] = node;
    return index;
  }
};

}  // namespace

TriangleBVH::TriangleBVH(const TriangleSurface& surface, int leaf_size) {
  const auto count = static_cast<std::size_t>(surface.triangle_count());
  if (count == 0) return;
  std::vector<double> boxes(6 * count), centroids(3 * count);
  for (std::size_t t = 0; t < count; ++t) {
    for (int a = 0; a < 3; ++a) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0;
      for (int c = 0; c < 3; ++c) {
        const double x =
            surface.points[3 * static_cast<std::size_t>(surface.triangles[3 * t + static_cast<std::size_t>(c)]) +
                           static_cast<std::size_t>(a)];
        lo = std::min(lo, x);
        hi = std::max(hi, x);
        sum += x;
      }
      boxes[6 * t + static_cast<std::size_t>(a)] = lo;
      boxes[6 * t + 3 + static_cast<std::size_t>(a)] = hi;
      centroids[3 * t + static_cast<std::size_t>(a)] = sum / 3;
    }
  }
  order_.resize(count);
  std::iota(order_.begin(), order_.end(), 0);
  nodes_.reserve(4 * count / static_cast<std::size_t>(std::max(1, leaf_size)) + 2);
  Builder builder{boxes, centroids, order_, nodes_, std::max(1, leaf_size)};
  builder.build(0, static_cast<int>(count), 0);
  boxes_.resize(6 * count);
  for (std::size_t k = 0; k < count; ++k)
    std::copy_n(boxes.begin() + static_cast<long>(6 * static_cast<std::size_t>(order_[k])), 6,
                boxes_.begin() + static_cast<long>(6 * k));
}

std::vector<int> TriangleBVH::overlapping(const SurfaceBox& box) const {
  std::vector<int> result;
  for_each_overlapping(box.min.data(), box.max.data(), [&](int t) { result.push_back(t); });
  return result;
}

}  // namespace tensormass
