// An explicit dynamic solver written outside tensormass, against the installed
// package: a cantilever beam of hex8 elements (StVK), clamped at x = 0, sags
// under gravity. Symplectic Euler, lumped mass, mass-proportional damping.
// Exits 0 only if the final state is finite and the tip moved downward.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <tensormass/kernels/registry.hpp>
#include <vector>

int main() {
  const double L = 0.2, W = 0.05, H = 0.05;               // beam size (m)
  const int nx = 8, ny = 2, nz = 2;                       // hexes along x, y, z
  const double young = 1e5, poisson = 0.3, rho = 1000.0;  // Pa, -, kg/m^3
  const double gravity = -9.81;                           // along z (m/s^2)

  const auto& registry = tensormass::Registry::instance();
  const tm_kernel& k = registry.get("stvk", "hex8", "whole");
  const tm_element_info& info = *registry.element("hex8");
  if (info.quadrature_points != k.quadrature_points) return 1;  // shape_values are of the default rule

  // Structured mesh; element corners in tensormass hex8 order (= VTK order).
  auto id = [&](int i, int j, int l) { return (l * (ny + 1) + j) * (nx + 1) + i; };
  const int n = (nx + 1) * (ny + 1) * (nz + 1), dofs = 3 * n;
  std::vector<double> X(dofs);
  for (int l = 0; l <= nz; ++l)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const int p = id(i, j, l);
        X[3 * p] = L * i / nx, X[3 * p + 1] = W * j / ny, X[3 * p + 2] = H * l / nz;
      }
  std::vector<std::array<int, 8>> hexes;
  for (int l = 0; l < nz; ++l)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        hexes.push_back({id(i, j, l), id(i + 1, j, l), id(i + 1, j + 1, l), id(i, j + 1, l), id(i, j, l + 1),
                         id(i + 1, j, l + 1), id(i + 1, j + 1, l + 1), id(i, j + 1, l + 1)});

  // Parameters by name, in the kernel's order.
  std::vector<double> params(k.params);
  for (int p = 0; p < k.params; ++p) {
    if (std::strcmp(k.param_names[p], "young") == 0) params[p] = young;
    else if (std::strcmp(k.param_names[p], "poisson") == 0) params[p] = poisson;
    else return std::fprintf(stderr, "unexpected parameter %s\n", k.param_names[p]), 1;
  }

  // Element constants, lumped mass (row sums of the consistent mass: rho *
  // sum_q w_q det J_q N_i(q)), and a Gershgorin bound on the highest
  // eigenvalue of M^-1 K at rest, sum_j |K_ij| / m_i, for the time step.
  const int stride = 1 + k.dim * k.nodes;
  std::vector<double> consts(hexes.size() * k.consts), mass(n, 0.0), rowsum(dofs, 0.0);
  std::vector<double> xe(k.dofs), ue(k.dofs, 0.0), fe(k.dofs), Ke(k.dofs * k.dofs);
  for (size_t e = 0; e < hexes.size(); ++e) {
    double* c = &consts[e * k.consts];
    for (int a = 0; a < k.nodes; ++a)
      for (int d = 0; d < 3; ++d) xe[3 * a + d] = X[3 * hexes[e][a] + d];
    if (k.precompute(xe.data(), params.data(), k.params, c) != 0)
      return std::fprintf(stderr, "inverted hex %zu\n", e), 1;
    for (int q = 0; q < k.quadrature_points; ++q)
      for (int a = 0; a < k.nodes; ++a)
        mass[hexes[e][a]] += rho * c[k.derived_params + q * stride] * info.shape_values[q * k.nodes + a];
    k.hessian(ue.data(), c, Ke.data());
    for (int r = 0; r < k.dofs; ++r)
      for (int s = 0; s < k.dofs; ++s) rowsum[3 * hexes[e][r / 3] + r % 3] += std::abs(Ke[r * k.dofs + s]);
  }
  double omega_max = 0.0;
  for (int i = 0; i < dofs; ++i) omega_max = std::max(omega_max, std::sqrt(rowsum[i] / mass[i / 3]));
  const double dt = 0.5 * 2.0 / omega_max;  // half the symplectic-Euler limit 2/omega

  // Euler-Bernoulli: static tip deflection q L^4 / (8 E I) and first bending
  // frequency, whose critical damping sets the mass damping.
  const double A = W * H, I = W * H * H * H / 12.0, q = rho * A * std::abs(gravity);
  const double w_theory = q * std::pow(L, 4) / (8.0 * young * I);
  const double omega1 = 1.8751 * 1.8751 * std::sqrt(young * I / (rho * A * std::pow(L, 4)));
  const double damping = 2.0 * omega1;  // 1/s
  const double t_end = 1.0;
  const int steps = static_cast<int>(std::ceil(t_end / dt));

  std::vector<double> u(dofs, 0.0), v(dofs, 0.0), f(dofs);
  auto tip = [&] {  // mean z displacement of the nodes at x = L
    double sum = 0.0;
    for (int l = 0; l <= nz; ++l)
      for (int j = 0; j <= ny; ++j) sum += u[3 * id(nx, j, l) + 2];
    return sum / ((ny + 1) * (nz + 1));
  };
  double total_mass = 0.0;
  for (double m : mass) total_mass += m;
  std::printf("stvk/hex8/whole: %zu hexes, %d nodes, mass %.4f kg; omega_max <= %.0f rad/s, dt = %.3e s, %d steps\n",
              hexes.size(), n, total_mass, omega_max, dt, steps);
  std::printf("%8s %14s\n", "t (s)", "tip w (m)");
  for (int step = 1; step <= steps; ++step) {
    std::fill(f.begin(), f.end(), 0.0);
    for (size_t e = 0; e < hexes.size(); ++e) {  // internal forces dW/du
      for (int a = 0; a < k.nodes; ++a)
        for (int d = 0; d < 3; ++d) ue[3 * a + d] = u[3 * hexes[e][a] + d];
      k.gradient(ue.data(), &consts[e * k.consts], fe.data());
      for (int a = 0; a < k.nodes; ++a)
        for (int d = 0; d < 3; ++d) f[3 * hexes[e][a] + d] -= fe[3 * a + d];
    }
    for (int i = 0; i < dofs; ++i) {
      const int p = i / 3;
      if (X[3 * p] == 0.0) continue;  // clamped at x = 0
      const double force = f[i] + (i % 3 == 2 ? mass[p] * gravity : 0.0) - damping * mass[p] * v[i];
      v[i] += dt * force / mass[p];
      u[i] += dt * v[i];
    }
    if (step % std::max(1, steps / 20) == 0 || step == steps) std::printf("%8.3f %+14.6e\n", step * dt, tip());
  }

  bool finite = true;
  for (int i = 0; i < dofs; ++i) finite = finite && std::isfinite(u[i]) && std::isfinite(v[i]);
  const double w = tip();
  std::printf("final tip deflection    %+.6e m (t = %.3f s)\n", w, steps * dt);
  std::printf("Euler-Bernoulli static  %+.6e m (q L^4 / 8EI, small-deflection theory)\n", -w_theory);
  const bool ok = finite && w < 0.0;
  std::printf("%s\n", ok ? "OK: finite, tip moved down" : "FAILED: non-finite state or tip did not move down");
  return ok ? 0 : 1;
}
