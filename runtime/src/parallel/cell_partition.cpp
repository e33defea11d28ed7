// Scotch, sequential, in a context made deterministic with a fixed seed:
// PT-Scotch through PETSc's MatPartitioning cut the same mesh differently
// from run to run (its threaded algorithms), so runs did not repeat bit for bit.
#include "tensormass/parallel/cell_partition.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>

#include "tensormass/common/errors.hpp"

extern "C" {
#include <scotch.h>
}

namespace tensormass::parallel {

namespace {

void check(int code, const char* what) {
  if (code != 0) throw NumericalError(std::string("Scotch: ") + what + " failed while cutting the mesh for MPI ranks");
}

/// Scotch's graph, strategy and context, released in reverse order.
struct ScotchCut {
  SCOTCH_Context context;
  SCOTCH_Graph graph, bound;
  SCOTCH_Strat strategy;
  bool context_ready = false, graph_ready = false, bound_ready = false, strategy_ready = false;
  ~ScotchCut() {
    if (strategy_ready) SCOTCH_stratExit(&strategy);
    if (bound_ready) SCOTCH_graphExit(&bound);
    if (graph_ready) SCOTCH_graphExit(&graph);
    if (context_ready) SCOTCH_contextExit(&context);
  }
};

}  // namespace

std::vector<int> partition_cells(const Mesh& mesh, int parts) {
  const int cells = mesh.cell_count();
  if (parts <= 1 || cells == 0) return std::vector<int>(cells, 0);
  if (parts > cells)
    throw InputError("cannot share " + std::to_string(cells) + " cells among " + std::to_string(parts) +
                     " MPI ranks (run on fewer ranks)");
  const CellGraph graph = make_cell_graph(mesh);
  static_assert(sizeof(SCOTCH_Num) == sizeof(int), "the cell graph's integers are Scotch's");
  ScotchCut cut;
  check(SCOTCH_contextInit(&cut.context), "SCOTCH_contextInit");
  cut.context_ready = true;
  check(SCOTCH_contextOptionSetNum(&cut.context, SCOTCH_OPTIONNUMDETERMINISTIC, 1), "SCOTCH_contextOptionSetNum");
  check(SCOTCH_contextOptionSetNum(&cut.context, SCOTCH_OPTIONNUMRANDOMFIXEDSEED, 1), "SCOTCH_contextOptionSetNum");
  SCOTCH_contextRandomSeed(&cut.context, 1);
  check(SCOTCH_graphInit(&cut.graph), "SCOTCH_graphInit");
  cut.graph_ready = true;
  check(SCOTCH_graphBuild(&cut.graph, 0, cells, graph.row_start.data(), nullptr, nullptr, nullptr,
                          static_cast<SCOTCH_Num>(graph.columns.size()), graph.columns.data(), nullptr),
        "SCOTCH_graphBuild");
  check(SCOTCH_graphInit(&cut.bound), "SCOTCH_graphInit");
  cut.bound_ready = true;
  check(SCOTCH_contextBindGraph(&cut.context, &cut.graph, &cut.bound), "SCOTCH_contextBindGraph");
  check(SCOTCH_stratInit(&cut.strategy), "SCOTCH_stratInit");
  cut.strategy_ready = true;
  constexpr double kImbalance = 0.01;  // PETSc's PT-Scotch default
  check(SCOTCH_stratGraphMapBuild(&cut.strategy, SCOTCH_STRATDEFAULT, parts, kImbalance), "SCOTCH_stratGraphMapBuild");
  std::vector<int> owner(static_cast<std::size_t>(cells), 0);
  check(SCOTCH_graphPart(&cut.bound, parts, &cut.strategy, owner.data()), "SCOTCH_graphPart");
  for (int p = 0; p < parts; ++p)
    if (std::find(owner.begin(), owner.end(), p) == owner.end())
      throw NumericalError("the mesh cut for " + std::to_string(parts) + " MPI ranks left rank " + std::to_string(p) +
                           " without cells");
  return owner;
}

}  // namespace tensormass::parallel
