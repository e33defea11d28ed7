// `tensormass kernels [--json]`: the registry, one row per LES triple.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands.hpp"
#include "tensormass/kernels/law_parameters.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass::cli {

namespace {

void print_table() {
  std::printf("%-11s %-9s %-7s %5s %4s %6s %7s %12s %12s\n", "law", "element", "split", "nodes", "dim", "points",
              "consts", "flops_grad", "flops_hess");
  for (const tm_kernel* k : Registry::instance().kernels())
    std::printf("%-11s %-9s %-7s %5d %4d %6d %7d %12ld %12ld\n", k->law, k->element, k->split, k->nodes, k->dim,
                k->quadrature_points, k->consts, k->flops_gradient, k->flops_hessian);
  std::printf("%zu kernels\n", Registry::instance().kernels().size());
}

/// Each law with its parameters and their limits: the keys a scene's material gives.
void print_laws() {
  const Registry& registry = Registry::instance();
  std::printf("\nlaws and their parameters (a scene material's keys besides region, law, split, density):\n");
  for (const std::string& law : registry.laws()) {
    const tm_kernel& kernel = *registry.law_kernel(law);
    std::string parameters;
    for (int p = 0; p < kernel.params; ++p)
      parameters +=
          std::string(p ? ", " : "") + kernel.param_names[p] + " (" + describe_limit(kernel.param_limits[p]) + ")";
    std::printf("  %-18s %s\n", law.c_str(), parameters.c_str());
  }
}

void print_json() {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const tm_kernel* k : Registry::instance().kernels())
    rows.push_back({{"law", k->law},
                    {"element", k->element},
                    {"split", k->split},
                    {"nodes", k->nodes},
                    {"dim", k->dim},
                    {"quadrature_points", k->quadrature_points},
                    {"consts", k->consts},
                    {"flops_energy", k->flops_energy},
                    {"flops_gradient", k->flops_gradient},
                    {"flops_hessian", k->flops_hessian},
                    {"parameters", std::vector<std::string>(k->param_names, k->param_names + k->params)}});
  std::printf("%s\n", rows.dump(2).c_str());
}

}  // namespace

int kernels_command(const Arguments& args) {
  bool json = false;
  for (const std::string& arg : args) {
    if (arg == "--json") {
      json = true;
    } else {
      std::fprintf(stderr, "tensormass kernels: unknown argument '%s' (expected --json)\n", arg.c_str());
      return 2;
    }
  }
  if (json) {
    print_json();
  } else {
    print_table();
    print_laws();
  }
  return 0;
}

}  // namespace tensormass::cli
