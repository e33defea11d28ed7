#!/usr/bin/python3
"""docs/results/thick_cylinder.md from bench/thick_cylinder.py's JSON.

usage: /usr/bin/python3 scripts/results/render_thick_cylinder.py thick_cylinder.json > docs/results/thick_cylinder.md
"""
import sys

from results_common import fixed, load, table

PAGE = """# A pressurised thick cylinder, nearly incompressible

A long cylinder of radii a = {inner} and b = {outer} under an internal
pressure of {pressure}, in plane strain, linear elastic (Hooke, E = {young},
nu = {poisson}), static, default settings: a quarter of its section with
symmetry conditions on the axes, the pressure on the inner arc. Lamé's
closed form gives u_r(a) = {lame}. Each element type meshes the quarter
with N x N cells (radial by circumferential; tri3 cuts each quad in two,
tet4 each hex8 in six), the 3D meshes one cell thick with u_z = 0 at every
node. Each cell gives u_r(a) over Lamé's and, in brackets, the largest error
of u_r over the nodes, over Lamé's u_r(a).

Measured on {machine} ({threads} threads) on {date}, tensormass
{version}, commit `{commit}`:

```sh
/usr/bin/python3 bench/thick_cylinder.py --json docs/results/thick_cylinder.json
/usr/bin/python3 scripts/results/render_thick_cylinder.py docs/results/thick_cylinder.json > docs/results/thick_cylinder.md
```

{rows}

The plain elements lock and converge slowly from far below: at
N = {finest} u_r(a) is {quad4_finest} of Lamé's for quad4 and hex8,
{tri3_finest} for tri3 and {tet4_finest} for tet4. Under pressure nearly
all of the cylinder's strain is an incompressible shear, which their
volume constraints at every quadrature point resist. With the mean
dilatation (quad4, hex8 `fbar`) and the averaged nodal pressure (tri3,
tet4 `anp`, [formulations.md](../formulations.md)) every element converges
to Lamé's answer: at N = {finest}, {free_finest}.
"""


def main(argv):
    if len(argv) != 2:
        sys.exit(__doc__)
    data = load(argv[1])
    meta, settings = data["metadata"], data["settings"]
    sizes = settings["sizes"]
    finest = sizes[-1]
    labels = list(dict.fromkeys(r["label"] for r in data["rows"]))
    cell = {(r["label"], r["size"]): r for r in data["rows"]}

    def entry(row):
        return f"{row['inner_ratio']:.4f} ({row['field_error']:.4f})"

    rows = table(["element"] + [f"N = {n}" for n in sizes],
                 [[label] + [entry(cell[(label, n)]) for n in sizes] for label in labels],
                 ["l"] + ["r"] * len(sizes))

    def ratio(label):
        row = cell.get((label, finest))
        return f"{row['inner_ratio']:.4f}" if row else "-"

    free = [f"{label} {ratio(label)}" for label in labels if " " in label]
    print(PAGE.format(
        inner=fixed(settings["inner"], 0), outer=fixed(settings["outer"], 0), pressure=fixed(settings["pressure"], 0),
        young=fixed(settings["young"], 0), poisson=settings["poisson"], lame=f"{settings['lame_inner']:.6f}",
        machine=meta["machine"], threads=meta["threads"], date=meta["date"][:10], version=meta["tensormass_version"],
        commit=meta["commit"], rows=rows, finest=finest, quad4_finest=ratio("quad4"), tri3_finest=ratio("tri3"),
        tet4_finest=ratio("tet4"), free_finest=", ".join(free)).rstrip())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
