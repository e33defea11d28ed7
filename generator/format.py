"""Stage 6 (format): deterministic whitespace for every emitted file.

Trailing spaces removed, runs of blank lines collapsed to one, exactly one
final newline; no timestamps or machine facts ever enter the output."""
from __future__ import annotations


def format_source(text: str) -> str:
    lines = [line.rstrip() for line in text.splitlines()]
    result: list[str] = []
    for line in lines:
        if not line and result and not result[-1]:
            continue
        result.append(line)
    while result and not result[-1]:
        result.pop()
    return "\n".join(result) + "\n"
