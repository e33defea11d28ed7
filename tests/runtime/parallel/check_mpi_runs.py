"""`mpirun -n 1/2/3 tensormass run ... --set solver.backend=petsc` against the
serial solver (ctest parallel.mpirun): static StVK (CG + GAMG, and MUMPS's
direct Cholesky) and implicit runs of a 3D beam, a mixed-element beam, a run
whose cells switch laws, an explicit run and one whose cells switch (the
criteria screen on), a tet10 beam and a 2D quad plate under pressure and
nodal forces on their tips, runs that refine their mesh (a tet beam, and the
mixed beam with its pyramids); each rank holds its part of the mesh (the
whole mesh in refining runs); the .pvtu pieces hold every cell once; a run
resumed from its checkpoint ends where a straight run does, its track the
serial run's; the same run twice gives the same bytes; a bad scene, a truncated mesh
(read by rank 0 alone), an element inverted at rest (met by the rank building
its part) and a numerical failure exit non-zero on every rank with one
message and no hang.

usage: check_mpi_runs.py TENSORMASS WORKDIR [--without-petsc] [--json FILE]
(--without-petsc: the build has no PETSc; the test says so and is skipped;
--json: the differences, scene by scene and rank count by rank count, with
the run's metadata, for docs/results/mpi.md)
"""
import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np

TOLERANCE = 1e-8  # largest nodal difference over the largest displacement
RANKS = (1, 2, 3)
DIFFERENCES = []  # (scene, ranks, difference, laws equal), for --json

def clamped_beam(rest, law="stvk", mesh="beam.msh"):
    """A clamped beam under gravity; `rest`: the solver and what else the scene has."""
    return f"""mesh: {mesh}
materials: [{{region: all, law: {law}, young: 2.0e6, poisson: 0.3, density: 1000}}]
fixed: [clamp]
loads: {{gravity: [0, -9.81, 0]}}
{rest}"""


def loaded_beam(mesh, solver, pressure, force):
    """A clamped beam under gravity, a pressure on its tip's facets and a
    force on each tip node: the facets and nodes of a group cut among ranks."""
    return f"""mesh: {mesh}
materials: [{{region: all, law: stvk, young: 2.0e6, poisson: 0.3, density: 1000}}]
fixed: [clamp]
loads:
  gravity: [0, -9.81, 0]
  pressure: [{{region: tip, pressure: {pressure}}}]
  nodal_forces: [{{region: tip, force: {force}}}]
solver: {solver}
"""


SCENES = {
    "static_stvk": clamped_beam(
        "solver: {type: static, load_steps: 3, tolerance: 1.0e-11, linear: {tolerance: 1.0e-12}}\n"),
    "static_mumps_direct": clamped_beam("""solver:
  type: static
  load_steps: 3
  tolerance: 1.0e-11
  linear: {petsc_options: "-ksp_type preonly -pc_type cholesky -pc_factor_mat_solver_type mumps"}
"""),
    "implicit_damped": clamped_beam("""solver:
  type: implicit
  dt: 0.01
  steps: 15
  newton_iterations: 2
  damping: {mass: 0.1, stiffness: 0.001}
  linear: {tolerance: 1.0e-12}
output: {every: 5}
"""),
    "static_mixed": clamped_beam(
        "solver: {type: static, load_steps: 2, tolerance: 1.0e-11, linear: {tolerance: 1.0e-12}}\n",
        law="neohookean", mesh="mixed.msh"),
    "implicit_switching": clamped_beam("""solver: {type: implicit, dt: 0.01, steps: 25, linear: {tolerance: 1.0e-12}}
adaptivity:
  criteria: [{name: R_NL, threshold: 0.003}]
  ladder: [hooke, neohookean]
""", law="hooke"),
    "explicit": clamped_beam("solver: {type: explicit, dt: 2.0e-4, steps: 300, damping: {mass: 0.1}}\n"),
    "explicit_switching": clamped_beam("""solver: {type: explicit, dt: 2.0e-4, steps: 300, damping: {mass: 0.1}}
adaptivity:
  criteria: [{name: R_NL, threshold: 1.0e-4}]
  ladder: [hooke, neohookean]
  every: 5
""", law="hooke"),
    "implicit_refining": clamped_beam("""solver: {type: implicit, dt: 0.01, steps: 12, linear: {tolerance: 1.0e-12}}
adaptivity:
  refine: {criteria: [{name: R_ZZ, threshold: 0.4}], max_level: 1, every: 4}
output: {every: 4}
""", law="hooke"),
    "static_loads_tet10": loaded_beam(
        "tet10.msh", "{type: static, load_steps: 2, tolerance: 1.0e-11, linear: {tolerance: 1.0e-12}}",
        2000, "[0, -5, 0]"),
    "implicit_loads_2d": loaded_beam(
        "plate.msh", "{type: implicit, dt: 0.01, steps: 10, linear: {tolerance: 1.0e-12}}", 2000, "[0, -5]"),
    "static_refining_mixed": clamped_beam("""solver: {type: static, load_steps: 2, tolerance: 1.0e-11, linear: {tolerance: 1.0e-12}}
adaptivity:
  refine: {criteria: [{name: R_ZZ, threshold: 0.5}], max_level: 1}
""", law="neohookean", mesh="mixed.msh"),
}


def mpirun(ranks):
    command = ["mpirun", "-n", str(ranks)]
    if ranks > os.cpu_count():
        command.append("--oversubscribe")
    return command


def run(command, cwd, timeout=240):
    return subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=timeout)


def read_result(directory):
    """(displacement by node, law_id by cell) of final.vtu or final.pvtu's pieces."""
    single = os.path.join(directory, "final.vtu")
    if os.path.exists(single):
        mesh = meshio.read(single)
        return mesh.point_data["displacement"], np.concatenate(mesh.cell_data["law_id"]).ravel()
    root = ET.parse(os.path.join(directory, "final.pvtu")).getroot()
    pieces = [meshio.read(os.path.join(directory, p.get("Source"))) for p in root.iter("Piece")]
    nodes = int(max(p.point_data["global_node"].max() for p in pieces)) + 1
    cells = sum(len(np.concatenate(p.cell_data["global_cell"])) for p in pieces)
    displacement = np.full((nodes, 3), np.nan)
    laws = np.full(cells, -1.0)
    for piece in pieces:
        displacement[piece.point_data["global_node"].ravel().astype(int)] = piece.point_data["displacement"]
        global_cell = np.concatenate(piece.cell_data["global_cell"]).ravel().astype(int)
        assert np.all(laws[global_cell] == -1), "a cell is in two pieces"
        laws[global_cell] = np.concatenate(piece.cell_data["law_id"]).ravel()
    assert not np.isnan(displacement).any(), "a node is in no piece"
    assert np.all(laws >= 0), "a cell is in no piece"
    return displacement, laws


def check_scene(binary, work, name):
    failures = []
    scene = os.path.join(work, name + ".yaml")
    with open(scene, "w") as f:
        f.write(SCENES[name])
    serial = run([binary, "run", scene, "--quiet", "--set", f"output.directory=out-{name}-serial"], work)
    if serial.returncode != 0:
        return [f"{name}: serial run failed: {serial.stderr}"]
    reference, reference_laws = read_result(os.path.join(work, f"out-{name}-serial"))
    scale = np.abs(reference).max()
    for ranks in RANKS:
        out = f"out-{name}-{ranks}"
        result = run(mpirun(ranks) + [binary, "run", scene, "--quiet", "--set", "solver.backend=petsc",
                                      "--set", f"output.directory={out}"], work)
        if result.returncode != 0:
            failures.append(f"{name}, {ranks} ranks: exit {result.returncode}: {result.stderr[-2000:]}")
            continue
        displacement, laws = read_result(os.path.join(work, out))
        difference = np.abs(displacement - reference).max() / scale
        summary = json.load(open(os.path.join(work, out, "summary.json")))
        DIFFERENCES.append({"scene": name, "ranks": ranks, "difference": float(difference),
                            "laws_equal": bool(np.array_equal(laws, reference_laws))})
        print(f"{name:20s} {ranks} ranks: difference {difference:.2e} of the largest displacement "
              f"{scale:.4g}; laws {'equal' if np.array_equal(laws, reference_laws) else 'DIFFER'}")
        if not difference <= TOLERANCE:
            failures.append(f"{name}, {ranks} ranks: differs from serial by {difference:.3e} (> {TOLERANCE})")
        if not np.array_equal(laws, reference_laws):
            failures.append(f"{name}, {ranks} ranks: cells ended under other laws than in the serial run")
        if "refinement" in summary:
            cells = [event["cells"] for event in summary["refinement"]["events"]]
            serial_summary = json.load(open(os.path.join(work, f"out-{name}-serial", "summary.json")))
            serial_cells = [event["cells"] for event in serial_summary["refinement"]["events"]]
            if cells != serial_cells or len(cells) < 2:
                failures.append(f"{name}, {ranks} ranks: meshes {cells}, serial {serial_cells} (refined alike?)")
        if summary["mpi_ranks"] != ranks:
            failures.append(f"{name}, {ranks} ranks: summary.json says mpi_ranks {summary['mpi_ranks']}")
        held = summary["cells_per_rank"]
        whole = summary["elements"]
        if "refinement" in summary or ranks == 1:  # refining runs keep the whole mesh on every rank
            expected = "the whole mesh" if all(count == whole for count in held) else None
        else:  # each rank its part: fewer cells than the mesh, together at least all of them
            expected = "parts" if all(count < whole for count in held) and sum(held) >= whole else None
        if len(held) != ranks or expected is None:
            failures.append(f"{name}, {ranks} ranks: cells_per_rank {held} of {whole} cells")
        phases = summary["peak_memory_mib_by_phase"]
        if list(phases) != ["mesh", "model and assembler", "shared", "solver", "first step", "end"] or any(
                len(per_rank) != ranks for per_rank in phases.values()) or phases["end"] != summary[
                    "peak_memory_mib_per_rank"]:
            failures.append(f"{name}, {ranks} ranks: peak_memory_mib_by_phase {phases}")
    return failures


def run_on_two_ranks(binary, work, name, scene_text):
    """Writes NAME.yaml and runs it on 2 ranks with PETSc; the finished process."""
    scene = os.path.join(work, name + ".yaml")
    with open(scene, "w") as f:
        f.write(scene_text)
    return run(mpirun(2) + [binary, "run", scene, "--set", "solver.backend=petsc"], work, timeout=60)


def check_bad_scene(binary, work):
    result = run_on_two_ranks(binary, work, "bad", SCENES["static_stvk"].replace("load_steps: 3", "load_step: 3"))
    count = result.stderr.count("unknown key")
    print(f"bad scene on 2 ranks: exit {result.returncode}, the key named {count} time(s)")
    failures = []
    if result.returncode == 0:
        failures.append("a bad scene exited 0 under mpirun")
    if count < 1:
        failures.append("the bad scene's message does not name the key: " + result.stderr)
    if count > 1:
        failures.append(f"the bad scene's message came {count} times: " + result.stderr)
    return failures


def check_bad_mesh(binary, work):
    """Rank 0 reads the mesh for all ranks: its error must reach every rank."""
    with open(os.path.join(work, "beam.msh"), "rb") as f:
        head = f.read(3000)
    with open(os.path.join(work, "truncated.msh"), "wb") as f:
        f.write(head)
    result = run_on_two_ranks(binary, work, "truncated", SCENES["static_stvk"].replace("beam.msh", "truncated.msh"))
    count = result.stderr.count("truncated.msh:")
    print(f"truncated mesh on 2 ranks: exit {result.returncode}, the file named {count} time(s)")
    if result.returncode != 2 or count != 1:
        return [f"a truncated mesh on 2 ranks: exit {result.returncode}, named {count} times: " + result.stderr]
    return []


def invert_last_volume_element(source, target):
    """Copies the MSH 4.1 text mesh `source` to `target` with the last
    element of its 3D blocks turned inside out (two nodes swapped)."""
    with open(source) as f:
        lines = f.read().split("\n")
    start = lines.index("$Elements")
    at, last = start + 2, None
    while lines[at] != "$EndElements":
        dim, _, _, count = map(int, lines[at].split())
        if dim == 3:
            last = at + count
        at += count + 1
    fields = lines[last].split()
    fields[1], fields[2] = fields[2], fields[1]
    lines[last] = " ".join(fields)
    with open(target, "w") as f:
        f.write("\n".join(lines))


def check_inverted_at_rest(binary, work):
    """An element inverted at rest, met while each rank builds its model on its
    part: every rank stops at once, with the message of one process."""
    invert_last_volume_element(os.path.join(work, "beam.msh"), os.path.join(work, "inverted.msh"))
    text = SCENES["static_stvk"].replace("beam.msh", "inverted.msh")
    result = run_on_two_ranks(binary, work, "inverted", text)
    serial = run([binary, "run", os.path.join(work, "inverted.yaml")], work, timeout=60)
    message = serial.stderr.strip().splitlines()[-1] if serial.stderr.strip() else "(no message)"
    count = result.stderr.count(message)
    print(f"element inverted at rest on 2 ranks: exit {result.returncode}, the serial message told {count} time(s)")
    if result.returncode != 2 or serial.returncode != 2 or count != 1 or "at rest" not in message:
        return [f"an element inverted at rest on 2 ranks: exit {result.returncode} (serial {serial.returncode}), "
                f"'{message}' told {count} times: " + result.stderr]
    return []


def check_resume(binary, work):
    """A run on parts of the mesh stopped after 10 steps and resumed from its
    checkpoint to 20 ends where a run of 20 steps does, its track (kept by
    rank 0, made from the whole mesh) one row per step; the 2-rank track
    (its nodes gathered from their owners each step) is the serial one's."""
    scene = os.path.join(work, "resumed.yaml")
    with open(scene, "w") as f:
        f.write(clamped_beam("solver: {type: implicit, dt: 0.01, steps: 10, linear: {tolerance: 1.0e-12}}\n"
                             "output: {checkpoint_every: 5, track: [body]}\n"))
    common = mpirun(2) + [binary, "run", scene, "--quiet", "--set", "solver.backend=petsc"]
    runs = [common + ["--set", "output.directory=out-resumed"],
            common + ["--set", "output.directory=out-resumed", "--set", "solver.steps=20", "--resume"],
            common + ["--set", "output.directory=out-straight", "--set", "solver.steps=20"],
            [binary, "run", scene, "--quiet", "--set", "output.directory=out-serial", "--set", "solver.steps=20"]]
    for command in runs:
        result = run(command, work)
        if result.returncode != 0:
            return [f"resume on 2 ranks: exit {result.returncode}: {result.stderr[-2000:]}"]
    resumed, _ = read_result(os.path.join(work, "out-resumed"))
    straight, _ = read_result(os.path.join(work, "out-straight"))
    difference = np.abs(resumed - straight).max() / np.abs(straight).max()
    rows = [len(open(os.path.join(work, d, "track_body.csv")).read().splitlines())
            for d in ("out-resumed", "out-straight")]
    tracks = [np.loadtxt(os.path.join(work, d, "track_body.csv"), delimiter=",", skiprows=1)
              for d in ("out-straight", "out-serial")]
    track_difference = (np.abs(tracks[0] - tracks[1]).max() / np.abs(tracks[1][:, 4:]).max()
                        if tracks[0].shape == tracks[1].shape else np.inf)
    DIFFERENCES.append({"scene": "resumed_track", "ranks": 2, "difference": float(track_difference), "laws_equal": True})
    print(f"resumed on 2 ranks: difference {difference:.2e} of the largest displacement; track rows {rows}; "
          f"2-rank track against the serial one: {track_difference:.2e} of its largest displacement")
    if not difference <= TOLERANCE or rows[0] != rows[1] or not track_difference <= TOLERANCE:
        return [f"resume on 2 ranks: differs by {difference:.3e}, track rows {rows}, track {track_difference:.3e}"]
    return []


def check_repeats(binary, work):
    """The same adaptive implicit run on 2 ranks twice writes the same
    pieces byte for byte: the mesh cut (Scotch in a deterministic context),
    the ghost exchanges and the PETSc solves repeat."""
    scene = os.path.join(work, "implicit_switching.yaml")
    pieces = []
    for attempt in ("a", "b"):
        out = f"out-repeat-{attempt}"
        result = run(mpirun(2) + [binary, "run", scene, "--quiet", "--set", "solver.backend=petsc",
                                  "--set", f"output.directory={out}"], work)
        if result.returncode != 0:
            return [f"repeat on 2 ranks: exit {result.returncode}: {result.stderr[-2000:]}"]
        pieces.append([open(os.path.join(work, out, f"final_p{rank}.vtu"), "rb").read() for rank in (0, 1)])
    same = pieces[0] == pieces[1]
    print(f"the same run twice on 2 ranks: pieces {'identical' if same else 'DIFFER'}")
    return [] if same else ["repeat on 2 ranks: the pieces differ between two runs of the same scene"]


def check_numerical_failure(binary, work):
    scene = os.path.join(work, "diverging.yaml")
    with open(scene, "w") as f:
        f.write(SCENES["static_stvk"].replace("load_steps: 3", "load_steps: 1, max_iterations: 1"))
    result = run(mpirun(2) + [binary, "run", scene, "--set", "solver.backend=petsc",
                              "--set", "output.directory=out-diverging"], work, timeout=60)
    count = result.stderr.count("numerical failure")
    print(f"failing run on 2 ranks: exit {result.returncode}, the failure told {count} time(s)")
    failures = []
    if result.returncode != 3 or count != 1:
        failures.append(f"a numerical failure on 2 ranks: exit {result.returncode}, told {count} times: "
                        + result.stderr)
    pieces = ["last_good.pvtu", "last_good_p0.vtu", "last_good_p1.vtu", "summary.json"]
    missing = [p for p in pieces if not os.path.exists(os.path.join(work, "out-diverging", p))]
    if missing:
        failures.append(f"a numerical failure on 2 ranks left no {', '.join(missing)}")
    return failures


def main():
    if "--without-petsc" in sys.argv:
        print("SKIP: this build has no PETSc, so no MPI runs (apt-get install libpetsc-real-dev libopenmpi-dev)")
        return 77
    binary, work = os.path.abspath(sys.argv[1]), sys.argv[2]
    if not shutil.which("mpirun"):
        print("SKIP: no mpirun (apt-get install openmpi-bin)")
        return 77
    if os.geteuid() == 0:
        os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
        os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    for args, name in ((["--dim", "3", "--size", "4,1,1", "--cells", "12,3,3", "--type", "tet6"], "beam.msh"),
                       (["--dim", "3", "--size", "4,1,1", "--cells", "10,2,2", "--mix", "hex8:0.4,tet6:0.3,prism6:0.3"],
                        "mixed.msh"),
                       (["--dim", "3", "--size", "4,1,1", "--cells", "8,2,2", "--type", "tet6", "--order", "2"],
                        "tet10.msh"),
                       (["--dim", "2", "--size", "4,1", "--cells", "24,4", "--type", "quad4"], "plate.msh")):
        made = run([binary, "beam", *args, "-o", name], work)
        if made.returncode != 0:
            print(made.stderr)
            return 1
    failures = []
    for name in SCENES:
        failures += check_scene(binary, work, name)
    failures += check_bad_scene(binary, work)
    failures += check_bad_mesh(binary, work)
    failures += check_inverted_at_rest(binary, work)
    failures += check_resume(binary, work)
    failures += check_repeats(binary, work)
    failures += check_numerical_failure(binary, work)
    for failure in failures:
        print("FAIL:", failure)
    if "--json" in sys.argv:
        write_json(sys.argv[sys.argv.index("--json") + 1], binary)
    return 1 if failures else 0


def write_json(path, binary):
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "bench"))
    from bench_metadata import metadata
    with open(path, "w", encoding="utf-8") as handle:
        json.dump({"metadata": metadata(binary), "tolerance": TOLERANCE, "rows": DIFFERENCES}, handle, indent=1)
        handle.write("\n")


if __name__ == "__main__":
    sys.exit(main())
