// The tensormass runtime from another project (tensormass::runtime): a
// cantilever of tet4 cells built from arrays, a scene given as YAML text,
// integrated step by step with tensormass::Simulation (static Newton, 4 load
// steps). Exits 0 only if every step ran and the tip moved down.
#include <cmath>
#include <cstdio>
#include <tensormass/mesh/mesh_arrays.hpp>
#include <tensormass/scene/scene.hpp>
#include <tensormass/simulation/simulation.hpp>
#include <vector>

int main() {
  const int nx = 8, ny = 2, nz = 2;  // cubes along x, y, z; 6 tets each
  const double h = 0.025;            // cube edge (m)
  auto id = [&](int i, int j, int l) { return static_cast<long>((l * (ny + 1) + j) * (nx + 1) + i); };
  tensormass::MeshArrays arrays;
  for (int l = 0; l <= nz; ++l)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) arrays.points.insert(arrays.points.end(), {i * h, j * h, l * h});
  tensormass::CellArray tets{"tet4", {}};
  // Kuhn's six tets of a cube, all along its main diagonal (corner 0 to 6).
  const int kuhn[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
  for (int l = 0; l < nz; ++l)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const long corner[8] = {id(i, j, l),     id(i + 1, j, l),     id(i + 1, j + 1, l),     id(i, j + 1, l),
                                id(i, j, l + 1), id(i + 1, j, l + 1), id(i + 1, j + 1, l + 1), id(i, j + 1, l + 1)};
        for (const auto& tet : kuhn)
          for (int c : tet) tets.nodes.push_back(corner[c]);
      }
  arrays.cells.push_back(tets);
  std::vector<long> clamped;
  for (long p = 0; p < static_cast<long>(arrays.points.size() / 3); ++p)
    if (arrays.points[3 * p] == 0.0) clamped.push_back(p);
  arrays.point_groups.push_back({"clamped", clamped});

  const char* scene_text = R"(
mesh: cantilever
materials: [{law: stvk, young: 1.0e5, poisson: 0.3, density: 1000}]
fixed: [clamped]
loads: {gravity: [0, 0, -9.81]}
solver: {type: static, load_steps: 4}
output: {directory: external-scene-out}
)";
  try {
    const tensormass::Scene scene = tensormass::parse_scene(scene_text, "cantilever.yaml");
    tensormass::Simulation simulation(scene, tensormass::mesh_from_arrays(arrays, "cantilever"), {false, false});
    int steps = 0;
    while (simulation.step()) ++steps;
    const auto& u = simulation.state().displacement;
    const double tip = u[3 * id(nx, ny, nz) + 2];
    std::printf("scene_runner: %d load steps, tip displacement %.4g m\n", steps, tip);
    return steps == 4 && std::isfinite(tip) && tip < 0 ? 0 : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "scene_runner: %s\n", error.what());
    return 1;
  }
}
