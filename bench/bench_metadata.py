"""What a Python benchmark's JSON records about the run, as `tensormass bench`
does (bench/bench_metadata.cpp): version, date, commit, machine, threads and
load average, so that a results page can name them."""
import datetime
import json
import os
import subprocess


def _first_line(command, cwd=None):
    try:
        out = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=30, check=True).stdout
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return out.strip().splitlines()[0] if out.strip() else "unknown"


def _machine():
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as handle:
            for line in handle:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"


def metadata(binary):
    """The run's metadata, with `binary`'s version and this checkout's commit."""
    source = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    version = _first_line([binary, "--version"]).replace("tensormass ", "")
    return {
        "tensormass_version": version,
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "commit": _first_line(["git", "rev-parse", "--short", "HEAD"], cwd=source),
        "machine": _machine(),
        "threads": os.cpu_count(),
        "load_average": " ".join(f"{x:.2f}" for x in os.getloadavg()),
    }


def write_result(path, result):
    """Writes a benchmark's JSON to `path` (indented, one trailing newline) through a
    temporary file renamed into place: never a half-written result."""
    partial = f"{path}.partial"
    with open(partial, "w", encoding="utf-8") as handle:
        json.dump(result, handle, indent=1)
        handle.write("\n")
    os.replace(partial, path)
