// Hex-dominant mixed meshes from a closed surface: octree core with
// transition patterns, Gmsh tetrahedra in the gap (see octree_mesher.hpp).
#include "tensormass/meshing/octree_mesher.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <queue>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "common/vector3.hpp"
#include "meshing/gap_mesher.hpp"
#include "meshing/octree.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/mesh/mesh_quality.hpp"

namespace tensormass {
namespace {

using detail::cell_key;
using detail::cell_of_key;
using detail::lattice_key;
using detail::Octree;
using detail::OctreeCell;
using Key = std::uint64_t;
using Lattice = std::array<std::int64_t, 3>;
constexpr Key kApexFlag = Key{1} << 63;               ///< node key of a cap apex: its face centre's key with this bit
constexpr double kHalfDiagonal = 0.8660254037844386;  // sqrt(3) / 2
/// Largest angle between a point's normal (the prisms' extrusion direction)
/// and the normal of a triangle around it: cos 60 deg.
constexpr double kMinimumLayerAlignment = 0.5;

Key key_of(const Lattice& p) { return lattice_key(p[0], p[1], p[2]); }
Lattice lattice_of(Key key) {
  return {static_cast<std::int64_t>((key >> 42) & 0x1FFFFF), static_cast<std::int64_t>((key >> 21) & 0x1FFFFF),
          static_cast<std::int64_t>(key & 0x1FFFFF)};
}

/// A piece of a core cell's face: a quadrilateral or a triangle, its nodes
/// counter-clockwise seen from outside the cell.
struct FacePiece {
  std::vector<Key> nodes;
  bool exposed = false;  ///< no core cell on the other side: part of the core's boundary
};

/// What lies across a face of a core cell.
enum class Across { same, coarser, finer, none };

class CoreMesher {
 public:
  CoreMesher(const TriangleSurface& surface, const OctreeMeshOptions& options, OctreeMeshReport& report);
  Mesh run();

 private:
  void stage(const std::string& name);
  void build_octree();
  void classify();
  void clean();
  int remove_partial_faces();
  int remove_non_manifold();
  int keep_largest_component();
  void cut();
  void fill_gap();
  std::vector<std::array<int, 3>> add_boundary_layer(const std::vector<std::array<int, 3>>& outer);
  bool try_boundary_layer(double thickness, const std::vector<double>& normals, std::vector<int>& prisms,
                          std::vector<double>& offset_points, std::string& failure) const;
  double layer_thickness() const {
    return options_.boundary_layer * options_.size / static_cast<double>(1 << options_.surface_levels);
  }
  Mesh assemble();

  // Faces of core cells.
  std::vector<FacePiece> face_pieces(const OctreeCell& cell, int face, bool& plain) const;
  Across across(const OctreeCell& cell, int face, int& core_count, std::vector<Key>* core_neighbours) const;
  std::array<Lattice, 8> face_ring(const OctreeCell& cell, int face) const;
  Lattice face_centre(const OctreeCell& cell, int face) const;
  bool is_core(const OctreeCell& cell) const { return core_.count(cell_key(cell)) != 0; }
  void refresh_present();
  std::vector<std::array<Key, 3>> exposed_triangles() const;
  std::vector<Key> sorted_core() const;

  // Output cells.
  int node(Key key);
  void add_tet(int a, int b, int c, int d);
  void add_pyramid(std::array<int, 4> base, int apex);
  std::array<double, 3> point(int n) const { return {positions_[3 * n], positions_[3 * n + 1], positions_[3 * n + 2]}; }

  const TriangleSurface& surface_;
  const OctreeMeshOptions& options_;
  OctreeMeshReport& report_;
  SurfaceDistance distance_;
  std::unique_ptr<Octree> tree_;
  std::unordered_set<Key> core_;     ///< cell keys of the core
  std::unordered_set<Key> present_;  ///< lattice keys of the core cells' corners
  std::chrono::steady_clock::time_point stage_start_;
  std::string stage_name_;

  std::unordered_map<Key, int> node_of_key_;
  std::vector<double> positions_;
  std::vector<int> hexes_, pyramids_, tets_, prisms_;
  std::vector<std::array<int, 3>> inner_triangles_;
  int surface_first_node_ = 0;
};

CoreMesher::CoreMesher(const TriangleSurface& surface, const OctreeMeshOptions& options, OctreeMeshReport& report)
    : surface_(surface), options_(options), report_(report), distance_(surface) {}

void CoreMesher::stage(const std::string& name) {
  const auto now = std::chrono::steady_clock::now();
  if (!stage_name_.empty())
    report_.stage_seconds.emplace_back(stage_name_, std::chrono::duration<double>(now - stage_start_).count());
  stage_name_ = name;
  stage_start_ = now;
  if (!name.empty() && options_.on_stage) options_.on_stage(name);
}

Mesh CoreMesher::run() {
  stage("refine");
  build_octree();
  stage("classify");
  classify();
  stage("clean");
  clean();
  stage("cut");
  cut();
  stage("gap");
  fill_gap();
  stage("groups");
  Mesh mesh = assemble();
  stage("");
  return mesh;
}

// --- 1-2. Octree --------------------------------------------------------------

int depth_for_size(double base, double size) {
  int depth = 0;
  while (base / static_cast<double>(1 << depth) > size * (1 + 1e-9) && depth < 12) ++depth;
  return depth;
}

void CoreMesher::build_octree() {
  const double size = options_.size;
  int max_depth = options_.surface_levels;
  std::vector<int> roi_depth;
  for (const RegionOfInterest& roi : options_.regions_of_interest) {
    roi_depth.push_back(depth_for_size(size, roi.size));
    max_depth = std::max(max_depth, roi_depth.back());
  }
  const SurfaceBox box = bounding_box(surface_);
  std::array<double, 3> origin{};
  std::array<int, 3> counts{};
  for (int a = 0; a < 3; ++a) {
    counts[a] = static_cast<int>(std::ceil((box.max[a] - box.min[a]) / size)) + 2;
    origin[a] = 0.5 * (box.min[a] + box.max[a]) - 0.5 * counts[a] * size;
  }
  try {
    tree_ = std::make_unique<Octree>(origin, size, counts, max_depth);
  } catch (const std::invalid_argument&) {
    throw InputError("mesh: --size " + std::to_string(size) + " with " + std::to_string(max_depth) +
                     " refinement levels needs too many cells for " + surface_.source + " (" +
                     std::to_string(counts[0]) + " x " + std::to_string(counts[1]) + " x " + std::to_string(counts[2]) +
                     " base cells); use a larger size or fewer levels");
  }
  tree_->refine([&](const std::vector<OctreeCell>& cells, std::vector<char>& refine, std::vector<char>& drop) {
    const long n = static_cast<long>(cells.size());
#pragma omp parallel for schedule(dynamic, 256)
    for (long c = 0; c < n; ++c) {
      const OctreeCell& cell = cells[c];
      const double s = tree_->cell_size(cell.depth);
      const auto centre = tree_->centre(cell);
      const double sd = distance_.signed_distance(centre.data());
      if (sd > kHalfDiagonal * s) {  // entirely outside
        drop[c] = 1;
        continue;
      }
      bool split = cell.depth < options_.surface_levels && sd > -(kHalfDiagonal + 1.0) * s;
      for (std::size_t r = 0; r < roi_depth.size() && !split; ++r) {
        const RegionOfInterest& roi = options_.regions_of_interest[r];
        const double dx = centre[0] - roi.centre[0], dy = centre[1] - roi.centre[1], dz = centre[2] - roi.centre[2];
        split = cell.depth < roi_depth[r] && std::sqrt(dx * dx + dy * dy + dz * dz) <= roi.radius + kHalfDiagonal * s;
      }
      refine[c] = split;
    }
  });
  stage("balance");
  tree_->balance();
  report_.leaves = static_cast<int>(tree_->leaves().size());
}

// --- 3. Classify --------------------------------------------------------------

void CoreMesher::classify() {
  // The 15 sample points of each leaf: corners, face centres, centre.
  std::vector<Key> samples;
  std::vector<Key> leaves(tree_->leaves().begin(), tree_->leaves().end());
  std::sort(leaves.begin(), leaves.end());
  const auto sample_points = [&](const OctreeCell& cell, auto&& visit) {
    const Lattice o = tree_->lattice_origin(cell);
    const std::int64_t s = tree_->lattice_span(cell.depth), h = s / 2;
    for (std::int64_t x = 0; x <= s; x += h)
      for (std::int64_t y = 0; y <= s; y += h)
        for (std::int64_t z = 0; z <= s; z += h) {
          const int halves = (x == h) + (y == h) + (z == h);
          if (halves == 0 || halves == 2 || halves == 3) visit(Lattice{o[0] + x, o[1] + y, o[2] + z});
        }
  };
  for (Key leaf : leaves) sample_points(cell_of_key(leaf), [&](const Lattice& p) { samples.push_back(key_of(p)); });
  std::sort(samples.begin(), samples.end());
  samples.erase(std::unique(samples.begin(), samples.end()), samples.end());
  std::vector<double> sd(samples.size());
  const long n = static_cast<long>(samples.size());
#pragma omp parallel for schedule(dynamic, 512)
  for (long k = 0; k < n; ++k) {
    const Lattice p = lattice_of(samples[k]);
    const auto x = tree_->position(p[0], p[1], p[2]);
    sd[k] = distance_.signed_distance(x.data());
  }
  const auto sd_at = [&](const Lattice& p) {
    return sd[std::lower_bound(samples.begin(), samples.end(), key_of(p)) - samples.begin()];
  };
  for (Key leaf : leaves) {
    const OctreeCell cell = cell_of_key(leaf);
    const double limit = -options_.margin * tree_->cell_size(cell.depth) - layer_thickness();
    bool inside = true;
    sample_points(cell, [&](const Lattice& p) { inside = inside && sd_at(p) <= limit; });
    if (inside) core_.insert(leaf);
  }
}

// --- Faces ----------------------------------------------------------------------

/// Face f of a cell: axis f / 2, on its minimum (f even) or maximum side.
/// The ring: corners and edge midpoints, counter-clockwise seen from outside.
std::array<Lattice, 8> CoreMesher::face_ring(const OctreeCell& cell, int face) const {
  const int a = face / 2, b = (a + 1) % 3, c = (a + 2) % 3;
  const bool max_side = face % 2;
  const Lattice o = tree_->lattice_origin(cell);
  const std::int64_t s = tree_->lattice_span(cell.depth), h = s / 2;
  static constexpr int kU[8] = {0, 1, 2, 2, 2, 1, 0, 0}, kV[8] = {0, 0, 0, 1, 2, 2, 2, 1};
  std::array<Lattice, 8> ring{};
  for (int r = 0; r < 8; ++r) {
    const int slot = max_side ? r : (8 - r) % 8;  // reversed on the minimum side
    Lattice p = o;
    p[a] += max_side ? s : 0;
    p[b] += kU[slot] * h;
    p[c] += kV[slot] * h;
    ring[r] = p;
  }
  return ring;
}

Lattice CoreMesher::face_centre(const OctreeCell& cell, int face) const {
  const int a = face / 2;
  const Lattice o = tree_->lattice_origin(cell);
  const std::int64_t s = tree_->lattice_span(cell.depth);
  Lattice p{o[0] + s / 2, o[1] + s / 2, o[2] + s / 2};
  p[a] = o[a] + (face % 2 ? s : 0);
  return p;
}

/// The neighbour region across `face`; core_count counts the core cells
/// touching the face there (for `finer`: among the 4 children facing it).
Across CoreMesher::across(const OctreeCell& cell, int face, int& core_count, std::vector<Key>* core_neighbours) const {
  const int a = face / 2;
  const int step = face % 2 ? 1 : -1;
  OctreeCell next = cell;
  next.index[a] += step;
  core_count = 0;
  const auto count = [&](const OctreeCell& c) {
    if (!is_core(c)) return;
    ++core_count;
    if (core_neighbours) core_neighbours->push_back(cell_key(c));
  };
  if (!tree_->in_grid(next)) return Across::none;
  if (tree_->is_leaf(next)) {
    count(next);
    return Across::same;
  }
  OctreeCell leaf;
  if (tree_->find_containing_leaf(next, leaf)) {
    count(leaf);
    return Across::coarser;
  }
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  for (int u = 0; u < 2; ++u)
    for (int v = 0; v < 2; ++v) {
      OctreeCell child{cell.depth + 1, {2 * next.index[0], 2 * next.index[1], 2 * next.index[2]}};
      child.index[a] += step > 0 ? 0 : 1;
      child.index[b] += u;
      child.index[c] += v;
      count(child);
    }
  return Across::finer;
}

std::vector<FacePiece> CoreMesher::face_pieces(const OctreeCell& cell, int face, bool& plain) const {
  const std::array<Lattice, 8> ring = face_ring(cell, face);
  const Key centre = key_of(face_centre(cell, face));
  bool any_mid = false;
  std::vector<Key> polygon;  // corners and present midpoints
  for (int r = 0; r < 8; ++r) {
    const Key k = key_of(ring[r]);
    if (r % 2 == 0 || present_.count(k)) polygon.push_back(k);
    if (r % 2 == 1 && present_.count(k)) any_mid = true;
  }
  int core_count = 0;
  const Across kind = across(cell, face, core_count, nullptr);
  const auto corners = [&] {
    return std::vector<Key>{key_of(ring[0]), key_of(ring[2]), key_of(ring[4]), key_of(ring[6])};
  };
  const auto fan = [&](bool exposed) {
    std::vector<FacePiece> pieces;
    for (std::size_t i = 0; i < polygon.size(); ++i)
      pieces.push_back({{centre, polygon[i], polygon[(i + 1) % polygon.size()]}, exposed});
    return pieces;
  };
  plain = false;
  if (kind == Across::finer && core_count == 4) {
    std::vector<FacePiece> pieces;
    for (int r = 0; r < 8; r += 2)
      pieces.push_back({{key_of(ring[r]), key_of(ring[r + 1]), centre, key_of(ring[(r + 7) % 8])}, false});
    return pieces;
  }
  if (kind == Across::finer && core_count > 0)
    throw std::logic_error("octree mesher: a partially covered face survived the clean stage");
  const bool exposed = core_count == 0;
  if (kind == Across::coarser && !exposed && any_mid)
    throw std::logic_error("octree mesher: hanging node next to a coarser cell (balance broken)");
  if (!any_mid) {
    plain = true;
    return {FacePiece{corners(), exposed}};
  }
  return fan(exposed);
}

void CoreMesher::refresh_present() {
  present_.clear();
  for (Key key : core_) {
    const OctreeCell cell = cell_of_key(key);
    const Lattice o = tree_->lattice_origin(cell);
    const std::int64_t s = tree_->lattice_span(cell.depth);
    for (int c = 0; c < 8; ++c)
      present_.insert(lattice_key(o[0] + (c & 1) * s, o[1] + ((c >> 1) & 1) * s, o[2] + ((c >> 2) & 1) * s));
  }
}

std::vector<Key> CoreMesher::sorted_core() const {
  std::vector<Key> cells(core_.begin(), core_.end());
  std::sort(cells.begin(), cells.end());
  return cells;
}

/// The core's boundary as triangles (caps included), by node key.
std::vector<std::array<Key, 3>> CoreMesher::exposed_triangles() const {
  std::vector<std::array<Key, 3>> triangles;
  for (Key key : sorted_core()) {
    const OctreeCell cell = cell_of_key(key);
    for (int face = 0; face < 6; ++face) {
      bool plain = false;
      for (const FacePiece& piece : face_pieces(cell, face, plain)) {
        if (!piece.exposed) continue;
        if (piece.nodes.size() == 3) {
          triangles.push_back({piece.nodes[0], piece.nodes[1], piece.nodes[2]});
          continue;
        }
        const Key apex = key_of(face_centre(cell, face)) | kApexFlag;
        for (int i = 0; i < 4; ++i) triangles.push_back({piece.nodes[i], piece.nodes[(i + 1) % 4], apex});
      }
    }
  }
  return triangles;
}

// --- 4. Clean -------------------------------------------------------------------

void CoreMesher::clean() {
  const std::size_t before = core_.size();
  for (int round = 0; round < 1000; ++round) {
    refresh_present();
    if (remove_partial_faces()) continue;
    if (keep_largest_component()) continue;
    if (!remove_non_manifold()) break;
  }
  refresh_present();
  report_.removed_for_conformity = static_cast<int>(before - core_.size());
  report_.core_cells = static_cast<int>(core_.size());
}

/// Removes the core cells that cover part (not all) of a coarser core cell's face.
int CoreMesher::remove_partial_faces() {
  std::vector<Key> remove;
  for (Key key : core_) {
    const OctreeCell cell = cell_of_key(key);
    for (int face = 0; face < 6; ++face) {
      std::vector<Key> neighbours;
      int count = 0;
      if (across(cell, face, count, &neighbours) == Across::finer && count > 0 && count < 4)
        remove.insert(remove.end(), neighbours.begin(), neighbours.end());
    }
  }
  for (Key key : remove) core_.erase(key);
  return static_cast<int>(remove.size());
}

int CoreMesher::keep_largest_component() {
  std::unordered_map<Key, int> component;
  std::vector<int> sizes;
  for (Key seed : sorted_core()) {
    if (component.count(seed)) continue;
    const int id = static_cast<int>(sizes.size());
    sizes.push_back(0);
    std::vector<Key> stack{seed};
    component[seed] = id;
    while (!stack.empty()) {
      const Key key = stack.back();
      stack.pop_back();
      ++sizes[id];
      const OctreeCell cell = cell_of_key(key);
      for (int face = 0; face < 6; ++face) {
        std::vector<Key> neighbours;
        int count = 0;
        across(cell, face, count, &neighbours);
        for (Key next : neighbours)
          if (component.emplace(next, id).second) stack.push_back(next);
      }
    }
  }
  if (sizes.size() <= 1) return 0;
  const int largest = static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  int removed = 0;
  for (const auto& [key, id] : component)
    if (id != largest) {
      core_.erase(key);
      ++removed;
    }
  return removed;
}

/// Removes the core cells at edges used by more than two boundary triangles
/// and at points whose boundary triangles form more than one fan.
int CoreMesher::remove_non_manifold() {
  const std::vector<std::array<Key, 3>> triangles = exposed_triangles();
  std::map<std::pair<Key, Key>, int> edge_use;
  std::unordered_map<Key, std::vector<std::pair<Key, Key>>> link;  // point -> its triangles' opposite edges
  for (const auto& t : triangles)
    for (int i = 0; i < 3; ++i) {
      const Key p = t[i], q = t[(i + 1) % 3], r = t[(i + 2) % 3];
      ++edge_use[{std::min(p, q), std::max(p, q)}];
      link[p].push_back({q, r});
    }
  std::unordered_set<Key> bad_points;
  for (const auto& [edge, uses] : edge_use)
    if (uses != 2) bad_points.insert({edge.first, edge.second});
  for (const auto& [p, edges] : link) {
    // The link of a manifold point is one cycle: walk it from the first edge.
    std::unordered_map<Key, Key> next;
    for (const auto& [q, r] : edges) next[q] = r;
    std::size_t steps = 0;
    Key at = edges.front().first;
    do {
      const auto where = next.find(at);
      if (where == next.end()) break;
      at = where->second;
      ++steps;
    } while (at != edges.front().first && steps <= edges.size());
    if (steps != edges.size() || next.size() != edges.size()) bad_points.insert(p);
  }
  if (bad_points.empty()) return 0;
  std::vector<Key> remove;
  for (Key key : core_) {
    const OctreeCell cell = cell_of_key(key);
    const Lattice o = tree_->lattice_origin(cell);
    const std::int64_t s = tree_->lattice_span(cell.depth);
    for (int c = 0; c < 8; ++c)
      if (bad_points.count(lattice_key(o[0] + (c & 1) * s, o[1] + ((c >> 1) & 1) * s, o[2] + ((c >> 2) & 1) * s))) {
        remove.push_back(key);
        break;
      }
  }
  if (remove.empty()) throw std::logic_error("octree mesher: a non-manifold point belongs to no core cell");
  for (Key key : remove) core_.erase(key);
  return static_cast<int>(remove.size());
}

// --- 5. Cut ---------------------------------------------------------------------

int CoreMesher::node(Key key) {
  const auto [where, inserted] = node_of_key_.emplace(key, static_cast<int>(positions_.size() / 3));
  if (inserted) {
    if (key & kApexFlag) throw std::logic_error("octree mesher: apex node created without a position");
    const Lattice p = lattice_of(key);
    const auto x = tree_->position(p[0], p[1], p[2]);
    positions_.insert(positions_.end(), x.begin(), x.end());
  }
  return where->second;
}

void CoreMesher::add_tet(int a, int b, int c, int d) {
  using detail::cross, detail::dot, detail::minus;
  const auto pa = point(a);
  if (dot(cross(minus(point(b), pa), minus(point(c), pa)), minus(point(d), pa)) < 0) std::swap(b, c);
  tets_.insert(tets_.end(), {a, b, c, d});
}

/// pyramid5 convention: the base's right-hand normal points to the apex.
void CoreMesher::add_pyramid(std::array<int, 4> base, int apex) {
  using detail::cross, detail::dot, detail::minus;
  const auto p0 = point(base[0]);
  if (dot(cross(minus(point(base[1]), p0), minus(point(base[2]), p0)), minus(point(apex), p0)) < 0)
    std::swap(base[1], base[3]);
  pyramids_.insert(pyramids_.end(), {base[0], base[1], base[2], base[3], apex});
}

void CoreMesher::cut() {
  const double cap = options_.cap_height;
  for (Key key : sorted_core()) {
    const OctreeCell cell = cell_of_key(key);
    std::array<std::vector<FacePiece>, 6> faces;
    bool all_plain = true;
    for (int face = 0; face < 6; ++face) {
      bool plain = false;
      faces[face] = face_pieces(cell, face, plain);
      all_plain = all_plain && plain;
    }
    const Lattice o = tree_->lattice_origin(cell);
    const std::int64_t s = tree_->lattice_span(cell.depth);
    if (all_plain) {
      static constexpr int kCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                            {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
      for (const auto& c : kCorner)
        hexes_.push_back(node(lattice_key(o[0] + c[0] * s, o[1] + c[1] * s, o[2] + c[2] * s)));
      ++report_.core_hexahedra;
    } else {
      const int centre = node(lattice_key(o[0] + s / 2, o[1] + s / 2, o[2] + s / 2));
      for (const auto& pieces : faces)
        for (const FacePiece& piece : pieces) {
          if (piece.nodes.size() == 3)
            add_tet(node(piece.nodes[0]), node(piece.nodes[1]), node(piece.nodes[2]), centre);
          else
            add_pyramid({node(piece.nodes[0]), node(piece.nodes[1]), node(piece.nodes[2]), node(piece.nodes[3])},
                        centre);
        }
      ++report_.transition_cells;
    }
    // The core's boundary: exposed triangles as they are, exposed squares capped.
    const double edge = tree_->cell_size(cell.depth);
    for (int face = 0; face < 6; ++face)
      for (const FacePiece& piece : faces[face]) {
        if (!piece.exposed) continue;
        std::vector<int> ids;
        for (Key k : piece.nodes) ids.push_back(node(k));
        if (ids.size() == 3) {
          inner_triangles_.push_back({ids[0], ids[1], ids[2]});
          continue;
        }
        const Lattice fc = face_centre(cell, face);
        auto apex_position = tree_->position(fc[0], fc[1], fc[2]);
        apex_position[face / 2] += (face % 2 ? 1.0 : -1.0) * cap * edge;
        const int apex = static_cast<int>(positions_.size() / 3);
        node_of_key_.emplace(key_of(fc) | kApexFlag, apex);
        positions_.insert(positions_.end(), apex_position.begin(), apex_position.end());
        add_pyramid({ids[0], ids[1], ids[2], ids[3]}, apex);
        for (int i = 0; i < 4; ++i) inner_triangles_.push_back({ids[i], ids[(i + 1) % 4], apex});
        ++report_.caps;
      }
  }
}

// --- 6. Gap -------------------------------------------------------------------

void CoreMesher::fill_gap() {
  surface_first_node_ = static_cast<int>(positions_.size() / 3);
  positions_.insert(positions_.end(), surface_.points.begin(), surface_.points.end());
  std::vector<std::array<int, 3>> outer;
  for (int t = 0; t < surface_.triangle_count(); ++t)
    outer.push_back({surface_first_node_ + surface_.triangles[3 * t],
                     surface_first_node_ + surface_.triangles[3 * t + 1],
                     surface_first_node_ + surface_.triangles[3 * t + 2]});
  if (options_.boundary_layer > 0) outer = add_boundary_layer(outer);
  if (inner_triangles_.empty())
    report_.warnings.push_back("no octree cell fits inside " + surface_.source + " at --size " +
                               std::to_string(options_.size) + ": the mesh is all tetrahedra");
  const detail::GapMesh gap = detail::fill_gap(positions_, outer, inner_triangles_, omp_get_max_threads());
  positions_.insert(positions_.end(), gap.new_positions.begin(), gap.new_positions.end());
  for (const auto& t : gap.tets) add_tet(t[0], t[1], t[2], t[3]);
  report_.gap_tetrahedra = static_cast<int>(gap.tets.size());
}

/// Angle-weighted unit normals at the surface's points (#P by 3, outward).
std::vector<double> point_normals(const TriangleSurface& surface) {
  std::vector<double> normals(surface.points.size(), 0.0);
  for (int t = 0; t < surface.triangle_count(); ++t) {
    const int* c = &surface.triangles[3 * static_cast<std::size_t>(t)];
    const double* p[3] = {&surface.points[3 * c[0]], &surface.points[3 * c[1]], &surface.points[3 * c[2]]};
    double e1[3], e2[3], n[3];
    detail::sub(p[1], p[0], e1);
    detail::sub(p[2], p[0], e2);
    detail::cross(e1, e2, n);
    const double length = detail::norm(n);
    for (int k = 0; k < 3; ++k) {
      double a[3], b[3];
      detail::sub(p[(k + 1) % 3], p[k], a);
      detail::sub(p[(k + 2) % 3], p[k], b);
      const double angle = std::acos(std::clamp(detail::dot(a, b) / (detail::norm(a) * detail::norm(b)), -1.0, 1.0));
      for (int d = 0; d < 3; ++d) normals[3 * c[k] + d] += angle * n[d] / length;
    }
  }
  for (std::size_t v = 0; v < normals.size(); v += 3) {
    const double length = detail::norm(&normals[v]);
    for (int d = 0; d < 3; ++d) normals[v + d] /= length;
  }
  return normals;
}

/// Offsets the surface inward by `thickness` along `normals` and checks the
/// layer: the offset surface closed and free of self-intersection, every
/// prism well shaped, the core's boundary inside the offset surface.
bool CoreMesher::try_boundary_layer(double thickness, const std::vector<double>& normals, std::vector<int>& prisms,
                                    std::vector<double>& offset_points, std::string& failure) const {
  TriangleSurface offset = surface_;
  for (std::size_t i = 0; i < offset.points.size(); ++i) offset.points[i] -= thickness * normals[i];
  offset.source = "the boundary layer's inner surface";
  try {
    if (!check_closed_surface(offset).empty()) {
      failure = "its inner surface turns inside out";
      return false;
    }
  } catch (const InputError& error) {
    failure = error.what();
    return false;
  }
  const tm_element_info& prism = *Registry::instance().element("prism6");
  const int first_offset = static_cast<int>(positions_.size() / 3);
  prisms.clear();
  for (int t = 0; t < surface_.triangle_count(); ++t) {
    std::array<double, 18> xyz{};
    std::array<int, 6> nodes{};
    for (int k = 0; k < 3; ++k) {
      const int point = surface_.triangles[3 * t + k];
      nodes[k] = surface_first_node_ + point;
      nodes[k + 3] = first_offset + point;
      for (int d = 0; d < 3; ++d) {
        xyz[3 * k + d] = surface_.points[3 * point + d];
        xyz[3 * (k + 3) + d] = offset.points[3 * point + d];
      }
    }
    double e1[3], e2[3], n[3];
    detail::sub(&xyz[3], &xyz[0], e1);
    detail::sub(&xyz[6], &xyz[0], e2);
    detail::cross(e1, e2, n);
    double alignment = 1;
    for (int k = 0; k < 3; ++k)
      alignment = std::min(alignment, detail::dot(n, &normals[3 * surface_.triangles[3 * t + k]]) / detail::norm(n));
    if (alignment < kMinimumLayerAlignment || scaled_jacobian(prism, 3, xyz) <= 0) {
      failure = "the surface turns too sharply at " + surface_.describe_triangle(t) +
                " for a prism (point normals more than 60 degrees from the triangle's)";
      return false;
    }
    prisms.insert(prisms.end(), nodes.begin(), nodes.end());
  }
  const SurfaceDistance inner(offset);
  for (const auto& triangle : inner_triangles_)
    for (int node : triangle)
      if (inner.signed_distance(&positions_[3 * static_cast<std::size_t>(node)]) > -0.05 * thickness) {
        failure = "its inner surface comes too close to the octree core";
        return false;
      }
  offset_points = std::move(offset.points);
  return true;
}

/// A layer of prisms on the surface's triangles (their top: the surface
/// offset inward along the point normals); returns the surface the gap
/// must then fill up to. Halves the thickness up to twice when the layer
/// fails its checks, then goes without it (with a warning).
std::vector<std::array<int, 3>> CoreMesher::add_boundary_layer(const std::vector<std::array<int, 3>>& outer) {
  const std::vector<double> normals = point_normals(surface_);
  double thickness = layer_thickness();
  std::string failure;
  for (int attempt = 0; attempt < 3; ++attempt, thickness /= 2) {
    std::vector<int> prisms;
    std::vector<double> offset_points;
    if (!try_boundary_layer(thickness, normals, prisms, offset_points, failure)) continue;
    const int first_offset = static_cast<int>(positions_.size() / 3);
    positions_.insert(positions_.end(), offset_points.begin(), offset_points.end());
    prisms_ = std::move(prisms);
    report_.boundary_prisms = static_cast<int>(prisms_.size() / 6);
    report_.boundary_layer_thickness = thickness;
    std::vector<std::array<int, 3>> top;
    for (int t = 0; t < surface_.triangle_count(); ++t)
      top.push_back({first_offset + surface_.triangles[3 * t], first_offset + surface_.triangles[3 * t + 1],
                     first_offset + surface_.triangles[3 * t + 2]});
    return top;
  }
  report_.warnings.push_back("no boundary layer of prisms: " + failure);
  return outer;
}

// --- 7. Groups ------------------------------------------------------------------

void add_block(Mesh& mesh, const char* name, std::vector<int>& connectivity) {
  const tm_element_info* element = Registry::instance().element(name);
  ElementBlock block{element, std::move(connectivity), {}, mesh.cell_count()};
  for (int c = 0; c < block.count(); ++c) block.source_ids.push_back(block.first_cell + c + 1);
  if (block.count() > 0) mesh.blocks.push_back(std::move(block));
}

void sort_unique(std::vector<int>& values) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
}

std::array<double, 3> cell_centroid(const Mesh& mesh, const ElementBlock& block, int local) {
  std::array<double, 3> c{};
  const auto nodes = block.cell_nodes(local);
  for (int n : nodes)
    for (int a = 0; a < 3; ++a) c[a] += mesh.rest_positions[3 * static_cast<std::size_t>(n) + a] / nodes.size();
  return c;
}

Mesh CoreMesher::assemble() {
  Mesh mesh;
  mesh.dim = 3;
  mesh.source = surface_.source;
  mesh.rest_positions = positions_;
  for (int n = 0; n < mesh.node_count(); ++n) mesh.node_source_ids.push_back(n + 1);
  // Registry order: tet4 < pyramid5 < hex8 is whatever the registry says; add in its order.
  std::map<std::string, std::vector<int>*> lists{
      {"tet4", &tets_}, {"pyramid5", &pyramids_}, {"prism6", &prisms_}, {"hex8", &hexes_}};
  for (const tm_element_info* element : Registry::instance().elements()) {
    const auto where = lists.find(element->name);
    if (where != lists.end()) add_block(mesh, element->name, *where->second);
  }
  Group body{"body", 3, {}, {}, {}};
  for (int n = 0; n < mesh.node_count(); ++n) body.nodes.push_back(n);
  for (int c = 0; c < mesh.cell_count(); ++c) body.cells.push_back(c);
  mesh.groups.push_back(std::move(body));
  // Facet groups: the whole surface, then each named patch.
  std::vector<Group> patches(surface_.patch_names.size());
  Group all{"surface", 2, {}, {}, {}};
  for (int t = 0; t < surface_.triangle_count(); ++t) {
    const int patch = surface_.patches.empty() ? -1 : surface_.patches[t];
    for (Group* group : {&all, patch >= 0 ? &patches[patch] : nullptr}) {
      if (!group) continue;
      for (int c = 0; c < 3; ++c) group->facets.nodes.push_back(surface_first_node_ + surface_.triangles[3 * t + c]);
      group->facets.offsets.push_back(static_cast<int>(group->facets.nodes.size()));
      group->facets.orders.push_back(1);
    }
  }
  all.nodes = all.facets.nodes;
  sort_unique(all.nodes);
  mesh.groups.push_back(std::move(all));
  for (std::size_t p = 0; p < patches.size(); ++p) {
    const std::string& name = surface_.patch_names[p];
    if (name.empty() || patches[p].facets.count() == 0 || mesh.group(name)) continue;
    patches[p].name = name;
    patches[p].dim = 2;
    patches[p].nodes = patches[p].facets.nodes;
    sort_unique(patches[p].nodes);
    mesh.groups.push_back(std::move(patches[p]));
  }
  // Cell regions: centroid inside, first match wins.
  std::vector<int> owner(mesh.cell_count(), -1);
  for (std::size_t r = 0; r < options_.regions.size(); ++r) {
    const SurfaceDistance region(options_.regions[r].surface);
    for (const ElementBlock& block : mesh.blocks)
      for (int local = 0; local < block.count(); ++local) {
        const int cell = block.first_cell + local;
        if (owner[cell] >= 0) continue;
        const auto c = cell_centroid(mesh, block, local);
        if (region.inside(c.data())) owner[cell] = static_cast<int>(r);
      }
  }
  for (std::size_t r = 0; r < options_.regions.size(); ++r) {
    Group group{options_.regions[r].name, 3, {}, {}, {}};
    for (int cell = 0; cell < mesh.cell_count(); ++cell) {
      if (owner[cell] != static_cast<int>(r)) continue;
      group.cells.push_back(cell);
      const auto [b, local] = mesh.locate(cell);
      for (int n : mesh.blocks[b].cell_nodes(local)) group.nodes.push_back(n);
    }
    sort_unique(group.nodes);
    if (group.cells.empty())
      report_.warnings.push_back("region " + group.name + " (" + options_.regions[r].surface.source +
                                 ") contains no cell centroid");
    mesh.groups.push_back(std::move(group));
  }
  mesh.validate();
  const MeshQuality quality = mesh_quality(mesh);
  report_.mesh_volume = quality.volume;
  report_.surface_volume = enclosed_volume(surface_);
  return mesh;
}

void check_options(const TriangleSurface& surface, const OctreeMeshOptions& options) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(options.size)) throw InputError("mesh: --size must be a positive number");
  if (options.surface_levels < 0 || options.surface_levels > 8) throw InputError("mesh: --levels must be in 0..8");
  if (!(options.margin >= 0 && options.margin <= 2)) throw InputError("mesh: margin must be in [0, 2]");
  if (!(options.boundary_layer >= 0 && options.boundary_layer <= 1))
    throw InputError("mesh: --layer must be in [0, 1]");
  if (!(options.cap_height > 0 && options.cap_height < 0.5)) throw InputError("mesh: cap height must be in (0, 0.5)");
  for (const RegionOfInterest& roi : options.regions_of_interest)
    if (!positive(roi.radius) || !positive(roi.size) || !std::isfinite(roi.centre[0]) ||
        !std::isfinite(roi.centre[1]) || !std::isfinite(roi.centre[2]))
      throw InputError("mesh: --roi needs a finite centre, a positive radius and a positive size");
  if (surface.triangle_count() == 0) throw InputError(surface.source + ": the surface has no triangle");
  for (const VolumeRegion& region : options.regions)
    if (region.name.empty()) throw InputError("mesh: --region needs a name (NAME=FILE)");
}

}  // namespace

Mesh mesh_surface_volume(const TriangleSurface& surface, const OctreeMeshOptions& options, OctreeMeshReport* report) {
  check_options(surface, options);
  OctreeMeshReport local;
  OctreeMeshReport& out = report ? *report : local;
  out = OctreeMeshReport{};
  CoreMesher mesher(surface, options, out);
  return mesher.run();
}

}  // namespace tensormass
