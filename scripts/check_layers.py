#!/usr/bin/python3
"""Checks that the runtime's folders include one another in one direction only.

    check_layers.py [--root DIR]

The order is the line of docs/architecture.md that starts with

    Layers, lowest first: `common < kernels < mesh < ...`

A source under runtime/src/<folder>/ or a header under
runtime/include/tensormass/<folder>/ may include headers of its own folder
and of folders before it in that order, never of a folder after it
("tensormass/<folder>/x.hpp" or the internal "<folder>/x.hpp"). Every folder
of runtime/src and runtime/include/tensormass must be in the order.

Prints one line per include against the order, `path:line: ...`, and exits
1 when there is one; 2 when the order line is missing or names no folder
that exists; 0 otherwise, with a one-line count.
"""
import argparse
import re
import sys
from pathlib import Path

ORDER_LINE = re.compile(r"^Layers, lowest first: `([^`]+)`")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
SOURCE_SUFFIXES = {".h", ".hpp", ".cpp", ".in"}


def layer_order(architecture: Path) -> list[str]:
    for line in architecture.read_text(encoding="utf-8").splitlines():
        match = ORDER_LINE.match(line)
        if match:
            return [name.strip() for name in match.group(1).split("<")]
    raise ValueError(f"{architecture}: no line 'Layers, lowest first: `a < b < ...`'")


def source_folders(root: Path) -> dict[str, list[Path]]:
    """Each runtime folder and the files under it (sources and public headers)."""
    folders: dict[str, list[Path]] = {}
    for base in (root / "runtime" / "src", root / "runtime" / "include" / "tensormass"):
        if not base.is_dir():
            continue
        for folder in sorted(p for p in base.iterdir() if p.is_dir()):
            files = [f for f in sorted(folder.rglob("*")) if f.suffix in SOURCE_SUFFIXES and f.is_file()]
            folders.setdefault(folder.name, []).extend(files)
    return folders


def included_folder(target: str, layers: set[str]) -> str | None:
    parts = target.split("/")
    if len(parts) > 2 and parts[0] == "tensormass" and parts[1] in layers:
        return parts[1]
    if len(parts) > 1 and parts[0] in layers:
        return parts[0]
    return None


def violations(root: Path, order: list[str], folders: dict[str, list[Path]]):
    rank = {name: i for i, name in enumerate(order)}
    includes = 0
    found = []
    for folder, files in folders.items():
        for path in files:
            for number, line in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
                match = INCLUDE.match(line)
                target = included_folder(match.group(1), set(rank)) if match else None
                if target is None or target == folder:
                    continue
                includes += 1
                if rank[target] > rank[folder]:
                    found.append(f"{path.relative_to(root)}:{number}: {folder}/ includes \"{match.group(1)}\" "
                                 f"but {target}/ comes after {folder}/ in the layer order")
    return found, includes


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--root", type=Path, default=Path(__file__).resolve().parents[1])
    args = parser.parse_args(argv)
    architecture = args.root / "docs" / "architecture.md"
    try:
        order = layer_order(architecture)
    except (OSError, ValueError) as error:
        print(f"check_layers.py: {error}", file=sys.stderr)
        return 2
    folders = source_folders(args.root)
    unknown = sorted(set(folders) - set(order))
    if unknown:
        for name in unknown:
            print(f"check_layers.py: runtime folder {name}/ is not in the layer order of {architecture}",
                  file=sys.stderr)
        return 2
    found, includes = violations(args.root, order, folders)
    for line in found:
        print(line)
    if found:
        print(f"check_layers.py: {len(found)} include(s) against the layer order", file=sys.stderr)
        return 1
    files = sum(len(f) for f in folders.values())
    print(f"layers: {files} files, {includes} includes between folders, all one way ({' < '.join(order)})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
