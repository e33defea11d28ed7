#!/usr/bin/python3
"""docs/results/viscous.md from bench/viscous_cost.py's JSON.

usage: /usr/bin/python3 scripts/results/render_viscous.py viscous.json > docs/results/viscous.md
"""
import sys

from results_common import load

PAGE = """# The cost of viscoelasticity

The median step of a block clamped at one end under gravity, default
settings: `viscoelastic_neohookean` (mu = {mu}, kappa = {kappa}, two Prony
terms) against `mooney_rivlin` with c10 = mu/2, c01 = 0 and the same
kappa, whose elastic energy is the same, run one after the other. The
ratio is what the viscous part costs: per quadrature point and step the
bulk part's force and tangent and the history stress's geometric
stiffness, one stress evaluation per cell at the end of the step, and on
tet4 the cells leaving the batched (SIMD across cells) kernels.

Measured on {machine} ({threads} threads) on {date}, tensormass
{version}, commit `{commit}`:

```sh
/usr/bin/python3 bench/viscous_cost.py --json docs/results/viscous.json
/usr/bin/python3 scripts/results/render_viscous.py docs/results/viscous.json > docs/results/viscous.md
```

| element | solver | cells | steps | elastic step (ms) | viscoelastic step (ms) | ratio |
|---|---|---:|---:|---:|---:|---:|
{rows}

An implicit step is mostly the linear solve, which the viscous part does
not change. An explicit step of a cheap law is mostly the viscous part's
own passes over the cells: setting up the step's history stress, the
correction of each cell's force (F, J and the bulk part at each point)
and, after the step, the history update with one stress evaluation per
cell. They run in the runtime, apart from the generated kernels.
"""


def main(argv):
    if len(argv) != 2:
        sys.exit(__doc__.strip())
    result = load(argv[1])
    meta, settings = result["metadata"], result["settings"]
    rows = "\n".join(f"| {r['element']} | {r['solver']} | {r['cells']} | {r['steps']} | {r['elastic_ms']:.2f} | "
                     f"{r['viscoelastic_ms']:.2f} | {r['ratio']:.2f}x |" for r in result["rows"])
    print(PAGE.format(mu=f"{settings['mu']:g} Pa", kappa=f"{settings['kappa']:g} Pa", machine=meta["machine"],
                      threads=meta["threads"], date=meta["date"][:10], version=meta["tensormass_version"],
                      commit=meta["commit"], rows=rows).rstrip())
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
