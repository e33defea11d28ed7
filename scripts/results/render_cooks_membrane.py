#!/usr/bin/python3
"""docs/results/cooks_membrane.md from bench/cooks_membrane.py's JSON.

usage: /usr/bin/python3 scripts/results/render_cooks_membrane.py cooks_membrane.json > docs/results/cooks_membrane.md
"""
import sys

from results_common import bold, fixed, load, table

PAGE = """# Cook's membrane, nearly incompressible

The tapered panel of Cook (1974), corners (0, 0), (48, 44), (48, 60) and
(0, 44), clamped at x = 0 and sheared by a total vertical force of
{force} spread uniformly over its right edge, in plane strain, linear
elastic (Hooke, E = {young}, nu = {poisson}), static, default settings. Each
element type meshes it with N x N cells mapped from the unit square (tri3
cuts each quad in two, tet4 each hex8 in six around its diagonal); the 3D
meshes are one cell thick with u_z = 0 at every node. Each cell gives the
vertical displacement of the tip (48, 60) and, in brackets, its ratio to
the reference: CalculiX's CPE8 (eight-node plane-strain quads, `ccx`) on
{reference_size} x {reference_size} cells, {reference_tip}. CalculiX on
coarser quad8 meshes: {calculix}; its answer still moves by {drift} over
the last halving of its cells, which bounds how far the ratios' third
decimal can be trusted.

Measured on {machine} ({threads} threads) on {date}, tensormass
{version}, commit `{commit}`:

```sh
/usr/bin/python3 bench/cooks_membrane.py --json docs/results/cooks_membrane.json
/usr/bin/python3 scripts/results/render_cooks_membrane.py docs/results/cooks_membrane.json > docs/results/cooks_membrane.md
```

{tips}

## Against the target

The target: within 1 % of the reference at the finest mesh, for tet4, hex8
(3D), quad4 and tri3 (2D), each with its locking-free split (`fbar`,
`anp`; [formulations.md](../formulations.md)).

{targets}

The plain elements lock: at N = {finest} they give {plain_worst} to
{plain_best} of the reference. The mean dilatation converges fastest
(quad4 fbar {quad4_fbar_16} at N = 16); the averaged nodal pressure,
whose triangles and tetrahedra keep their shear stiffness in bending,
converges more slowly from below (tri3 anp {tri3_anp_16} at N = 16,
{tri3_anp_finest} at N = {finest}).
"""


def drift(calculix):
    """How much CalculiX's tip moved between its two finest meshes, in per cent of the finest."""
    if len(calculix) < 2:
        return "-"
    return f"{100 * abs(calculix[-1]['tip'] - calculix[-2]['tip']) / abs(calculix[-1]['tip']):.1f} %"


def main(argv):
    if len(argv) != 2:
        sys.exit(__doc__)
    data = load(argv[1])
    meta, settings, reference = data["metadata"], data["settings"], data["reference"]
    sizes = settings["sizes"]
    finest = sizes[-1]
    labels = list(dict.fromkeys(r["label"] for r in data["rows"]))
    cell = {(r["label"], r["size"]): r for r in data["rows"]}

    def tip(row):
        return f"{row['tip']:.4f} ({row['ratio']:.4f})"

    rows = [[label] + [tip(cell[(label, n)]) for n in sizes] for label in labels]
    tips = table(["element"] + [f"N = {n}" for n in sizes], rows, ["l"] + ["r"] * len(sizes))
    target_rows = []
    for label in labels:
        if " " not in label:
            continue  # the plain elements are shown, not targeted
        row = cell[(label, finest)]
        met = abs(row["ratio"] - 1) <= 0.01
        target_rows.append([label, f"{row['ratio']:.4f}", "within 1 %", bold("met") if met else bold("missed")])
    plain = [cell[(label, finest)]["ratio"] for label in labels if " " not in label]

    def ratio(label, n):
        row = cell.get((label, n))
        return f"{row['ratio']:.4f}" if row else "-"

    print(PAGE.format(
        force=fixed(settings["force"], 0), young=fixed(settings["young"], 0), poisson=settings["poisson"],
        reference_size=reference["size"], reference_tip=f"{reference['tip']:.4f}",
        drift=drift(data["calculix"]),
        calculix=", ".join(f"{r['tip']:.4f} on {r['size']} x {r['size']}" for r in data["calculix"][:-1]) or "-",
        machine=meta["machine"], threads=meta["threads"], date=meta["date"][:10], version=meta["tensormass_version"],
        commit=meta["commit"], tips=tips, finest=finest,
        targets=table(["element", f"ratio at N = {finest}", "target", "result"], target_rows),
        plain_worst=f"{min(plain):.3f}", plain_best=f"{max(plain):.3f}",
        quad4_fbar_16=ratio("quad4 fbar", 16), tri3_anp_16=ratio("tri3 anp", 16),
        tri3_anp_finest=ratio("tri3 anp", finest)).rstrip())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
