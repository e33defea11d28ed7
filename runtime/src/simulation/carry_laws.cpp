#include "simulation/carry_laws.hpp"

#include <numeric>

namespace tensormass::detail {

CellLaws cell_laws(const Model& model) {
  CellLaws laws;
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    laws.kernels.push_back(&model.kernel(cell));
    laws.blend_from.push_back(model.blend_from(cell));
    laws.blend_weights.push_back(model.blend_weight(cell));
  }
  return laws;
}

std::vector<int> cell_origins(const std::vector<LeafTransfer>& transfers) {
  std::vector<int> origin(static_cast<std::size_t>(transfers.front().old_cell_count));
  std::iota(origin.begin(), origin.end(), 0);
  for (const LeafTransfer& transfer : transfers) origin = transfer_cell_field<int>(transfer, origin);
  return origin;
}

int carry_laws(const CellLaws& before, std::span<const int> origin, Model& model) {
  int missed = 0;
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    const std::size_t source = static_cast<std::size_t>(origin[static_cast<std::size_t>(cell)]);
    const tm_kernel* law = model.law_kernel(cell, before.kernels[source]->law);
    if (!law) {
      ++missed;
      continue;
    }
    model.set_law(cell, law->law);
    const tm_kernel* from = before.blend_from[source];
    if (!from) continue;
    const tm_kernel* blend = model.law_kernel(cell, from->law);
    if (!blend || blend == &model.kernel(cell)) continue;
    model.start_blend(cell, blend);
    model.set_blend_weight(cell, before.blend_weights[source]);
  }
  return missed;
}

}  // namespace tensormass::detail
