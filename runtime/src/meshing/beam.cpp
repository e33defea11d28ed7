// Beam generator: structured squares/cubes cut into cells, conforming across
// phases through a per-face diagonal rule and centred transition cubes
// (see beam.hpp for the rules).
#include "tensormass/meshing/beam.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <span>
#include <stdexcept>
#include <unordered_map>

#include "common/vector3.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass {
namespace {

constexpr std::string_view kCuts2D[] = {"quad4", "tri3"};
constexpr std::string_view kCuts3D[] = {"hex8", "tet5", "tet6", "prism6", "pyramid5"};
constexpr double kMaxCubes = 5e7;

bool is_cut(int dim, std::string_view cut) {
  const auto cuts = beam_cuts(dim);
  return std::find(cuts.begin(), cuts.end(), cut) != cuts.end();
}

std::string cut_list(int dim) {
  std::string list;
  for (std::string_view cut : beam_cuts(dim)) list += (list.empty() ? "" : ", ") + std::string(cut);
  return list;
}

/// The message for a cut name that is not valid in `dim`.
std::string bad_cut_message(int dim, const std::string& cut) {
  static const std::map<std::string, std::string> hints{
      {"tet10", "tet5 or tet6 with --order 2"}, {"tet4", "tet5 or tet6"}, {"wedge", "prism6"}};
  std::string message = "unknown cell type '" + cut + "'";
  if (is_cut(5 - dim, cut)) message = "'" + cut + "' is a " + std::to_string(5 - dim) + "D cell type";
  if (const auto hint = hints.find(cut); hint != hints.end()) message += " (use " + hint->second + ")";
  return message + "; " + std::to_string(dim) + "D types: " + cut_list(dim);
}

bool tetrahedral(std::string_view cut) { return cut == "tet5" || cut == "tet6"; }

void check_phases(const BeamSpec& spec) {
  if (spec.phases.empty()) throw InputError("beam: no cell type given");
  double total = 0;
  for (std::size_t p = 0; p < spec.phases.size(); ++p) {
    const BeamPhase& phase = spec.phases[p];
    if (!is_cut(spec.dim, phase.cut)) throw InputError("beam: " + bad_cut_message(spec.dim, phase.cut));
    if (!std::isfinite(phase.fraction) || phase.fraction <= 0 || phase.fraction > 1)
      throw InputError("beam: fraction of " + phase.cut + " must be in (0, 1], got " + std::to_string(phase.fraction));
    for (std::size_t q = 0; q < p; ++q)
      if (spec.phases[q].cut == phase.cut)
        throw InputError("beam: " + phase.cut + " appears twice in the mix (one phase per cell type)");
    total += phase.fraction;
  }
  if (std::abs(total - 1.0) > 1e-6) throw InputError("beam: mix fractions sum to " + std::to_string(total) + ", not 1");
}

// --- Order 2: the registry's quadratic version of each linear element ---------------

/// The element order 2 turns `linear` into: the one `chosen` names among
/// those with its corners, else the one with the fewest nodes (serendipity:
/// quad8, hex20); nullptr when the registry has none.
const tm_element_info* quadratic_version(const tm_element_info& linear, const std::vector<std::string>& chosen) {
  const tm_element_info* best = nullptr;
  for (const tm_element_info* element : Registry::instance().elements()) {
    if (element->order != 2 || linear_version(*element) != &linear) continue;
    if (std::find(chosen.begin(), chosen.end(), element->name) != chosen.end()) return element;
    if (!best || element->nodes < best->nodes) best = element;
  }
  return best;
}

/// Whether a face of `element` has a node besides its corners and mid-edge nodes.
bool has_face_nodes(const tm_element_info& element) {
  for (int f = 0; f < element.face_count; ++f)
    if (element.face_sizes[f] > 2 * face_corner_count(element, f)) return true;
  return false;
}

/// The linear elements a cut makes (pyramid5 and tet4 also fill the
/// transition cubes between a tetrahedral cut and another).
std::vector<std::string> cut_elements(const std::string& cut) {
  if (tetrahedral(cut)) return {"tet4"};
  if (cut == "pyramid5") return {"pyramid5", "tet4"};
  return {cut};
}

void check_order(const BeamSpec& spec) {
  if (spec.order != 1 && spec.order != 2)
    throw InputError("beam: order must be 1 or 2, got " + std::to_string(spec.order));
  if (spec.order == 1) {
    if (!spec.quadratic.empty()) throw InputError("beam: " + spec.quadratic.front() + " needs order 2");
    return;
  }
  std::vector<std::string> needed;
  for (std::size_t p = 0; p < spec.phases.size(); ++p) {
    for (const std::string& name : cut_elements(spec.phases[p].cut)) needed.push_back(name);
    if (p + 1 < spec.phases.size() && tetrahedral(spec.phases[p].cut) != tetrahedral(spec.phases[p + 1].cut))
      needed.insert(needed.end(), {"pyramid5", "tet4"});
  }
  for (const std::string& name : needed) {
    const tm_element_info* linear = Registry::instance().element(name);
    if (!quadratic_version(*linear, spec.quadratic))
      throw InputError("beam: " + name + " has no quadratic version in the registry (no order-2 element with its " +
                       "corners), so order 2 cannot make it");
  }
  for (const std::string& name : spec.quadratic) {
    const tm_element_info* element = Registry::instance().element(name);
    const tm_element_info* linear = element && element->order == 2 ? linear_version(*element) : nullptr;
    if (!linear || std::find(needed.begin(), needed.end(), linear->name) == needed.end())
      throw InputError("beam: " + name + " is not a quadratic version of a cell this beam makes");
    const bool others =
        std::any_of(needed.begin(), needed.end(), [&](const std::string& n) { return n != linear->name; });
    if (has_face_nodes(*element) && others)
      throw InputError("beam: " + name +
                       " has face-centre nodes that the cells of the other types next to it lack "
                       "(the mesh would not conform); make a beam of " +
                       name + " alone");
  }
}

/// `spec` with each quadratic element named as a cell type (e.g. quad9,
/// hex27, prism15) replaced by the cut of its linear version, the element
/// added to `quadratic` and the order set to 2.
BeamSpec resolve_quadratic_types(BeamSpec spec) {
  for (BeamPhase& phase : spec.phases) {
    if (is_cut(spec.dim, phase.cut)) continue;
    const tm_element_info* element = Registry::instance().element(phase.cut);
    const tm_element_info* linear =
        element && element->order == 2 && element->dim == spec.dim ? linear_version(*element) : nullptr;
    if (!linear || !is_cut(spec.dim, linear->name)) continue;
    spec.quadratic.push_back(phase.cut);
    phase.cut = linear->name;
    spec.order = 2;
  }
  return spec;
}

// --- Positions and orientation -------------------------------------------------

using Point = detail::Vector3;
using detail::cross;
using detail::dot;
using detail::minus;

/// Coordinate of grid line `index` of `count` cells over [0, length]; exact at both ends.
double grid_coordinate(int index, int count, double length) { return index == count ? length : length * index / count; }

/// How a square face between cubes is cut: kept whole, or split by the
/// diagonal from its (0,0) to (1,1) corner ("low_high") or (1,0) to (0,1) ("cross"),
/// (u, v) being its two in-plane axes in x, y, z order.
enum class FaceStyle { quad, low_high, cross };

/// The cells of one reference element, with the phase of each cell.
struct CellList {
  const tm_element_info* element = nullptr;
  std::vector<int> connectivity;
  std::vector<int> phase;
};

class BeamBuilder {
 public:
  /// `spec` resolved (resolve_quadratic_types); `phase_names` name the phase groups.
  BeamBuilder(const BeamSpec& spec, std::vector<std::string> phase_names);
  Mesh build();

 private:
  // Grid, nodes and cells.
  int grid_node(int i, int j, int k) const { return k + (n_[2] + 1) * (j + (n_[1] + 1) * i); }
  int add_node(const Point& position, bool clamp, bool tip);
  Point point(int node) const { return {positions_[3 * node], positions_[3 * node + 1], positions_[3 * node + 2]}; }
  void add_cell(std::string_view element, std::initializer_list<int> nodes);
  // 2D.
  void cut_square(int i, int j);
  // 3D.
  const std::string& cut_at(int i) const { return spec_.phases[phase_of_column_[i]].cut; }
  FaceStyle native_style(int i, int j, int k, int face) const;
  FaceStyle face_style(int i, int j, int k, int face) const;
  void cut_cube(int i, int j, int k);
  void cut_hex(const std::array<int, 8>& c);
  void cut_tet5(const std::array<int, 8>& c, int parity);
  void cut_tet6(const std::array<int, 8>& c);
  void cut_prisms(const std::array<int, 8>& c);
  void cut_centred(const std::array<int, 8>& c, const std::array<FaceStyle, 6>& styles);
  void add_tet(int a, int b, int c, int d);
  void add_triangle(int a, int b, int c);
  void add_pyramid(const std::array<int, 4>& base, int apex);
  void add_prism(std::array<int, 3> bottom, std::array<int, 3> top);
  // Order 2 and output.
  int mid_node(int a, int b);
  int face_node(std::vector<int> corners);
  int centre_node(const std::vector<int>& nodes);
  std::vector<int> quadratic_nodes(const tm_element_info& element, std::span<const int> corners);
  void make_quadratic();
  Mesh assemble();
  void add_boundary_groups(Mesh& mesh) const;
  void add_phase_groups(Mesh& mesh, const std::vector<int>& cell_phase) const;

  const BeamSpec& spec_;
  std::array<int, 3> n_;
  std::vector<int> phase_of_column_;
  int phase_ = 0;  ///< phase of the cells being added
  std::vector<double> positions_;
  std::vector<char> at_clamp_, at_tip_;
  std::vector<CellList> lists_;  ///< indexed like Registry::elements()
  std::unordered_map<std::uint64_t, int> mid_nodes_;
  std::map<std::vector<int>, int> face_nodes_;  ///< sorted face corners -> face-centre node
  std::vector<std::string> phase_names_;        ///< as the spec named the cell types, for the groups
};

BeamBuilder::BeamBuilder(const BeamSpec& spec, std::vector<std::string> phase_names)
    : spec_(spec),
      n_{spec.cells[0], spec.cells[1], spec.dim == 3 ? spec.cells[2] : 0},
      phase_names_(std::move(phase_names)) {
  const std::vector<int> bounds = beam_phase_bounds(spec);
  for (std::size_t p = 0; p + 1 < bounds.size(); ++p)
    phase_of_column_.insert(phase_of_column_.end(), bounds[p + 1] - bounds[p], static_cast<int>(p));
  for (const tm_element_info* element : Registry::instance().elements()) lists_.push_back({element, {}, {}});
  for (int i = 0; i <= n_[0]; ++i)
    for (int j = 0; j <= n_[1]; ++j)
      for (int k = 0; k <= n_[2]; ++k)
        add_node({grid_coordinate(i, n_[0], spec.size[0]), grid_coordinate(j, n_[1], spec.size[1]),
                  spec.dim == 3 ? grid_coordinate(k, n_[2], spec.size[2]) : 0.0},
                 i == 0, i == n_[0]);
}

int BeamBuilder::add_node(const Point& position, bool clamp, bool tip) {
  positions_.insert(positions_.end(), position.begin(), position.end());
  at_clamp_.push_back(clamp);
  at_tip_.push_back(tip);
  return static_cast<int>(at_clamp_.size()) - 1;
}

void BeamBuilder::add_cell(std::string_view element, std::initializer_list<int> nodes) {
  for (CellList& list : lists_)
    if (list.element->name == element) {
      list.connectivity.insert(list.connectivity.end(), nodes);
      list.phase.push_back(phase_);
      return;
    }
  throw std::logic_error("beam: the registry has no element " + std::string(element));
}

// --- 2D ----------------------------------------------------------------------------

void BeamBuilder::cut_square(int i, int j) {
  const int c00 = grid_node(i, j, 0), c10 = grid_node(i + 1, j, 0);
  const int c01 = grid_node(i, j + 1, 0), c11 = grid_node(i + 1, j + 1, 0);
  if (cut_at(i) == "quad4") {
    add_cell("quad4", {c00, c10, c11, c01});
  } else if ((i + j) % 2 == 0) {  // diagonal c00-c11
    add_triangle(c00, c10, c11);
    add_triangle(c00, c11, c01);
  } else {  // diagonal c10-c01
    add_triangle(c00, c10, c01);
    add_triangle(c10, c11, c01);
  }
}

void BeamBuilder::add_triangle(int a, int b, int c) {
  const Point normal = cross(minus(point(b), point(a)), minus(point(c), point(a)));
  if (normal[2] < 0) std::swap(b, c);
  add_cell("tri3", {a, b, c});
}

// --- 3D: face rule -------------------------------------------------------------------
// Cube corners are numbered by bits: corner c is at offset (c & 1, c >> 1 & 1, c >> 2 & 1).
// Face f lies on axis f / 2, at the cube's low (f even) or high (f odd) side.

FaceStyle BeamBuilder::native_style(int i, int j, int k, int face) const {
  const std::string& cut = cut_at(i);
  if (cut == "tet6") return FaceStyle::low_high;
  if (cut == "prism6") return face / 2 == 2 ? FaceStyle::low_high : FaceStyle::quad;
  if (cut == "tet5")  // the diagonal joins the face corners of even grid parity
    return (i + j + k + face % 2) % 2 == 0 ? FaceStyle::low_high : FaceStyle::cross;
  return FaceStyle::quad;  // hex8, pyramid5
}

FaceStyle BeamBuilder::face_style(int i, int j, int k, int face) const {
  const int axis = face / 2;
  std::array<int, 3> low{i, j, k};
  if (face % 2 == 0) --low[axis];
  std::array<int, 3> high = low;
  ++high[axis];
  if (low[axis] < 0 || high[axis] >= n_[axis]) return native_style(i, j, k, face);
  const FaceStyle from_low = native_style(low[0], low[1], low[2], 2 * axis + 1);
  const FaceStyle from_high = native_style(high[0], high[1], high[2], 2 * axis);
  if (from_low == from_high) return from_low;
  if (from_low == FaceStyle::quad || from_high == FaceStyle::quad) return FaceStyle::quad;
  return from_low;
}

/// The face's corners as the cycle (0,0), (1,0), (1,1), (0,1) in its in-plane axes.
std::array<int, 4> face_cycle(const std::array<int, 8>& corners, int face) {
  const int axis = face / 2;
  const int u = axis == 0 ? 1 : 0;
  const int v = axis == 2 ? 1 : 2;
  const int base = (face % 2) << axis;
  return {corners[base], corners[base | 1 << u], corners[base | 1 << u | 1 << v], corners[base | 1 << v]};
}

void BeamBuilder::cut_cube(int i, int j, int k) {
  std::array<int, 8> corners{};
  for (int c = 0; c < 8; ++c) corners[c] = grid_node(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1));
  std::array<FaceStyle, 6> styles{};
  bool native = true;
  for (int face = 0; face < 6; ++face) {
    styles[face] = face_style(i, j, k, face);
    native = native && styles[face] == native_style(i, j, k, face);
  }
  const std::string& cut = cut_at(i);
  if (!native && (cut == "hex8" || cut == "prism6"))
    throw std::logic_error("beam: a " + cut + " cube cannot take a split face");
  if (!native || cut == "pyramid5") return cut_centred(corners, styles);
  if (cut == "hex8") return cut_hex(corners);
  if (cut == "tet5") return cut_tet5(corners, (i + j + k) % 2);
  if (cut == "tet6") return cut_tet6(corners);
  cut_prisms(corners);
}

// --- 3D: cuts ----------------------------------------------------------------------

void BeamBuilder::cut_hex(const std::array<int, 8>& c) {
  add_cell("hex8", {c[0], c[1], c[3], c[2], c[4], c[5], c[7], c[6]});
}

/// Central tet on the corners of even grid parity, one tet on each odd corner.
void BeamBuilder::cut_tet5(const std::array<int, 8>& c, int parity) {
  std::vector<int> even;
  for (int corner = 0; corner < 8; ++corner) {
    const bool is_even = (std::popcount(static_cast<unsigned>(corner)) + parity) % 2 == 0;
    if (is_even) even.push_back(c[corner]);
    else add_tet(c[corner], c[corner ^ 1], c[corner ^ 2], c[corner ^ 4]);
  }
  add_tet(even[0], even[1], even[2], even[3]);
}

/// Six tets, each a monotone path from corner 0 to corner 7 (Kuhn).
void BeamBuilder::cut_tet6(const std::array<int, 8>& c) {
  std::array<int, 3> axes{0, 1, 2};
  do {
    const int first = 1 << axes[0];
    const int second = first | 1 << axes[1];
    add_tet(c[0], c[first], c[second], c[7]);
  } while (std::next_permutation(axes.begin(), axes.end()));
}

/// Two prisms on the bottom triangles split by the diagonal corner 0 - corner 3.
void BeamBuilder::cut_prisms(const std::array<int, 8>& c) {
  add_prism({c[0], c[1], c[3]}, {c[4], c[5], c[7]});
  add_prism({c[0], c[3], c[2]}, {c[4], c[7], c[6]});
}

/// A centre node, a pyramid on each quad face and two tets on each split face.
void BeamBuilder::cut_centred(const std::array<int, 8>& c, const std::array<FaceStyle, 6>& styles) {
  const Point low = point(c[0]), high = point(c[7]);
  const int centre = add_node({(low[0] + high[0]) / 2, (low[1] + high[1]) / 2, (low[2] + high[2]) / 2}, false, false);
  for (int face = 0; face < 6; ++face) {
    const std::array<int, 4> q = face_cycle(c, face);
    if (styles[face] == FaceStyle::quad) {
      add_pyramid(q, centre);
    } else if (styles[face] == FaceStyle::low_high) {
      add_tet(q[0], q[1], q[2], centre);
      add_tet(q[0], q[2], q[3], centre);
    } else {
      add_tet(q[0], q[1], q[3], centre);
      add_tet(q[1], q[2], q[3], centre);
    }
  }
}

/// tet4 convention: a, b, c counter-clockwise seen from d.
void BeamBuilder::add_tet(int a, int b, int c, int d) {
  const Point pa = point(a);
  if (dot(cross(minus(point(b), pa), minus(point(c), pa)), minus(point(d), pa)) < 0) std::swap(b, c);
  add_cell("tet4", {a, b, c, d});
}

/// pyramid5 convention: the base's right-hand normal points to the apex.
void BeamBuilder::add_pyramid(const std::array<int, 4>& base, int apex) {
  const Point p0 = point(base[0]);
  const Point normal = cross(minus(point(base[1]), p0), minus(point(base[2]), p0));
  if (dot(normal, minus(point(apex), p0)) > 0) add_cell("pyramid5", {base[0], base[1], base[2], base[3], apex});
  else add_cell("pyramid5", {base[0], base[3], base[2], base[1], apex});
}

/// prism6 convention (VTK): the bottom's right-hand normal points away from the top.
void BeamBuilder::add_prism(std::array<int, 3> bottom, std::array<int, 3> top) {
  const Point p0 = point(bottom[0]);
  const Point normal = cross(minus(point(bottom[1]), p0), minus(point(bottom[2]), p0));
  if (dot(normal, minus(point(top[0]), p0)) > 0) {
    std::swap(bottom[1], bottom[2]);
    std::swap(top[1], top[2]);
  }
  add_cell("prism6", {bottom[0], bottom[1], bottom[2], top[0], top[1], top[2]});
}

// --- Order 2 -----------------------------------------------------------------------

/// The node in the middle of edge a-b, shared by every cell on that edge.
int BeamBuilder::mid_node(int a, int b) {
  const std::uint64_t key =
      static_cast<std::uint64_t>(std::min(a, b)) << 32 | static_cast<std::uint32_t>(std::max(a, b));
  if (const auto found = mid_nodes_.find(key); found != mid_nodes_.end()) return found->second;
  const int node = centre_node({a, b});
  mid_nodes_.emplace(key, node);
  return node;
}

/// The node at the centre of a face (its corners), shared by the two cells on it.
int BeamBuilder::face_node(std::vector<int> corners) {
  std::sort(corners.begin(), corners.end());
  if (const auto found = face_nodes_.find(corners); found != face_nodes_.end()) return found->second;
  const int node = centre_node(corners);
  face_nodes_.emplace(std::move(corners), node);
  return node;
}

/// A new node at the mean of `nodes`, at the clamp or tip when they all are.
int BeamBuilder::centre_node(const std::vector<int>& nodes) {
  Point mean{0, 0, 0};
  bool clamp = true, tip = true;
  for (int node : nodes) {
    for (int a = 0; a < 3; ++a) mean[a] += point(node)[a] / static_cast<double>(nodes.size());
    clamp = clamp && at_clamp_[node];
    tip = tip && at_tip_[node];
  }
  return add_node(mean, clamp, tip);
}

/// The nodes of `element` (order 2) on a cell whose corners are given: its
/// mid-edge nodes at edge midpoints, its face nodes at face centres, its
/// interior nodes at the mean of the corners (exact on the beam's straight
/// sided cells).
std::vector<int> BeamBuilder::quadratic_nodes(const tm_element_info& element, std::span<const int> corners) {
  std::vector<int> nodes(element.nodes, -1);
  std::copy(corners.begin(), corners.end(), nodes.begin());
  for (int e = 0; e < element.edge_count; ++e) {
    const int* edge = element.edges + e * element.edge_size;
    nodes[edge[2]] = mid_node(nodes[edge[0]], nodes[edge[1]]);
  }
  for (int f = 0; f < element.face_count; ++f) {
    const int* face = element.faces + element.face_offsets[f];
    const int size = element.face_sizes[f];
    if (nodes[face[size - 1]] >= 0) continue;  // no face node: its last node is a mid-edge node
    std::vector<int> face_corners;
    for (int k = 0; k < face_corner_count(element, f); ++k) face_corners.push_back(nodes[face[k]]);
    nodes[face[size - 1]] = face_node(std::move(face_corners));
  }
  const std::vector<int> all_corners(corners.begin(), corners.end());
  for (int& node : nodes)
    if (node < 0) node = centre_node(all_corners);
  return nodes;
}

/// Replaces every linear cell by its quadratic version (quadratic_version).
void BeamBuilder::make_quadratic() {
  for (CellList& linear : lists_) {
    if (linear.phase.empty() || linear.element->order == 2) continue;
    const tm_element_info* element = quadratic_version(*linear.element, spec_.quadratic);
    if (!element) throw InputError(std::string("beam: ") + linear.element->name + " has no quadratic version");
    CellList* target = nullptr;
    for (CellList& list : lists_)
      if (list.element == element) target = &list;
    const int corners = linear.element->nodes;
    for (std::size_t cell = 0; cell < linear.phase.size(); ++cell) {
      const std::span<const int> cell_corners(linear.connectivity.data() + cell * corners, corners);
      const std::vector<int> nodes = quadratic_nodes(*element, cell_corners);
      target->connectivity.insert(target->connectivity.end(), nodes.begin(), nodes.end());
      target->phase.push_back(linear.phase[cell]);
    }
    linear.connectivity.clear();
    linear.phase.clear();
  }
}

// --- Mesh and groups ------------------------------------------------------------------

Mesh BeamBuilder::build() {
  for (int i = 0; i < n_[0]; ++i) {
    phase_ = phase_of_column_[i];
    for (int j = 0; j < n_[1]; ++j) {
      if (spec_.dim == 2) {
        cut_square(i, j);
        continue;
      }
      for (int k = 0; k < n_[2]; ++k) cut_cube(i, j, k);
    }
  }
  if (spec_.order == 2) make_quadratic();
  return assemble();
}

Mesh BeamBuilder::assemble() {
  Mesh mesh;
  mesh.dim = spec_.dim;
  mesh.rest_positions = positions_;
  for (int node = 0; node < mesh.node_count(); ++node) mesh.node_source_ids.push_back(node + 1);
  std::vector<int> cell_phase;
  for (const CellList& list : lists_) {
    if (list.phase.empty()) continue;
    ElementBlock block{list.element, list.connectivity, {}, static_cast<int>(cell_phase.size())};
    for (std::size_t cell = 0; cell < list.phase.size(); ++cell)
      block.source_ids.push_back(block.first_cell + cell + 1);
    cell_phase.insert(cell_phase.end(), list.phase.begin(), list.phase.end());
    mesh.blocks.push_back(std::move(block));
  }
  add_boundary_groups(mesh);
  Group body{"body", mesh.dim, {}, {}, {}};
  for (int node = 0; node < mesh.node_count(); ++node) body.nodes.push_back(node);
  for (int cell = 0; cell < mesh.cell_count(); ++cell) body.cells.push_back(cell);
  mesh.groups.push_back(std::move(body));
  if (spec_.phases.size() > 1) add_phase_groups(mesh, cell_phase);
  mesh.validate();
  return mesh;
}

void sort_unique(std::vector<int>& values) {
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
}

bool all_flagged(const std::vector<int>& nodes, const std::vector<char>& flags) {
  return std::all_of(nodes.begin(), nodes.end(), [&](int node) { return flags[node] != 0; });
}

void add_facet(FacetSet& facets, const std::vector<int>& nodes, int order) {
  facets.nodes.insert(facets.nodes.end(), nodes.begin(), nodes.end());
  facets.offsets.push_back(static_cast<int>(facets.nodes.size()));
  facets.orders.push_back(order);
}

/// clamp (x = 0) and tip (x = L): the cells' faces (3D) or edges (2D) lying there.
void BeamBuilder::add_boundary_groups(Mesh& mesh) const {
  Group clamp{"clamp", mesh.dim - 1, {}, {}, {}};
  Group tip{"tip", mesh.dim - 1, {}, {}, {}};
  for (const ElementBlock& block : mesh.blocks) {
    const tm_element_info& element = *block.element;
    const bool edges = mesh.dim == 2;
    const int count = edges ? element.edge_count : element.face_count;
    for (int local = 0; local < block.count(); ++local) {
      const std::span<const int> nodes = block.cell_nodes(local);
      for (int f = 0; f < count; ++f) {
        const int* first = edges ? element.edges + f * element.edge_size : element.faces + element.face_offsets[f];
        const int size = edges ? element.edge_size : element.face_sizes[f];
        std::vector<int> facet;
        for (int n = 0; n < size; ++n) facet.push_back(nodes[first[n]]);
        if (all_flagged(facet, at_clamp_)) add_facet(clamp.facets, facet, element.order);
        if (all_flagged(facet, at_tip_)) add_facet(tip.facets, facet, element.order);
      }
    }
  }
  for (Group* group : {&clamp, &tip}) {
    group->nodes = group->facets.nodes;
    sort_unique(group->nodes);
    mesh.groups.push_back(std::move(*group));
  }
}

void BeamBuilder::add_phase_groups(Mesh& mesh, const std::vector<int>& cell_phase) const {
  for (std::size_t p = 0; p < spec_.phases.size(); ++p) {
    Group group{"phase_" + phase_names_[p], mesh.dim, {}, {}, {}};
    for (int cell = 0; cell < static_cast<int>(cell_phase.size()); ++cell) {
      if (cell_phase[cell] != static_cast<int>(p)) continue;
      group.cells.push_back(cell);
      const auto [b, local] = mesh.locate(cell);
      for (int node : mesh.blocks[b].cell_nodes(local)) group.nodes.push_back(node);
    }
    sort_unique(group.nodes);
    mesh.groups.push_back(std::move(group));
  }
}

}  // namespace

std::span<const std::string_view> beam_cuts(int dim) {
  if (dim == 2) return kCuts2D;
  if (dim == 3) return kCuts3D;
  return {};
}

std::vector<BeamPhase> parse_beam_mix(std::string_view text) {
  std::vector<BeamPhase> phases;
  while (!text.empty()) {
    const std::size_t comma = text.find(',');
    const std::string_view item = text.substr(0, comma);
    const std::size_t colon = item.find(':');
    if (colon == std::string_view::npos || colon == 0)
      throw InputError("--mix: expected TYPE:FRACTION, got '" + std::string(item) + "'");
    const std::string number(item.substr(colon + 1));
    std::size_t used = 0;
    double fraction = 0;
    try {
      fraction = std::stod(number, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != number.size())
      throw InputError("--mix: '" + number + "' is not a fraction (in '" + std::string(item) + "')");
    phases.push_back({std::string(item.substr(0, colon)), fraction});
    text = comma == std::string_view::npos ? std::string_view() : text.substr(comma + 1);
  }
  if (phases.empty()) throw InputError("--mix: empty");
  return phases;
}

std::vector<int> beam_phase_bounds(const BeamSpec& spec) {
  std::vector<int> bounds{0};
  double cumulative = 0;
  const int columns = spec.cells[0];
  for (std::size_t p = 0; p < spec.phases.size(); ++p) {
    cumulative += spec.phases[p].fraction;
    const int end = p + 1 == spec.phases.size() ? columns : static_cast<int>(std::lround(cumulative * columns));
    if (end <= bounds.back())
      throw InputError("beam: phase " + spec.phases[p].cut + " (fraction " + std::to_string(spec.phases[p].fraction) +
                       ") gets no column of the " + std::to_string(columns) +
                       "; use more cells along x or a larger fraction");
    bounds.push_back(std::min(end, columns));
  }
  return bounds;
}

void check_beam_spec(const BeamSpec& given) {
  const BeamSpec spec = resolve_quadratic_types(given);
  if (spec.dim != 2 && spec.dim != 3)
    throw InputError("beam: dimension must be 2 or 3, got " + std::to_string(spec.dim));
  double cubes = 1;
  for (int a = 0; a < spec.dim; ++a) {
    if (spec.cells[a] < 1)
      throw InputError("beam: cell counts must be at least 1, got " + std::to_string(spec.cells[a]) + " along " +
                       "xyz"[a]);
    if (!std::isfinite(spec.size[a]) || spec.size[a] <= 0)
      throw InputError(std::string("beam: sizes must be positive, got ") + std::to_string(spec.size[a]) + " along " +
                       "xyz"[a]);
    cubes *= spec.cells[a];
  }
  if (cubes > kMaxCubes) throw InputError("beam: " + std::to_string(static_cast<long>(cubes)) + " cubes is too many");
  check_phases(spec);
  check_order(spec);
  beam_phase_bounds(spec);
}

Mesh make_beam(const BeamSpec& spec) {
  check_beam_spec(spec);
  std::vector<std::string> names;
  for (const BeamPhase& phase : spec.phases) names.push_back(phase.cut);
  return BeamBuilder(resolve_quadratic_types(spec), std::move(names)).build();
}

}  // namespace tensormass
