"""Input hashing (standard library only, so that an up-to-date `generated/`
is recognised without importing SymPy).

`generated/INPUTS.sha256` holds one line `HASH  KEY` per generated (law,
element) pair, KEY = `law/element`, and one line for the element tables,
KEY = `elements`. A pair's hash covers its law file, its element file, the
templates, the generator's own sources and the splits emitted (`--splits`);
the element tables' hash covers
every element file, the templates and the generator. A pair is stale when
its line is missing or differs; registry.cpp, sources.cmake and
manifest.json are rewritten whenever any pair or the element tables are.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

HASH_FILE = "INPUTS.sha256"
ELEMENTS_KEY = "elements"
GENERATOR_DIR = Path(__file__).resolve().parent
GENERATOR_PATTERNS = ("*.py", "splits/*.py")


def _read(path: Path) -> bytes:
    return path.read_bytes().replace(b"\r\n", b"\n")


def _digest(chunks: list[bytes]) -> str:
    digest = hashlib.sha256()
    for chunk in chunks:
        digest.update(chunk + b"\0")
    return digest.hexdigest()


def generator_hash() -> str:
    """The generator package's sources (what derives the law and element results)."""
    files = sorted({p for pattern in GENERATOR_PATTERNS for p in GENERATOR_DIR.glob(pattern) if p.is_file()})
    return _digest([c for p in files for c in (p.relative_to(GENERATOR_DIR).as_posix().encode(), _read(p))])


def shared_hash(root: Path) -> str:
    """The generator's sources and the project's templates: inputs of every output."""
    templates = sorted(p for p in (root / "templates").glob("*.j2") if p.is_file())
    return _digest([generator_hash().encode()] + [c for p in templates for c in (p.name.encode(), _read(p))])


def law_files(root: Path) -> dict[str, Path]:
    return {p.stem: p for p in sorted((root / "laws").glob("*.toml"))}


def element_files(root: Path) -> dict[str, Path]:
    return {p.stem: p for p in sorted((root / "elements").glob("*.toml"))}


# Every split the generator lowers (lower.SPLITS, kept here for the path
# that imports no SymPy) and those it emits by default: `terms` is no default
# path's split and is generated on request (`--splits`, the CMake option
# TENSORMASS_TERMS_SPLIT, which generates into the build tree).
SPLITS = ("whole", "terms", "tensor", "fbar", "anp")
DEFAULT_SPLITS = ("whole", "tensor", "fbar", "anp")


def split_selection(names: list[str]) -> tuple[str, ...]:
    """The named splits in SPLITS order; ValueError for an unknown name."""
    unknown = [name for name in names if name not in SPLITS]
    if unknown:
        raise ValueError(f"unknown split {unknown[0]!r} (splits: {', '.join(SPLITS)})")
    return tuple(split for split in SPLITS if split in names)


def pair_key(law: str, element: str) -> str:
    return f"{law}/{element}"


def expected_hashes(root: Path, splits: tuple[str, ...] = DEFAULT_SPLITS) -> dict[str, str]:
    """{KEY: hash} of every (law, element) pair of the project, generated
    with `splits`, and of the element tables."""
    shared = (shared_hash(root) + " " + ",".join(splits)).encode()
    laws, elements = law_files(root), element_files(root)
    law_bytes = {name: _read(path) for name, path in laws.items()}
    element_bytes = {name: _read(path) for name, path in elements.items()}
    hashes = {pair_key(law, element): _digest([shared, law_bytes[law], element_bytes[element]])
              for law in laws for element in elements}
    hashes[ELEMENTS_KEY] = _digest([shared] + [c for name in elements for c in (name.encode(), element_bytes[name])])
    return hashes


def recorded_hashes(output: Path) -> dict[str, str]:
    """The hashes the last generation recorded in output (empty when there are none)."""
    path = output / HASH_FILE
    if not path.exists():
        return {}
    recorded = {}
    for line in path.read_text().splitlines():
        fields = line.split()
        if len(fields) == 2:
            recorded[fields[1]] = fields[0]
    return recorded


def format_hashes(hashes: dict[str, str]) -> str:
    return "".join(f"{hashes[key]}  {key}\n" for key in sorted(hashes))


def is_current(root: Path, output: Path, splits: tuple[str, ...] = DEFAULT_SPLITS) -> bool:
    """True when every pair and the element tables were generated from the inputs as they are."""
    return recorded_hashes(output) == expected_hashes(root, splits)
