/// \file criteria.cpp
/// The criteria of criteria.hpp. Every evaluation reads the element's
/// constants (per quadrature point: w_q det(J0_q), then G^T, see
/// kernel_abi.h), its rest positions and displacements, and allocates
/// nothing: the only arrays are on the stack (D by D matrices; R_P's two
/// stresses). R_P's block evaluation allocates its batch buffers once per
/// block and thread. The dimension
/// (2 or 3) and, for the node counts of the registry's elements, the number
/// of nodes N are template parameters so that the loops unroll; N = 0 reads
/// the node count at run time.
#include "tensormass/adaptivity/criteria.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string_view>

#include "tensormass/kernels/registry.hpp"

namespace tensormass {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// --- Element geometry --------------------------------------------------------

/// The per-point block of the constants: weight w_q det(J0_q), then G^T.
template <int D, int N>
struct QuadraturePoints {
  const double* first;
  int count;
  int nodes;
  int stride;

  explicit QuadraturePoints(const ElementView& view)
      : first(view.consts + view.kernel.derived_params),
        count(view.kernel.quadrature_points),
        nodes(N > 0 ? N : view.kernel.nodes),
        stride(1 + D * nodes) {}

  double weight(int q) const { return first[q * stride]; }
  const double* gradients_t(int q) const { return first + q * stride + 1; }
};

/// H[a][c] = sum_j u[j*D + a] GT[c*nodes + j], the displacement gradient.
template <int D, int N>
void displacement_gradient(const double* u, const double* GT, int nodes, double (&H)[D][D]) {
  const int n = N > 0 ? N : nodes;
  for (int a = 0; a < D; ++a)
    for (int c = 0; c < D; ++c) {
      double sum = 0.0;
      for (int j = 0; j < n; ++j) sum += u[j * D + a] * GT[c * n + j];
      H[a][c] = sum;
    }
}

/// det(I + H).
template <int D>
double deformation_determinant(const double (&H)[D][D]) {
  if constexpr (D == 2) {
    return (1.0 + H[0][0]) * (1.0 + H[1][1]) - H[0][1] * H[1][0];
  } else {
    const double f00 = 1.0 + H[0][0], f11 = 1.0 + H[1][1], f22 = 1.0 + H[2][2];
    return f00 * (f11 * f22 - H[1][2] * H[2][1]) - H[0][1] * (H[1][0] * f22 - H[1][2] * H[2][0]) +
           H[0][2] * (H[1][0] * H[2][1] - f11 * H[2][0]);
  }
}

/// v0 = sum_q w_q det(J0_q) (area in 2D).
template <int D, int N>
double rest_volume(const ElementView& view) {
  const QuadraturePoints<D, N> points(view);
  double volume = 0.0;
  for (int q = 0; q < points.count; ++q) volume += points.weight(q);
  return volume;
}

/// v = sum_q w_q det(J0_q) det(F_q) (area in 2D).
template <int D, int N>
double deformed_volume(const ElementView& view) {
  const QuadraturePoints<D, N> points(view);
  double volume = 0.0;
  for (int q = 0; q < points.count; ++q) {
    double H[D][D];
    displacement_gradient<D, N>(view.u, points.gradients_t(q), points.nodes, H);
    volume += points.weight(q) * deformation_determinant<D>(H);
  }
  return volume;
}

/// Squared length of the segment between nodes a and b of `positions` (+ `u` when given).
template <int D>
double squared_distance(const double* positions, const double* u, int a, int b) {
  double squared = 0.0;
  for (int c = 0; c < D; ++c) {
    double delta = positions[b * D + c] - positions[a * D + c];
    if (u != nullptr) delta += u[b * D + c] - u[a * D + c];
    squared += delta * delta;
  }
  return squared;
}

/// The end corners of edge e.
struct EdgeEnds {
  int a;
  int b;
};

EdgeEnds edge_ends(const tm_element_info& element, int e) {
  const int* edge = element.edges + e * element.edge_size;
  return {edge[0], edge[1]};
}

/// Mean of the deformed edge lengths.
template <int D>
double deformed_mean_edge(const ElementView& view) {
  double sum = 0.0;
  for (int e = 0; e < view.element.edge_count; ++e) {
    const auto [a, b] = edge_ends(view.element, e);
    sum += std::sqrt(squared_distance<D>(view.rest, view.u, a, b));
  }
  return sum / view.element.edge_count;
}

/// Arithmetic and harmonic means of the deformed edge lengths.
struct EdgeMeans {
  double mean;
  double harmonic;
};

template <int D>
EdgeMeans deformed_edge_means(const ElementView& view) {
  const int count = view.element.edge_count;
  double sum = 0.0, inverse_sum = 0.0;
  for (int e = 0; e < count; ++e) {
    const auto [a, b] = edge_ends(view.element, e);
    const double length = std::sqrt(squared_distance<D>(view.rest, view.u, a, b));
    sum += length;
    inverse_sum += length > 0.0 ? 1.0 / length : kInfinity;
  }
  return {sum / count, count / inverse_sum};
}

// --- The criteria --------------------------------------------------------------

/// Calls Self::value<2> or Self::value<3> on the view's dimension.
template <typename Self>
double by_dimension(const ElementView& view) {
  assert(view.dim == 2 || view.dim == 3);
  return view.dim == 2 ? Self::template value<2>(view) : Self::template value<3>(view);
}

/// Calls visit.template operator()<D, N>() with the dimension D and, for
/// the node counts of the registry's elements, the node count N (else N = 0,
/// read at run time).
template <typename Visit>
decltype(auto) with_shape(int dim, int nodes, Visit&& visit) {
  assert(dim == 2 || dim == 3);
  switch (dim * 100 + nodes) {
    case 203: return visit.template operator()<2, 3>();
    case 204: return visit.template operator()<2, 4>();
    case 206: return visit.template operator()<2, 6>();
    case 208: return visit.template operator()<2, 8>();
    case 304: return visit.template operator()<3, 4>();
    case 305: return visit.template operator()<3, 5>();
    case 306: return visit.template operator()<3, 6>();
    case 308: return visit.template operator()<3, 8>();
    case 310: return visit.template operator()<3, 10>();
    case 320: return visit.template operator()<3, 20>();
    default: return dim == 2 ? visit.template operator()<2, 0>() : visit.template operator()<3, 0>();
  }
}

constexpr int kMaxDofs = kMaxCellDofs;

/// to[j * D + a] = from[nodes[j] * stride + a] for the cell's N nodes.
template <int D, int N>
inline void gather_nodes(const int* nodes, const double* from, int stride, double* to) {
  for (int j = 0; j < N; ++j)
    for (int a = 0; a < D; ++a) to[j * D + a] = from[static_cast<std::size_t>(nodes[j]) * stride + a];
}

/// Self::value<D, N> on every cell of the block, the nodes gathered inline.
template <typename Self, int D, int N>
void evaluate_cells(const Criterion& self, const BlockInput& in, std::span<double> values) {
  const Model& model = in.model;
  const ElementBlock& block = in.block;
  const bool rest_needed = self.needs_rest(), force_needed = self.needs_force();
  const double* rest_positions = model.mesh().rest_positions.data();
  const double* u_all = in.u.data();
  const double* forces = in.forces.data();
#pragma omp for schedule(static) nowait
  for (int local = 0; local < block.count(); ++local) {
    const int cell = block.first_cell + local;
    if (in.distribution && !in.distribution->owns_cell(cell)) continue;
    if (in.selected && in.selected[cell] != 1) continue;
    const int* nodes = model.cell_nodes(cell).data();
    double rest[D * N], u[D * N], force[D * N];
    if (rest_needed) gather_nodes<D, N>(nodes, rest_positions, 3, rest);
    gather_nodes<D, N>(nodes, u_all, D, u);
    if (force_needed) gather_nodes<D, N>(nodes, forces, D, force);
    const ElementView view{*block.element,          model.kernel(cell), model.consts(cell), rest, u, force, D,
                           model.cell_modulus(cell)};
    values[cell] = Self::template value<D, N>(view);
  }
}

/// A criterion whose Self::value<D, N> is compiled per element shape:
/// evaluate() and evaluate_block() dispatch on the shape once (per element,
/// per block), evaluate_block() to a loop compiled for the shape (the
/// generic loop for node counts outside the registry's).
template <typename Self>
class ShapedCriterion : public Criterion {
 public:
  double evaluate(const ElementView& view) const override {
    return with_shape(view.dim, view.kernel.nodes, [&]<int D, int N>() { return Self::template value<D, N>(view); });
  }
  void evaluate_block(const BlockInput& in, std::span<double> values) const override {
    with_shape(in.model.dim(), in.block.element->nodes, [&]<int D, int N>() {
      if constexpr (N == 0) Criterion::evaluate_block(in, values);
      else evaluate_cells<Self, D, N>(*this, in, values);
    });
  }
};

/// R_EL = max over edges |l - l0| / l0 = |sqrt(r) - 1| with r = l^2 / l0^2,
/// largest at the smallest or the largest r (two square roots per element).
class EdgeLengthCriterion final : public Criterion {
 public:
  std::string name() const override { return "R_EL"; }
  double evaluate(const ElementView& view) const override { return by_dimension<EdgeLengthCriterion>(view); }

  template <int D>
  static double value(const ElementView& view) {
    double smallest = 1.0, largest = 1.0;
    for (int e = 0; e < view.element.edge_count; ++e) {
      const auto [a, b] = edge_ends(view.element, e);
      const double r = squared_distance<D>(view.rest, view.u, a, b) / squared_distance<D>(view.rest, nullptr, a, b);
      smallest = std::min(smallest, r);
      largest = std::max(largest, r);
    }
    return std::max(1.0 - std::sqrt(smallest), std::sqrt(largest) - 1.0);
  }
};

/// R_V = |v - v0| / v0.
class VolumeCriterion final : public ShapedCriterion<VolumeCriterion> {
 public:
  std::string name() const override { return "R_V"; }
  bool needs_rest() const override { return false; }

  template <int D, int N>
  static double value(const ElementView& view) {
    const double rest = rest_volume<D, N>(view);
    return std::fabs(deformed_volume<D, N>(view) - rest) / rest;
  }
};

/// R_VL = v / mean_edge^D.
class VolumeLengthCriterion final : public ShapedCriterion<VolumeLengthCriterion> {
 public:
  std::string name() const override { return "R_VL"; }
  bool is_quality() const override { return true; }

  template <int D, int N>
  static double value(const ElementView& view) {
    const double mean = deformed_mean_edge<D>(view);
    if (!(mean > 0.0)) return 0.0;
    return deformed_volume<D, N>(view) / (D == 2 ? mean * mean : mean * mean * mean);
  }
};

/// R_VLX = 6 sqrt(2) v l_harm / mean^4 (3D), (4 / sqrt 3) a l_harm / mean^3 (2D).
class VolumeLengthHarmonicCriterion final : public ShapedCriterion<VolumeLengthHarmonicCriterion> {
 public:
  std::string name() const override { return "R_VLX"; }
  bool is_quality() const override { return true; }

  template <int D, int N>
  static double value(const ElementView& view) {
    const EdgeMeans means = deformed_edge_means<D>(view);
    if (!(means.mean > 0.0)) return 0.0;
    const double volume = deformed_volume<D, N>(view);
    if constexpr (D == 2)
      return 4.0 / std::sqrt(3.0) * volume * means.harmonic / (means.mean * means.mean * means.mean);
    else return 6.0 * std::sqrt(2.0) * volume * means.harmonic / (means.mean * means.mean * means.mean * means.mean);
  }
};

/// R_S = |(1/v) sum_q w_q det(J0_q) sum_j N_j(q) f_j|; infinite for v <= 0.
class StressCriterion final : public ShapedCriterion<StressCriterion> {
 public:
  std::string name() const override { return "R_S"; }
  bool needs_rest() const override { return false; }
  bool needs_force() const override { return true; }

  template <int D, int N>
  static double value(const ElementView& view) {
    const QuadraturePoints<D, N> points(view);
    assert(view.element.quadrature_points == points.count && view.element.nodes == points.nodes);
    double s[D] = {};
    for (int q = 0; q < points.count; ++q) {
      const double* shape = view.element.shape_values + q * points.nodes;
      for (int j = 0; j < points.nodes; ++j) {
        const double weight = points.weight(q) * shape[j];
        for (int c = 0; c < D; ++c) s[c] += weight * view.force[j * D + c];
      }
    }
    const double volume = deformed_volume<D, N>(view);
    if (!(volume > 0.0)) return kInfinity;
    double squared = 0.0;
    for (int c = 0; c < D; ++c) squared += s[c] * s[c];
    return std::sqrt(squared) / volume;
  }
};

/// Four cells evaluated at once (criteria of H alone, tet4: one quadrature
/// point and constant shape gradients).
using Lanes = double __attribute__((vector_size(4 * sizeof(double))));

/// Self::finish(Self::point_squared(H)) for `used` <= 4 tet4 cells, H and
/// the criterion computed for the four in vector registers (lanes past
/// `used` repeat the first cell). Each lane's entries are put together in a
/// register before they are used: no vector load waits on scalar stores.
template <typename Self>
void evaluate_tet4_lanes(const Model& model, const double* u_all, const int* cells, int used, double* values) {
  const double* node_u[4][4];  // [lane][node]
  const double* gradients[4];  // [lane]: G^T (3 by 4) of the cell's one quadrature point
  for (int lane = 0; lane < 4; ++lane) {
    const int cell = cells[lane < used ? lane : 0];
    const int* nodes = model.cell_nodes(cell).data();
    for (int j = 0; j < 4; ++j) node_u[lane][j] = u_all + static_cast<std::size_t>(nodes[j]) * 3;
    gradients[lane] = model.consts(cell) + model.kernel(cell).derived_params + 1;
  }
  Lanes u[12], G[12];
  for (int j = 0; j < 4; ++j)
    for (int a = 0; a < 3; ++a)
      u[j * 3 + a] = Lanes{node_u[0][j][a], node_u[1][j][a], node_u[2][j][a], node_u[3][j][a]};
  for (int k = 0; k < 12; ++k) G[k] = Lanes{gradients[0][k], gradients[1][k], gradients[2][k], gradients[3][k]};
  Lanes H[3][3];
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) {
      Lanes sum{};
      for (int j = 0; j < 4; ++j) sum += u[j * 3 + a] * G[c * 4 + j];
      H[a][c] = sum;
    }
  const Lanes squared = Self::template point_squared<3, Lanes>(H);
  for (int lane = 0; lane < used; ++lane) values[cells[lane]] = Self::finish(std::max(0.0, squared[lane]));
}

/// A criterion of H alone on a tet4 block, 4 cells at a time
/// (evaluate_tet4_lanes); false for other blocks, which the caller
/// evaluates cell by cell. Same contract as Criterion::evaluate_block.
template <typename Self>
bool evaluate_tet4_block(const BlockInput& in, std::span<double> values) {
  const Model& model = in.model;
  const ElementBlock& block = in.block;
  if (model.dim() != 3 || block.element->nodes != 4 || block.element->quadrature_points != 1) return false;
  const double* u_all = in.u.data();
  int pending[4];
  int used = 0;
#pragma omp for schedule(static) nowait
  for (int local = 0; local < block.count(); ++local) {
    const int cell = block.first_cell + local;
    if (in.distribution && !in.distribution->owns_cell(cell)) continue;
    if (in.selected && in.selected[cell] != 1) continue;
    if (model.kernel(cell).quadrature_points != 1) {  // a law on another rule: alone
      double u[12];
      gather_nodes<3, 4>(model.cell_nodes(cell).data(), u_all, 3, u);
      const ElementView view{*block.element,          model.kernel(cell), model.consts(cell), nullptr, u, nullptr, 3,
                             model.cell_modulus(cell)};
      values[cell] = Self::template value<3, 4>(view);
      continue;
    }
    pending[used++] = cell;
    if (used == 4) {
      evaluate_tet4_lanes<Self>(model, u_all, pending, used, values.data());
      used = 0;
    }
  }
  if (used > 0) evaluate_tet4_lanes<Self>(model, u_all, pending, used, values.data());
  return true;
}

/// The largest of per_point(H) over the element's quadrature points.
template <int D, int N, typename PerPoint>
double largest_over_points(const ElementView& view, PerPoint per_point) {
  const QuadraturePoints<D, N> points(view);
  double largest = 0.0;
  for (int q = 0; q < points.count; ++q) {
    double H[D][D];
    displacement_gradient<D, N>(view.u, points.gradients_t(q), points.nodes, H);
    largest = std::max(largest, per_point(H));
  }
  return largest;
}

/// A criterion of the displacement gradients H_q alone:
/// Self::finish(max_q Self::point_squared(H_q)), with point_squared a
/// template on the value type (one H, or lanes of them); tet4 blocks are
/// evaluated four cells at a time (evaluate_tet4_block).
template <typename Self>
class GradientCriterion : public ShapedCriterion<Self> {
 public:
  bool needs_rest() const override { return false; }

  template <int D, int N>
  static double value(const ElementView& view) {
    return Self::finish(largest_over_points<D, N>(view, Self::template point_squared<D, double>));
  }
  void evaluate_block(const BlockInput& in, std::span<double> values) const override {
    if (!evaluate_tet4_block<Self>(in, values)) ShapedCriterion<Self>::evaluate_block(in, values);
  }
};

/// R_NL = max over points of |1/2 H^T H|_F.
class NonlinearStrainCriterion final : public GradientCriterion<NonlinearStrainCriterion> {
 public:
  std::string name() const override { return "R_NL"; }
  /// |H^T H|_F^2, for one H (T = double) or for lanes of them.
  template <int D, typename T>
  static T point_squared(const T (&H)[D][D]) {
    T squared{};
    for (int c = 0; c < D; ++c)
      for (int e = 0; e < D; ++e) {
        T entry{};
        for (int a = 0; a < D; ++a) entry += H[a][c] * H[a][e];
        squared += entry * entry;
      }
    return squared;
  }
  static double finish(double largest) { return 0.5 * std::sqrt(largest); }
  /// |H|_F^2 = sum sigma_i^2 <= sqrt(D) sqrt(sum sigma_i^4) = sqrt(D) |H^T H|_F <= 2 sqrt(D) value.
  double gradient_norm_bound(double value, int dim) const override {
    return std::sqrt(2.0 * std::sqrt(static_cast<double>(dim)) * value);
  }
  /// |H'^T H' - H^T H|_F <= 2 h delta + delta^2, halved.
  double change_slope(double h) const override { return h; }
};

/// R_E = max over points of |E|_F, E = (H + H^T + H^T H) / 2: the strain with
/// the rotation removed (zero under any rigid motion), what a corotational law
/// still treats linearly.
class GreenStrainCriterion final : public GradientCriterion<GreenStrainCriterion> {
 public:
  std::string name() const override { return "R_E"; }
  /// |E|_F^2 with E = (H + H^T + H^T H) / 2, for one H (T = double) or for lanes of them.
  template <int D, typename T>
  static T point_squared(const T (&H)[D][D]) {
    T squared{};
    for (int c = 0; c < D; ++c)
      for (int e = 0; e < D; ++e) {
        T entry = 0.5 * (H[c][e] + H[e][c]);
        for (int a = 0; a < D; ++a) entry += 0.5 * H[a][c] * H[a][e];
        squared += entry * entry;
      }
    return squared;
  }
  static double finish(double largest) { return std::sqrt(largest); }
  /// |H|_F <= |I + H|_F + |I|_F, |I + H|_F^2 = tr(I + 2E) <= D + 2 sqrt(D) |E|_F.
  double gradient_norm_bound(double value, int dim) const override {
    const double d = dim;
    return std::sqrt(d + 2.0 * std::sqrt(d) * value) + std::sqrt(d);
  }
  /// E' - E = sym(dH) + (dH^T H + H^T dH + dH^T dH) / 2: at most delta + h delta + delta^2 / 2.
  double change_slope(double h) const override { return 1.0 + h; }
};

/// R_P = max over points of |P_target(F_q) - P_base(F_q)|_F / E (the
/// material's small-strain Young's modulus, Model::cell_modulus), both
/// stresses from the laws' generated `whole` kernels on the cell's constants
/// (the adaptive model shares them between the ladder's laws). A cell whose
/// kernel lays its constants out otherwise (another quadrature rule) reads 0:
/// it is not on the ladder. A non-finite stress (an inverted cell) gives +inf.
class StressErrorCriterion final : public Criterion {
 public:
  explicit StressErrorCriterion(const CriterionLaws& laws) {
    const Registry& registry = Registry::instance();
    for (const tm_element_info* element : registry.elements()) {
      const tm_kernel* base = registry.find(laws.base, element->name, "whole");
      const tm_kernel* target = registry.find(laws.target, element->name, "whole");
      if (base && target && base->stress && target->stress) pairs_.push_back({element->name, base, target});
    }
    if (pairs_.empty())
      throw std::invalid_argument("criterion R_P: no element has stress kernels of both '" + laws.base + "' and '" +
                                  laws.target + "'");
  }
  std::string name() const override { return "R_P"; }
  bool needs_rest() const override { return false; }

  double evaluate(const ElementView& view) const override {
    const LawPair* pair = pair_on(view.element.name);
    if (pair == nullptr || !fits(view.kernel, *pair)) return 0.0;
    return value(*pair, view.kernel.quadrature_points, view.dim, view.u, view.consts, view.modulus);
  }

  /// The block's laws looked up once, the nodes gathered inline (as
  /// evaluate_cells); where both laws have batched stress kernels, a batch of
  /// cells per call (the same values to round-off: the batch tests hold the
  /// batched stresses to 1e-12 of the per-element ones).
  void evaluate_block(const BlockInput& in, std::span<double> values) const override {
    const LawPair* pair = pair_on(in.block.element->name);
    with_shape(in.model.dim(), in.block.element->nodes, [&]<int D, int N>() {
      if constexpr (N == 0) Criterion::evaluate_block(in, values);
      else if (pair && batched(*pair)) evaluate_batches<D, N>(*pair, in, values);
      else evaluate_cells<D, N>(pair, in, values);
    });
  }

 private:
  static constexpr int kMaxStress = 64 * 9;  // quadrature points by D by D
  struct LawPair {
    std::string_view element;
    const tm_kernel* base;
    const tm_kernel* target;
  };

  const LawPair* pair_on(std::string_view element) const {
    for (const LawPair& pair : pairs_)
      if (pair.element == element) return &pair;
    return nullptr;
  }

  /// The cell's constants fit both laws' kernels: the same parameters
  /// (so the leading constants mean the same) and the same layout.
  static bool fits(const tm_kernel& kernel, const LawPair& pair) {
    const auto same_parameters = [&](const tm_kernel* other) {
      if (other->params != kernel.params) return false;
      if (other->param_names == kernel.param_names) return true;
      for (int p = 0; p < kernel.params; ++p)
        if (std::strcmp(other->param_names[p], kernel.param_names[p]) != 0) return false;
      return true;
    };
    const auto same_layout = [&](const tm_kernel* other) {
      return same_parameters(other) && other->derived_params == kernel.derived_params &&
             other->quadrature_points == kernel.quadrature_points && other->consts <= kernel.consts &&
             kernel.quadrature_points * kernel.dim * kernel.dim <= kMaxStress;
    };
    return same_layout(pair.base) && same_layout(pair.target);
  }

  static double value(const LawPair& pair, int points, int dim, const double* u, const double* consts, double modulus) {
    double base[kMaxStress], target[kMaxStress];
    pair.base->stress(u, consts, base);
    pair.target->stress(u, consts, target);
    return from_stresses(points, dim, base, target, modulus);
  }

  /// R_P from the two laws' stresses at the cell's points (points by dim by dim each) over the material's modulus.
  static double from_stresses(int points, int dim, const double* base, const double* target, double modulus) {
    const int entries = dim * dim;
    double largest = 0.0;
    bool finite = true;
    for (int q = 0; q < points; ++q) {
      double squared = 0.0;
      for (int k = q * entries; k < (q + 1) * entries; ++k) squared += (target[k] - base[k]) * (target[k] - base[k]);
      finite = finite && std::isfinite(squared);
      largest = std::max(largest, squared);
    }
    if (!finite) return kInfinity;
    return std::sqrt(largest) / modulus;
  }

  /// visit(cell, kernel) for the block's cells this call evaluates (the
  /// schedule of Criterion::evaluate_block) whose constants fit the pair; the
  /// others read 0.
  template <class Visit>
  static void for_fitting_cells(const LawPair* pair, const BlockInput& in, std::span<double> values, Visit&& visit) {
    const Model& model = in.model;
    const ElementBlock& block = in.block;
    const tm_kernel* fitting = nullptr;  // the last kernel seen that fits the pair
#pragma omp for schedule(static) nowait
    for (int local = 0; local < block.count(); ++local) {
      const int cell = block.first_cell + local;
      if (in.distribution && !in.distribution->owns_cell(cell)) continue;
      if (in.selected && in.selected[cell] != 1) continue;
      const tm_kernel& kernel = model.kernel(cell);
      if (&kernel != fitting) {
        if (pair == nullptr || !fits(kernel, *pair)) {
          values[cell] = 0.0;
          continue;
        }
        fitting = &kernel;
      }
      visit(cell, kernel);
    }
  }

  template <int D, int N>
  void evaluate_cells(const LawPair* pair, const BlockInput& in, std::span<double> values) const {
    for_fitting_cells(pair, in, values, [&](int cell, const tm_kernel& kernel) {
      double u[D * N];
      gather_nodes<D, N>(in.model.cell_nodes(cell).data(), in.u.data(), D, u);
      values[cell] = value(*pair, kernel.quadrature_points, D, u, in.model.consts(cell), in.model.cell_modulus(cell));
    });
  }

  static constexpr int kMaxLanes = 8;

  static bool batched(const LawPair& pair) {
    return pair.base->stress_batch && pair.target->stress_batch && pair.base->batch_width == pair.target->batch_width &&
           pair.base->batch_width <= kMaxLanes;
  }

  /// Lanes of `width` cells: the pending cells' displacements and constants
  /// packed (kernel_abi.h), both laws' stresses in one call each.
  struct Batches {
    int width, consts, stresses;
    std::vector<double> u, c, base, target;
    int pending[kMaxLanes];
    int used = 0;

    Batches(const LawPair& pair, int dim)
        : width(pair.base->batch_width),
          consts(std::max(pair.base->consts, pair.target->consts)),
          stresses(pair.base->quadrature_points * dim * dim),
          u(static_cast<std::size_t>(pair.base->dofs) * width),
          c(static_cast<std::size_t>(consts) * width),
          base(static_cast<std::size_t>(stresses) * width),
          target(static_cast<std::size_t>(stresses) * width) {}
  };

  template <int D, int N>
  void evaluate_batches(const LawPair& pair, const BlockInput& in, std::span<double> values) const {
    Batches batches(pair, D);
    for_fitting_cells(&pair, in, values, [&](int cell, const tm_kernel&) {
      batches.pending[batches.used++] = cell;
      if (batches.used == batches.width) run_batch<D, N>(pair, in, batches, values);
    });
    if (batches.used > 0) run_batch<D, N>(pair, in, batches, values);
  }

  template <int D, int N>
  void run_batch(const LawPair& pair, const BlockInput& in, Batches& b, std::span<double> values) const {
    const Model& model = in.model;
    const int W = b.width;
    for (int lane = 0; lane < W; ++lane) {
      const int cell = b.pending[lane < b.used ? lane : 0];
      const int* nodes = model.cell_nodes(cell).data();
      for (int j = 0; j < N; ++j)
        for (int a = 0; a < D; ++a) b.u[(j * D + a) * W + lane] = in.u[static_cast<std::size_t>(nodes[j]) * D + a];
      const double* consts = model.consts(cell);
      for (int i = 0; i < b.consts; ++i) b.c[i * W + lane] = consts[i];
    }
    pair.base->stress_batch(b.u.data(), b.c.data(), b.base.data());
    pair.target->stress_batch(b.u.data(), b.c.data(), b.target.data());
    for (int lane = 0; lane < b.used; ++lane) {
      const int cell = b.pending[lane];
      const std::size_t offset = static_cast<std::size_t>(lane) * b.stresses;
      values[cell] = from_stresses(pair.base->quadrature_points, D, b.base.data() + offset, b.target.data() + offset,
                                   model.cell_modulus(cell));
    }
    b.used = 0;
  }

  std::vector<LawPair> pairs_;
};

}  // namespace

void Criterion::evaluate_block(const BlockInput& in, std::span<double> values) const {
  const Model& model = in.model;
  const Mesh& mesh = model.mesh();
  const ElementBlock& block = in.block;
  const int d = model.dim();
  const bool rest_needed = needs_rest(), force_needed = needs_force();
#pragma omp for schedule(static) nowait
  for (int local = 0; local < block.count(); ++local) {
    double rest[kMaxDofs], local_u[kMaxDofs], force[kMaxDofs];
    const int cell = block.first_cell + local;
    if (in.distribution && !in.distribution->owns_cell(cell)) continue;
    if (in.selected && in.selected[cell] != 1) continue;
    if (rest_needed) {
      const auto nodes = model.cell_nodes(cell);
      for (std::size_t j = 0; j < nodes.size(); ++j)
        for (int a = 0; a < d; ++a) rest[j * d + a] = mesh.rest_positions[3 * nodes[j] + a];
    }
    model.gather(cell, in.u, local_u);
    if (force_needed) model.gather(cell, in.forces, force);
    const ElementView view{*block.element,          model.kernel(cell), model.consts(cell), rest, local_u, force, d,
                           model.cell_modulus(cell)};
    values[cell] = evaluate(view);
  }
}

std::unique_ptr<Criterion> make_criterion(const std::string& name, const CriterionLaws& laws) {
  if (name == "R_EL") return std::make_unique<EdgeLengthCriterion>();
  if (name == "R_V") return std::make_unique<VolumeCriterion>();
  if (name == "R_VL") return std::make_unique<VolumeLengthCriterion>();
  if (name == "R_VLX") return std::make_unique<VolumeLengthHarmonicCriterion>();
  if (name == "R_S") return std::make_unique<StressCriterion>();
  if (name == "R_NL") return std::make_unique<NonlinearStrainCriterion>();
  if (name == "R_E") return std::make_unique<GreenStrainCriterion>();
  if (name == "R_P") return std::make_unique<StressErrorCriterion>(laws);
  throw std::invalid_argument("unknown criterion '" + name + "' (known: R_EL, R_V, R_VL, R_VLX, R_S, R_NL, R_E, R_P)");
}

const std::vector<std::string>& criterion_names() {
  static const std::vector<std::string> names{"R_EL", "R_V", "R_VL", "R_VLX", "R_S", "R_NL", "R_E", "R_P"};
  return names;
}

}  // namespace tensormass
