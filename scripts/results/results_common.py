"""Helpers shared by the docs/results page renderers (scripts/results/render_*.py).

Each renderer reads a benchmark's JSON and prints its page to stdout: the
tables come from the JSON, the prose from a template in the renderer, and
the figures the prose quotes are filled in from the JSON too, so that a
page cannot disagree with its measurement.
"""
import json
import sys


def load(path):
    """The JSON file at path; exits 2 with a message when it cannot be read."""
    try:
        with open(path, encoding="utf-8") as handle:
            return json.load(handle)
    except (OSError, ValueError) as error:
        sys.exit(f"{sys.argv[0]}: cannot read {path}: {error}")


def thousands(value):
    """An integer with thousands separators: 35301 -> '35,301'."""
    return f"{int(value):,}"


def fixed(value, digits):
    """value with digits decimals ('-0.0' printed as '0.0')."""
    text = f"{value:.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def bold(text):
    return f"**{text}**"


def table(header, rows, align=None):
    """A markdown table. header: column titles; align: one of 'l' / 'r' per column."""
    align = align or ["l"] * len(header)
    rule = ["---" if a == "l" else "--:" for a in align]
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join(rule) + "|"]
    lines += ["| " + " | ".join(str(cell) for cell in row) + " |" for row in rows]
    return "\n".join(lines)


def find(rows, label, key="label"):
    """The row whose key is label; exits with a message when there is none."""
    for row in rows:
        if row[key] == label:
            return row
    sys.exit(f"{sys.argv[0]}: no run '{label}' in the JSON")
