// CalculiX deck writer and runner: see calculix_runner.hpp.
#include "calculix_runner.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace tensormass::bench {

namespace {

namespace fs = std::filesystem;

// Newton controls of *CONTROLS, PARAMETERS=FIELD: R_n, C_n, q_0, q_u, R_P,
// epsilon, C_epsilon, R_l. The defaults (0.005, 0.01, -, -, 0.02, 1e-5,
// 1e-3, 1e-8) accept an increment whose largest residual force is 0.5 % of
// the average force; these ask for round-off.
constexpr const char* kTightFieldControls = "1.e-12, 1.e-10, , , 1.e-12, 1.e-5, 1.e-3, 1.e-14";

std::string number(double x) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

/// Set members as data lines of at most 16 entries (each line stands alone).
void write_list(std::ostringstream& out, const std::vector<long>& values) {
  for (std::size_t i = 0; i < values.size(); i += 16) {
    const std::size_t end = std::min(values.size(), i + 16);
    for (std::size_t k = i; k < end; ++k) out << values[k] << (k + 1 < end ? ", " : "");
    out << "\n";
  }
}

std::string read_text(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

std::string tail(const std::string& text, std::size_t characters) {
  return text.size() <= characters ? text : "..." + text.substr(text.size() - characters);
}

std::string quoted(const std::string& text) {  // for /bin/sh
  std::string out = "'";
  for (const char ch : text) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

/// Law of each material; every material must use the same one (NLGEOM is per step).
std::string common_law(const Scene& scene) {
  if (scene.model.materials.empty()) throw std::runtime_error("calculix: the scene has no material");
  const std::string law = scene.model.materials.front().law;
  for (const MaterialSpec& m : scene.model.materials)
    if (m.law != law)
      throw std::runtime_error("calculix: every material must use the same law (found " + law + " and " + m.law + ")");
  if (law != "stvk" && law != "hooke")
    throw std::runtime_error("calculix: law '" + law + "' has no CalculiX equivalent here (stvk, hooke)");
  return law;
}

/// Material index of each cell (first matching region), as Model does.
std::vector<int> cell_materials(const Mesh& mesh, const Scene& scene) {
  const int cells = mesh.cell_count();
  std::vector<int> material(cells, -1);
  for (int m = static_cast<int>(scene.model.materials.size()) - 1; m >= 0; --m) {
    const std::string& region = scene.model.materials[m].region;
    if (region == "all") {
      std::fill(material.begin(), material.end(), m);
      continue;
    }
    const Group* group = mesh.group(region);
    if (group == nullptr) throw std::runtime_error("calculix: no group '" + region + "' in the mesh");
    for (const int cell : group->cells) material[cell] = m;
  }
  for (int cell = 0; cell < cells; ++cell)
    if (material[cell] < 0) throw std::runtime_error("calculix: no material for " + mesh.describe_cell(cell));
  return material;
}

}  // namespace

std::string find_calculix(const std::string& name) {
  std::string wanted = name;
  if (wanted.empty()) {
    const char* forced = std::getenv("TENSORMASS_CCX");
    wanted = forced != nullptr && *forced != '\0' ? forced : "ccx";
  }
  if (wanted.find('/') != std::string::npos)
    return ::access(wanted.c_str(), X_OK) == 0 && fs::is_regular_file(wanted) ? wanted : std::string();
  const char* path = std::getenv("PATH");
  std::stringstream directories(path != nullptr ? path : "/usr/local/bin:/usr/bin:/bin");
  std::string directory;
  while (std::getline(directories, directory, ':')) {
    if (directory.empty()) directory = ".";
    const std::string candidate = directory + "/" + wanted;
    if (::access(candidate.c_str(), X_OK) == 0 && fs::is_regular_file(candidate)) return candidate;
  }
  return {};
}

std::string calculix_deck(const Mesh& mesh, const Scene& scene, const CalculixOptions& options) {
  const std::string law = common_law(scene);
  const bool nlgeom = law == "stvk";
  if (!scene.model.prescribed.empty()) throw std::runtime_error("calculix: prescribed displacements are not supported");
  if (!scene.model.loads.pressures.empty()) throw std::runtime_error("calculix: pressures are not supported");
  if (options.increments < 1) throw std::runtime_error("calculix: increments must be >= 1");
  const int dim = mesh.dim;

  std::ostringstream out;
  out << "*HEADING\ntensormass bench: " << mesh.cell_count() << " cells, " << mesh.node_count() << " nodes, " << law
      << (nlgeom ? " (NLGEOM)" : " (linear)") << "\n";
  out << "*NODE, NSET=NALL\n";
  for (int node = 0; node < mesh.node_count(); ++node) {
    const double* x = &mesh.rest_positions[static_cast<std::size_t>(node) * 3];
    out << node + 1 << ", " << number(x[0]) << ", " << number(x[1]) << ", " << number(x[2]) << "\n";
  }
  // Cells: CalculiX id = mesh-wide cell index + 1; one ELSET per material.
  const std::vector<int> material = cell_materials(mesh, scene);
  for (const ElementBlock& block : mesh.blocks) {
    const tm_element_info& info = *block.element;
    if (info.calculix_type == nullptr || info.calculix_type[0] == '\0')
      throw std::runtime_error(std::string("calculix: no CalculiX element for ") + info.name);
    out << "*ELEMENT, TYPE=" << info.calculix_type << ", ELSET=EALL\n";
    for (int local = 0; local < block.count(); ++local) {
      const auto nodes = block.cell_nodes(local);
      std::vector<long> ids{block.first_cell + local + 1L};
      for (int k = 0; k < info.nodes; ++k) ids.push_back(nodes[info.calculix_order[k]] + 1L);
      // One element per data line: continued lines end with a comma.
      for (std::size_t i = 0; i < ids.size(); i += 16) {
        const std::size_t end = std::min(ids.size(), i + 16);
        for (std::size_t k = i; k < end; ++k) out << ids[k] << (k + 1 < end ? ", " : "");
        out << (end < ids.size() ? ",\n" : "\n");
      }
    }
  }
  for (std::size_t m = 0; m < scene.model.materials.size(); ++m) {
    std::vector<long> cells;
    for (int cell = 0; cell < mesh.cell_count(); ++cell)
      if (material[cell] == static_cast<int>(m)) cells.push_back(cell + 1L);
    if (cells.empty()) continue;
    out << "*ELSET, ELSET=E" << m + 1 << "\n";
    write_list(out, cells);
  }
  // Constraints.
  std::set<int> fixed;
  for (const std::string& name : scene.model.fixed) {
    const Group* group = mesh.group(name);
    if (group == nullptr) throw std::runtime_error("calculix: no group '" + name + "' in the mesh");
    fixed.insert(group->nodes.begin(), group->nodes.end());
  }
  if (!fixed.empty()) {
    out << "*NSET, NSET=FIXED\n";
    std::vector<long> ids;
    for (const int node : fixed) ids.push_back(node + 1L);
    write_list(out, ids);
  }
  // Materials and sections.
  for (std::size_t m = 0; m < scene.model.materials.size(); ++m) {
    const MaterialSpec& spec = scene.model.materials[m];
    bool used = false;
    for (const int c : material) used = used || c == static_cast<int>(m);
    if (!used) continue;
    const auto young = spec.constants.find("young"), poisson = spec.constants.find("poisson");
    if (young == spec.constants.end() || poisson == spec.constants.end())
      throw std::invalid_argument("calculix_runner: material " + std::to_string(m) +
                                  " has no young and poisson (CalculiX's *ELASTIC needs both)");
    out << "*MATERIAL, NAME=MAT" << m + 1 << "\n*ELASTIC\n"
        << number(young->second) << ", " << number(poisson->second) << "\n*DENSITY\n"
        << number(spec.density) << "\n";
    out << "*SOLID SECTION, ELSET=E" << m + 1 << ", MATERIAL=MAT" << m + 1 << "\n";
    if (dim == 2) out << "1.\n";  // plane strain, unit thickness (as tensormass)
  }
  if (!fixed.empty()) out << "*BOUNDARY\nFIXED, 1, " << dim << "\n";
  // The step.
  if (nlgeom) {
    out << "*STEP, NLGEOM, INC=" << std::max(1000, 10 * options.increments) << "\n*STATIC, DIRECT\n"
        << number(1.0 / options.increments) << ", 1.0\n";
    if (options.tight_controls) out << "*CONTROLS, PARAMETERS=FIELD\n" << kTightFieldControls << "\n";
  } else {
    out << "*STEP\n*STATIC\n1.0, 1.0\n";
  }
  const auto& g = scene.model.loads.gravity;
  const double magnitude = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (magnitude > 0.0)
    out << "*DLOAD\nEALL, GRAV, " << number(magnitude) << ", " << number(g[0] / magnitude) << ", "
        << number(g[1] / magnitude) << ", " << number(g[2] / magnitude) << "\n";
  // Nodal forces: the same force on each node of the group, summed over groups.
  std::map<int, std::array<double, 3>> forces;
  for (const NodalForceSpec& load : scene.model.loads.nodal_forces) {
    const Group* group = mesh.group(load.region);
    if (group == nullptr) throw std::runtime_error("calculix: no group '" + load.region + "' in the mesh");
    for (const int node : group->nodes) {
      auto& f = forces[node];
      for (int a = 0; a < 3; ++a) f[a] += load.force[a];
    }
  }
  bool cload = false;
  for (const auto& [node, f] : forces)
    for (int a = 0; a < dim; ++a) {
      if (f[a] == 0.0) continue;
      if (!cload) out << "*CLOAD\n";
      cload = true;
      out << node + 1 << ", " << a + 1 << ", " << number(f[a]) << "\n";
    }
  // Displacements of the last increment only.
  out << "*NODE PRINT, NSET=NALL, FREQUENCY=" << options.increments + 1 << "\nU\n*END STEP\n";
  return out.str();
}

CalculixResult run_calculix(const Mesh& mesh, const Scene& scene, const CalculixOptions& options) {
  const std::string deck = calculix_deck(mesh, scene, options);
  std::string pattern = (fs::temp_directory_path() / "tensormass-ccx-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("calculix: cannot create a temporary directory");
  const fs::path directory = pattern;
  CalculixResult result;
  result.directory = directory.string();
  struct Cleanup {
    fs::path path;
    bool keep;
    ~Cleanup() {
      std::error_code ignored;
      if (!keep) fs::remove_all(path, ignored);
    }
  } cleanup{directory, options.keep_directory};
  {
    std::ofstream file(directory / "job.inp", std::ios::binary);
    file << deck;
    if (!file.flush()) throw std::runtime_error("calculix: cannot write " + (directory / "job.inp").string());
  }
  const std::string command = "cd " + quoted(directory.string()) +
                              " && OMP_NUM_THREADS=" + std::to_string(std::max(1, options.threads)) + " " +
                              quoted(options.executable) + " -i job > ccx.log 2>&1";
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system(command.c_str());
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const std::string log = read_text(directory / "ccx.log");
  auto fail = [&](const std::string& why) {
    cleanup.keep = true;  // leave the evidence
    throw std::runtime_error("calculix: " + why + " (work directory " + directory.string() + ")\n" + tail(log, 2000));
  };
  if (status != 0) fail("ccx exited with status " + std::to_string(status));
  if (log.find("*ERROR") != std::string::npos || log.find("Job finished") == std::string::npos)
    fail("ccx did not finish the job");
  if (const auto at = log.find("Total CalculiX Time:"); at != std::string::npos)
    result.reported_seconds = std::atof(log.c_str() + at + 20);

  // .sta: one line per increment: STEP INC ATT ITRS TOT-TIME STEP-TIME INC-TIME.
  {
    std::istringstream sta(read_text(directory / "job.sta"));
    std::string line;
    while (std::getline(sta, line)) {
      std::istringstream fields(line);
      long step = 0, increment = 0, attempt = 0, iterations = 0;
      if (fields >> step >> increment >> attempt >> iterations) {
        ++result.increments;
        result.iterations += static_cast<int>(iterations);
      }
    }
  }
  // .dat: the last " displacements (vx,vy,vz) for set NALL and time  T" block.
  const std::string dat = read_text(directory / "job.dat");
  const std::string header = "displacements (vx,vy,vz) for set NALL and time";
  const auto at = dat.rfind(header);
  if (at == std::string::npos) fail("no displacement printout in job.dat");
  std::istringstream block(dat.substr(at + header.size()));
  double time = 0.0;
  block >> time;
  if (std::abs(time - 1.0) > 1e-9) fail("the last printout is at time " + std::to_string(time) + ", not 1");
  const int nodes = mesh.node_count();
  result.displacement.assign(static_cast<std::size_t>(nodes) * 3, 0.0);
  std::vector<char> seen(nodes, 0);
  int rows = 0;
  std::string line;
  std::getline(block, line);  // rest of the header line
  while (std::getline(block, line)) {
    std::istringstream fields(line);
    long id = 0;
    double u[3];
    if (!(fields >> id >> u[0] >> u[1] >> u[2])) {
      if (rows > 0) break;  // end of the block
      continue;             // blank line after the header
    }
    if (id < 1 || id > nodes || seen[id - 1]) fail("bad or repeated node " + std::to_string(id) + " in job.dat");
    seen[id - 1] = 1;
    for (int a = 0; a < 3; ++a) result.displacement[static_cast<std::size_t>(id - 1) * 3 + a] = u[a];
    ++rows;
  }
  if (rows != nodes) fail(std::to_string(rows) + " displacement rows in job.dat, expected " + std::to_string(nodes));
  return result;
}

}  // namespace tensormass::bench
