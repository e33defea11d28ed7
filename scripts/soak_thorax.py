#!/usr/bin/env python3
"""Soak test of the thorax example: N breathing cycles in one run.

Builds the example's surfaces and mesh (as examples/thorax/run.sh does), runs
examples/thorax/thorax.yaml for N cycles of 4 s, samples the process's
resident memory (VmRSS) twice a second, and reports:
  - the resident memory at the end of the first cycle and its largest value
    after it (growth in %; the target is under 1 %);
  - the tumour's displacement at every end-exhale (t = 4 k s, where the
    diaphragm is back at rest) and at every inspiration (t = 4 k + 2 s):
    without drift, both repeat from cycle to cycle.

usage: /usr/bin/python3 scripts/soak_thorax.py [--cycles 50] [--binary build/tensormass] [--json FILE] [--work DIR]
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
from bench_metadata import metadata  # noqa: E402


def build_mesh(binary, work):
    subprocess.run([sys.executable, f"{ROOT}/examples/thorax/make_thorax.py", "--out", work, "--edge", "0.018"],
                   check=True, stdout=subprocess.DEVNULL)
    tumour = json.load(open(f"{work}/thorax.json"))["tumour"]
    roi = ",".join(str(x) for x in [*tumour["centre"], 2 * tumour["radius"], 0.01])
    subprocess.run([binary, "mesh", "thorax.stl", "--size", "0.02", "--levels", "0", "--layer", "0.5", "--roi", roi,
                    "--region", "tumour=tumour.stl", "--region", "lung_right=lung_right.stl",
                    "--region", "lung_left=lung_left.stl", "-o", "thorax.msh"],
                   check=True, cwd=work, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def resident_kib(pid):
    with open(f"/proc/{pid}/status") as status:
        for line in status:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def run(binary, work, cycles):
    steps = int(round(cycles * 4.0 / 0.05))
    command = [binary, "run", "thorax.yaml", "--quiet", "--set", f"solver.steps={steps}", "--set", "output.every=0",
               "--set", "output.directory=out/soak"]
    start = time.monotonic()
    process = subprocess.Popen(command, cwd=work)
    samples = []  # (seconds, KiB)
    while process.poll() is None:
        try:
            samples.append((time.monotonic() - start, resident_kib(process.pid)))
        except (FileNotFoundError, ProcessLookupError):
            break
        time.sleep(0.5)
    if process.returncode != 0:
        sys.exit(f"soak: the run failed (exit {process.returncode})")
    return samples, time.monotonic() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cycles", type=int, default=50)
    parser.add_argument("--binary", default=f"{ROOT}/build/tensormass")
    parser.add_argument("--work", default="/tmp/tensormass-soak")
    parser.add_argument("--json", help="write the figures and the run's metadata here")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    subprocess.run(["cp", f"{ROOT}/examples/thorax/thorax.yaml", args.work], check=True)
    build_mesh(args.binary, args.work)
    samples, seconds = run(args.binary, args.work, args.cycles)
    # The run is steady: the first cycle ends after about 1/cycles of the wall time.
    first_cycle = [kib for t, kib in samples if t <= seconds / args.cycles] or [samples[0][1]]
    after = [kib for t, kib in samples if t > seconds / args.cycles] or [first_cycle[-1]]
    base, peak = first_cycle[-1], max(after)
    print(f"{args.cycles} cycles, {len(samples)} memory samples over {seconds:.0f} s")
    print(f"resident memory: {base / 1024:.1f} MiB after the first cycle, largest after it {peak / 1024:.1f} MiB "
          f"(growth {100 * (peak - base) / base:.2f} %), last {samples[-1][1] / 1024:.1f} MiB")
    rows = list(csv.DictReader(open(f"{args.work}/out/soak/track_tumour.csv")))
    by_time = {round(float(r["time"]), 6): r for r in rows}

    def displacement(t):
        r = by_time[round(t, 6)]
        return math.sqrt(sum(float(r[k]) ** 2 for k in ("ux", "uy", "uz")))

    rest = [displacement(4.0 * k) for k in range(1, args.cycles + 1)]
    peak_motion = [displacement(4.0 * k + 2.0) for k in range(args.cycles)]
    print(f"tumour at end-exhale (t = 4k s): largest {1e3 * max(rest):.4f} mm over {args.cycles} cycles")
    print(f"tumour at inspiration (t = 4k + 2 s): cycle 1 {1e3 * peak_motion[0]:.4f} mm, cycle {args.cycles} "
          f"{1e3 * peak_motion[-1]:.4f} mm (difference {1e3 * abs(peak_motion[-1] - peak_motion[0]):.2e} mm)")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump({"metadata": metadata(os.path.abspath(args.binary)),
                       "settings": {"cycles": args.cycles, "cycle_seconds": 4.0, "dt": 0.05},
                       "samples": len(samples), "seconds": seconds, "first_cycle_mib": base / 1024,
                       "largest_after_mib": peak / 1024, "last_mib": samples[-1][1] / 1024,
                       "end_exhale_mm": [1e3 * x for x in rest], "inspiration_mm": [1e3 * x for x in peak_motion]},
                      handle, indent=1)
            handle.write("\n")


if __name__ == "__main__":
    main()
