"""Input hashing (standard library only, so the build can skip generation
without SymPy when `generated/` is up to date with its inputs)."""
from __future__ import annotations

import hashlib
from pathlib import Path

HASH_FILE = "INPUTS.sha256"
INPUT_PATTERNS = ("elements/*.toml", "laws/*.toml", "templates/*.j2", "generator/*.py", "generator/splits/*.py")


def input_files(root: Path) -> list[Path]:
    return sorted({p for pattern in INPUT_PATTERNS for p in root.glob(pattern) if p.is_file()})


def input_hash(root: Path) -> str:
    digest = hashlib.sha256()
    for path in input_files(root):
        digest.update(path.relative_to(root).as_posix().encode() + b"\0")
        digest.update(path.read_bytes().replace(b"\r\n", b"\n") + b"\0")
    return digest.hexdigest()


def is_current(root: Path, output: Path) -> bool:
    recorded = output / HASH_FILE
    return recorded.exists() and recorded.read_text().strip() == input_hash(root)
