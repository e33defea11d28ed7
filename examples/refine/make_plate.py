#!/usr/bin/env python3
"""Writes plate.msh for plate_probe.yaml: a 10 x 5 cm plate of 20 x 10 quads
(Gmsh 2.2 ASCII) with the line groups `bottom` (y = 0) and `probe` (the
top edges within 1 cm of the middle), as in `tensormass bench refine`.

usage: python3 examples/refine/make_plate.py [OUT.msh]   (default: plate.msh beside this script)
"""
import pathlib
import sys

NX, NY, WIDTH, HEIGHT = 20, 10, 0.1, 0.05


def node(i, j):
    return 1 + j * (NX + 1) + i


def main():
    out = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).with_name("plate.msh")
    nodes = [(node(i, j), WIDTH * i / NX, HEIGHT * j / NY) for j in range(NY + 1) for i in range(NX + 1)]
    lines = []  # (physical tag, a, b)
    for i in range(NX):
        lines.append((1, node(i, 0), node(i + 1, 0)))
        if abs(WIDTH * (i + 0.5) / NX - WIDTH / 2) < 0.01:
            lines.append((2, node(i, NY), node(i + 1, NY)))
    quads = [(node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)) for j in range(NY) for i in range(NX)]
    text = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "3",
            '1 1 "bottom"', '1 2 "probe"', '2 3 "plate"', "$EndPhysicalNames", "$Nodes", str(len(nodes))]
    text += [f"{n} {x!r} {y!r} 0" for n, x, y in nodes]
    text += ["$EndNodes", "$Elements", str(len(lines) + len(quads))]
    number = 0
    for tag, a, b in lines:
        number += 1
        text.append(f"{number} 1 2 {tag} {tag} {a} {b}")
    for q in quads:
        number += 1
        text.append(f"{number} 3 2 3 3 {' '.join(map(str, q))}")
    text.append("$EndElements")
    partial = out.with_name(out.name + ".tmp")  # renamed once complete: never a half-written mesh
    partial.write_text("\n".join(text) + "\n")
    partial.replace(out)
    print(f"wrote {out}: {len(quads)} quads, groups bottom, probe, plate")


if __name__ == "__main__":
    main()
