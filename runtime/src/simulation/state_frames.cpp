#include "simulation/state_frames.hpp"

#include <filesystem>
#include <utility>
#include <vector>

#include "tensormass/io/vtk_writer.hpp"

namespace tensormass::detail {

namespace {

namespace fs = std::filesystem;

/// Point displacement (and velocity) with 3 components, and per-cell fields.
struct StateFields {
  std::vector<io::Field> point_data, cell_data;
};

StateFields state_fields(const Model& model, const State& state, std::span<const int> levels,
                         const Adaptivity* adaptivity) {
  const Mesh& mesh = model.mesh();
  const int d = model.dim(), nodes = mesh.node_count();
  std::vector<double> displacement(3 * static_cast<std::size_t>(nodes), 0.0);
  io::Field velocity{"velocity", 3, std::vector<double>(3 * static_cast<std::size_t>(nodes), 0.0)};
  for (int i = 0; i < nodes; ++i)
    for (int a = 0; a < d; ++a) {
      displacement[3 * i + a] = state.displacement[i * d + a];
      velocity.values[3 * i + a] = state.velocity[i * d + a];
    }
  io::Field law{"law_id", 1, {}}, type{"element_type", 1, {}}, material{"material", 1, {}};
  for (io::Field* field : {&law, &type, &material}) field->values.reserve(model.cell_count());
  for (const ElementBlock& block : mesh.blocks)
    for (int local = 0; local < block.count(); ++local) {
      const int cell = block.first_cell + local;
      law.values.push_back(model.law_id(cell));
      type.values.push_back(block.element->vtk_type);
      material.values.push_back(model.material(cell));
    }
  // The deformed shape is displacement applied to the rest positions: keep
  // the points at rest so ParaView's "Warp By Vector" shows the motion.
  // Moved, not copied: at a million cells each cell field is 8 MB.
  StateFields fields;
  fields.point_data.push_back({"displacement", 3, std::move(displacement)});
  fields.point_data.push_back(std::move(velocity));
  for (io::Field* field : {&law, &type, &material}) fields.cell_data.push_back(std::move(*field));
  if (!levels.empty()) fields.cell_data.push_back({"level", 1, std::vector<double>(levels.begin(), levels.end())});
  if (adaptivity)
    for (io::Field& field : adaptivity->cell_fields()) fields.cell_data.push_back(std::move(field));
  return fields;
}

}  // namespace

std::string write_state(const std::string& directory, const std::string& name, const Model& model, const State& state,
                        std::span<const int> levels, const Adaptivity* adaptivity, const Distribution* distribution) {
  const StateFields fields = state_fields(model, state, levels, adaptivity);
  const fs::path folder(directory);
  if (!distribution) {
    io::write_vtu((folder / (name + ".vtu")).string(), model.mesh(), {}, fields.point_data, fields.cell_data);
    return name + ".vtu";
  }
  const auto piece = [&](int rank) { return name + "_p" + std::to_string(rank) + ".vtu"; };
  std::vector<bool> own(model.cell_count());
  std::vector<int> numbers(model.cell_count());
  for (int cell = 0; cell < model.cell_count(); ++cell) {
    own[cell] = distribution->owns_cell(cell);
    numbers[cell] = distribution->global_cell(cell);
  }
  io::write_vtu_piece((folder / piece(distribution->rank())).string(), model.mesh(), own, {}, fields.point_data,
                      fields.cell_data, numbers, distribution->global_nodes());
  if (distribution->rank() == 0) {
    std::vector<std::string> pieces;
    for (int rank = 0; rank < distribution->size(); ++rank) pieces.push_back(piece(rank));
    io::write_pvtu((folder / (name + ".pvtu")).string(), pieces, fields.point_data, fields.cell_data);
  }
  return name + ".pvtu";
}

}  // namespace tensormass::detail
