// tensormass.Simulation: a scene run step by step from Python, its state as
// NumPy arrays, laws and boundary conditions changed between steps.
#include "simulation_bindings.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "tensormass/common/errors.hpp"
#include "tensormass/mesh/mesh_arrays.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/scene/scene.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace py = pybind11;

namespace tensormass::python {

namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Indices = py::array_t<long, py::array::c_style | py::array::forcecast>;

/// A scene value as YAML text: JSON is YAML, and NumPy arrays and scalars
/// become lists and numbers.
std::string yaml_text(const py::handle& value) {
  py::module_ json = py::module_::import("json");
  py::cpp_function plain([](const py::object& o) { return o.attr("tolist")(); });
  return py::str(json.attr("dumps")(value, py::arg("default") = plain));
}

/// {"solver.steps": 10} -> {"solver.steps=10"}.
std::vector<std::string> override_texts(const py::object& overrides) {
  std::vector<std::string> out;
  if (overrides.is_none()) return out;
  if (!py::isinstance<py::dict>(overrides))
    throw py::type_error("overrides must be a dict of scene keys to values, e.g. {\"solver.steps\": 10}");
  for (const auto& [key, value] : overrides.cast<py::dict>())
    out.push_back(std::string(py::str(key)) + "=" + yaml_text(value));
  return out;
}

/// (nodes, dim) copy of a node-major dof vector.
Array node_array(const std::vector<double>& dofs, int dim) {
  const py::ssize_t nodes = static_cast<py::ssize_t>(dofs.size()) / dim;
  Array out(std::vector<py::ssize_t>{nodes, dim});
  std::copy(dofs.begin(), dofs.end(), out.mutable_data());
  return out;
}

/// points: (n, 2) or (n, 3) -> n x 3.
std::vector<double> points_xyz(const Array& points) {
  if (points.ndim() != 2 || (points.shape(1) != 2 && points.shape(1) != 3))
    throw py::value_error("points must have shape (n, 2) or (n, 3)");
  const py::ssize_t n = points.shape(0), columns = points.shape(1);
  std::vector<double> xyz(3 * static_cast<std::size_t>(n), 0.0);
  for (py::ssize_t p = 0; p < n; ++p)
    for (py::ssize_t c = 0; c < columns; ++c) xyz[3 * p + c] = points.at(p, c);
  return xyz;
}

std::vector<long> flat_indices(const py::handle& values) {
  const Indices array = py::cast<Indices>(values);
  return {array.data(), array.data() + array.size()};
}

/// {name: indices} -> named groups.
std::vector<std::pair<std::string, std::vector<long>>> groups_of(const py::object& groups, const char* what) {
  std::vector<std::pair<std::string, std::vector<long>>> out;
  if (groups.is_none()) return out;
  if (!py::isinstance<py::dict>(groups)) throw py::type_error(std::string(what) + " must be a dict of name to indices");
  for (const auto& [name, members] : groups.cast<py::dict>()) out.push_back({py::str(name), flat_indices(members)});
  return out;
}

MeshArrays mesh_arrays(const Array& points, const py::dict& cells, const py::object& groups,
                       const py::object& cell_groups) {
  MeshArrays arrays;
  arrays.points = points_xyz(points);
  for (const auto& [element, connectivity] : cells) {
    const Indices array = py::cast<Indices>(connectivity);
    if (array.ndim() != 2)
      throw py::value_error("cells['" + std::string(py::str(element)) + "'] must have shape (count, nodes per cell)");
    arrays.cells.push_back({py::str(element), {array.data(), array.data() + array.size()}});
  }
  arrays.point_groups = groups_of(groups, "groups");
  arrays.cell_groups = groups_of(cell_groups, "cell_groups");
  return arrays;
}

/// Scene keys given to from_arrays, as the YAML text of a scene.
std::string scene_text(const std::string& name, const py::kwargs& keys) {
  py::dict scene;
  scene["mesh"] = name;  // stands for the arrays in messages; never read
  for (const auto& [key, value] : keys) scene[key] = value;
  return yaml_text(scene);
}

py::dict report_dict(const RunReport& report) {
  py::dict d;
  d["output_directory"] = report.output_directory;
  d["files"] = report.files;
  d["steps"] = report.state.step;
  d["wall_seconds"] = report.wall_seconds;
  d["loop_seconds"] = report.loop_seconds;
  d["real_time_factor"] = report.real_time_factor();
  d["newton_iterations"] = report.statistics.newton_iterations;
  d["linear_iterations"] = report.statistics.linear_iterations;
  d["factorizations"] = report.statistics.factorizations;
  d["assembly_seconds"] = report.statistics.assembly_seconds;
  d["solve_seconds"] = report.statistics.solve_seconds;
  d["criteria_seconds"] = report.criteria_seconds;
  d["switches"] = report.switches;
  d["max_displacement"] = report.max_displacement;
  d["warnings"] = report.statistics.warnings;
  return d;
}

/// Steps with the GIL released (other Python threads run meanwhile).
bool step_released(Simulation& simulation) {
  py::gil_scoped_release release;
  return simulation.step();
}

std::array<bool, 3> given_components(const py::object& displacement, int dim, std::array<double, 3>& values) {
  std::array<bool, 3> components{false, false, false};
  const py::sequence items = py::cast<py::sequence>(displacement);
  if (static_cast<int>(items.size()) != dim)
    throw py::value_error("displacement must have " + std::to_string(dim) + " components (None leaves one as it is)");
  for (int a = 0; a < dim; ++a) {
    if (items[a].is_none()) continue;
    values[a] = items[a].cast<double>();
    components[a] = true;
  }
  return components;
}

const char* kSimulationDoc = R"(A scene run step by step.

Simulation(scene, overrides=None, resume=False, progress=False): reads the
scene file (overrides: {"solver.steps": 10, "materials.0.young": 2e6}),
checks everything and creates the output directory; nothing is integrated
yet. step() advances one step (static: one load step) and writes frames,
tracks and checkpoints as the scene asks; the step that ends the run writes
final.vtu, the tracks and summary.json, like `tensormass run`. Stepping
releases the GIL. Bad input raises ValueError, a numerical failure
tensormass.NumericalError (after writing last_good.vtu).)";

}  // namespace

void bind_simulation(py::module_& m) {
  py::class_<Simulation>(m, "Simulation", kSimulationDoc)
      .def(py::init([](const std::string& scene, const py::object& overrides, bool resume, bool progress) {
             const Scene loaded = load_scene(scene, override_texts(overrides));
             py::gil_scoped_release release;
             return std::make_unique<Simulation>(loaded, RunOptions{progress, resume, true});
           }),
           py::arg("scene"), py::arg("overrides") = py::none(), py::arg("resume") = false, py::arg("progress") = false)
      .def_static(
          "from_arrays",
          [](const Array& points, const py::dict& cells, const py::object& groups, const py::object& cell_groups,
             const std::string& name, bool progress, const py::kwargs& keys) {
            const Scene scene = parse_scene(scene_text(name, keys), name);
            Mesh mesh = mesh_from_arrays(mesh_arrays(points, cells, groups, cell_groups), name);
            py::gil_scoped_release release;
            return std::make_unique<Simulation>(scene, std::move(mesh), RunOptions{progress, false, true});
          },
          py::arg("points"), py::arg("cells"), py::arg("groups") = py::none(), py::arg("cell_groups") = py::none(),
          py::arg("name") = "from_arrays", py::arg("progress") = false,
          R"(A simulation of a mesh given as arrays and a scene given as keywords.

points: (n, 2) or (n, 3); cells: {element: (count, nodes) indices}, element a
registry name (tet4, hex8, ...) or meshio's (tetra, hexahedron, ...), VTK
node order; groups: {name: point indices}; cell_groups: {name: cell indices
numbered through `cells` in order}. Every other keyword is a top-level
scene key with its YAML value as Python data: materials=[{...}],
solver={...}, fixed=[...], prescribed=[...], loads={...}, adaptivity={...},
output={...} (docs/scene.md). Relative output directories are taken from
the current directory. Every point must belong to a cell.)")
      .def("step", &step_released,
           "Advances one step (static: one load step). Returns False, doing nothing, once the run is finished.")
      .def(
          "run",
          [](Simulation& simulation, const py::object& callback) {
            while (step_released(simulation))
              if (!callback.is_none()) callback(py::cast(simulation, py::return_value_policy::reference));
            return report_dict(simulation.report());
          },
          py::arg("callback") = py::none(),
          "Steps to the end, calling callback(simulation) after each step; returns the report as a dict.")
      .def_property_readonly("finished", &Simulation::finished)
      .def_property_readonly(
          "time", [](const Simulation& s) { return s.state().time; },
          "Seconds (dynamic) or load factor in [0, 1] (static).")
      .def_property_readonly(
          "step_index", [](const Simulation& s) { return s.state().step; }, "Steps (load steps) completed.")
      .def_property_readonly(
          "steps", [](const Simulation& s) { return s.scene().solver.total_steps(); },
          "Steps (load steps) of the whole run.")
      .def_property_readonly(
          "displacement", [](const Simulation& s) { return node_array(s.state().displacement, s.model().dim()); },
          "(nodes, dim) copy.")
      .def_property_readonly(
          "velocity", [](const Simulation& s) { return node_array(s.state().velocity, s.model().dim()); },
          "(nodes, dim) copy.")
      .def_property_readonly(
          "rest_positions",
          [](const Simulation& s) {
            const Mesh& mesh = s.mesh();
            const int dim = mesh.dim;
            Array out(std::vector<py::ssize_t>{mesh.node_count(), dim});
            for (int n = 0; n < mesh.node_count(); ++n)
              for (int a = 0; a < dim; ++a) out.mutable_at(n, a) = mesh.rest_positions[3 * n + a];
            return out;
          },
          "(nodes, dim) copy.")
      .def_property_readonly("output_directory", [](const Simulation& s) { return s.scene().output.directory; })
      .def(
          "internal_force",
          [](const Simulation& s) {
            std::vector<double> force;
            {
              py::gil_scoped_release release;
              force = s.internal_force();
            }
            return node_array(force, s.model().dim());
          },
          "dW/du at the current displacement, (nodes, dim): the body's internal force on each node. At a "
          "constrained node in static equilibrium it is the constraint's reaction (minus it: the force on the "
          "tool or support).")
      .def(
          "cell_laws",
          [](const Simulation& s) {
            std::vector<std::string> laws;
            for (int cell = 0; cell < s.model().cell_count(); ++cell) laws.emplace_back(s.model().kernel(cell).law);
            return laws;
          },
          "The law of every cell (cells numbered block by block in registry element order).")
      .def(
          "set_law",
          [](Simulation& s, const py::object& cells, const std::string& law) {
            std::vector<int> list;
            for (long cell : flat_indices(cells)) list.push_back(static_cast<int>(cell));
            s.set_law(list, law);
          },
          py::arg("cells"), py::arg("law"), "Puts the cells under `law` from the next step on.")
      .def(
          "set_prescribed",
          [](Simulation& s, const std::string& group, const py::object& displacement) {
            std::array<double, 3> values{};
            const std::array<bool, 3> components = given_components(displacement, s.model().dim(), values);
            s.set_prescribed(group, values, components);
          },
          py::arg("group"), py::arg("displacement"),
          "Holds the group's constrained dofs at `displacement` (dim values; None keeps a component) from the next "
          "step on. The group must be fixed or prescribed in the scene.")
      .def(
          "criteria",
          [](const Simulation& s) {
            py::dict out;
            for (const auto& [name, values] : s.criteria())
              out[py::str(name)] = Array(static_cast<py::ssize_t>(values.size()), values.data());
            return out;
          },
          "The adaptive criteria's last values per cell, by name (empty without `adaptivity`).")
      .def(
          "report", [](const Simulation& s) { return report_dict(s.report()); },
          "The run's figures so far, as a dict (complete once finished).")
      .def("__repr__", [](const Simulation& s) {
        return "<tensormass.Simulation " + s.scene().path + ": step " + std::to_string(s.state().step) + "/" +
               std::to_string(s.scene().solver.total_steps()) + ">";
      });
}

}  // namespace tensormass::python
