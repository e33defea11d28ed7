#include "tensormass/adaptivity/criteria_screen.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tensormass {

namespace {

/// Round-off of H per side, in metres per metre of |u| (about N eps for N <= 27 nodes, with room).
constexpr double kGradientRoundOff = 1e-13;
/// Round-off of a computed value, relative to the value and the boundary.
constexpr double kValueRoundOff = 1e-12;
/// Round-off of a chunk's running motion, relative to it.
constexpr double kRunningRoundOff = 1e-12;
/// The expiry of a cell (or chunk) whose values are unknown: it is evaluated.
constexpr double kUnknown = -std::numeric_limits<double>::infinity();

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

// Per point the constants hold the weight, then G^T: D rows of `nodes` (kernel_abi.h).
double shape_gradient_sum(const Model& model, int cell) {
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

CriteriaScreen::CriteriaScreen(const Model& model, std::vector<const Criterion*> criteria,
                               std::vector<double> thresholds, double hysteresis)
    : model_(&model), criteria_(std::move(criteria)), thresholds_(std::move(thresholds)), hysteresis_(hysteresis) {
  if (!applies(criteria_)) throw std::invalid_argument("CriteriaScreen: a criterion cannot be screened");
  if (thresholds_.size() != criteria_.size())
    throw std::invalid_argument("CriteriaScreen: one threshold per criterion expected");
  const int cells = model.cell_count(), nodes = model.mesh().node_count();
  cells_.resize(cells);
  for (int cell = 0; cell < cells; ++cell) cells_[cell] = {kUnknown, 1.0 / shape_gradient_sum(model, cell)};
  build_chunks();
  reference_.assign(model.dof_count(), 0.0);
  delta_.assign(model.dof_count(), 0.0);
  length_.assign(nodes, 0.0);
}

void CriteriaScreen::build_chunks() {
  const int cells = model_->cell_count();
  const int chunks = (cells + kChunkCells - 1) / kChunkCells;
  chunk_node_offsets_.assign(1, 0);
  for (int chunk = 0; chunk < chunks; ++chunk) {
    const int first = chunk * kChunkCells, last = std::min(cells, first + kChunkCells);
    chunk_first_.push_back(first);
    std::vector<int> nodes;
    for (int cell = first; cell < last; ++cell)
      for (int node : model_->cell_nodes(cell)) nodes.push_back(node);
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    chunk_nodes_.insert(chunk_nodes_.end(), nodes.begin(), nodes.end());
    chunk_node_offsets_.push_back(static_cast<int>(chunk_nodes_.size()));
  }
  chunk_first_.push_back(cells);
  chunk_motion_.assign(chunks, 0.0);
  chunk_expiry_.assign(chunks, kUnknown);
}

bool CriteriaScreen::applies(std::span<const Criterion* const> criteria) {
  return !criteria.empty() &&
         std::all_of(criteria.begin(), criteria.end(), [](const Criterion* c) { return c->screenable(); });
}

void CriteriaScreen::reset() {
  for (CellSlack& cell : cells_) cell.expiry = kUnknown;
  std::fill(chunk_expiry_.begin(), chunk_expiry_.end(), kUnknown);
}

void CriteriaScreen::forget(int cell) {
  cells_[cell].expiry = kUnknown;
  chunk_expiry_[cell / kChunkCells] = kUnknown;
}

void CriteriaScreen::select(std::span<const double> u, std::span<const unsigned char> movable,
                            std::span<unsigned char> flags) {
  measure_nodes(u);
  const int chunks = static_cast<int>(chunk_motion_.size());
  long evaluated = 0;
#pragma omp for schedule(static) nowait
  for (int chunk = 0; chunk < chunks; ++chunk) evaluated += flag_chunk(chunk, movable, flags);
#pragma omp atomic
  evaluated_ += evaluated;
#pragma omp single
  ++evaluations_;  // and the barrier at the end of `single`
}

void CriteriaScreen::measure_nodes(std::span<const double> u) {
  const int d = model_->dim(), nodes = static_cast<int>(length_.size());
#pragma omp for schedule(static)
  for (int node = 0; node < nodes; ++node) {
    double length2 = 0.0;
    for (int a = 0; a < d; ++a) {
      const std::size_t dof = static_cast<std::size_t>(node) * d + a;
      delta_[dof] = u[dof] - reference_[dof];
      length2 += u[dof] * u[dof];
      reference_[dof] = u[dof];
    }
    length_[node] = std::sqrt(length2);
  }
}

double CriteriaScreen::chunk_motion(int chunk) const {
  // sum_j grad N_j = 0, so delta H = sum_j (du_j - w) grad N_j for any w:
  // the middle of the chunk's node motions takes out what they share.
  const int d = model_->dim(), first = chunk_node_offsets_[chunk], last = chunk_node_offsets_[chunk + 1];
  double low[3] = {0, 0, 0}, high[3] = {0, 0, 0};
  for (int a = 0; a < d; ++a) low[a] = high[a] = delta_[static_cast<std::size_t>(chunk_nodes_[first]) * d + a];
  for (int n = first + 1; n < last; ++n)
    for (int a = 0; a < d; ++a) {
      const double value = delta_[static_cast<std::size_t>(chunk_nodes_[n]) * d + a];
      low[a] = std::min(low[a], value);
      high[a] = std::max(high[a], value);
    }
  double motion = 0.0;
  for (int n = first; n < last; ++n) {
    const int node = chunk_nodes_[n];
    double squared = 0.0;
    for (int a = 0; a < d; ++a) {
      const double relative = delta_[static_cast<std::size_t>(node) * d + a] - 0.5 * (low[a] + high[a]);
      squared += relative * relative;
    }
    motion = std::max(motion, std::sqrt(squared) + kGradientRoundOff * length_[node]);
  }
  return motion;
}

int CriteriaScreen::flag_chunk(int chunk, std::span<const unsigned char> movable, std::span<unsigned char> flags) {
  const double running = chunk_motion_[chunk] += chunk_motion(chunk);
  const int first = chunk_first_[chunk], last = chunk_first_[chunk + 1];
  if (running < chunk_expiry_[chunk]) {  // every cell keeps its values
    std::fill(flags.begin() + first, flags.begin() + last, kScreenKeep);
    return 0;
  }
  double earliest = std::numeric_limits<double>::infinity();  // settle() lowers it for the cells evaluated
  int evaluated = 0;
  for (int cell = first; cell < last; ++cell) {
    const bool keep = !movable[cell] || running < cells_[cell].expiry;
    flags[cell] = keep ? kScreenKeep : kScreenEvaluate;
    if (keep && movable[cell]) earliest = std::min(earliest, cells_[cell].expiry);
    evaluated += !keep;
  }
  chunk_expiry_[chunk] = earliest;
  return evaluated;
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
  CellSlack& slot = cells_[cell];
  const double slack = gradient_change_allowed(cell, values) * slot.inverse_gradient_sum - kGradientRoundOff * length;
  const int chunk = cell / kChunkCells;
  const double running = chunk_motion_[chunk];
  // The running sum's own round-off over many evaluations is far below 1e-12 of it.
  const double expiry = slack > 0.0 ? running + slack - kRunningRoundOff * running : kUnknown;  // NaN too
  slot.expiry = expiry;
  std::atomic_ref<double> earliest(chunk_expiry_[chunk]);  // cells of one chunk may settle on two threads
  double seen = earliest.load(std::memory_order_relaxed);
  while (expiry < seen && !earliest.compare_exchange_weak(seen, expiry, std::memory_order_relaxed)) {
  }
}

}  // namespace tensormass
