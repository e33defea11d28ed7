#include "tensormass/adaptivity/criteria_screen.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tensormass {

namespace {

/// Round-off of H per side, in metres per metre of |u| (about N eps for N <= 27 nodes, with room).
constexpr double kGradientRoundOff = 1e-13;
/// Round-off of a computed value, relative to the value and the boundary.
constexpr double kValueRoundOff = 1e-12;

/// G = max_q sum_j |grad N_j(x_q)|: the rest gradients of the cell's constants
/// (per point: the weight, then G^T, D rows of `nodes`; kernel_abi.h).
double gradient_sum(const Model& model, int cell) {
  const tm_kernel& kernel = model.kernel(cell);
  const int d = model.dim(), nodes = kernel.nodes, stride = 1 + d * nodes;
  const double* points = model.consts(cell) + kernel.derived_params;
  double largest = 0.0;
  for (int q = 0; q < kernel.quadrature_points; ++q) {
    const double* gradients_t = points + q * stride + 1;
    double sum = 0.0;
    for (int j = 0; j < nodes; ++j) {
      double squared = 0.0;
      for (int c = 0; c < d; ++c) squared += gradients_t[c * nodes + j] * gradients_t[c * nodes + j];
      sum += std::sqrt(squared);
    }
    largest = std::max(largest, sum);
  }
  return largest;
}

/// The delta at which a delta + delta^2 / 2 reaches margin m (0 when m <= 0).
double change_reaching(double slope, double margin) {
  if (!(margin > 0.0)) return 0.0;
  return 2.0 * margin / (slope + std::sqrt(slope * slope + 2.0 * margin));
}

/// Distance from value to boundary, less the round-off of both.
double margin_to(double value, double boundary) {
  return std::fabs(value - boundary) - kValueRoundOff * (std::fabs(value) + std::fabs(boundary));
}

}  // namespace

CriteriaScreen::CriteriaScreen(const Model& model, std::vector<const Criterion*> criteria,
                               std::vector<double> thresholds, double hysteresis)
    : model_(&model), criteria_(std::move(criteria)), thresholds_(std::move(thresholds)), hysteresis_(hysteresis) {
  if (!applies(criteria_)) throw std::invalid_argument("CriteriaScreen: a criterion cannot be screened");
  if (thresholds_.size() != criteria_.size())
    throw std::invalid_argument("CriteriaScreen: one threshold per criterion expected");
  const int cells = model.cell_count(), nodes = model.mesh().node_count();
  gradient_sum_.resize(cells);
  for (int cell = 0; cell < cells; ++cell) gradient_sum_[cell] = gradient_sum(model, cell);
  slack_.assign(cells, -1.0);
  reference_.assign(model.dof_count(), 0.0);
  motion_.assign(nodes, 0.0);
  length_.assign(nodes, 0.0);
}

bool CriteriaScreen::applies(std::span<const Criterion* const> criteria) {
  return !criteria.empty() &&
         std::all_of(criteria.begin(), criteria.end(), [](const Criterion* c) { return c->screenable(); });
}

void CriteriaScreen::reset() { std::fill(slack_.begin(), slack_.end(), -1.0); }

void CriteriaScreen::measure(std::span<const double> u) {
  const int d = model_->dim(), nodes = static_cast<int>(motion_.size());
#pragma omp for schedule(static)
  for (int node = 0; node < nodes; ++node) {
    double drift2 = 0.0, length2 = 0.0;
    for (int a = 0; a < d; ++a) {
      const std::size_t dof = static_cast<std::size_t>(node) * d + a;
      const double delta = u[dof] - reference_[dof];
      drift2 += delta * delta;
      length2 += u[dof] * u[dof];
      reference_[dof] = u[dof];
    }
    length_[node] = std::sqrt(length2);
    motion_[node] = std::sqrt(drift2) + kGradientRoundOff * length_[node];
  }
}

void CriteriaScreen::flag_block(const ElementBlock& block, std::span<const unsigned char> movable,
                                std::span<unsigned char> flags) {
  long evaluated = 0;
#pragma omp for schedule(static) nowait
  for (int local = 0; local < block.count(); ++local) {
    const int cell = block.first_cell + local;
    if (!movable[cell]) {
      flags[cell] = kScreenIdle;
      slack_[cell] = -1.0;
      continue;
    }
    if (slack_[cell] > 0.0) {  // what the last interval used of it (with the round-off of this evaluation)
      double motion = 0.0;
      for (int node : model_->cell_nodes(cell)) motion = std::max(motion, motion_[node]);
      slack_[cell] -= motion;
    }
    const bool keep = slack_[cell] > 0.0;
    flags[cell] = keep ? kScreenKeep : kScreenEvaluate;
    evaluated += !keep;
  }
#pragma omp atomic
  evaluated_ += evaluated;
}

double CriteriaScreen::gradient_change_allowed(int cell, const std::vector<std::vector<double>>& values) const {
  const int d = model_->dim();
  double h = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < criteria_.size(); ++c)
    h = std::min(h, criteria_[c]->gradient_norm_bound(values[c][cell], d));
  if (!std::isfinite(h)) return 0.0;
  double allowed = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < criteria_.size(); ++c) {
    const double value = values[c][cell];
    double margin = margin_to(value, thresholds_[c]);
    if (hysteresis_ > 0.0) margin = std::min(margin, margin_to(value, thresholds_[c] * hysteresis_));
    allowed = std::min(allowed, change_reaching(criteria_[c]->change_slope(h), margin));
  }
  return allowed;
}

void CriteriaScreen::settle(int cell, const std::vector<std::vector<double>>& values) {
  double length = 0.0;
  for (int node : model_->cell_nodes(cell)) length = std::max(length, length_[node]);
  const double slack = gradient_change_allowed(cell, values) / gradient_sum_[cell] - kGradientRoundOff * length;
  slack_[cell] = slack > 0.0 ? slack : -1.0;  // NaN too
}

}  // namespace tensormass
