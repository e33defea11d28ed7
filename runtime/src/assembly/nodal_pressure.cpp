#include "tensormass/assembly/nodal_pressure.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <tuple>

#include "tensormass/kernels/mean_dilatation.hpp"

namespace tensormass {

namespace {

constexpr int kParallelCells = 4096;

/// d2J/du_a du_b (d by d) of nodes a, b with shape gradients g_a, g_b:
/// eps_ijm (F (g_a x g_b))_m in 3D, eps_ij (g_a x g_b)_z in 2D.
void second_derivative_block(int d, const double* F, const double* ga, const double* gb, double* M) {
  if (d == 2) {
    const double s = ga[0] * gb[1] - ga[1] * gb[0];
    M[0] = 0.0, M[1] = s, M[2] = -s, M[3] = 0.0;
    return;
  }
  const double c[3] = {ga[1] * gb[2] - ga[2] * gb[1], ga[2] * gb[0] - ga[0] * gb[2], ga[0] * gb[1] - ga[1] * gb[0]};
  double v[3];
  for (int i = 0; i < 3; ++i) v[i] = F[i * 3] * c[0] + F[i * 3 + 1] * c[1] + F[i * 3 + 2] * c[2];
  M[0] = 0.0, M[1] = v[2], M[2] = -v[1];
  M[3] = -v[2], M[4] = 0.0, M[5] = v[0];
  M[6] = v[1], M[7] = -v[0], M[8] = 0.0;
}

}  // namespace

NodalPressure::NodalPressure(const Model& model) : model_(&model) {
  std::vector<std::tuple<int, int, int, int>> entries;  // (node, material, anp cell, corner)
  corner_start_.assign(1, 0);
  point_start_.assign(1, 0);
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const tm_kernel& kernel = model.kernel(cell);
    if (!nodal_pressure_split(kernel)) continue;
    if (kernel.dofs > kCellDofs) throw std::logic_error("NodalPressure: an anp kernel with more than 18 dofs");
    const int index = static_cast<int>(cells_.size());
    cells_.push_back(cell);
    const double* points = model.consts(cell) + kernel.derived_params;
    double volume = 0.0;  // the points' w_q det J_q
    for (int q = 0; q < kernel.quadrature_points; ++q) volume += points[q * (1 + kernel.dim * kernel.nodes)];
    rest_volume_.push_back(volume);
    point_start_.push_back(point_start_.back() + kernel.quadrature_points);
    const auto nodes = model.cell_nodes(cell);
    for (int k = 0; k < static_cast<int>(nodes.size()); ++k)
      entries.emplace_back(nodes[k], model.material(cell), index, k);
    corner_start_.push_back(corner_start_.back() + static_cast<int>(nodes.size()));
  }
  if (cells_.empty()) return;
  std::sort(entries.begin(), entries.end());
  corner_patch_.assign(corner_start_.back(), -1);
  patch_start_.assign(1, 0);
  patch_cell_start_.assign(1, 0);
  pair_local_start_.assign(1, 0);
  const int node_count = model.mesh().node_count();
  node_first_patch_.assign(node_count + 1, 0);
  for (std::size_t first = 0; first < entries.size();) {
    const int node = std::get<0>(entries[first]), material = std::get<1>(entries[first]);
    std::size_t last = first;
    while (last < entries.size() && std::get<0>(entries[last]) == node && std::get<1>(entries[last]) == material)
      ++last;
    const int patch = patch_count();
    std::vector<int> nodes;
    double volume = 0.0;
    for (std::size_t k = first; k < last; ++k) {
      const int e = std::get<2>(entries[k]), corner = std::get<3>(entries[k]);
      const auto cell_nodes = model.cell_nodes(cells_[e]);
      nodes.insert(nodes.end(), cell_nodes.begin(), cell_nodes.end());
      volume += rest_volume_[e] / corners(e);
      patch_cells_.push_back(e);
      pair_corner_.push_back(corner);
      corner_patch_[corner_start_[e] + corner] = patch;
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    for (std::size_t k = first; k < last; ++k) {
      for (int cell_node : model.cell_nodes(cells_[std::get<2>(entries[k])]))
        pair_local_.push_back(
            static_cast<int>(std::lower_bound(nodes.begin(), nodes.end(), cell_node) - nodes.begin()));
      pair_local_start_.push_back(static_cast<int>(pair_local_.size()));
    }
    patch_nodes_.insert(patch_nodes_.end(), nodes.begin(), nodes.end());
    patch_start_.push_back(static_cast<int>(patch_nodes_.size()));
    patch_cell_start_.push_back(static_cast<int>(patch_cells_.size()));
    patch_node_.push_back(node);
    patch_volume_.push_back(volume);
    ++node_first_patch_[node + 1];
    first = last;
  }
  for (int node = 0; node < node_count; ++node) node_first_patch_[node + 1] += node_first_patch_[node];
  // The patches holding each node, in patch order.
  node_patch_start_.assign(node_count + 1, 0);
  for (int node : patch_nodes_) ++node_patch_start_[node + 1];
  for (int node = 0; node < node_count; ++node) node_patch_start_[node + 1] += node_patch_start_[node];
  node_patches_.resize(patch_nodes_.size());
  node_patch_local_.resize(patch_nodes_.size());
  std::vector<int> next(node_patch_start_.begin(), node_patch_start_.end() - 1);
  for (int patch = 0; patch < patch_count(); ++patch)
    for (int k = patch_start_[patch]; k < patch_start_[patch + 1]; ++k) {
      const int slot = next[patch_nodes_[k]]++;
      node_patches_[slot] = patch;
      node_patch_local_[slot] = k - patch_start_[patch];
    }
}

bool NodalPressure::patch_changes(int patch) const {
  for (int k = patch_cell_start_[patch]; k < patch_cell_start_[patch + 1]; ++k) {
    const int cell = cells_[patch_cells_[k]];
    if (!model_->kernel(cell).linear || model_->blend_from(cell)) return true;
  }
  return false;
}

namespace {

/// J, dJ/du (n by d) and F (d by d) of a one-point cell of D dims and N
/// nodes: loops of fixed length the compiler unrolls.
template <int D, int N>
void one_point_kinematics(bool linear, const double* local, const double* GT, double& J, double* dJ, double* F) {
  for (int i = 0; i < D; ++i)
    for (int c = 0; c < D; ++c) {
      double sum = i == c ? 1.0 : 0.0;
      for (int j = 0; j < N; ++j) sum += local[j * D + i] * GT[c * N + j];
      F[i * D + c] = sum;
    }
  if (linear) {  // J = 1 + tr(H), dJ/du_ji = G_ji
    J = 1.0;
    for (int i = 0; i < D; ++i) J += F[i * D + i] - 1.0;
    for (int j = 0; j < N; ++j)
      for (int i = 0; i < D; ++i) dJ[j * D + i] = GT[i * N + j];
    return;
  }
  double cof[9];
  J = kernel::mean_dilatation::finite_strain::cofactor<D>(F, cof);  // det F
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < D; ++i) {
      double sum = 0.0;
      for (int c = 0; c < D; ++c) sum += cof[i * D + c] * GT[c * N + j];
      dJ[j * D + i] = sum;
    }
}

}  // namespace

void NodalPressure::cell_kinematics(int cell, const double* local, double& J, double* dJ, double* F) const {
  const tm_kernel& kernel = model_->kernel(cell);
  const int d = kernel.dim, n = kernel.nodes, stride = 1 + d * n;
  const double* points = model_->consts(cell) + kernel.derived_params;
  if (kernel.quadrature_points == 1 && d == 3 && n == 4)
    return one_point_kinematics<3, 4>(kernel.linear, local, points + 1, J, dJ, F);
  if (kernel.quadrature_points == 1 && d == 2 && n == 3)
    return one_point_kinematics<2, 3>(kernel.linear, local, points + 1, J, dJ, F);
  // Several points (an fbar base): J = J̄ = sum_q w_q J_q / V and its derivative.
  double volume = 0.0, point_J, point_dJ[kCellDofs];
  J = 0.0;
  std::fill(dJ, dJ + n * d, 0.0);
  for (int q = 0; q < kernel.quadrature_points; ++q) {
    const double* point = points + q * stride;
    if (d == 3) one_point_kinematics<3, 6>(kernel.linear, local, point + 1, point_J, point_dJ, F + q * 9);
    else throw std::logic_error(std::string("NodalPressure: no kinematics for ") + kernel.element);
    volume += point[0];
    J += point[0] * point_J;
    for (int k = 0; k < n * d; ++k) dJ[k] += point[0] * point_dJ[k];
  }
  J /= volume;
  for (int k = 0; k < n * d; ++k) dJ[k] /= volume;
}

/// d2J_e/du_a du_b (d by d) into block: the points' blocks weighted by w_q / V_e.
void NodalPressure::second_derivative(int e, int a, int b, double* block) const {
  const tm_kernel& kernel = model_->kernel(cells_[e]);
  const int d = kernel.dim, n = kernel.nodes, stride = 1 + d * n;
  const double* points = model_->consts(cells_[e]) + kernel.derived_params;
  std::fill(block, block + d * d, 0.0);
  double point_block[9], ga[3], gb[3];
  for (int q = 0; q < kernel.quadrature_points; ++q) {
    const double* GT = points + q * stride + 1;
    for (int c = 0; c < d; ++c) ga[c] = GT[c * n + a], gb[c] = GT[c * n + b];
    second_derivative_block(d, &F_[static_cast<std::size_t>(point_start_[e] + q) * 9], ga, gb, point_block);
    const double share = points[q * stride] / rest_volume_[e];
    for (int m = 0; m < d * d; ++m) block[m] += share * point_block[m];
  }
}

void NodalPressure::cell_bulk(int cell, double J, double* out) const {
  const tm_kernel& kernel = model_->kernel(cell);
  const double* consts = model_->consts(cell);
  kernel.bulk(J, consts, out);
  const tm_kernel* before = model_->blend_from(cell);
  if (!before) return;
  const double w = model_->blend_weight(cell);
  double old[3] = {0.0, 0.0, 0.0};
  if (before->bulk) before->bulk(J, consts, old);
  for (int k = 0; k < 3; ++k) out[k] = w * out[k] + (1.0 - w) * old[k];
}

void NodalPressure::update_uniform_patches() const {
  const std::pair<long, long> revision{model_->law_revision(), model_->consts_revision()};
  if (revision == uniform_revision_ && !uniform_.empty()) return;
  uniform_.resize(patch_count());
  for (int patch = 0; patch < patch_count(); ++patch) uniform_[patch] = uniform_patch(patch);
  uniform_revision_ = revision;
}

bool NodalPressure::uniform_patch(int patch) const {
  const Model& model = *model_;
  const int first = cells_[patch_cells_[patch_cell_start_[patch]]];
  const tm_kernel& kernel = model.kernel(first);
  const double* consts = model.consts(first);
  for (int k = patch_cell_start_[patch] + 1; k < patch_cell_start_[patch + 1]; ++k) {
    const int cell = cells_[patch_cells_[k]];
    if (&model.kernel(cell) != &kernel || model.blend_from(cell) != model.blend_from(first) ||
        model.blend_weight(cell) != model.blend_weight(first) ||
        !std::equal(consts, consts + kernel.derived_params, model.consts(cell)))
      return false;
  }
  return true;
}

void NodalPressure::evaluate(std::span<const double> u) const {
  const Model& model = *model_;
  const int count = static_cast<int>(cells_.size()), patches = patch_count();
  for (auto* values : {&J_, &U_, &dU_, &d2U_, &coefficient_, &geometric_}) values->resize(count);
  dJ_.resize(static_cast<std::size_t>(corner_start_.back()) * model.dim());
  F_.resize(static_cast<std::size_t>(point_start_.back()) * 9);
  for (auto* values : {&JA_, &pA_, &kA_}) values->resize(patches);
  update_uniform_patches();
#pragma omp parallel for schedule(static) if (count >= kParallelCells)
  for (int e = 0; e < count; ++e) {
    double local[kMaxCellDofs], bulk[3];
    model.gather(cells_[e], u, local);
    cell_kinematics(cells_[e], local, J_[e], cell_dJ(e), &F_[static_cast<std::size_t>(point_start_[e]) * 9]);
    cell_bulk(cells_[e], J_[e], bulk);
    U_[e] = bulk[0], dU_[e] = bulk[1], d2U_[e] = bulk[2];
  }
#pragma omp parallel for schedule(static) if (count >= kParallelCells)
  for (int patch = 0; patch < patches; ++patch) {
    double sum = 0.0;
    for (int k = patch_cell_start_[patch]; k < patch_cell_start_[patch + 1]; ++k) {
      const int e = patch_cells_[k];
      sum += rest_volume_[e] / corners(e) * J_[e];
    }
    const double JA = sum / patch_volume_[patch];
    double p = 0.0, stiffness = 0.0, bulk[3];
    if (uniform_[patch]) {  // one U for the patch: p_A = U'(J_A), k_A = U''(J_A)
      cell_bulk(cells_[patch_cells_[patch_cell_start_[patch]]], JA, bulk);
      p = bulk[1] * patch_volume_[patch], stiffness = bulk[2] * patch_volume_[patch];
    } else {
      for (int k = patch_cell_start_[patch]; k < patch_cell_start_[patch + 1]; ++k) {
        const int e = patch_cells_[k];
        const double share = rest_volume_[e] / corners(e);
        cell_bulk(cells_[e], JA, bulk);
        p += share * bulk[1];
        stiffness += share * bulk[2];
      }
    }
    JA_[patch] = JA;
    pA_[patch] = p / patch_volume_[patch];
    kA_[patch] = stiffness / patch_volume_[patch];
  }
#pragma omp parallel for schedule(static) if (count >= kParallelCells)
  for (int e = 0; e < count; ++e) {
    double mean = 0.0;
    for (int k = corner_start_[e]; k < corner_start_[e + 1]; ++k) mean += pA_[corner_patch_[k]];
    const double pressure = mean / corners(e);
    coefficient_[e] = rest_volume_[e] * (pressure - dU_[e]);
    // The pressure's geometric stiffness p d2J is indefinite; where |p|
    // exceeds the cell's modulus (Newton's first iterates near nu = 1/2,
    // whose linearised volume errors lambda amplifies) it is scaled down to
    // that size, so that the tangent stays near positive definite there.
    const double cap = model.cell_modulus(cells_[e]);
    const double scaled = std::abs(pressure) > cap ? std::copysign(cap, pressure) : pressure;
    geometric_[e] = rest_volume_[e] * (scaled - dU_[e]);
  }
}

double NodalPressure::energy(std::span<const double> u) const {
  if (empty()) return 0.0;
  evaluate(u);
  double total = 0.0, bulk[3];
  for (std::size_t e = 0; e < cells_.size(); ++e) total -= rest_volume_[e] * U_[e];
  for (int patch = 0; patch < patch_count(); ++patch)
    for (int k = patch_cell_start_[patch]; k < patch_cell_start_[patch + 1]; ++k) {
      const int e = patch_cells_[k];
      cell_bulk(cells_[e], JA_[patch], bulk);
      total += rest_volume_[e] / corners(e) * bulk[0];
    }
  return total;
}

void NodalPressure::build_positions(const SparseMatrix& stiffness) const {
  const Model& model = *model_;
  const int d = model.dim();
  const auto& free_index = model.free_index();
  const auto first_free = [&](int node) {
    for (int c = 0; c < d; ++c)
      if (free_index[node * d + c] >= 0) return free_index[node * d + c];
    return -1;
  };
  pair_start_.assign(1, 0);
  pair_position_.clear();
  for (int patch = 0; patch < patch_count(); ++patch) {
    const auto nodes = patch_nodes(patch);
    for (int a : nodes)
      for (int b : nodes) {
        const int row = first_free(a), column = first_free(b);
        int position = -1;
        if (row >= 0 && column >= 0) {
          const auto begin = stiffness.columns.begin() + stiffness.row_start[row];
          const auto end = stiffness.columns.begin() + stiffness.row_start[row + 1];
          const auto found = std::lower_bound(begin, end, column);
          if (found == end || *found != column)
            throw std::logic_error("NodalPressure: the stiffness pattern does not couple a patch's nodes");
          position = static_cast<int>(found - stiffness.columns.begin());
        }
        pair_position_.push_back(position);
      }
    pair_start_.push_back(pair_position_.size());
  }
  positions_row_start_ = stiffness.row_start;
  full_row_length_.assign(model.mesh().node_count(), 0);
  for (int node = 0; node < model.mesh().node_count(); ++node)
    if (std::all_of(&free_index[node * d], &free_index[node * d] + d, [](int i) { return i >= 0; })) {
      const int row = free_index[node * d];
      full_row_length_[node] = stiffness.row_start[row + 1] - stiffness.row_start[row];
    }
}

void NodalPressure::add_block(SparseMatrix& stiffness, int patch, int a, int b, const double* block) const {
  const auto nodes = patch_nodes(patch);
  const int position = pair_position_[pair_start_[patch] + static_cast<std::size_t>(a) * nodes.size() + b];
  if (position < 0) return;
  const int d = model_->dim();
  if (const int length = full_row_length_[nodes[a]]; length > 0 && full_row_length_[nodes[b]] > 0) {
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < d; ++j) stiffness.values[position + i * length + j] += block[i * d + j];
    return;
  }
  const auto& free_index = model_->free_index();
  const int* rows = &free_index[nodes[a] * d];
  const int* columns = &free_index[nodes[b] * d];
  const int first_row = *std::find_if(rows, rows + d, [](int r) { return r >= 0; });
  const int row_length = stiffness.row_start[first_row + 1] - stiffness.row_start[first_row];
  for (int i = 0, r = 0; i < d; ++i) {
    if (rows[i] < 0) continue;
    for (int j = 0, c = 0; j < d; ++j) {
      if (columns[j] < 0) continue;
      stiffness.values[position + r * row_length + c] += block[i * d + j];
      ++c;
    }
    ++r;
  }
}

void NodalPressure::assemble_node(int node, std::span<double> gradient, SparseMatrix* stiffness) const {
  const Model& model = *model_;
  const int d = model.dim();
  double block[9];
  // The cells around the node: its force and its rows of their element blocks.
  for (int patch = node_first_patch_[node]; patch < node_first_patch_[node + 1]; ++patch)
    for (int k = patch_cell_start_[patch]; k < patch_cell_start_[patch + 1]; ++k) {
      const int e = patch_cells_[k], cell = cells_[e], n = corners(e), a = pair_corner_[k];
      const double* g = cell_dJ(e);
      for (int i = 0; i < d; ++i) gradient[node * d + i] += coefficient_[e] * g[a * d + i];
      if (!stiffness) continue;
      const bool linear = model.kernel(cell).linear;
      const int* in_patch = &pair_local_[pair_local_start_[k]];
      const double curvature = rest_volume_[e] * d2U_[e];
      for (int b = 0; b < n; ++b) {
        std::fill(block, block + d * d, 0.0);
        if (!linear) {
          second_derivative(e, a, b, block);
          for (int m = 0; m < d * d; ++m) block[m] *= geometric_[e];
        }
        for (int i = 0; i < d; ++i)
          for (int j = 0; j < d; ++j) block[i * d + j] -= curvature * g[a * d + i] * g[b * d + j];
        add_block(*stiffness, patch, in_patch[a], in_patch[b], block);
      }
    }
  if (!stiffness) return;
  // The rank-one terms of the patches holding the node: its rows of them.
  for (int slot = node_patch_start_[node]; slot < node_patch_start_[node + 1]; ++slot) {
    const int patch = node_patches_[slot], a = node_patch_local_[slot];
    const int size = patch_start_[patch + 1] - patch_start_[patch];
    const double* w = &w_[static_cast<std::size_t>(patch_start_[patch]) * d];
    const double scale = kA_[patch] / patch_volume_[patch];
    for (int b = 0; b < size; ++b) {
      for (int i = 0; i < d; ++i)
        for (int j = 0; j < d; ++j) block[i * d + j] = scale * w[a * d + i] * w[b * d + j];
      add_block(*stiffness, patch, a, b, block);
    }
  }
}

void NodalPressure::assemble(std::span<const double> u, std::span<double> gradient, SparseMatrix* stiffness) const {
  if (empty()) return;
  const Model& model = *model_;
  const int d = model.dim();
  evaluate(u);
  const int count = static_cast<int>(cells_.size()), patches = patch_count();
  if (stiffness) {
    if (stiffness->row_start != positions_row_start_) build_positions(*stiffness);
    // w_A = sum_{e in A} (V_e / n_e) dJ_e/du over the patch's nodes.
    w_.assign(patch_nodes_.size() * d, 0.0);
#pragma omp parallel for schedule(static) if (count >= kParallelCells)
    for (int patch = 0; patch < patches; ++patch) {
      double* w = &w_[static_cast<std::size_t>(patch_start_[patch]) * d];
      for (int k = patch_cell_start_[patch]; k < patch_cell_start_[patch + 1]; ++k) {
        const int e = patch_cells_[k], n = corners(e);
        const double share = rest_volume_[e] / n;
        const int* in_patch = &pair_local_[pair_local_start_[k]];
        const double* g = cell_dJ(e);
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < d; ++i) w[in_patch[j] * d + i] += share * g[j * d + i];
      }
    }
  }
  const int nodes = model.mesh().node_count();
#pragma omp parallel for schedule(dynamic, 256) if (count >= kParallelCells)
  for (int node = 0; node < nodes; ++node)
    if (node_first_patch_[node] < node_first_patch_[node + 1] || node_patch_start_[node] < node_patch_start_[node + 1])
      assemble_node(node, gradient, stiffness);
}

}  // namespace tensormass
