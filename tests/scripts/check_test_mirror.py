#!/usr/bin/python3
"""Checks that the tests mirror the runtime's sources file for file.

    check_test_mirror.py [--root DIR]

Every runtime/src/<folder>/<name>.cpp has a test file
tests/runtime/<folder>/test_<name>*.cpp (tests/kernels/ for the kernels
folder), or is listed in ALLOWED below with the file where its tests live.

Prints one line per source without tests, and one per entry of ALLOWED
that names no source or whose source has its own test file now, and exits
1 when there is one; 0 otherwise, with a one-line count.
"""
import argparse
import sys
from pathlib import Path

# Folders of runtime/src whose tests are not under tests/runtime/<folder>.
TEST_FOLDERS = {"kernels": "tests/kernels"}

# Sources tested under another name: source -> where its tests live.
ALLOWED = {
    "linear_solvers/petsc_missing.cpp": "built without PETSc only: tests/runtime/linear_solvers/test_linear_solver.cpp, "
    "scene/test_scene_load.cpp",
    "parallel/mpi_missing.cpp": "built without PETSc only: tests/runtime/parallel/test_mpi_world.cpp (one rank)",
    "simulation/carry_laws.cpp": "tests/runtime/simulation/test_refinement_run.cpp (laws carried to the children)",
    "simulation/discretisation.cpp": "tests/runtime/simulation/test_simulation.cpp, parallel/check_mpi_runs.py",
    "simulation/report_figures.cpp": "tests/runtime/cli/test_run_command.cpp, simulation/test_track_run.cpp",
    "simulation/resume_checkpoint.cpp": "tests/runtime/simulation/test_checkpoint.cpp (run --resume)",
    "simulation/run_refinement.cpp": "tests/runtime/simulation/test_refinement_run.cpp, test_refinement_run_3d.cpp",
    "simulation/state_frames.cpp": "tests/runtime/simulation/test_refinement_run.cpp, cli/test_run_command.cpp",
}


def test_folder(root: Path, folder: str) -> Path:
    return root / TEST_FOLDERS.get(folder, f"tests/runtime/{folder}")


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", type=Path, default=Path(__file__).resolve().parents[2])
    args = parser.parse_args(argv)
    sources_root = args.root / "runtime" / "src"
    if not sources_root.is_dir():
        print(f"check_test_mirror.py: no {sources_root}", file=sys.stderr)
        return 2
    sources = sorted(p.relative_to(sources_root).as_posix() for p in sources_root.rglob("*.cpp"))
    problems = []
    for source in sources:
        folder, name = source.rsplit("/", 1) if "/" in source else ("", source)
        tests = sorted(test_folder(args.root, folder).glob(f"test_{name[:-len('.cpp')]}*.cpp"))
        if tests and source in ALLOWED:
            problems.append(f"runtime/src/{source}: has {tests[0].relative_to(args.root).as_posix()} now; "
                            f"remove it from ALLOWED in {Path(__file__).name}")
        elif not tests and source not in ALLOWED:
            expected = test_folder(args.root, folder).relative_to(args.root).as_posix()
            problems.append(f"runtime/src/{source}: no {expected}/test_{name[:-len('.cpp')]}*.cpp (write it, or list "
                            f"the source in ALLOWED in {Path(__file__).name} with where its tests live)")
    for source in sorted(set(ALLOWED) - set(sources)):
        problems.append(f"runtime/src/{source}: listed in ALLOWED but there is no such source")
    for line in problems:
        print(line)
    if problems:
        print(f"check_test_mirror.py: {len(problems)} source(s) out of the mirror", file=sys.stderr)
        return 1
    print(f"test mirror: {len(sources)} sources, {len(sources) - len(ALLOWED)} with their own test file, "
          f"{len(ALLOWED)} tested elsewhere (ALLOWED)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
