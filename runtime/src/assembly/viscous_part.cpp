#include "tensormass/assembly/viscous_part.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <string_view>

#include "tensormass/common/errors.hpp"
#include "tensormass/kernels/mean_dilatation.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass {

namespace {

constexpr int kMaxPoints = 27;  // hex20's default rule has the most points

/// The kinematics of one quadrature point: F, J = det F and its cofactor
/// matrix (J F^-T), D by D row-major.
template <int D>
struct Point {
  static constexpr int d = D;
  int n = 0;
  double weight = 0;  ///< w_q det J_q
  const double* GT;   ///< d by n: dN_j/dX_c at GT[c*n + j]
  double F[9], cof[9];
  double J = 1;

  Point(const tm_kernel& kernel, const double* consts, int q, const double* u) : n(kernel.nodes) {
    const double* point = consts + kernel.derived_params + q * (1 + d * n);
    weight = point[0];
    GT = point + 1;
    for (int a = 0; a < d; ++a)
      for (int c = 0; c < d; ++c) {
        double sum = a == c ? 1.0 : 0.0;
        for (int j = 0; j < n; ++j) sum += u[j * d + a] * GT[c * n + j];
        F[a * d + c] = sum;
      }
    J = tensormass::kernel::mean_dilatation::finite_strain::cofactor<D>(F, cof);  // not the parameter `kernel`
  }
  /// F^-1 (d by d) into Finv.
  void inverse(double* Finv) const {
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b) Finv[a * d + b] = cof[b * d + a] / J;
  }
  double G(int j, int c) const { return GT[c * n + j]; }
  /// dJ/du_(j a) = sum_c cof_ac G_jc.
  double dJ(int j, int a) const {
    double sum = 0.0;
    for (int c = 0; c < d; ++c) sum += cof[a * d + c] * G(j, c);
    return sum;
  }
  /// The d by d block d2J/du_(j a) du_(k b): eps_ab (G_j x G_k) in 2D,
  /// eps_abc (F (G_j x G_k))_c in 3D.
  void d2J(int j, int k, double* M) const {
    if constexpr (D == 2) {
      const double s = G(j, 0) * G(k, 1) - G(j, 1) * G(k, 0);
      M[0] = 0.0, M[1] = s, M[2] = -s, M[3] = 0.0;
      return;
    }
    const double cross[3] = {G(j, 1) * G(k, 2) - G(j, 2) * G(k, 1), G(j, 2) * G(k, 0) - G(j, 0) * G(k, 2),
                             G(j, 0) * G(k, 1) - G(j, 1) * G(k, 0)};
    double v[3];
    for (int c = 0; c < 3; ++c) v[c] = F[c * 3] * cross[0] + F[c * 3 + 1] * cross[1] + F[c * 3 + 2] * cross[2];
    M[0] = 0.0, M[1] = v[2], M[2] = -v[1];
    M[3] = -v[2], M[4] = 0.0, M[5] = v[0];
    M[6] = v[1], M[7] = -v[0], M[8] = 0.0;
  }
};

/// {U, U', U''} of the kernel's bulk part at J (zeros without one).
void bulk(const tm_kernel& kernel, const double* consts, double J, double* out) {
  out[0] = out[1] = out[2] = 0.0;
  if (kernel.bulk) kernel.bulk(J, consts, out);
}

bool supported_split(const tm_kernel& kernel) {
  const std::string_view split(kernel.split);
  return split == "whole" || (split == "anp" && kernel.quadrature_points == 1);
}

}  // namespace

ViscousPart::ViscousPart(const Model& model) : model_(&model) {
  term_start_.assign(1, 0);
  history_start_.assign(1, 0);
  point_start_.assign(1, 0);
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const tm_kernel& kernel = model.kernel(cell);
    if (kernel.prony_terms == 0) continue;
    const MaterialLaws& material = model.material_laws(model.material(cell));
    if (!supported_split(kernel))
      throw InputError(material.owner() + ": law '" + kernel.law + "' is viscoelastic, and its " + kernel.element +
                       " cells run the " + kernel.split +
                       " split; viscoelastic cells take the whole split or, on tet4 and tri3, anp");
    if (kernel.quadrature_points > kMaxPoints)
      throw std::logic_error(std::string("ViscousPart: more than 27 quadrature points in ") + kernel.element);
    if (cell_index_.empty()) cell_index_.assign(model.cell_count(), -1);
    const std::vector<double>& params = material.parameters(kernel);
    std::vector<double> weights, times, volumetric(kernel.prony_terms, 0.0);
    for (int i = 0; i < kernel.prony_terms; ++i) {
      weights.push_back(params[kernel.prony_weights[i]]);
      times.push_back(params[kernel.prony_times[i]]);
      if (kernel.prony_volumetric_weights) volumetric[i] = params[kernel.prony_volumetric_weights[i]];
    }
    for (const auto& [values, what] : {std::pair{&weights, "weights"}, {&volumetric, "volumetric weights"}})
      if (const double sum = std::accumulate(values->begin(), values->end(), 0.0); !(sum < 1.0))
        throw InputError(material.owner() + ": the Prony " + what + " of law '" + kernel.law + "' sum to " +
                         std::to_string(sum) + "; they must sum to less than 1 (the long-term share 1 - sum > 0)");
    cell_index_[cell] = cell_count();
    const int series = series_of(weights, times, volumetric);
    cells_.push_back({cell, series});
    const std::size_t block = static_cast<std::size_t>(kernel.dim) * kernel.dim;
    history_start_.push_back(history_start_.back() + kernel.quadrature_points * blocks_per_point(series) * block);
    point_start_.push_back(point_start_.back() + kernel.quadrature_points * block);
  }
  fixed_stress_.assign(point_start_.back(), 0.0);
  decay_.assign(weight_.size(), 1.0);
  ramp_.assign(weight_.size(), 1.0);
  beta_.assign(term_start_.size() - 1, 1.0);
  beta_bulk_.assign(term_start_.size() - 1, 1.0);
}

int ViscousPart::series_of(const std::vector<double>& weights, const std::vector<double>& times,
                           const std::vector<double>& volumetric) {
  const auto same = [](const std::vector<double>& a, const std::vector<double>& all, int from, int to) {
    return std::equal(a.begin(), a.end(), all.begin() + from, all.begin() + to);
  };
  for (std::size_t s = 0; s + 1 < term_start_.size(); ++s)
    if (same(weights, weight_, term_start_[s], term_start_[s + 1]) &&
        same(times, time_, term_start_[s], term_start_[s + 1]) &&
        same(volumetric, volumetric_weight_, term_start_[s], term_start_[s + 1]))
      return static_cast<int>(s);
  weight_.insert(weight_.end(), weights.begin(), weights.end());
  time_.insert(time_.end(), times.begin(), times.end());
  volumetric_weight_.insert(volumetric_weight_.end(), volumetric.begin(), volumetric.end());
  term_start_.push_back(static_cast<int>(weight_.size()));
  relaxes_bulk_.push_back(std::any_of(volumetric.begin(), volumetric.end(), [](double k) { return k > 0.0; }));
  return static_cast<int>(term_start_.size()) - 2;
}

int ViscousPart::blocks_per_point(int series) const {
  const int terms = term_start_[series + 1] - term_start_[series];
  return relaxes_bulk_[series] ? 2 * terms + 2 : terms + 1;
}

void ViscousPart::begin_step(std::span<const double> history, double dt) {
  if (!history.empty() && history.size() != history_size())
    throw std::invalid_argument("ViscousPart::begin_step: the history has " + std::to_string(history.size()) +
                                " doubles, the model's viscous cells " + std::to_string(history_size()));
  for (std::size_t i = 0; i < weight_.size(); ++i) {
    const double x = dt / time_[i];
    if (std::isinf(dt)) decay_[i] = 0.0, ramp_[i] = 0.0;
    else if (x < 1e-8) decay_[i] = 1.0 - x, ramp_[i] = 1.0 - 0.5 * x;  // the limits, without 0/0
    else decay_[i] = std::exp(-x), ramp_[i] = -std::expm1(-x) / x;
  }
  for (std::size_t s = 0; s < beta_.size(); ++s) {
    beta_[s] = beta_bulk_[s] = 1.0;
    for (int i = term_start_[s]; i < term_start_[s + 1]; ++i) {
      beta_[s] -= weight_[i] * (1.0 - ramp_[i]);
      beta_bulk_[s] -= volumetric_weight_[i] * (1.0 - ramp_[i]);
    }
  }
#pragma omp parallel for schedule(dynamic, 256) if (cell_count() >= 1024)
  for (int v = 0; v < cell_count(); ++v) {
    const tm_kernel& kernel = model_->kernel(cells_[v].cell);
    const int series = cells_[v].series, first = term_start_[series], terms = term_start_[series + 1] - first;
    const int block = kernel.dim * kernel.dim;
    double* fixed = fixed_stress_.data() + point_start_[v];
    std::fill(fixed, fixed + kernel.quadrature_points * block, 0.0);
    if (history.empty()) continue;
    const int parts = relaxes_bulk_[series] ? 2 : 1;  // S_d, then S_U
    for (int q = 0; q < kernel.quadrature_points; ++q) {
      const double* point = history.data() + history_start_[v] + q * blocks_per_point(series) * block;
      for (int part = 0; part < parts; ++part) {
        const double* terms_h = point + part * (terms + 1) * block;
        const double* last = terms_h + terms * block;  // the part's stress at the step's start
        const double* weights = (part == 0 ? weight_ : volumetric_weight_).data();
        for (int t = 0; t < terms; ++t) {
          const int i = first + t;
          for (int m = 0; m < block; ++m)
            fixed[q * block + m] += weights[i] * (decay_[i] * terms_h[t * block + m] - ramp_[i] * last[m]);
        }
      }
    }
  }
}

void ViscousPart::adjust(int index, const double* u, double* g, double* k) const {
  if (model_->kernel(cells_[index].cell).dim == 2) adjust_cell<2>(index, u, g, k);
  else adjust_cell<3>(index, u, g, k);
}

template <int D>
void ViscousPart::adjust_cell(int index, const double* u, double* g, double* k) const {
  const int cell = cells_[index].cell;
  const tm_kernel& kernel = model_->kernel(cell);
  const double* consts = model_->consts(cell);
  const double beta = beta_[cells_[index].series], bulk_extra = beta_bulk_[cells_[index].series] - beta;
  constexpr int d = D;
  const int n = kernel.nodes, dofs = kernel.dofs;
  for (int i = 0; i < dofs; ++i) g[i] *= beta;
  if (k)
    for (int i = 0; i < dofs * dofs; ++i) k[i] *= beta;
  for (int q = 0; q < kernel.quadrature_points; ++q) {
    const Point<D> p(kernel, consts, q, u);
    double U[3];
    bulk(kernel, consts, p.J, U);
    const double* S = fixed_stress_.data() + point_start_[index] + q * d * d;
    double FS[9];  // F S_h
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b) {
        double sum = 0.0;
        for (int c = 0; c < d; ++c) sum += p.F[a * d + c] * S[c * d + b];
        FS[a * d + b] = sum;
      }
    double dJ[kMaxCellDofs];
    for (int j = 0; j < n; ++j)
      for (int a = 0; a < d; ++a) {
        dJ[j * d + a] = p.dJ(j, a);
        double h = 0.0;
        for (int b = 0; b < d; ++b) h += FS[a * d + b] * p.G(j, b);
        g[j * d + a] += p.weight * (bulk_extra * U[1] * dJ[j * d + a] + h);
      }
    if (!k) continue;
    double SG[kMaxCellDofs];  // S_h G_l, node-major
    for (int l = 0; l < n; ++l)
      for (int b = 0; b < d; ++b) {
        double sum = 0.0;
        for (int c = 0; c < d; ++c) sum += S[b * d + c] * p.G(l, c);
        SG[l * d + b] = sum;
      }
    const double second = p.weight * bulk_extra * U[2], first = p.weight * bulk_extra * U[1];
    double M[9];
    for (int j = 0; j < n; ++j)
      for (int l = 0; l < n; ++l) {
        double geometric = 0.0;  // G_j . S_h G_l
        for (int b = 0; b < d; ++b) geometric += p.G(j, b) * SG[l * d + b];
        p.d2J(j, l, M);
        double* block = k + (j * d) * dofs + l * d;
        for (int a = 0; a < d; ++a)
          for (int b = 0; b < d; ++b)
            block[a * dofs + b] +=
                second * dJ[j * d + a] * dJ[l * d + b] + first * M[a * d + b] + (a == b ? p.weight * geometric : 0.0);
      }
  }
}

double ViscousPart::adjust_energy(int index, const double* u, double W) const {
  return model_->kernel(cells_[index].cell).dim == 2 ? energy_cell<2>(index, u, W) : energy_cell<3>(index, u, W);
}

template <int D>
double ViscousPart::energy_cell(int index, const double* u, double W) const {
  const int cell = cells_[index].cell;
  const tm_kernel& kernel = model_->kernel(cell);
  const double* consts = model_->consts(cell);
  const double beta = beta_[cells_[index].series], bulk_extra = beta_bulk_[cells_[index].series] - beta;
  constexpr int d = D;
  double energy = beta * W;
  for (int q = 0; q < kernel.quadrature_points; ++q) {
    const Point<D> p(kernel, consts, q, u);
    double U[3];
    bulk(kernel, consts, p.J, U);
    const double* S = fixed_stress_.data() + point_start_[index] + q * d * d;
    double SE = 0.0;  // S_h : E, E = (F^T F - I) / 2
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b) {
        double C = 0.0;
        for (int c = 0; c < d; ++c) C += p.F[c * d + a] * p.F[c * d + b];
        SE += S[a * d + b] * 0.5 * (C - (a == b ? 1.0 : 0.0));
      }
    energy += p.weight * (bulk_extra * U[0] + SE);
  }
  return energy;
}

void ViscousPart::commit(std::span<const double> u, std::vector<double>& history) const {
  history.resize(history_size(), 0.0);
  // Each cell writes its own range of the history: the same bits on any thread count.
#pragma omp parallel for schedule(dynamic, 64) if (cell_count() >= 256)
  for (int v = 0; v < cell_count(); ++v) {
    if (model_->kernel(cells_[v].cell).dim == 2) commit_cell<2>(v, u, history);
    else commit_cell<3>(v, u, history);
  }
}

template <int D>
void ViscousPart::commit_cell(int v, std::span<const double> u, std::vector<double>& history) const {
  double local[kMaxCellDofs], P[kMaxPoints * 9];
  const int cell = cells_[v].cell;
  const tm_kernel& kernel = model_->kernel(cell);
  const double* consts = model_->consts(cell);
  const int series = cells_[v].series, first = term_start_[series], terms = term_start_[series + 1] - first;
  constexpr int d = D, block = D * D;
  model_->gather(cell, u, local);
  kernel.stress(local, consts, P);
  for (int q = 0; q < kernel.quadrature_points; ++q) {
    const Point<D> p(kernel, consts, q, local);
    double U[3];
    bulk(kernel, consts, p.J, U);
    double Finv[9], stresses[2][9];  // S_d = F^-1 P - S_U, S_U = J U'(J) C^-1, C^-1 = F^-1 F^-T
    p.inverse(Finv);
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b) {
        double S = 0.0, Cinv = 0.0;
        for (int c = 0; c < d; ++c) {
          S += Finv[a * d + c] * P[q * block + c * d + b];
          Cinv += Finv[a * d + c] * Finv[b * d + c];
        }
        stresses[1][a * d + b] = p.J * U[1] * Cinv;
        stresses[0][a * d + b] = S - stresses[1][a * d + b];
      }
    double* point = history.data() + history_start_[v] + q * blocks_per_point(series) * block;
    for (int part = 0; part < (relaxes_bulk_[series] ? 2 : 1); ++part) {
      double* terms_h = point + part * (terms + 1) * block;
      double* last = terms_h + terms * block;
      for (int t = 0; t < terms; ++t) {
        const int i = first + t;
        for (int m = 0; m < block; ++m)
          terms_h[t * block + m] = decay_[i] * terms_h[t * block + m] + ramp_[i] * (stresses[part][m] - last[m]);
      }
      std::copy(stresses[part], stresses[part] + block, last);
    }
  }
}

}  // namespace tensormass
