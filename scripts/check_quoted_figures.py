#!/usr/bin/python3
"""Every figure the README's headline table quotes is on the results page its row links to.

Reads the table under "## Headline figures" in README.md: for each row, every
number of its "measured" cell (0.58, 7.9e-8, 3,857, 150.2, ...) must appear,
as written, in the page of its last cell's link. Prints one line per figure
that is missing, naming the row, and exits 1; exits 0 when all are there.

usage: /usr/bin/python3 scripts/check_quoted_figures.py [--root DIR]
"""
import argparse
import os
import re
import sys

# A figure, with its percent sign when it has one: "0.35 %" must be a percentage on the page too.
NUMBER = re.compile(r"(?<![\w.])\d[\d,]*(?:\.\d+)?(?:e-?\d+)?(?: ?%)?")
LINK = re.compile(r"\]\(([^)]+\.md)\)")


def headline_rows(readme):
    """(line number, measured cell, linked page) of each row of the headline table."""
    rows, inside = [], False
    for number, line in enumerate(readme.splitlines(), 1):
        if line.startswith("## "):
            inside = line.strip() == "## Headline figures"
            continue
        if not inside or not line.startswith("|") or line.startswith("|---") or line.startswith("| what"):
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        link = LINK.search(cells[-1])
        if len(cells) >= 3 and link:
            rows.append((number, cells[1], link.group(1)))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    args = parser.parse_args()
    readme_path = os.path.join(args.root, "README.md")
    with open(readme_path, encoding="utf-8") as handle:
        rows = headline_rows(handle.read())
    if not rows:
        print(f"{readme_path}: no headline table (a '## Headline figures' section with linked rows)")
        return 1
    missing = 0
    for line, measured, page in rows:
        path = os.path.join(args.root, page)
        try:
            with open(path, encoding="utf-8") as handle:
                text = handle.read()
        except OSError as error:
            print(f"README.md:{line}: cannot read {page}: {error}")
            missing += 1
            continue
        for figure in NUMBER.findall(measured):
            number = figure.rstrip(" %")
            pattern = re.escape(number) + (r" ?%" if figure.endswith("%") else r"(?![\d])")
            if not re.search(r"(?<![\w.])" + pattern, text):
                print(f"README.md:{line}: {figure} is not on {page}")
                missing += 1
    if missing:
        return 1
    print(f"every figure of the {len(rows)} headline rows is on its page")
    return 0


if __name__ == "__main__":
    sys.exit(main())
