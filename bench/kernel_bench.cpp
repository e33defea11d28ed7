// `tensormass bench kernels [--json FILE] [--quick]`: see kernel_bench.hpp.
//
// Method. For each element type, a few thousand random valid elements are
// built once (reference nodes mildly distorted, randomly rotated and
// stretched, 1 cm in size; displacements from a random 1-5 % displacement
// gradient plus small nodal noise). Every kernel of that element (all laws and
// splits, and the hand-written baseline) gets its own constants for the first
// `elements` of them, as many as keep consts + u within ~1 MiB (L2), at most
// 2048. One sample times `sweeps` sweeps over all those elements through the
// kernel's function pointer (output written to one scratch buffer, a checksum
// of it accumulated so nothing can be elided); samples of all kernels of an
// element are taken round-robin, so slow drifts of the machine hit them alike.
// Reported: the median over the samples, in ns per element, single thread.
#include "kernel_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_json.hpp"
#include "bench_metadata.hpp"
#include "handwritten_stvk.hpp"
#include "machine_info.hpp"
#include "polar_bench.hpp"
#include "tensormass/kernels/law_parameters.hpp"
#include "tensormass/kernels/registry.hpp"

#ifndef TENSORMASS_BENCH_BUILD_INFO
#define TENSORMASS_BENCH_BUILD_INFO "unknown build flags"
#endif

namespace tensormass::bench {

namespace {

using Clock = std::chrono::steady_clock;

constexpr const char* kUsage =
    "usage: tensormass bench kernels [--json FILE] [--quick]\n"
    "  --json FILE   also write the settings, rows and polar rotation timings to FILE (atomically)\n"
    "  --quick       fewer elements and repetitions (CI smoke test, a few seconds)\n";

struct Options {
  bool quick = false;
  std::string json;
};

struct Settings {
  int repetitions;           // samples per kernel and function (odd: a true median)
  double sample_ns;          // target duration of one sample
  int max_elements;          // elements per kernel, at most
  double working_set_bytes;  // consts + u of all elements, at most (about)
};

constexpr Settings kFull{31, 2.0e6, 2048, 1024.0 * 1024.0};
constexpr Settings kQuick{7, 0.2e6, 512, 1024.0 * 1024.0};

constexpr double kYoung = 3.0e3;  // Pa, soft tissue
constexpr double kPoisson = 0.45;

/// One timed kernel: a registry triple or the baseline.
struct Row {
  std::string law, element, split;
  int dim = 0, nodes = 0, dofs = 0, consts = 0, elements = 0;
  long flops_gradient = 0, flops_hessian = 0, flops_gradient_hessian = 0;
  tm_precompute_fn precompute = nullptr;
  std::vector<double> params;  ///< the law's parameters (bench_parameters)
  tm_gradient_fn gradient = nullptr;
  tm_gradient_hessian_fn gradient_hessian = nullptr;
  /// Batched rows (split "batched"): elements per call and the batched entry
  /// points; the working set is then in structure-of-arrays batches.
  int batch_width = 0;
  tm_gradient_batch_fn gradient_batch = nullptr;
  tm_gradient_hessian_batch_fn gradient_hessian_batch = nullptr;
  bool baseline = false;
  /// Baseline rows: the largest relative differences from stvk/ELEMENT/whole.
  double check_gradient = 0, check_hessian = 0;
  // Working set.
  std::vector<double> constants, u;
  int sweeps_gradient = 1, sweeps_gradient_hessian = 1;
  std::vector<double> samples_gradient, samples_gradient_hessian;
  // Results (ns per element).
  double ns_gradient = 0, ns_gradient_hessian = 0, min_gradient = 0, min_gradient_hessian = 0;
};

/// Random elements of one type, shared by all its kernels.
struct Geometry {
  int count = 0, dofs = 0;
  std::vector<double> rest, u;  // count by dofs
};

volatile double g_sink = 0.0;  // the checksums end here: nothing can be elided

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

/// A random rotation (dim 2 or 3) as a row-major dim by dim matrix.
std::vector<double> random_rotation(int dim, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double pi = std::acos(-1.0);
  if (dim == 2) {
    const double t = 2 * pi * unit(rng);
    return {std::cos(t), -std::sin(t), std::sin(t), std::cos(t)};
  }
  // Uniform unit quaternion (Shoemake).
  const double u1 = unit(rng), u2 = unit(rng), u3 = unit(rng);
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  const double w = a * std::sin(2 * pi * u2), x = a * std::cos(2 * pi * u2);
  const double y = b * std::sin(2 * pi * u3), z = b * std::cos(2 * pi * u3);
  return {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
          2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
          2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
}

/// Soft tissue (kYoung, kPoisson) for laws with Young's modulus and
/// Poisson's ratio, else values within the law's limits.
std::vector<double> bench_parameters(const tm_kernel& k) {
  if (tensormass::parameter_names(k) == std::vector<std::string>{"young", "poisson"}) return {kYoung, kPoisson};
  return tensormass::admissible_parameters(k);
}

/// `count` random valid elements of type `info`; `check` (any kernel of that
/// element) must accept the rest shape, else the element is drawn again.
Geometry make_geometry(const tm_element_info& info, const tm_kernel& check, int count, unsigned seed) {
  const int d = info.dim, n = info.nodes;
  Geometry geometry;
  geometry.count = count;
  geometry.dofs = n * d;
  geometry.rest.resize(static_cast<std::size_t>(count) * n * d);
  geometry.u.resize(geometry.rest.size());
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> symmetric(-1.0, 1.0), unit(0.0, 1.0);

  // Reference size, to scale the element to ~1 cm.
  double low[3] = {1e300, 1e300, 1e300}, high[3] = {-1e300, -1e300, -1e300};
  for (int j = 0; j < n; ++j)
    for (int a = 0; a < d; ++a) {
      low[a] = std::min(low[a], info.reference_nodes[j * d + a]);
      high[a] = std::max(high[a], info.reference_nodes[j * d + a]);
    }
  double size = 0.0;
  for (int a = 0; a < d; ++a) size = std::max(size, high[a] - low[a]);
  const double scale = 0.01 / size;

  std::vector<double> consts(check.consts);
  const std::vector<double> params = bench_parameters(check);
  for (int e = 0; e < count; ++e) {
    double* X = &geometry.rest[static_cast<std::size_t>(e) * n * d];
    double* u = &geometry.u[static_cast<std::size_t>(e) * n * d];
    for (int attempt = 0;; ++attempt) {
      if (attempt == 1000) throw std::runtime_error(std::string("bench: cannot draw a valid ") + info.name);
      const std::vector<double> R = random_rotation(d, rng);
      double stretch[3];
      for (int a = 0; a < d; ++a) stretch[a] = std::exp(0.2 * symmetric(rng));  // 0.82 .. 1.22
      double shift[3];
      for (int a = 0; a < d; ++a) shift[a] = 0.05 * symmetric(rng);
      for (int j = 0; j < n; ++j) {
        double p[3];
        for (int a = 0; a < d; ++a)
          p[a] = stretch[a] * (info.reference_nodes[j * d + a] + 0.04 * size * symmetric(rng));  // mild distortion
        for (int a = 0; a < d; ++a) {
          double sum = shift[a];
          for (int b = 0; b < d; ++b) sum += R[a * d + b] * p[b] * scale;
          X[j * d + a] = sum;
        }
      }
      if (check.precompute(X, params.data(), check.params, consts.data()) == 0) break;
    }
    // Displacement gradient: diagonal strains of 1-5 % (random sign), shears
    // up to 2 %, plus a translation and nodal noise of 0.1 % of the size.
    double G[9];
    for (int a = 0; a < d; ++a)
      for (int b = 0; b < d; ++b)
        G[a * d + b] = a == b ? (unit(rng) < 0.5 ? -1 : 1) * (0.01 + 0.04 * unit(rng)) : 0.02 * symmetric(rng);
    double translation[3];
    for (int a = 0; a < d; ++a) translation[a] = 1e-3 * symmetric(rng);
    for (int j = 0; j < n; ++j)
      for (int a = 0; a < d; ++a) {
        double sum = translation[a] + 1e-5 * symmetric(rng);
        for (int b = 0; b < d; ++b) sum += G[a * d + b] * X[j * d + b];
        u[j * d + a] = sum;
      }
  }
  return geometry;
}

/// Whole batches only, each in structure-of-arrays layout (kernel_abi.h):
/// entry i of the batch's element l at [i*W + l]. The transposition is not
/// timed (the assembler's is, in the scaling and adaptive benchmarks).
void to_batches(Row& row) {
  const int width = row.batch_width;
  row.elements -= row.elements % width;
  auto transpose = [&](std::vector<double>& values, int per_element) {
    std::vector<double> batched(static_cast<std::size_t>(row.elements) * per_element);
    for (int e = 0; e < row.elements; ++e) {
      const std::size_t base = static_cast<std::size_t>(e / width) * per_element * width + e % width;
      for (int i = 0; i < per_element; ++i)
        batched[base + static_cast<std::size_t>(i) * width] = values[static_cast<std::size_t>(e) * per_element + i];
    }
    values.swap(batched);
  };
  transpose(row.constants, row.consts);
  transpose(row.u, row.dofs);
}

/// Fills the row's constants and displacements from the first elements of `geometry`.
void load(Row& row, const Geometry& geometry, const Settings& settings) {
  const double bytes = 8.0 * (row.consts + row.dofs);
  row.elements = static_cast<int>(std::clamp(settings.working_set_bytes / bytes, 32.0,
                                             static_cast<double>(std::min(settings.max_elements, geometry.count))));
  row.constants.assign(static_cast<std::size_t>(row.elements) * row.consts, 0.0);
  row.u.assign(geometry.u.begin(), geometry.u.begin() + static_cast<std::ptrdiff_t>(row.elements) * row.dofs);
  for (int e = 0; e < row.elements; ++e)
    if (const int bad = row.precompute(&geometry.rest[static_cast<std::size_t>(e) * row.dofs], row.params.data(),
                                       static_cast<int>(row.params.size()),
                                       &row.constants[static_cast<std::size_t>(e) * row.consts]))
      throw std::runtime_error("bench: " + row.law + "/" + row.element + "/" + row.split +
                               " precompute refused element " + std::to_string(e) + " (point " +
                               std::to_string(bad - 1) + ")");
  if (row.batch_width > 0) to_batches(row);
}

/// Scratch outputs, big enough for any kernel (reused by every element).
struct Scratch {
  std::vector<double> gradient, hessian;
};

/// ns per element of `sweeps` sweeps of gradient (hessian == false) or gradient_hessian.
double sample(const Row& row, bool hessian, int sweeps, Scratch& scratch) {
  const int n = row.elements, dofs = row.dofs, nc = row.consts;
  const double* u = row.u.data();
  const double* c = row.constants.data();
  double* g = scratch.gradient.data();
  double* K = scratch.hessian.data();
  const int dofs2 = dofs * dofs;
  double checksum = 0.0;
  const auto start = Clock::now();
  if (row.batch_width > 0) {
    const int width = row.batch_width, batches = n / width;
    const std::ptrdiff_t u_step = static_cast<std::ptrdiff_t>(dofs) * width,
                         c_step = static_cast<std::ptrdiff_t>(nc) * width;
    for (int s = 0; s < sweeps; ++s)
      for (int b = 0; b < batches; ++b) {
        if (hessian) {
          row.gradient_hessian_batch(u + b * u_step, c + b * c_step, g, K);
          checksum += g[b % dofs] + K[(b * 13) % dofs2];
        } else {
          row.gradient_batch(u + b * u_step, c + b * c_step, g);
          checksum += g[b % dofs];
        }
      }
  } else if (hessian) {
    const tm_gradient_hessian_fn fn = row.gradient_hessian;
    for (int s = 0; s < sweeps; ++s)
      for (int e = 0; e < n; ++e) {
        fn(u + static_cast<std::ptrdiff_t>(e) * dofs, c + static_cast<std::ptrdiff_t>(e) * nc, g, K);
        checksum += g[e % dofs] + K[(e * 13) % dofs2];
      }
  } else {
    const tm_gradient_fn fn = row.gradient;
    for (int s = 0; s < sweeps; ++s)
      for (int e = 0; e < n; ++e) {
        fn(u + static_cast<std::ptrdiff_t>(e) * dofs, c + static_cast<std::ptrdiff_t>(e) * nc, g);
        checksum += g[e % dofs];
      }
  }
  const auto stop = Clock::now();
  g_sink = g_sink + checksum;
  return std::chrono::duration<double, std::nano>(stop - start).count() / (static_cast<double>(sweeps) * n);
}

/// Times the rows of one element, round-robin.
void time_rows(std::vector<Row*>& rows, const Settings& settings, Scratch& scratch) {
  for (Row* row : rows) {  // warm up (caches, branch predictors) and calibrate
    for (int pass = 0; pass < 2; ++pass) {
      const double g = sample(*row, false, 1, scratch), gh = sample(*row, true, 1, scratch);
      row->sweeps_gradient = std::max(1, static_cast<int>(settings.sample_ns / (g * row->elements)));
      row->sweeps_gradient_hessian = std::max(1, static_cast<int>(settings.sample_ns / (gh * row->elements)));
    }
  }
  for (int rep = 0; rep < settings.repetitions; ++rep)
    for (Row* row : rows) {
      row->samples_gradient.push_back(sample(*row, false, row->sweeps_gradient, scratch));
      row->samples_gradient_hessian.push_back(sample(*row, true, row->sweeps_gradient_hessian, scratch));
    }
  for (Row* row : rows) {
    row->ns_gradient = median(row->samples_gradient);
    row->ns_gradient_hessian = median(row->samples_gradient_hessian);
    row->min_gradient = *std::min_element(row->samples_gradient.begin(), row->samples_gradient.end());
    row->min_gradient_hessian =
        *std::min_element(row->samples_gradient_hessian.begin(), row->samples_gradient_hessian.end());
  }
}

/// max |a - b| / max |b|.
double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double difference = 0.0, magnitude = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    difference = std::max(difference, std::abs(a[i] - b[i]));
    magnitude = std::max(magnitude, std::abs(b[i]));
  }
  return magnitude > 0.0 ? difference / magnitude : difference;
}

struct Outputs {
  std::vector<double> gradient, gradient_from_gh, hessian;
};

Outputs evaluate(const Row& row, const double* rest, const double* u) {
  std::vector<double> consts(row.consts);
  if (row.precompute(rest, row.params.data(), static_cast<int>(row.params.size()), consts.data()) != 0)
    throw std::runtime_error("bench: precompute refused");
  Outputs out{std::vector<double>(row.dofs), std::vector<double>(row.dofs),
              std::vector<double>(static_cast<std::size_t>(row.dofs) * row.dofs)};
  row.gradient(u, consts.data(), out.gradient.data());
  row.gradient_hessian(u, consts.data(), out.gradient_from_gh.data(), out.hessian.data());
  return out;
}

/// The baseline against the registry's stvk/ELEMENT/whole on a few elements,
/// at the bench's strains and at 10x them. Returns false (after printing) on
/// disagreement beyond 1e-10 relative.
bool verify_baseline(Row& baseline, const Row& reference, const Geometry& geometry) {
  double worst_gradient = 0.0, worst_hessian = 0.0;
  for (int e = 0; e < std::min(4, geometry.count); ++e)
    for (const double amplify : {1.0, 10.0}) {
      const double* rest = &geometry.rest[static_cast<std::size_t>(e) * baseline.dofs];
      std::vector<double> u(geometry.u.begin() + static_cast<std::ptrdiff_t>(e) * baseline.dofs,
                            geometry.u.begin() + static_cast<std::ptrdiff_t>(e + 1) * baseline.dofs);
      for (double& x : u) x *= amplify;
      const Outputs mine = evaluate(baseline, rest, u.data()), theirs = evaluate(reference, rest, u.data());
      worst_gradient = std::max({worst_gradient, relative_difference(mine.gradient, theirs.gradient),
                                 relative_difference(mine.gradient_from_gh, theirs.gradient_from_gh)});
      worst_hessian = std::max(worst_hessian, relative_difference(mine.hessian, theirs.hessian));
    }
  baseline.check_gradient = worst_gradient;
  baseline.check_hessian = worst_hessian;
  const bool ok = worst_gradient <= 1e-10 && worst_hessian <= 1e-10;
  std::printf(
      "baseline check: handwritten stvk/%s vs %s/%s/%s on 4 elements (x1 and x10 strain): "
      "gradient %.1e, hessian %.1e relative: %s\n",
      baseline.element.c_str(), reference.law.c_str(), reference.element.c_str(), reference.split.c_str(),
      worst_gradient, worst_hessian, ok ? "agree (<= 1e-10)" : "DISAGREE");
  if (!ok)
    std::fprintf(stderr,
                 "tensormass bench: the hand-written stvk/%s baseline disagrees with the generated %s/%s/%s "
                 "(gradient %.3e, hessian %.3e relative, limit 1e-10)\n",
                 baseline.element.c_str(), reference.law.c_str(), reference.element.c_str(), reference.split.c_str(),
                 worst_gradient, worst_hessian);
  return ok;
}

/// Every split against the law's whole split on two elements; returns the
/// warnings (the bench goes on: it times what there is).
std::vector<std::string> cross_check(const std::vector<Row*>& rows, const Geometry& geometry) {
  std::vector<std::string> warnings;
  std::map<std::string, const Row*> whole;
  for (const Row* row : rows)
    if (!row->baseline && row->split == "whole") whole[row->law] = row;
  char line[512];
  for (const Row* row : rows) {
    if (row->baseline) continue;
    double self = 0.0, gradient = 0.0, hessian = 0.0, asymmetry = 0.0;
    const auto found = whole.find(row->law);
    for (int e = 0; e < std::min(2, geometry.count); ++e) {
      const double* rest = &geometry.rest[static_cast<std::size_t>(e) * row->dofs];
      const double* u = &geometry.u[static_cast<std::size_t>(e) * row->dofs];
      const Outputs mine = evaluate(*row, rest, u);
      self = std::max(self, relative_difference(mine.gradient_from_gh, mine.gradient));
      std::vector<double> transposed(mine.hessian.size());
      for (int i = 0; i < row->dofs; ++i)
        for (int j = 0; j < row->dofs; ++j) transposed[j * row->dofs + i] = mine.hessian[i * row->dofs + j];
      asymmetry = std::max(asymmetry, relative_difference(transposed, mine.hessian));
      if (found != whole.end() && found->second != row) {
        const Outputs theirs = evaluate(*found->second, rest, u);
        gradient = std::max(gradient, relative_difference(mine.gradient, theirs.gradient));
        hessian = std::max(hessian, relative_difference(mine.hessian, theirs.hessian));
      }
    }
    if (self > 1e-12 || asymmetry > 1e-12 || gradient > 1e-8 || hessian > 1e-8) {
      std::snprintf(line, sizeof line,
                    "%s/%s/%s: gradient_hessian's gradient vs gradient %.1e, K asymmetry %.1e, vs whole: "
                    "gradient %.1e, hessian %.1e (relative)",
                    row->law.c_str(), row->element.c_str(), row->split.c_str(), self, asymmetry, gradient, hessian);
      warnings.emplace_back(line);
    }
  }
  return warnings;
}

double gflops(long flops, double ns) { return ns > 0.0 ? static_cast<double>(flops) / ns : 0.0; }

/// One row of --json: ns with six figures, GFLOP/s with four.
Json json_row(const Row& r) {
  Json row = {{"law", r.law},
              {"element", r.element},
              {"split", r.split},
              {"elements", r.elements},
              {"consts", r.consts},
              {"dofs", r.dofs},
              {"batch_width", r.batch_width},
              {"ns_gradient", number(r.ns_gradient, 6)},
              {"ns_gradient_hessian", number(r.ns_gradient_hessian, 6)},
              {"ns_gradient_min", number(r.min_gradient, 6)},
              {"ns_gradient_hessian_min", number(r.min_gradient_hessian, 6)},
              {"flops_gradient", r.flops_gradient},
              {"flops_hessian", r.flops_hessian},
              {"flops_gradient_hessian", r.flops_gradient_hessian},
              {"gflops_gradient", number(gflops(r.flops_gradient, r.ns_gradient), 4)},
              {"gflops_gradient_hessian", number(gflops(r.flops_gradient_hessian, r.ns_gradient_hessian), 4)}};
  if (r.baseline) {
    row["check_gradient"] = number(r.check_gradient, 3);
    row["check_hessian"] = number(r.check_hessian, 3);
  }
  return row;
}

Json json_polar(const std::vector<PolarTiming>& timings) {
  Json rows = Json::array();
  for (const PolarTiming& t : timings)
    rows.push_back({{"strain", t.strain},
                    {"ns", number(t.ns, 4)},
                    {"ns_before", number(t.ns_before, 4)},
                    {"ns_batched", number(t.ns_batched, 4)},
                    {"difference", number(t.difference, 3)},
                    {"batched_difference", number(t.batched_difference, 3)}});
  return rows;
}

/// {"metadata", "settings", "rows", "polar_rotation"}: what
/// scripts/results/render_kernels.py renders docs/results/kernels.md from.
bool write_json(const std::string& path, const std::vector<const Row*>& rows, const Settings& settings, bool quick,
                const std::vector<PolarTiming>& polar, double seconds) {
  Json json = {{"metadata", metadata()}};
  json["metadata"]["build"] = TENSORMASS_BENCH_BUILD_INFO;
  json["metadata"]["load_average"] = load_average();  // the other cores' work adds noise
  json["settings"] = {{"quick", quick},
                      {"repetitions", settings.repetitions},
                      {"sample_ns", settings.sample_ns},
                      {"max_elements", settings.max_elements},
                      {"working_set_bytes", settings.working_set_bytes},
                      {"young", kYoung},
                      {"poisson", kPoisson},
                      {"seconds", number(seconds, 3)}};
  json["rows"] = Json::array();
  for (const Row* row : rows) json["rows"].push_back(json_row(*row));
  json["polar_rotation"] = json_polar(polar);
  const std::string text = json_text(json);
  const std::string temporary = path + ".tmp";
  std::FILE* file = std::fopen(temporary.c_str(), "w");
  if (file == nullptr) {
    std::fprintf(stderr, "tensormass bench: cannot write '%s'\n", temporary.c_str());
    return false;
  }
  const bool written = std::fputs(text.c_str(), file) >= 0 && std::fflush(file) == 0 && !std::ferror(file);
  if (std::fclose(file) != 0 || !written || std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::fprintf(stderr, "tensormass bench: cannot write '%s'\n", path.c_str());
    std::remove(temporary.c_str());
    return false;
  }
  return true;
}

Row registry_row(const tm_kernel& k) {
  Row row;
  row.law = k.law;
  row.element = k.element;
  row.split = k.split;
  row.dim = k.dim;
  row.nodes = k.nodes;
  row.dofs = k.dofs;
  row.consts = k.consts;
  row.flops_gradient = k.flops_gradient;
  row.flops_hessian = k.flops_hessian;
  // The fused whole split computes P with A (counted in flops_hessian); the
  // other splits' gradient_hessian calls gradient, then hessian.
  row.flops_gradient_hessian = row.split == "whole" ? k.flops_hessian : k.flops_gradient + k.flops_hessian;
  row.precompute = k.precompute;
  row.params = bench_parameters(k);
  row.gradient = k.gradient;
  row.gradient_hessian = k.gradient_hessian;
  return row;
}

/// The batched entry points of `k` as a row of their own (split "batched").
Row batched_row(const tm_kernel& k) {
  Row row = registry_row(k);
  row.split = "batched";
  row.batch_width = k.batch_width;
  row.gradient_batch = k.gradient_batch;
  row.gradient_hessian_batch = k.gradient_hessian_batch;
  return row;
}

Row baseline_row(const std::string& element) {
  namespace hw = handwritten;
  Row row;
  row.law = "stvk";
  row.element = element;
  row.split = "handwritten";
  row.dim = 3;
  row.baseline = true;
  row.params = {kYoung, kPoisson};
  int points;
  if (element == "tet4") {
    row.nodes = hw::kTet4Nodes;
    points = hw::kTet4Points;
    row.consts = hw::kTet4Consts;
    row.precompute = hw::stvk_tet4_precompute;
    row.gradient = hw::stvk_tet4_gradient;
    row.gradient_hessian = hw::stvk_tet4_gradient_hessian;
  } else {
    row.nodes = hw::kHex8Nodes;
    points = hw::kHex8Points;
    row.consts = hw::kHex8Consts;
    row.precompute = hw::stvk_hex8_precompute;
    row.gradient = hw::stvk_hex8_gradient;
    row.gradient_hessian = hw::stvk_hex8_gradient_hessian;
  }
  row.dofs = 3 * row.nodes;
  row.flops_gradient = hw::stvk_flops_gradient(row.nodes, points);
  row.flops_gradient_hessian = hw::stvk_flops_gradient_hessian(row.nodes, points);
  row.flops_hessian = row.flops_gradient_hessian - row.flops_gradient;
  return row;
}

void print_table(const std::vector<const Row*>& rows) {
  std::printf("\n%-11s %-8s %-11s %5s %6s %11s %12s %8s %8s %10s %10s\n", "law", "element", "split", "elems", "consts",
              "ns_grad", "ns_grad+hess", "GF/s g", "GF/s g+h", "flops_g", "flops_g+h");
  std::string previous;
  for (const Row* r : rows) {
    if (!previous.empty() && previous != r->element) std::printf("\n");
    previous = r->element;
    std::printf("%-11s %-8s %-11s %5d %6d %11.1f %12.1f %8.2f %8.2f %10ld %10ld\n", r->law.c_str(), r->element.c_str(),
                r->split.c_str(), r->elements, r->consts, r->ns_gradient, r->ns_gradient_hessian,
                gflops(r->flops_gradient, r->ns_gradient), gflops(r->flops_gradient_hessian, r->ns_gradient_hessian),
                r->flops_gradient, r->flops_gradient_hessian);
  }
}

struct Tally {
  int pass = 0, miss = 0;
  const char* mark(bool ok) {
    ++(ok ? pass : miss);
    return ok ? "PASS" : "MISS";
  }
};

void print_targets(const std::vector<const Row*>& rows, const Registry& registry) {
  auto find = [&](const std::string& law, const std::string& element, const std::string& split) -> const Row* {
    for (const Row* r : rows)
      if (r->law == law && r->element == element && r->split == split) return r;
    return nullptr;
  };
  auto best = [&](const std::string& law, const std::string& element) -> const Row* {
    const Row* winner = nullptr;
    for (const Row* r : rows)
      if (!r->baseline && r->law == law && r->element == element &&
          (winner == nullptr || r->ns_gradient_hessian < winner->ns_gradient_hessian))
        winner = r;
    return winner;
  };
  Tally tally;
  std::printf("\ntargets (ratios of medians; < 1 means the generated kernel is faster)\n");

  // (i) stvk tet4 vs the hand-written baseline.
  const Row* tet4_baseline = find("stvk", "tet4", "handwritten");
  const Row* tet4_best = best("stvk", "tet4");
  std::printf("\n(i) stvk tet4 gradient+hessian, best split vs the hand-written baseline (target: ratio <= 1)\n");
  if (tet4_baseline && tet4_best) {
    for (const Row* r : rows)
      if (!r->baseline && r->law == "stvk" && r->element == "tet4")
        std::printf("    %-7s g+h %8.1f ns vs %8.1f ns: ratio %.2f   (gradient alone %6.1f vs %6.1f ns: %.2f)\n",
                    r->split.c_str(), r->ns_gradient_hessian, tet4_baseline->ns_gradient_hessian,
                    r->ns_gradient_hessian / tet4_baseline->ns_gradient_hessian, r->ns_gradient,
                    tet4_baseline->ns_gradient, r->ns_gradient / tet4_baseline->ns_gradient);
    const double ratio = tet4_best->ns_gradient_hessian / tet4_baseline->ns_gradient_hessian;
    std::printf("    best: %s, ratio %.2f  %s\n", tet4_best->split.c_str(), ratio, tally.mark(ratio <= 1.0));
  } else {
    std::printf("    no stvk/tet4 kernel: MISS\n");
    ++tally.miss;
  }

  // (ii) stvk hex8 best split vs 8 tet4 baselines (and the hex8 baseline).
  const Row* hex8_best = best("stvk", "hex8");
  const Row* hex8_baseline = find("stvk", "hex8", "handwritten");
  std::printf("\n(ii) stvk hex8 gradient+hessian, best split vs 8 x the tet4 baseline (target: ratio <= 1)\n");
  if (hex8_best && tet4_baseline) {
    const double eight = 8.0 * tet4_baseline->ns_gradient_hessian;
    for (const Row* r : rows)
      if (!r->baseline && r->law == "stvk" && r->element == "hex8")
        std::printf("    %-7s g+h %8.1f ns vs 8 x %.1f = %8.1f ns: ratio %.2f\n", r->split.c_str(),
                    r->ns_gradient_hessian, tet4_baseline->ns_gradient_hessian, eight, r->ns_gradient_hessian / eight);
    const double ratio = hex8_best->ns_gradient_hessian / eight;
    std::printf("    best: %s, ratio %.2f  %s\n", hex8_best->split.c_str(), ratio, tally.mark(ratio <= 1.0));
    if (hex8_baseline)
      std::printf(
          "    (info) vs the hand-written hex8 (2x2x2 points, %.1f ns): ratio %.2f; gradient alone %.1f vs "
          "%.1f ns: %.2f\n",
          hex8_baseline->ns_gradient_hessian, hex8_best->ns_gradient_hessian / hex8_baseline->ns_gradient_hessian,
          hex8_best->ns_gradient, hex8_baseline->ns_gradient, hex8_best->ns_gradient / hex8_baseline->ns_gradient);
  } else {
    std::printf("    no stvk/hex8 kernel: MISS\n");
    ++tally.miss;
  }

  // (iii) stvk / hooke for each element and split.
  std::printf(
      "\n(iii) stvk / hooke, same element and split (target: gradient+hessian ratio <= 2.5; gradient ratio "
      "for information)\n");
  std::printf("    %-8s %-7s %10s %10s\n", "element", "split", "g+h ratio", "g ratio");
  std::vector<std::string> splits = registry.splits();
  splits.push_back("batched");
  for (const tm_element_info* info : registry.elements())
    for (const std::string& split : splits) {
      const Row* stvk = find("stvk", info->name, split);
      const Row* hooke = find("hooke", info->name, split);
      if (!stvk || !hooke) continue;
      const double ratio = stvk->ns_gradient_hessian / hooke->ns_gradient_hessian;
      std::printf("    %-8s %-7s %10.2f %10.2f  %s\n", info->name, split.c_str(), ratio,
                  stvk->ns_gradient / hooke->ns_gradient, tally.mark(ratio <= 2.5));
    }

  // (iv) tensor vs whole.
  std::printf(
      "\n(iv) tensor vs whole (quadrature) split, first-order elements: time ratio tensor/whole (< 1: tensor "
      "faster)\n");
  std::printf("    %-11s %-8s %10s %10s   %s\n", "law", "element", "g+h ratio", "g ratio", "faster (g+h)");
  for (const tm_element_info* info : registry.elements())
    for (const std::string& law : registry.laws()) {
      const Row* tensor = find(law, info->name, "tensor");
      const Row* whole = find(law, info->name, "whole");
      if (!tensor || !whole) continue;
      const double ratio = tensor->ns_gradient_hessian / whole->ns_gradient_hessian;
      std::printf("    %-11s %-8s %10.2f %10.2f   %s by %.2fx\n", law.c_str(), info->name, ratio,
                  tensor->ns_gradient / whole->ns_gradient, ratio < 1.0 ? "tensor" : "whole",
                  ratio < 1.0 ? 1.0 / ratio : ratio);
    }
  // (v) batched vs per-element whole.
  std::printf(
      "\n(v) batched vs per-element whole split: time ratio batched/whole per element (< 1: batched faster; "
      "the batched rows exclude the transposition to structure of arrays)\n");
  std::printf("    %-11s %-8s %10s %10s\n", "law", "element", "g+h ratio", "g ratio");
  for (const tm_element_info* info : registry.elements())
    for (const std::string& law : registry.laws()) {
      const Row* batched = find(law, info->name, "batched");
      const Row* whole = find(law, info->name, "whole");
      if (!batched || !whole) continue;
      std::printf("    %-11s %-8s %10.2f %10.2f\n", law.c_str(), info->name,
                  batched->ns_gradient_hessian / whole->ns_gradient_hessian, batched->ns_gradient / whole->ns_gradient);
    }
  std::printf("\ntargets: %d PASS, %d MISS\n", tally.pass, tally.miss);
}

}  // namespace

int kernels_command(const std::vector<std::string>& args) {
  Options options;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--quick") {
      options.quick = true;
    } else if (args[i] == "--json") {
      if (i + 1 >= args.size() || args[i + 1].empty() || args[i + 1].rfind("--", 0) == 0) {
        std::fprintf(stderr, "tensormass bench kernels: --json needs a FILE\n%s", kUsage);
        return 2;
      }
      options.json = args[++i];
    } else if (args[i] == "--help" || args[i] == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    } else {
      std::fprintf(stderr, "tensormass bench kernels: unknown argument '%s'\n%s", args[i].c_str(), kUsage);
      return 2;
    }
  }
  if (!options.json.empty()) {  // fail now rather than after the run
    const std::string temporary = options.json + ".tmp";
    std::FILE* probe = std::fopen(temporary.c_str(), "w");
    if (probe == nullptr) {
      std::fprintf(stderr, "tensormass bench kernels: cannot write '%s'\n", temporary.c_str());
      return 2;
    }
    std::fclose(probe);
    std::remove(temporary.c_str());
  }
  const Settings settings = options.quick ? kQuick : kFull;
  const Registry& registry = Registry::instance();
  const auto started = Clock::now();

  std::printf("tensormass bench kernels%s: single thread, median of %d samples, ns per element\n",
              options.quick ? " (quick)" : "", settings.repetitions);
  std::printf("cpu: %s; build: %s\n", cpu_model().c_str(), TENSORMASS_BENCH_BUILD_INFO);
  std::printf(
      "elements: random valid ones (mild distortion, 1-5 %% strain); per kernel as many as keep consts + u "
      "within %.0f KiB (at most %d); outputs go to one scratch buffer\n",
      settings.working_set_bytes / 1024.0, settings.max_elements);
  std::printf(
      "GF/s g+h counts flops_hessian for the fused whole split, flops_gradient + flops_hessian otherwise "
      "(their gradient_hessian calls both)\n\n");

  // Rows, grouped by element in registry order.
  std::vector<Row> rows;
  rows.reserve(2 * registry.kernels().size() + 2);
  for (const tm_kernel* k : registry.kernels()) {
    rows.push_back(registry_row(*k));
    if (k->batch_width > 0) rows.push_back(batched_row(*k));
  }
  for (const char* element : {"tet4", "hex8"})
    if (registry.element(element)) rows.push_back(baseline_row(element));

  Scratch scratch;
  int max_dofs = 0;
  for (const Row& r : rows) max_dofs = std::max(max_dofs, r.dofs);
  int max_width = 1;
  for (const Row& r : rows) max_width = std::max(max_width, r.batch_width);
  scratch.gradient.assign(static_cast<std::size_t>(max_dofs) * max_width, 0.0);
  scratch.hessian.assign(static_cast<std::size_t>(max_dofs) * max_dofs * max_width, 0.0);

  std::vector<std::string> warnings;
  bool baseline_ok = true;
  std::vector<const Row*> ordered;
  unsigned seed = 20261122;
  for (const tm_element_info* info : registry.elements()) {
    std::vector<Row*> group;
    for (Row& r : rows)
      if (r.element == info->name) group.push_back(&r);
    if (group.empty()) continue;
    std::sort(group.begin(), group.end(), [](const Row* a, const Row* b) {
      return a->law != b->law ? a->law < b->law : a->split > b->split;  // whole, terms, tensor, handwritten, batched
    });
    const tm_kernel* check = nullptr;
    for (const tm_kernel* k : registry.kernels())
      if (info->name == std::string(k->element)) check = k;
    if (check == nullptr) continue;
    const Geometry geometry = make_geometry(*info, *check, settings.max_elements, seed++);

    for (Row* r : group) {
      if (!r->baseline) continue;
      const Row* reference = nullptr;
      for (const Row* other : group)
        if (!other->baseline && other->law == "stvk" && other->split == "whole") reference = other;
      if (reference == nullptr) {
        std::fprintf(stderr, "tensormass bench: no stvk/%s/whole kernel to check the baseline against\n",
                     r->element.c_str());
        baseline_ok = false;
      } else {
        baseline_ok = verify_baseline(*r, *reference, geometry) && baseline_ok;
      }
    }
    if (!baseline_ok) {
      std::fprintf(stderr, "tensormass bench: FAILED: the baseline does not agree with the generated kernels\n");
      return 1;
    }
    const std::vector<std::string> found = cross_check(group, geometry);
    warnings.insert(warnings.end(), found.begin(), found.end());

    for (Row* r : group) load(*r, geometry, settings);
    time_rows(group, settings, scratch);
    for (Row* r : group) {
      std::vector<double>().swap(r->constants);
      std::vector<double>().swap(r->u);
      ordered.push_back(r);
    }
    std::fflush(stdout);
  }
  std::sort(ordered.begin(), ordered.end(), [&](const Row* a, const Row* b) {
    auto element_index = [&](const std::string& name) {
      int index = 0;
      for (const tm_element_info* info : registry.elements()) {
        if (name == info->name) return index;
        ++index;
      }
      return index;
    };
    const int ea = element_index(a->element), eb = element_index(b->element);
    if (ea != eb) return ea < eb;
    if (a->law != b->law) return a->law < b->law;
    return a->split > b->split;
  });

  if (!warnings.empty()) {
    std::printf("\nconsistency warnings (splits should agree with the law's whole split to 1e-8):\n");
    for (const std::string& w : warnings) std::printf("  WARNING %s\n", w.c_str());
  } else {
    std::printf(
        "consistency: every split agrees with its law's whole split (gradient, hessian <= 1e-8 relative), "
        "gradient_hessian's gradient matches gradient, K symmetric\n");
  }
  print_table(ordered);
  print_targets(ordered, registry);
  bool polar_agrees = true;
  const std::vector<PolarTiming> polar =
      print_polar_rotation_timings(options.quick ? 2000 : 100000, options.quick ? 3 : 7, polar_agrees);
  if (!polar_agrees) {
    std::fprintf(stderr, "tensormass bench: FAILED: the polar rotation disagrees with its previous iteration\n");
    return 1;
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - started).count();
  std::printf("\n%zu rows in %.1f s (checksum %.6e)\n", ordered.size(), seconds, static_cast<double>(g_sink));
  if (!options.json.empty()) {
    if (!write_json(options.json, ordered, settings, options.quick, polar, seconds)) return 1;
    std::printf("wrote %s\n", options.json.c_str());
  }
  return 0;
}

}  // namespace tensormass::bench
