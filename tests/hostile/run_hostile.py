#!/usr/bin/python3
"""The hostile-input suite: every class of hostile input and fault that the
readers and a run must survive, run against the tensormass binary.

Usage:
    /usr/bin/python3 tests/hostile/run_hostile.py --binary build/tensormass
        [--only NAME ...] [--list] [--timeout SECONDS] [--keep]

Each case builds its inputs in code in a fresh temporary directory (nothing
big is kept in the tree), runs the binary there and checks what
docs/outputs.md, docs/scene.md and docs/checkpoints.md promise:

- the exit code (0 ok, 2 bad input, 3 numerical failure, 4 failed write);
- the message: the file's name and the key words of the refusal, and none
  of the words of an unclear one ("bad file", "std::bad_alloc");
- the run ends within its wall-clock timeout (20 s); past it the run's
  process group is killed. A refusal must also come quickly: within 1 to 3
  seconds (by case) of the program's start, the time `tensormass version`
  takes (measured first, the slower of two runs), so a slow build or a
  loaded machine moves the bound with it;
- its peak resident memory stays under 150 MiB plus 20 times the size of
  the case's input files;
- nothing is left behind: no `*.tmp-*` file anywhere in the case's
  directory, and a refused run (exit 2) neither creates nor changes any
  file (the lock file `.tensormass.lock`, whose content names the last
  process that held it, is left out of that comparison).

Every run of the binary is a direct child of this script, started with an
address-space cap (RLIMIT_AS, 4 GiB) set between fork and exec, so a reader
that sizes an allocation by a hostile count fails there instead of taking
the machine. The script reaps each child itself with os.wait4, whose
resource usage is that one child's own: its ru_maxrss is the child's peak
resident memory, with no other run mixed in (RUSAGE_CHILDREN would give
the largest of all the children so far). OMP_NUM_THREADS is 2 unless the
environment sets it, so the threads' stacks and malloc arenas, and with
them the address space, do not grow with the machine's core count.

The cases run one after another (their times are not disturbed by each
other); the whole suite takes about 15 s. The script prints one line per
case (name, exit code, seconds, peak MiB, PASS or FAIL with the reasons)
and exits 1 when a case fails, 0 when all pass. ctest runs it as
`hostile.suite` (tests/hostile/CMakeLists.txt, label `hostile`).
"""

from __future__ import annotations

import argparse
import fcntl
import hashlib
import json
import os
import re
import resource
import shutil
import signal
import stat
import struct
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable

ADDRESS_SPACE_CAP = 4 << 30  # bytes, RLIMIT_AS of every run
DEFAULT_TIMEOUT_S = 20.0
MEMORY_BASELINE_MIB = 150.0
MEMORY_PER_INPUT_BYTE = 20.0
FULL_DISK_BYTES = 8 << 10  # RLIMIT_FSIZE of the full-disk case
LOCK_FILE = ".tensormass.lock"
POLL_S = 0.002

# --- Running the binary -----------------------------------------------------


@dataclass
class RunResult:
    """One run of the binary: its exit code (negative: killed by that
    signal), wall time, peak resident memory and output."""

    args: list[str]
    exit_code: int
    seconds: float
    peak_mib: float
    output: str
    timed_out: bool = False
    killed_on_purpose: bool = False


def child_limits(fsize_limit: int | None) -> Callable[[], None]:
    """The function run in the child between fork and exec: the
    address-space cap, and for the full-disk case a file-size limit with
    SIGXFSZ ignored (so a write past it fails with EFBIG instead of killing
    the process)."""

    def apply() -> None:
        _, hard = resource.getrlimit(resource.RLIMIT_AS)
        cap = ADDRESS_SPACE_CAP if hard == resource.RLIM_INFINITY else min(ADDRESS_SPACE_CAP, hard)
        resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
        if fsize_limit is not None:
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize_limit, fsize_limit))

    return apply


def run_binary(binary: Path, args: list[str], cwd: Path, timeout: float, fsize_limit: int | None = None,
               kill_when: Callable[[float], bool] | None = None) -> RunResult:
    """Runs `binary args` in `cwd` under the limits of child_limits, in its
    own process group. The child is polled with wait4(WNOHANG), so it is
    killed (SIGKILL to its group) only while it is still unreaped: at
    `timeout`, or as soon as kill_when(elapsed seconds) is true."""
    env = dict(os.environ)
    env.setdefault("OMP_NUM_THREADS", "2")
    with tempfile.TemporaryFile() as output:
        start = time.monotonic()
        process = subprocess.Popen([str(binary), *args], cwd=cwd, stdin=subprocess.DEVNULL, stdout=output,
                                   stderr=subprocess.STDOUT, env=env, start_new_session=True,
                                   preexec_fn=child_limits(fsize_limit))
        timed_out = killed_on_purpose = False
        while True:
            pid, status, usage = os.wait4(process.pid, os.WNOHANG)
            if pid == process.pid:
                break
            elapsed = time.monotonic() - start
            if not (timed_out or killed_on_purpose):
                if elapsed > timeout:
                    timed_out = True
                    os.killpg(process.pid, signal.SIGKILL)
                elif kill_when is not None and kill_when(elapsed):
                    killed_on_purpose = True
                    os.killpg(process.pid, signal.SIGKILL)
            time.sleep(POLL_S)
        seconds = time.monotonic() - start
        process.returncode = os.waitstatus_to_exitcode(status)  # reaped here, not by Popen
        output.seek(0)
        text = output.read().decode("utf-8", "replace")
    return RunResult(args, process.returncode, seconds, usage.ru_maxrss / 1024.0, text, timed_out,
                     killed_on_purpose)


# --- What a case's directory holds ------------------------------------------


def input_bytes(directory: Path) -> int:
    """The size of the regular files under `directory` (links not followed:
    a link to /dev/zero counts for nothing)."""
    total = 0
    for root, _, files in os.walk(directory):
        for name in files:
            info = os.lstat(os.path.join(root, name))
            if stat.S_ISREG(info.st_mode):
                total += info.st_size
    return total


def snapshot(directory: Path) -> dict[str, str]:
    """Every entry under `directory`: its kind, and for a regular file its
    size and SHA-256 (the lock file: its existence only)."""
    entries: dict[str, str] = {}
    for root, dirs, files in os.walk(directory):
        for name in dirs + files:
            path = os.path.join(root, name)
            relative = os.path.relpath(path, directory)
            info = os.lstat(path)
            if stat.S_ISREG(info.st_mode):
                if name == LOCK_FILE:
                    entries[relative] = "lock file"
                else:
                    digest = hashlib.sha256(Path(path).read_bytes()).hexdigest()
                    entries[relative] = f"file {info.st_size} {digest}"
            elif stat.S_ISDIR(info.st_mode):
                entries[relative] = "directory"
            else:
                entries[relative] = f"mode {stat.filemode(info.st_mode)}"
    return entries


def temporaries(directory: Path) -> list[str]:
    """The `*.tmp-*` files under `directory` (what an atomic write leaves
    while it is under way)."""
    return sorted(str(path.relative_to(directory)) for path in directory.rglob("*.tmp-*"))


# --- A case -------------------------------------------------------------------


class CaseFailure(Exception):
    """A setup step of a case failed; the case cannot go on."""


@dataclass
class CaseContext:
    """The directory of one case and the checks on its runs. `reported` is
    the run the case's line shows (the last hostile run)."""

    name: str
    directory: Path
    suite: "Suite"
    failures: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    reported: RunResult | None = None

    def path(self, name: str) -> Path:
        return self.directory / name

    def write(self, name: str, content: str | bytes) -> Path:
        path = self.path(name)
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, str):
            path.write_text(content)
        else:
            path.write_bytes(content)
        return path

    def check(self, condition: bool, reason: str) -> bool:
        if not condition:
            self.failures.append(reason)
        return condition

    def run(self, args: list[str], expect_code: int | Iterable[int], expect_text: Iterable[str | re.Pattern] = (),
            forbid_text: Iterable[str] = (), seconds_past_start: float | None = None,
            writes_nothing: bool | None = None, timeout: float | None = None, fsize_limit: int | None = None,
            kill_when: Callable[[float], bool] | None = None) -> RunResult:
        """A hostile run and its checks: exit code, message, time, memory,
        temporaries, and (by default for an expected exit 2) that the
        directory is the same after the run as before."""
        expected_codes = {expect_code} if isinstance(expect_code, int) else set(expect_code)
        if writes_nothing is None:
            writes_nothing = expected_codes == {2}
        limit = timeout if timeout is not None else self.suite.timeout
        memory_bound = MEMORY_BASELINE_MIB + MEMORY_PER_INPUT_BYTE * input_bytes(self.directory) / (1 << 20)
        before = snapshot(self.directory) if writes_nothing else None

        result = run_binary(self.suite.binary, args, self.directory, limit, fsize_limit, kill_when)
        self.reported = result
        command = " ".join(args)
        if result.timed_out:
            self.failures.append(f"`{command}` ran past its {limit:g} s timeout and was killed")
        elif result.exit_code not in expected_codes:
            expected = " or ".join(str(code) for code in sorted(expected_codes))
            self.failures.append(f"`{command}` exited {result.exit_code}, expected {expected}: "
                                 f"{first_lines(result.output)}")
        for wanted in expect_text:
            found = wanted.search(result.output) if isinstance(wanted, re.Pattern) else wanted in result.output
            label = wanted.pattern if isinstance(wanted, re.Pattern) else wanted
            self.check(bool(found), f"the output lacks '{label}': {first_lines(result.output)}")
        for unwanted in forbid_text:
            self.check(unwanted not in result.output, f"the output says '{unwanted}': {first_lines(result.output)}")
        if seconds_past_start is not None and not result.timed_out:
            bound = self.suite.startup_seconds + seconds_past_start
            self.check(result.seconds <= bound,
                       f"took {result.seconds:.2f} s, more than {seconds_past_start:g} s past the program's "
                       f"start ({bound:.2f} s)")
        self.check(result.peak_mib <= memory_bound,
                   f"peak memory {result.peak_mib:.1f} MiB is over its bound of {memory_bound:.1f} MiB")
        left = temporaries(self.directory)
        self.check(not left, f"temporaries left behind: {', '.join(left)}")
        if before is not None:
            after = snapshot(self.directory)
            created = sorted(set(after) - set(before))
            changed = sorted(name for name in set(before) & set(after) if before[name] != after[name])
            removed = sorted(set(before) - set(after))
            self.check(not created, f"the refused run created {', '.join(created)}")
            self.check(not changed, f"the refused run changed {', '.join(changed)}")
            self.check(not removed, f"the refused run removed {', '.join(removed)}")
        return result


def first_lines(text: str, count: int = 2) -> str:
    lines = [line for line in text.strip().splitlines() if line.strip()]
    shown = " | ".join(lines[-count:]) if lines else "(no output)"
    return shown if len(shown) <= 400 else shown[:400] + "..."


# --- Inputs -------------------------------------------------------------------

GMSH_INT64_IDS = """$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
-9223372036854775808 0 0 0
9223372036854775807 1 0 0
2 0 1 0
3 0 0 1
$EndNodes
$Elements
1
1 4 2 1 1 -9223372036854775808 9223372036854775807 2 3
$EndElements
"""

GMSH22_HUGE_NODE_COUNT = """$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4611686018427387904
1 0 0 0
2 1 0 0
$EndNodes
"""

GMSH22_HUGE_ELEMENT_COUNT = """$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
$EndNodes
$Elements
1000000000
1 4 2 1 1 1 2 3 4
$EndElements
"""

GMSH41_HUGE_ELEMENT_BLOCK = """$MeshFormat
4.1 0 8
$EndMeshFormat
$Nodes
1 4 1 4
3 1 0 4
1
2
3
4
0 0 0
1 0 0
0 1 0
0 0 1
$EndNodes
$Elements
1 1000000000 1 1000000000
3 1 4 1000000000
1 1 2 3 4
$EndElements
"""

SCENE = """mesh: {mesh}
materials:
  - {{region: all, law: stvk, young: 1.0e7, poisson: 0.3, density: 1000}}
fixed: [clamp]
loads: {{gravity: [0, -9.81]}}
solver: {{type: implicit, dt: 0.01, steps: {steps}}}
output: {{directory: out{every}, checkpoint_every: {checkpoint_every}{track}}}
"""


def scene(mesh: str = "beam.msh", steps: int = 10, every: int | None = None, checkpoint_every: int = 4,
          track: bool = False) -> str:
    return SCENE.format(mesh=mesh, steps=steps, every="" if every is None else f", every: {every}",
                        checkpoint_every=checkpoint_every, track=", track: [body]" if track else "")


def alias_bomb_scene() -> str:
    """About 400 bytes whose `fixed:` list expands to 10^9 leaves: nine
    levels of anchors, each alias list naming the level below ten times."""
    levels = ["&a0 [x,x,x,x,x,x,x,x,x,x]"]
    levels += [f"&a{level} [" + ",".join([f"*a{level - 1}"] * 10) + "]" for level in range(1, 9)]
    return "mesh: beam.msh\nfixed: [" + ", ".join(levels) + "]\n"


def nested_lists(depth: int) -> str:
    return "[" * depth + "]" * depth


VTU_EMPTY_PIECE = ('<Piece NumberOfPoints="0" NumberOfCells="0"><Points><DataArray type="Float64" '
                   'NumberOfComponents="3" format="ascii"></DataArray></Points><Cells><DataArray type="Int64" '
                   'Name="connectivity" format="ascii"></DataArray><DataArray type="Int64" Name="offsets" '
                   'format="ascii"></DataArray><DataArray type="UInt8" Name="types" format="ascii"></DataArray>'
                   '</Cells></Piece>\n')
VTU_TRIANGLE_PIECE = ('<Piece NumberOfPoints="3" NumberOfCells="1"><Points><DataArray type="Float64" '
                      'NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0</DataArray></Points><Cells>'
                      '<DataArray type="Int64" Name="connectivity" format="ascii">0 1 2</DataArray><DataArray '
                      'type="Int64" Name="offsets" format="ascii">3</DataArray><DataArray type="UInt8" '
                      'Name="types" format="ascii">5</DataArray></Cells></Piece>\n')


def vtu_many_empty_pieces(count: int) -> str:
    """`count` empty pieces, then one triangle (the layout of
    fuzz/corpus/vtu_reader/regression_many_empty_pieces.vtu, scaled up)."""
    return ('<VTKFile type="UnstructuredGrid">\n<UnstructuredGrid>\n' + VTU_EMPTY_PIECE * count +
            VTU_TRIANGLE_PIECE + '</UnstructuredGrid>\n</VTKFile>\n')


def vtu_pieces_sharing_block(pieces: int, block_bytes: int) -> bytes:
    """`pieces` pieces whose appended DataArrays (offsets, types, region)
    all point at offset 0 of one raw appended block of `block_bytes` bytes
    (fuzz/corpus/vtu_reader/regression_pieces_share_appended_block.vtu,
    scaled up): decoded as written, they would need pieces x 3 x the block."""
    piece = (f'<Piece NumberOfPoints="0" NumberOfCells="{block_bytes}"><Points><DataArray type="Float64" '
             'NumberOfComponents="3" format="ascii"></DataArray></Points><Cells><DataArray type="Int64" '
             'Name="connectivity" format="ascii"></DataArray><DataArray type="UInt8" Name="offsets" '
             'format="appended" offset="0"/><DataArray type="UInt8" Name="types" format="appended" offset="0"/>'
             '</Cells><CellData><DataArray type="UInt8" Name="region" format="appended" offset="0"/></CellData>'
             '</Piece>\n')
    head = ('<VTKFile type="UnstructuredGrid" header_type="UInt64">\n<UnstructuredGrid>\n' + piece * pieces +
            '</UnstructuredGrid>\n<AppendedData encoding="raw">\n_')
    return (head.encode() + struct.pack("<Q", block_bytes) + bytes(block_bytes) +
            b"\n</AppendedData>\n</VTKFile>\n")


# --- The suite's shared inputs ----------------------------------------------


class Suite:
    """The binary, the root of the cases' directories and the inputs that
    several cases start from (the beam mesh and a finished run with a
    checkpoint), each made once."""

    def __init__(self, binary: Path, root: Path, timeout: float):
        self.binary = binary
        self.root = root
        self.timeout = timeout
        self.shared = root / "shared"
        self.shared.mkdir()
        self._beam: Path | None = None
        self._checkpointed: Path | None = None
        self._setup_failures: dict[str, CaseFailure] = {}
        self.startup_seconds = max(run_binary(binary, ["version"], root, timeout).seconds for _ in range(2))

    def _setup(self, args: list[str], cwd: Path) -> None:
        """A shared setup run; a failure is kept, so the cases that need it
        fail at once instead of running it again."""
        key = f"{cwd} {' '.join(args)}"
        if key in self._setup_failures:
            raise self._setup_failures[key]
        result = run_binary(self.binary, args, cwd, self.timeout)
        if result.exit_code != 0:
            self._setup_failures[key] = CaseFailure(f"setup `tensormass {' '.join(args)}` exited "
                                                    f"{result.exit_code}: {first_lines(result.output)}")
            raise self._setup_failures[key]

    def beam_mesh(self) -> Path:
        """The 2D beam (20 x 4 quad4, groups clamp, tip, body) of
        `tensormass beam --dim 2 --cells 20,4 --size 5,1`."""
        if self._beam is None:
            self._setup(["beam", "--dim", "2", "--cells", "20,4", "--size", "5,1", "-o", "beam.msh"], self.shared)
            self._beam = self.shared / "beam.msh"
        return self._beam

    def checkpointed_run(self) -> Path:
        """A directory with beam.msh, scene.yaml (10 implicit steps, a
        checkpoint every 4) and the out/ of its finished run."""
        if self._checkpointed is None:
            directory = self.shared / "checkpointed"
            directory.mkdir(exist_ok=True)
            shutil.copy(self.beam_mesh(), directory / "beam.msh")
            (directory / "scene.yaml").write_text(scene())
            self._setup(["run", "--quiet", "scene.yaml"], directory)
            if not (directory / "out" / "checkpoint.bin").is_file():
                raise CaseFailure("setup run wrote no out/checkpoint.bin")
            self._checkpointed = directory
        return self._checkpointed


def with_beam_scene(ctx: CaseContext, **scene_options) -> None:
    shutil.copy(ctx.suite.beam_mesh(), ctx.path("beam.msh"))
    ctx.write("scene.yaml", scene(**scene_options))


def with_checkpointed_run(ctx: CaseContext) -> bytes:
    """Copies the finished checkpointed run into the case; returns its
    summary.json."""
    source = ctx.suite.checkpointed_run()
    for name in ("beam.msh", "scene.yaml"):
        shutil.copy(source / name, ctx.path(name))
    shutil.copytree(source / "out", ctx.path("out"))
    return ctx.path("out/summary.json").read_bytes()


# --- Cases: mesh readers ----------------------------------------------------


def case_gmsh_node_ids_int64_extremes(ctx: CaseContext) -> None:
    """Gmsh 2.2 node ids -2^63 and 2^63-1 (and two plain ones) under one
    tet4: ids of any 64-bit value are read, so mesh-info exits 0 and counts
    4 nodes and the tet4 (an id is a label, not an index to size a table by)."""
    ctx.write("extreme_ids.msh", GMSH_INT64_IDS)
    ctx.run(["mesh-info", "extreme_ids.msh"], expect_code=0,
            expect_text=[re.compile(r"nodes\s+4\n"), re.compile(r"tet4\s+1\n")])


def case_gmsh_huge_node_count(ctx: CaseContext) -> None:
    """A Gmsh 2.2 $Nodes header of 2^62 nodes followed by two lines: refused
    (exit 2) at once, with the file and the count, before anything is
    allocated for it."""
    ctx.write("huge_node_count.msh", GMSH22_HUGE_NODE_COUNT)
    ctx.run(["mesh-info", "huge_node_count.msh"], expect_code=2,
            expect_text=["huge_node_count.msh", "4611686018427387904 nodes"], seconds_past_start=1)


def case_gmsh22_huge_element_count(ctx: CaseContext) -> None:
    """A Gmsh 2.2 $Elements header of 10^9 elements followed by one: refused
    (exit 2) by comparing the count with the bytes left, with a message
    that says so, not an allocation failure ("std::bad_alloc")."""
    ctx.write("huge_element_count.msh", GMSH22_HUGE_ELEMENT_COUNT)
    ctx.run(["mesh-info", "huge_element_count.msh"], expect_code=2,
            expect_text=["huge_element_count.msh", "1000000000 elements"], forbid_text=["bad_alloc"],
            seconds_past_start=1)


def case_gmsh41_huge_element_block(ctx: CaseContext) -> None:
    """A Gmsh 4.1 element block that claims 10^9 tet4 (and holds one):
    refused (exit 2) with the count and the bytes left, never
    "std::bad_alloc" (the block's count is checked before its storage is
    reserved)."""
    ctx.write("huge_element_block.msh", GMSH41_HUGE_ELEMENT_BLOCK)
    ctx.run(["mesh-info", "huge_element_block.msh"], expect_code=2,
            expect_text=["huge_element_block.msh", "1000000000 elements"], forbid_text=["bad_alloc"],
            seconds_past_start=1)


def case_vtu_many_empty_pieces(ctx: CaseContext) -> None:
    """A VTU of 30,000 empty <Piece> elements and one triangle (10 MB):
    read in bounded time and memory. Accepting it (exit 0, the triangle)
    and refusing it (exit 2) are both correct; the line records which."""
    ctx.write("many_pieces.vtu", vtu_many_empty_pieces(30_000))
    result = ctx.run(["mesh-info", "many_pieces.vtu"], expect_code=(0, 2), seconds_past_start=3)
    if result.exit_code == 0:
        ctx.check(re.search(r"tri3\s+1\n", result.output) is not None,
                  f"accepted, but not as one tri3: {first_lines(result.output)}")
        ctx.notes.append("accepted: one tri3")
    elif result.exit_code == 2:
        ctx.notes.append(f"refused: {first_lines(result.output, 1)}")


def case_vtu_pieces_share_appended_block(ctx: CaseContext) -> None:
    """A VTU of 200 pieces whose appended DataArrays all point at one 1 MiB
    raw block: refused (exit 2) once the arrays together would decode more
    than the file holds, so memory stays near the file's size instead of
    200 x 3 MiB."""
    ctx.write("shared_block.vtu", vtu_pieces_sharing_block(200, 1 << 20))
    ctx.run(["mesh-info", "shared_block.vtu"], expect_code=2,
            expect_text=["shared_block.vtu", "more data in total than the file"], seconds_past_start=2)


# --- Cases: scene reader ----------------------------------------------------


def case_scene_alias_bomb(ctx: CaseContext) -> None:
    """A scene of about 400 bytes whose `fixed:` aliases expand to 10^9
    values: refused (exit 2) by the value limit of docs/scene.md (300,000
    values, aliases expanded), with the file, its line and "aliases",
    within a second of the program's start (walking 10^9 values would take
    minutes)."""
    shutil.copy(ctx.suite.beam_mesh(), ctx.path("beam.msh"))
    ctx.write("bomb.yaml", alias_bomb_scene())
    ctx.run(["run", "bomb.yaml"], expect_code=2, expect_text=["bomb.yaml:", "aliases"], seconds_past_start=1)


def case_scene_deep_nesting_under_key(ctx: CaseContext) -> None:
    """`fixed:` holding 100,000 nested lists: refused (exit 2) by the
    nesting limit of docs/scene.md (64 levels), with the file and "nest",
    without exhausting the stack."""
    shutil.copy(ctx.suite.beam_mesh(), ctx.path("beam.msh"))
    ctx.write("deep.yaml", "mesh: beam.msh\nfixed: " + nested_lists(100_000) + "\n")
    ctx.run(["run", "deep.yaml"], expect_code=2, expect_text=["deep.yaml:", "nest"], seconds_past_start=2)


def case_scene_is_deep_list(ctx: CaseContext) -> None:
    """A scene that is nothing but 100,000 nested lists: the message names
    the nesting ("nest"), not an unclear "bad file"."""
    ctx.write("deep_list.yaml", nested_lists(100_000) + "\n")
    ctx.run(["run", "deep_list.yaml"], expect_code=2, expect_text=["deep_list.yaml", "nest"],
            forbid_text=["bad file"], seconds_past_start=2)


# --- Cases: files that are not regular files --------------------------------


def case_mesh_is_fifo(ctx: CaseContext) -> None:
    """mesh-info on a FIFO with no writer: refused (exit 2, "FIFO") without
    blocking in the open (a reader that opens it waits forever)."""
    os.mkfifo(ctx.path("mesh.msh"))
    ctx.run(["mesh-info", "mesh.msh"], expect_code=2, expect_text=["mesh.msh", "FIFO"], seconds_past_start=2)


def case_scene_mesh_is_fifo(ctx: CaseContext) -> None:
    """A scene whose `mesh:` is a FIFO: the run is refused (exit 2, "FIFO")
    without blocking, and writes no output directory."""
    os.mkfifo(ctx.path("mesh.msh"))
    ctx.write("scene.yaml", scene(mesh="mesh.msh"))
    ctx.run(["run", "scene.yaml"], expect_code=2, expect_text=["mesh.msh", "FIFO"], seconds_past_start=2)


def case_scene_is_fifo(ctx: CaseContext) -> None:
    """A scene path that is a FIFO: refused (exit 2, "FIFO") without
    blocking."""
    os.mkfifo(ctx.path("scene.yaml"))
    ctx.run(["run", "scene.yaml"], expect_code=2, expect_text=["scene.yaml", "FIFO"], seconds_past_start=2)


def case_mesh_links_to_dev_zero(ctx: CaseContext) -> None:
    """mesh.msh, a symbolic link to /dev/zero (endless zeros): refused
    after following the link (exit 2, "character device"), never read."""
    os.symlink("/dev/zero", ctx.path("mesh.msh"))
    ctx.run(["mesh-info", "mesh.msh"], expect_code=2, expect_text=["mesh.msh", "character device"],
            seconds_past_start=2)


def case_scene_is_directory(ctx: CaseContext) -> None:
    """A scene path that is a directory: refused (exit 2, "directory")."""
    ctx.path("scene.yaml").mkdir()
    ctx.run(["run", "scene.yaml"], expect_code=2, expect_text=["scene.yaml", "directory"], seconds_past_start=2)


# --- Cases: checkpoints -------------------------------------------------------


def resume_refused(ctx: CaseContext, summary: bytes, expect_text: list[str]) -> None:
    """`run scene.yaml --resume` on the damaged checkpoint: exit 2, the
    message, and the first run's outputs (summary.json among them) as they
    were."""
    ctx.run(["run", "scene.yaml", "--resume"], expect_code=2, expect_text=expect_text, seconds_past_start=2)
    ctx.check(ctx.path("out/summary.json").read_bytes() == summary,
              "summary.json of the first run changed after the refused resume")


def case_checkpoint_flipped_byte(ctx: CaseContext) -> None:
    """A checkpoint with one byte in its middle flipped: --resume is
    refused by the payload's checksum (exit 2, "checksum"), and the first
    run's outputs are left as they were."""
    summary = with_checkpointed_run(ctx)
    checkpoint = ctx.path("out/checkpoint.bin")
    data = bytearray(checkpoint.read_bytes())
    data[len(data) // 2] ^= 0xFF
    checkpoint.write_bytes(bytes(data))
    resume_refused(ctx, summary, ["out/checkpoint.bin", "checksum"])


def case_checkpoint_truncated(ctx: CaseContext) -> None:
    """A checkpoint cut to half its length: --resume is refused (exit 2,
    "truncated"), and the first run's outputs are left as they were."""
    summary = with_checkpointed_run(ctx)
    checkpoint = ctx.path("out/checkpoint.bin")
    data = checkpoint.read_bytes()
    checkpoint.write_bytes(data[: len(data) // 2])
    resume_refused(ctx, summary, ["out/checkpoint.bin", "truncated"])


def case_checkpoint_is_directory(ctx: CaseContext) -> None:
    """out/checkpoint.bin replaced by a directory: --resume is refused
    (exit 2, "directory") without reading it, and the first run's outputs
    are left as they were."""
    summary = with_checkpointed_run(ctx)
    checkpoint = ctx.path("out/checkpoint.bin")
    checkpoint.unlink()
    checkpoint.mkdir()
    resume_refused(ctx, summary, ["out/checkpoint.bin", "directory"])


# --- Cases: the output directory ----------------------------------------------


def case_output_directory_locked(ctx: CaseContext) -> None:
    """A second run into an output directory whose lock this script holds
    (flock LOCK_EX on out/.tensormass.lock, this script's pid written in
    it): refused (exit 2) with "in use by another run (process PID)",
    writing nothing."""
    with_beam_scene(ctx)
    ctx.path("out").mkdir()
    lock = os.open(ctx.path("out") / LOCK_FILE, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        os.write(lock, f"{os.getpid()}\n".encode())
        ctx.run(["run", "scene.yaml"], expect_code=2,
                expect_text=["output directory out", f"in use by another run (process {os.getpid()})"],
                seconds_past_start=2)
    finally:
        os.close(lock)


def case_stale_temporary_removed(ctx: CaseContext) -> None:
    """out/frame_000002.vtu.tmp-99999, the temporary of a run killed while
    writing: the next run (exit 0) removes it when it takes the lock."""
    with_beam_scene(ctx)
    ctx.write("out/frame_000002.vtu.tmp-99999", "<VTKFile type=\"UnstructuredGrid\"><Unstr")
    ctx.run(["run", "--quiet", "scene.yaml"], expect_code=0)
    ctx.check(ctx.path("out/final.vtu").is_file(), "the run wrote no out/final.vtu")


def case_killed_run_resumes(ctx: CaseContext) -> None:
    """A 400-step run writing a frame every step, a track and a checkpoint
    every 50, killed with SIGKILL at about 0.5 s (once a checkpoint exists;
    earlier if frame 150 appears first, so a fast machine kills it before
    its end), then resumed: --resume exits 0 from the checkpoint, writes the
    last frame and the whole track (401 rows), and no `*.tmp-*` or
    `*.partial` file is left in out/."""
    with_beam_scene(ctx, steps=400, every=1, checkpoint_every=50, track=True)
    checkpoint = ctx.path("out/checkpoint.bin")
    late_frame = ctx.path("out/frame_000150.vtu")

    def kill_now(elapsed: float) -> bool:
        return (elapsed >= 0.5 and checkpoint.exists()) or late_frame.exists()

    killed = run_binary(ctx.suite.binary, ["run", "--quiet", "scene.yaml"], ctx.directory, ctx.suite.timeout,
                        kill_when=kill_now)
    if not ctx.check(killed.killed_on_purpose and killed.exit_code == -signal.SIGKILL,
                     f"the run was not killed part way (exit {killed.exit_code}, {killed.seconds:.2f} s): "
                     f"{first_lines(killed.output)}"):
        ctx.reported = killed
        return
    frames = len(list(ctx.path("out").glob("frame_*.vtu")))
    left = len(temporaries(ctx.directory))
    ctx.notes.append(f"killed at {killed.seconds:.2f} s after {frames} frames, "
                     f"{left} {'temporary' if left == 1 else 'temporaries'} left by the kill")
    ctx.run(["run", "scene.yaml", "--resume"], expect_code=0, expect_text=["resuming from"])
    ctx.check(ctx.path("out/frame_000400.vtu").is_file(), "the resumed run wrote no out/frame_000400.vtu")
    ctx.check(ctx.path("out/final.vtu").is_file(), "the resumed run wrote no out/final.vtu")
    track = ctx.path("out/track_body.csv")
    rows = len(track.read_text().splitlines()) - 1 if track.is_file() else 0
    ctx.check(rows == 401, f"out/track_body.csv holds {rows} rows, expected 401")
    partial = [path.name for path in ctx.path("out").glob("*.partial")]
    ctx.check(not partial, f"unfinished files left after the resume: {', '.join(partial)}")


def case_track_file_edited(ctx: CaseContext) -> None:
    """A finished 10-step run with a track, one digit of its
    out/track_body.csv changed: --resume (to 14 steps) is refused (exit 2,
    naming the file: it is not the one the checkpoint marked) and the track
    file is left as it was."""
    with_beam_scene(ctx, track=True)
    ctx.run(["run", "--quiet", "scene.yaml"], expect_code=0)
    track = ctx.path("out/track_body.csv")
    data = bytearray(track.read_bytes())
    at = data.index(b"\n") + 1
    data[at] = ord("1") if data[at] == ord("0") else ord("0")
    track.write_bytes(bytes(data))
    ctx.run(["run", "scene.yaml", "--resume", "--set", "solver.steps=14"], expect_code=2,
            expect_text=["out/track_body.csv", "not the file the checkpoint was written with"], seconds_past_start=2)
    ctx.check(track.read_bytes() == bytes(data), "the refused resume changed out/track_body.csv")


def case_disk_full(ctx: CaseContext) -> None:
    """A run whose file size is capped at 8 KiB (RLIMIT_FSIZE, SIGXFSZ
    ignored: each write past it fails with EFBIG, as on a full disk) while
    it writes 14 KB frames: exit 4 with "output failure", out/summary.json
    written with "status": "failed", no temporary left, and no partial
    frame (every frame present ends with </VTKFile>)."""
    with_beam_scene(ctx, every=1)
    ctx.run(["run", "--quiet", "scene.yaml"], expect_code=4, expect_text=["output failure", "out/"],
            fsize_limit=FULL_DISK_BYTES)
    summary_path = ctx.path("out/summary.json")
    if ctx.check(summary_path.is_file(), "no out/summary.json after the failed write"):
        try:
            status = json.loads(summary_path.read_text()).get("status")
        except (ValueError, UnicodeDecodeError) as error:
            status = f"unreadable ({error})"
        ctx.check(status == "failed", f"summary.json status is {status!r}, expected 'failed'")
    partial = [path.name for path in ctx.path("out").glob("frame_*.vtu")
               if not path.read_bytes().rstrip().endswith(b"</VTKFile>")]
    ctx.check(not partial, f"partial frames left: {', '.join(partial)}")


CASES: list[Callable[[CaseContext], None]] = [
    case_gmsh_node_ids_int64_extremes,
    case_gmsh_huge_node_count,
    case_gmsh22_huge_element_count,
    case_gmsh41_huge_element_block,
    case_vtu_many_empty_pieces,
    case_vtu_pieces_share_appended_block,
    case_scene_alias_bomb,
    case_scene_deep_nesting_under_key,
    case_scene_is_deep_list,
    case_mesh_is_fifo,
    case_scene_mesh_is_fifo,
    case_scene_is_fifo,
    case_mesh_links_to_dev_zero,
    case_scene_is_directory,
    case_checkpoint_flipped_byte,
    case_checkpoint_truncated,
    case_checkpoint_is_directory,
    case_output_directory_locked,
    case_stale_temporary_removed,
    case_killed_run_resumes,
    case_track_file_edited,
    case_disk_full,
]


def case_name(case: Callable[[CaseContext], None]) -> str:
    return case.__name__.removeprefix("case_")


def summary_line(case: Callable[[CaseContext], None]) -> str:
    """The docstring's first clause: up to its first ": " outside
    parentheses."""
    text = " ".join((case.__doc__ or "").split())
    depth = 0
    for index, character in enumerate(text):
        depth += {"(": 1, ")": -1}.get(character, 0)
        if depth == 0 and text.startswith(": ", index):
            return text[:index]
    return text


# --- Main -----------------------------------------------------------------------


def run_case(suite: Suite, case: Callable[[CaseContext], None]) -> bool:
    name = case_name(case)
    directory = suite.root / name
    directory.mkdir()
    ctx = CaseContext(name, directory, suite)
    try:
        case(ctx)
    except CaseFailure as error:
        ctx.failures.append(str(error))
    except Exception as error:  # a broken case reports itself instead of ending the suite
        ctx.failures.append(f"the case raised {type(error).__name__}: {error}")
    result = ctx.reported
    if result is None:
        measured = f"{'-':>4}  {'-':>6}    {'-':>7}    "
    else:
        code = "kill" if result.timed_out else str(result.exit_code)
        measured = f"{code:>4}  {result.seconds:6.2f} s  {result.peak_mib:7.1f} MiB"
    verdict = "PASS" if not ctx.failures else "FAIL: " + "; ".join(ctx.failures)
    notes = f" ({'; '.join(ctx.notes)})" if ctx.notes else ""
    print(f"{name:<38} {measured}  {verdict}{notes}", flush=True)
    return not ctx.failures


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--binary", type=Path, help="the tensormass binary")
    parser.add_argument("--only", action="append", metavar="NAME", help="run only this case (repeatable)")
    parser.add_argument("--list", action="store_true", help="list the cases and exit")
    parser.add_argument("--timeout", type=float, default=DEFAULT_TIMEOUT_S,
                        help=f"wall-clock limit of each run in seconds (default {DEFAULT_TIMEOUT_S:g})")
    parser.add_argument("--keep", action="store_true", help="keep the cases' directories (their path is printed)")
    options = parser.parse_args(argv)

    if options.list:
        for case in CASES:
            print(f"{case_name(case):<38} {summary_line(case)}")
        return 0
    if options.binary is None:
        parser.error("--binary is required")
    binary = options.binary.resolve()
    if not (binary.is_file() and os.access(binary, os.X_OK)):
        parser.error(f"{options.binary} is not an executable file")
    selected = CASES
    if options.only:
        known = {case_name(case): case for case in CASES}
        unknown = [name for name in options.only if name not in known]
        if unknown:
            parser.error(f"unknown case {', '.join(unknown)} (--list shows the cases)")
        selected = [known[name] for name in options.only]

    start = time.monotonic()
    root = Path(tempfile.mkdtemp(prefix="tensormass-hostile-"))
    try:
        suite = Suite(binary, root, options.timeout)
        print(f"program start: {suite.startup_seconds:.2f} s (tensormass version)")
        print(f"{'case':<38} {'exit':>4}  {'time':>8}  {'peak':>11}  result", flush=True)
        failed = [case_name(case) for case in selected if not run_case(suite, case)]
    finally:
        if options.keep:
            print(f"cases kept in {root}")
        else:
            shutil.rmtree(root, ignore_errors=True)
    elapsed = time.monotonic() - start
    print(f"{len(selected) - len(failed)} of {len(selected)} cases passed in {elapsed:.1f} s" +
          (f"; failed: {', '.join(failed)}" if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
