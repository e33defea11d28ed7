// `tensormass demo [LAW [ELEMENT [SPLIT]]]`: evaluates one element of the
// registry on its reference shape (scaled to 10 cm) under a 10 % stretch
// along x, and checks the force against a finite difference of the energy.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"
#include "tensormass/kernels/law_parameters.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass::cli {

int demo_command(const Arguments& args) {
  if (args.size() > 3) {
    std::fprintf(stderr, "tensormass demo: expected at most LAW ELEMENT SPLIT\n");
    return 2;
  }
  const std::string law = args.size() > 0 ? args[0] : "stvk";
  const std::string element = args.size() > 1 ? args[1] : "tet4";
  const std::string split = args.size() > 2 ? args[2] : "whole";
  const Registry& registry = Registry::instance();
  const tm_kernel& kernel = registry.get(law, element, split);
  const tm_element_info& info = *registry.element(element);

  const double scale = 0.1;  // metres
  std::vector<double> rest(info.reference_nodes, info.reference_nodes + kernel.dofs);
  for (double& x : rest) x *= scale;
  // Soft tissue (Young 3 kPa, Poisson 0.45) for laws with those constants, else values within the law's limits.
  const std::vector<std::string> names = parameter_names(kernel);
  const bool elastic = names == std::vector<std::string>{"young", "poisson"};
  const std::vector<double> params = elastic ? std::vector<double>{3.0e3, 0.45} : admissible_parameters(kernel);
  std::vector<double> consts(kernel.consts);
  if (const int bad = precompute_checked(kernel, rest.data(), params, consts.data(), "tensormass demo")) {
    std::fprintf(stderr, "tensormass demo: non-positive Jacobian at quadrature point %d\n", bad - 1);
    return 3;
  }
  std::vector<double> u(kernel.dofs, 0.0), g(kernel.dofs), K(kernel.dofs * kernel.dofs);
  for (int j = 0; j < kernel.nodes; ++j) u[j * kernel.dim] = 0.1 * rest[j * kernel.dim];  // 10 % stretch in x
  const double energy = kernel.energy(u.data(), consts.data());
  kernel.gradient_hessian(u.data(), consts.data(), g.data(), K.data());

  double worst = 0.0, force_norm = 0.0;
  for (int i = 0; i < kernel.dofs; ++i) {
    const double h = 1e-6 * scale;
    std::vector<double> plus = u, minus = u;
    plus[i] += h;
    minus[i] -= h;
    const double fd =
        (kernel.energy(plus.data(), consts.data()) - kernel.energy(minus.data(), consts.data())) / (2 * h);
    worst = std::max(worst, std::abs(fd - g[i]));
    force_norm = std::max(force_norm, std::abs(g[i]));
  }
  std::printf("tensormass demo: %s / %s / %s (%d nodes, %d quadrature points, %d constants)\n", kernel.law,
              kernel.element, kernel.split, kernel.nodes, kernel.quadrature_points, kernel.consts);
  std::string constants;
  for (std::size_t p = 0; p < names.size(); ++p) {
    char value[32];
    std::snprintf(value, sizeof value, "%g", params[p]);
    constants += (p ? ", " : "") + names[p] + " = " + value;
  }
  std::printf("  rest shape: the reference %s scaled to %.2f m; %s; 10 %% stretch along x\n", element.c_str(), scale,
              constants.c_str());
  std::printf("  strain energy        %.6e J\n", energy);
  std::printf("  internal force       max |g_i| = %.6e N\n", force_norm);
  std::printf("  force vs finite diff max error %.2e N (relative %.1e)\n", worst, worst / force_norm);
  std::printf("  stiffness K[0][0]    %.6e N/m\n", K[0]);
  std::printf("  nodal forces (x y%s):\n", kernel.dim == 3 ? " z" : "");
  for (int j = 0; j < kernel.nodes; ++j) {
    std::printf("    node %2d:", j);
    for (int a = 0; a < kernel.dim; ++a) std::printf(" %+.6e", g[j * kernel.dim + a]);
    std::printf("\n");
  }
  return worst <= 1e-5 * std::max(force_norm, 1e-30) ? 0 : 3;
}

}  // namespace tensormass::cli
