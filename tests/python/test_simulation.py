"""tensormass.Simulation: a scene stepped from Python.

Checked against the CLI's output of the same scene, a mesh given as arrays
against the same mesh read from its file, laws and boundary conditions
changed between steps, the GIL released while stepping, and every error
path (ValueError with the file/key, TypeError, NumericalError)."""
import os
import shutil
import subprocess
import sys
import threading

import meshio
import numpy as np
import pytest

import tensormass as tm

BINARY = os.environ.get("TENSORMASS_BINARY", "build/tensormass")

SCENE = """mesh: beam.msh
materials: [{{law: {law}, young: 2.0e6, poisson: 0.3, density: 1000}}]
fixed: [clamp]
{extra}
loads: {{gravity: [0, -9.81, 0]}}
solver: {{type: implicit, dt: 0.01, steps: 8, newton_iterations: 2}}
output: {{directory: {out}, every: 4}}
"""


def write_scene(directory, name, law="stvk", extra="", out=None):
    path = directory / name
    path.write_text(SCENE.format(law=law, extra=extra, out=out or "out-" + path.stem))
    return str(path)


@pytest.fixture(scope="module")
def beam(tmp_path_factory):
    """A 3D tet beam (8 x 2 x 2 cubes x 6 tets) in a scratch directory."""
    directory = tmp_path_factory.mktemp("beam")
    subprocess.run([BINARY, "beam", "--dim", "3", "--cells", "8,2,2", "--size", "0.4,0.1,0.1", "--type", "tet6",
                    "-o", str(directory / "beam.msh")], check=True, capture_output=True)
    return directory


def test_stepping_matches_the_cli(beam):
    scene = write_scene(beam, "cli.yaml")
    subprocess.run([BINARY, "run", scene, "--quiet"], check=True, capture_output=True)
    cli = meshio.read(beam / "out-cli" / "final.vtu").point_data["displacement"]
    sim = tm.Simulation(scene, overrides={"output.directory": "out-python"})
    steps = 0
    while sim.step():
        steps += 1
        assert sim.step_index == steps
    assert steps == sim.steps == 8
    assert sim.finished and not sim.step()
    assert sim.time == pytest.approx(0.08)
    assert sim.displacement.shape == (cli.shape[0], 3)
    assert np.abs(sim.displacement - cli).max() <= 1e-12 * np.abs(cli).max()
    assert np.abs(cli).max() > 1e-4  # the beam moved: the comparison means something
    for name in ("final.vtu", "series.pvd", "summary.json", "frame_000004.vtu"):
        assert (beam / "out-python" / name).exists(), name


def test_run_calls_back_and_reports(beam):
    sim = tm.Simulation(write_scene(beam, "callback.yaml"), overrides={"solver.steps": 3})
    seen = []
    report = sim.run(callback=lambda s: seen.append((s.step_index, float(np.abs(s.velocity).max()))))
    assert [step for step, _ in seen] == [1, 2, 3]
    assert all(speed > 0 for _, speed in seen)
    assert report["steps"] == 3 and report["newton_iterations"] > 0
    assert report["linear_iterations"] >= report["newton_iterations"] and report["factorizations"] >= 1
    assert "final.vtu" in report["files"]


def test_from_arrays_matches_the_file(beam):
    from_file = tm.Simulation(write_scene(beam, "file.yaml"))
    from_file.run()
    mesh = meshio.read(beam / "beam.msh")
    points = mesh.points
    assert points.shape[0] == from_file.rest_positions.shape[0]
    tets = np.vstack([block.data for block in mesh.cells if block.type == "tetra"])
    clamp = np.flatnonzero(points[:, 0] == 0.0)
    sim = tm.Simulation.from_arrays(
        points, {"tetra": tets}, groups={"clamp": clamp},
        materials=[{"law": "stvk", "young": 2.0e6, "poisson": 0.3, "density": 1000}],
        fixed=["clamp"], loads={"gravity": np.array([0, -9.81, 0])},
        solver={"type": "implicit", "dt": 0.01, "steps": 8, "newton_iterations": 2},
        output={"directory": str(beam / "out-arrays")})
    np.testing.assert_array_equal(sim.rest_positions, from_file.rest_positions)
    sim.run()
    scale = np.abs(from_file.displacement).max()
    assert np.abs(sim.displacement - from_file.displacement).max() <= 1e-12 * scale
    assert (beam / "out-arrays" / "final.vtu").exists()


def test_set_law_takes_effect(beam):
    stvk = tm.Simulation(write_scene(beam, "pure-stvk.yaml"))
    stvk.run()
    sim = tm.Simulation(write_scene(beam, "switched.yaml", law="hooke"))
    assert set(sim.cell_laws()) == {"hooke"}
    sim.set_law(np.arange(len(sim.cell_laws())), "stvk")
    assert set(sim.cell_laws()) == {"stvk"}
    sim.run()
    scale = np.abs(stvk.displacement).max()
    assert np.abs(sim.displacement - stvk.displacement).max() <= 1e-12 * scale
    with pytest.raises(ValueError, match="no kernel for law 'nonsense'"):
        sim.set_law([0], "nonsense")
    with pytest.raises(ValueError, match="cell 100000"):
        sim.set_law([100000], "stvk")


def test_set_prescribed_moves_the_group(beam):
    extra = "prescribed: [{region: tip, displacement: [0, -0.002, 0], profile: {type: ramp, duration: 1.0}}]"
    sim = tm.Simulation(write_scene(beam, "probe.yaml", extra=extra))
    tip = np.flatnonzero(np.isclose(sim.rest_positions[:, 0], 0.4))
    sim.step()
    np.testing.assert_allclose(sim.displacement[tip, 1], -0.002 * 0.01)
    sim.set_prescribed("tip", displacement=(0.001, -0.005, None))
    sim.step()
    np.testing.assert_array_equal(sim.displacement[tip, 0], 0.001)
    np.testing.assert_array_equal(sim.displacement[tip, 1], -0.005)
    assert np.abs(sim.displacement[:, 0]).max() >= 0.001
    with pytest.raises(ValueError, match="only dofs that are fixed or prescribed"):
        sim.set_prescribed("body", displacement=(0, 0, 0))
    with pytest.raises(ValueError, match="3 components"):
        sim.set_prescribed("tip", displacement=(0, 0))


def test_internal_force_balances_the_loads_at_equilibrium(beam):
    # A static solve: each element's internal forces sum to zero, so the
    # nodes' do too; at the free nodes they balance the gravity load, so
    # their sum is the weight of all but the clamp nodes' share (small here).
    sim = tm.Simulation(write_scene(beam, "static.yaml"),
                        overrides={"solver.type": "static", "solver.load_steps": 2, "solver.tolerance": 1e-12})
    before = sim.internal_force()
    assert before.shape == sim.displacement.shape and np.abs(before).max() == 0.0
    sim.run()
    force = sim.internal_force()
    clamp = np.isclose(sim.rest_positions[:, 0], 0.0)
    total_mass = 1000 * 0.4 * 0.1 * 0.1
    weight = 9.81 * total_mass
    np.testing.assert_allclose(force.sum(axis=0), 0.0, atol=1e-9 * weight)
    free_sum = force[~clamp].sum(axis=0)
    assert -weight < free_sum[1] < -0.8 * weight
    assert abs(free_sum[0]) < 1e-6 * weight and abs(free_sum[2]) < 1e-6 * weight
    # The reaction at the clamp (its internal force minus its own gravity load) carries the weight.
    assert force[clamp].sum(axis=0)[1] == pytest.approx(-free_sum[1], rel=1e-9)


def test_criteria_of_the_adaptive_model(beam):
    extra = "adaptivity: {criteria: [{name: R_NL, threshold: 0.001}]}"
    sim = tm.Simulation(write_scene(beam, "adaptive.yaml", law="hooke", extra=extra))
    sim.run()
    criteria = sim.criteria()
    assert list(criteria) == ["R_NL"]
    assert criteria["R_NL"].shape == (len(sim.cell_laws()),)
    assert criteria["R_NL"].max() > 0
    assert tm.Simulation(write_scene(beam, "plain.yaml")).criteria() == {}


def test_stepping_releases_the_gil(tmp_path):
    subprocess.run([BINARY, "beam", "--dim", "3", "--cells", "24,6,6", "--type", "tet6", "-o",
                    str(tmp_path / "beam.msh")], check=True, capture_output=True)
    scene = write_scene(tmp_path, "big.yaml")
    sim = tm.Simulation(scene, overrides={"solver.type": "static", "solver.load_steps": 1, "solver.tolerance": 1e-10})
    worker = threading.Thread(target=sim.step)
    counted = 0
    worker.start()
    while worker.is_alive():
        counted += 1
    worker.join()
    assert sim.finished
    assert counted > 1000  # this thread ran Python while the other solved


def test_errors(beam, tmp_path):
    with pytest.raises(ValueError, match="missing.yaml"):
        tm.Simulation(str(tmp_path / "missing.yaml"))
    scene = write_scene(beam, "errors.yaml")
    with pytest.raises(ValueError, match="stepz"):
        tm.Simulation(scene, overrides={"solver.stepz": 3})
    with pytest.raises(TypeError, match="dict"):
        tm.Simulation(scene, overrides=["solver.steps=3"])
    with pytest.raises(ValueError, match="unknown element 'tetrahedron'"):
        tm.Simulation.from_arrays(np.eye(4, 3), {"tetrahedron": [[0, 1, 2, 3]]},
                                  materials=[{"law": "stvk", "young": 1e6, "poisson": 0.3, "density": 1000}],
                                  solver={"type": "static"})
    with pytest.raises(ValueError, match="from_arrays:1: missing required key 'materials'"):
        tm.Simulation.from_arrays(np.eye(4, 3), {"tetra": [[0, 1, 2, 3]]}, solver={"type": "static"})
    material = [{"law": "stvk", "young": 1e6, "poisson": 0.3, "density": 1000}]
    with pytest.raises(ValueError, match="points must have shape"):
        tm.Simulation.from_arrays(np.zeros(4), {"tetra": [[0, 1, 2, 3]]}, materials=material,
                                  solver={"type": "static"})
    with pytest.raises(ValueError, match="no group 'base'"):
        tm.Simulation.from_arrays(np.eye(4, 3), {"tetra": [[0, 1, 2, 3]]}, materials=material, fixed=["base"],
                                  solver={"type": "static"})


def test_numerical_failure_raises_and_keeps_the_last_good_state(beam):
    sim = tm.Simulation(write_scene(beam, "diverges.yaml"),
                        overrides={"solver.type": "static", "solver.max_iterations": 1, "solver.tolerance": 1e-14,
                                   "materials.0.young": 2.0e3})
    with pytest.raises(tm.NumericalError, match="did not converge"):
        sim.run()
    assert sim.finished
    assert (beam / "out-diverges" / "last_good.vtu").exists()


MPI_SCRIPT = """
import sys, numpy as np, tensormass as tm
sim = tm.Simulation(sys.argv[1], overrides={"output.directory": "out-mpi-python", "solver.backend": "petsc",
                                            "solver.linear.tolerance": 1e-12})
sim.run()
if tm.mpi_rank() == 0:
    np.save(sys.argv[2], sim.displacement)
    print("ranks", tm.mpi_size())
"""


@pytest.mark.skipif(not tm.petsc_available() or not shutil.which("mpirun"), reason="no PETSc build or no mpirun")
def test_runs_shared_among_mpi_ranks(beam):
    scene = write_scene(beam, "mpi.yaml")
    serial = tm.Simulation(scene, overrides={"output.directory": "out-mpi-serial"})
    serial.run()
    script = beam / "mpi_run.py"
    script.write_text(MPI_SCRIPT)
    environment = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    result = subprocess.run(["mpirun", "-n", "2", sys.executable, str(script), scene, str(beam / "mpi.npy")],
                            capture_output=True, text=True, env=environment, timeout=120)
    assert result.returncode == 0, result.stderr
    assert "ranks 2" in result.stdout
    shared = np.load(beam / "mpi.npy")
    assert np.abs(shared - serial.displacement).max() <= 1e-8 * np.abs(serial.displacement).max()
    assert (beam / "out-mpi-python" / "final.pvtu").exists()
