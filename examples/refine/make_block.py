#!/usr/bin/env python3
"""Writes block.msh for block_probe.yaml: a 10 x 5 x 10 cm block of 10 x 5 x 10
hexahedra (Gmsh 2.2 ASCII, y up) with the face groups `base` (y = 0) and
`probe` (the top faces within 1 cm of the middle in x and z) and the volume
group `block`.

usage: python3 examples/refine/make_block.py [OUT.msh]   (default: block.msh beside this script)
"""
import pathlib
import sys

NX, NY, NZ = 10, 5, 10
SIZE = (0.1, 0.05, 0.1)


def node(i, j, k):
    return 1 + i + (NX + 1) * (j + (NY + 1) * k)


def main():
    out = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).with_name("block.msh")
    nodes = [(node(i, j, k), SIZE[0] * i / NX, SIZE[1] * j / NY, SIZE[2] * k / NZ)
             for k in range(NZ + 1) for j in range(NY + 1) for i in range(NX + 1)]
    faces = []  # (physical tag, quad corners counter-clockwise seen from outside)
    for k in range(NZ):
        for i in range(NX):
            faces.append((1, (node(i, 0, k), node(i + 1, 0, k), node(i + 1, 0, k + 1), node(i, 0, k + 1))))
            middle = (SIZE[0] * (i + 0.5) / NX - SIZE[0] / 2, SIZE[2] * (k + 0.5) / NZ - SIZE[2] / 2)
            if max(abs(middle[0]), abs(middle[1])) < 0.01:
                faces.append((2, (node(i, NY, k), node(i, NY, k + 1), node(i + 1, NY, k + 1), node(i + 1, NY, k))))
    hexes = [(node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
              node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1))
             for k in range(NZ) for j in range(NY) for i in range(NX)]
    text = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", "3",
            '2 1 "base"', '2 2 "probe"', '3 3 "block"', "$EndPhysicalNames", "$Nodes", str(len(nodes))]
    text += [f"{n} {x!r} {y!r} {z!r}" for n, x, y, z in nodes]
    text += ["$EndNodes", "$Elements", str(len(faces) + len(hexes))]
    number = 0
    for tag, quad in faces:
        number += 1
        text.append(f"{number} 3 2 {tag} {tag} {' '.join(map(str, quad))}")
    for hexa in hexes:
        number += 1
        text.append(f"{number} 5 2 3 3 {' '.join(map(str, hexa))}")
    text.append("$EndElements")
    partial = out.with_name(out.name + ".tmp")  # renamed once complete: never a half-written mesh
    partial.write_text("\n".join(text) + "\n")
    partial.replace(out)
    print(f"wrote {out}: {len(hexes)} hexahedra, groups base, probe, block")


if __name__ == "__main__":
    main()
