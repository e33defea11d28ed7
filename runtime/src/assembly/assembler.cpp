#include "tensormass/assembler.hpp"

#include <algorithm>

namespace tensormass {

namespace {
constexpr int kMaxDofs = 81;  // hex20 in 3D is 60; 27 nodes by 3 leaves room
constexpr int kParallelCells = 4096;


/// g = w g_new + (1 - w) g_old (and the same for K) for a blending cell.
void blend_cell(const Model& model, int cell, const double* u, double* g, double* K, double* old_g,
                std::vector<double>& old_K) {
  const tm_kernel& now = model.kernel(cell);
  const tm_kernel& before = *model.blend_from(cell);
  const double w = model.blend_weight(cell);
  const int dofs = now.dofs;
  if (K) {
    old_K.resize(static_cast<std::size_t>(dofs) * dofs);
    now.gradient_hessian(u, model.consts(cell), g, K);
    before.gradient_hessian(u, model.consts(cell), old_g, old_K.data());
    for (int e = 0; e < dofs * dofs; ++e) K[e] = w * K[e] + (1 - w) * old_K[e];
  } else {
    now.gradient(u, model.consts(cell), g);
    before.gradient(u, model.consts(cell), old_g);
  }
  for (int i = 0; i < dofs; ++i) g[i] = w * g[i] + (1 - w) * old_g[i];
}

}  // namespace

Assembler::Assembler(const Model& model) : model_(&model) {
  build_pattern();
  build_colours();
}

void Assembler::build_pattern() {
  const Model& model = *model_;
  const int d = model.dim();
  const int nodes = model.mesh().node_count();
  std::vector<std::vector<int>> neighbours(nodes);
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const auto cn = model.cell_nodes(cell);
    for (int a : cn) neighbours[a].insert(neighbours[a].end(), cn.begin(), cn.end());
  }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  const auto& free_index = model.free_index();
  SparseMatrix& m = pattern_;
  m.rows = model.free_dof_count();
  m.row_start.assign(1, 0);
  m.diagonal.assign(m.rows, -1);
  for (int dof : model.free_dofs()) {
    const int row = free_index[dof];
    for (int neighbour : neighbours[dof / d])
      for (int b = 0; b < d; ++b) {
        const int column = free_index[neighbour * d + b];
        if (column < 0) continue;
        if (column == row) m.diagonal[row] = static_cast<int>(m.columns.size());
        m.columns.push_back(column);
      }
    m.row_start.push_back(static_cast<int>(m.columns.size()));
  }
  m.values.assign(m.columns.size(), 0.0);
  // Scatter map: each entry of each cell's dense Hessian -> index in values.
  scatter_offsets_.assign(1, 0);
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const auto cn = model.cell_nodes(cell);
    const int dofs = static_cast<int>(cn.size()) * d;
    for (int i = 0; i < dofs; ++i) {
      const int row = free_index[cn[i / d] * d + i % d];
      for (int j = 0; j < dofs; ++j) {
        const int column = free_index[cn[j / d] * d + j % d];
        int position = -1;
        if (row >= 0 && column >= 0) {
          const auto begin = m.columns.begin() + m.row_start[row], end = m.columns.begin() + m.row_start[row + 1];
          position = static_cast<int>(std::lower_bound(begin, end, column) - m.columns.begin());
        }
        scatter_.push_back(position);
      }
    }
    scatter_offsets_.push_back(scatter_.size());
  }
}

void Assembler::build_colours() {
  // Greedy colouring: no two cells of a colour share a node.
  const Model& model = *model_;
  const int cells = model.cell_count();
  std::vector<std::vector<int>> node_cells(model.mesh().node_count());
  for (int cell = 0; cell < cells; ++cell)
    for (int node : model.cell_nodes(cell)) node_cells[node].push_back(cell);
  std::vector<int> colour(cells, -1);
  std::vector<int> used_by;  // used_by[c] == cell: colour c is taken by a neighbour of cell
  int colours = 0;
  for (int cell = 0; cell < cells; ++cell) {
    for (int node : model.cell_nodes(cell))
      for (int other : node_cells[node])
        if (colour[other] >= 0) used_by[colour[other]] = cell;
    int c = 0;
    while (c < colours && used_by[c] == cell) ++c;
    if (c == colours) {
      ++colours;
      used_by.push_back(-1);
    }
    colour[cell] = c;
  }
  colour_start_.assign(colours + 1, 0);
  for (int cell = 0; cell < cells; ++cell) ++colour_start_[colour[cell] + 1];
  for (int c = 0; c < colours; ++c) colour_start_[c + 1] += colour_start_[c];
  coloured_cells_.resize(cells);
  std::vector<int> next(colour_start_.begin(), colour_start_.end() - 1);
  for (int cell = 0; cell < cells; ++cell) coloured_cells_[next[colour[cell]]++] = cell;
}

void Assembler::assemble(std::span<const double> u, std::span<double> gradient, SparseMatrix* stiffness) const {
  const Model& model = *model_;
  const int d = model.dim();
  std::fill(gradient.begin(), gradient.end(), 0.0);
  if (stiffness) std::fill(stiffness->values.begin(), stiffness->values.end(), 0.0);
  // One parallel region for all colours; small meshes stay on one thread,
  // where the barriers between colours would cost more than they save.
  const int colours = colour_count();
#pragma omp parallel if (model.cell_count() >= kParallelCells)
  {
    double local_u[kMaxDofs], local_g[kMaxDofs], blend_g[kMaxDofs];
    std::vector<double> local_k(stiffness ? kMaxDofs * kMaxDofs : 0), blend_k;
    for (int c = 0; c < colours; ++c) {
#pragma omp for schedule(static)
      for (int k = colour_start_[c]; k < colour_start_[c + 1]; ++k) {
        const int cell = coloured_cells_[k];
        const tm_kernel& kernel = model.kernel(cell);
        model.gather(cell, u, local_u);
        if (model.blend_from(cell)) {
          blend_cell(model, cell, local_u, local_g, stiffness ? local_k.data() : nullptr, blend_g, blend_k);
        } else if (stiffness) {
          kernel.gradient_hessian(local_u, model.consts(cell), local_g, local_k.data());
        } else {
          kernel.gradient(local_u, model.consts(cell), local_g);
        }
        if (stiffness) {
          const int* scatter = scatter_.data() + scatter_offsets_[cell];
          const int dofs2 = kernel.dofs * kernel.dofs;
          for (int e = 0; e < dofs2; ++e)
            if (scatter[e] >= 0) stiffness->values[scatter[e]] += local_k[e];
        }
        const auto cn = model.cell_nodes(cell);
        for (int j = 0; j < static_cast<int>(cn.size()); ++j)
          for (int a = 0; a < d; ++a) gradient[static_cast<std::size_t>(cn[j]) * d + a] += local_g[j * d + a];
      }
    }
  }
}

}  // namespace tensormass
