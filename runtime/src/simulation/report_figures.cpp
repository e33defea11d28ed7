#include "simulation/report_figures.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "tensormass/kernels/registry.hpp"
#include "tensormass/parallel/mpi_world.hpp"

namespace tensormass::detail {

void locate_max_displacement(const Model& model, const State& state, RunReport& report) {
  const int d = model.dim();
  report.max_displacement = 0;
  for (int i = 0; i < static_cast<int>(state.displacement.size()) / d; ++i) {
    double length2 = 0;
    for (int a = 0; a < d; ++a) length2 += state.displacement[i * d + a] * state.displacement[i * d + a];
    if (std::sqrt(length2) > report.max_displacement || report.max_displacement_node < 0) {
      report.max_displacement = std::sqrt(length2);
      report.max_displacement_node = i;
    }
  }
}

void collect_adaptivity(const Adaptivity* adaptivity, RunReport& report) {
  if (!adaptivity) return;
  report.criteria_seconds = adaptivity->criteria_seconds();
  report.criterion_seconds = adaptivity->criterion_seconds();
  report.switches = adaptivity->total_switches();
  report.adaptivity = adaptivity->records();
}

double peak_memory_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // KiB on Linux
}

void count_cells(const Model& model, const Distribution* distribution, RunReport& report) {
  const std::vector<std::string>& laws = model.law_names();
  const auto elements = Registry::instance().elements();
  std::vector<double> counted(laws.size() + elements.size(), 0.0);  // laws, then element types
  for (const ElementBlock& block : model.mesh().blocks) {
    const tm_kernel* last = nullptr;
    std::size_t law = 0;
    const std::size_t type =
        laws.size() + (std::find(elements.begin(), elements.end(), block.element) - elements.begin());
    for (int cell = block.first_cell; cell < block.first_cell + block.count(); ++cell) {
      if (distribution && !distribution->owns_cell(cell)) continue;
      if (&model.kernel(cell) != last) {  // the law's name looked up once per run of cells under one kernel
        last = &model.kernel(cell);
        law = std::find(laws.begin(), laws.end(), last->law) - laws.begin();
      }
      counted[law] += 1;
      counted[type] += 1;
    }
  }
  if (distribution) parallel::sum_over_ranks(counted);
  std::map<std::string, int> per_law;
  for (std::size_t law = 0; law < laws.size(); ++law)
    if (counted[law] > 0) per_law[laws[law]] = static_cast<int>(counted[law]);
  report.cells_per_law.assign(per_law.begin(), per_law.end());
  report.cells_per_type.clear();
  for (std::size_t type = 0; type < elements.size(); ++type)
    if (const double count = counted[laws.size() + type]; count > 0)
      report.cells_per_type.push_back({elements[type]->name, static_cast<int>(count)});
}

void time_loop(const Scene& scene, const State& state, double adaptivity_seconds, RunReport& report) {
  if (scene.solver.is_static()) return;
  report.simulated_seconds = state.step * scene.solver.dt;
  report.loop_seconds = adaptivity_seconds;
  report.loop_seconds += report.statistics.step_ms.sum() / 1e3;
}

}  // namespace tensormass::detail
