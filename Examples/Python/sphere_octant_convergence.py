#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Study Fig. 10: convergence on the sphere octant.

The rational quartic sphere octant (exact positions, derivatives and mid-edge gradients from
vtkSampledSurfaceSource) is sampled on the equilateral parameter triangle refined l = 1..5 times
and converted with CTo, FO, Ka, MGo and KaG (MGo and KaG read the exact EdgeGradients). The error
is the distance to the unit sphere, |‖p‖ - 1|, maximised over the spline's tessellation (exact
evaluation at SubdivisionLevel^2 points per micro-triangle); observed orders are
log2(e_l / e_{l+1}). The study expects order 3 for CTo, FO, Ka (boundary-limited) and 4 for MGo
and KaG. Also reported: the parametric error max |S(u, v) - f(u, v)| against a dense exact
sampling (vtkApproximationErrorFilter, Parametric mode).

Writes convergence.csv / .md, convergence.png (log-log plot) and, unless --no-render,
octant_<construction>.png coloured by the error. Exits nonzero when an observed final order is
below the asserted bound (3rd order: > 2.8, 4th order: > 3.7; --quick uses levels 1..4).

    xvfb-run -a /usr/bin/python3 Examples/Python/sphere_octant_convergence.py [--quick] [--output DIR]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np  # noqa: E402

import example_common as ex  # noqa: E402

CONSTRUCTIONS = ["CTo", "FO", "Ka", "MGo", "KaG"]
EXPECTED_ORDER = {"CTo": 3, "FO": 3, "Ka": 3, "MGo": 4, "KaG": 4}


def main():
    args = ex.parse_args("sphere_octant_convergence", __doc__.splitlines()[1])
    levels = list(range(1, 5 if args.quick else 6))
    bound = {3: 2.8, 4: 3.7}
    tess_level = 6 if args.quick else 10
    reference = ex.source("SphereOctant", "EquilateralTriangle", 5 if args.quick else 7)

    sphere_err = {c: [] for c in CONSTRUCTIONS}
    param_err = {c: [] for c in CONSTRUCTIONS}
    finest = {}
    for c in CONSTRUCTIONS:
        for level in levels:
            spl = ex.spline(ex.source("SphereOctant", "EquilateralTriangle", level), c)
            tess = ex.tessellate(spl, tess_level).GetOutput()
            dist = np.abs(np.linalg.norm(ex.points(tess), axis=1) - 1.0)
            sphere_err[c].append(float(dist.max()))
            _, values = ex.approximation_error(spl, reference, "Parametric")
            param_err[c].append(values["MaxError"])
            if level == levels[-1]:
                ex.add_point_array(tess, "SphereError", dist)
                finest[c] = tess
        print(c, " ".join(f"{e:.3e}" for e in sphere_err[c]))

    header = ["construction", "expected order"] + [f"e(l={l})" for l in levels] + \
        [f"order {l}->{l + 1}" for l in levels[:-1]] + [f"parametric e(l={levels[-1]})"]
    rows = []
    for c in CONSTRUCTIONS:
        o = ex.orders(sphere_err[c])
        rows.append([c, EXPECTED_ORDER[c]] + sphere_err[c] + [float(x) for x in o] + [param_err[c][-1]])
    text = ex.write_tables(args.output, "convergence", header, rows,
                           title="Sphere octant: max |‖p‖ - 1| and observed orders (study Fig. 10)",
                           notes=["Equilateral domain refined l times (4^l macro-triangles); "
                                  f"error over the tessellation at SubdivisionLevel {tess_level}."])
    print(text)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = [2.0 ** -l for l in levels]
    fig, ax = plt.subplots(figsize=(6, 4.5))
    # FO and Ka coincide, as do MGo and KaG on fine levels: distinct markers and dashes.
    styles = {"CTo": "o-", "FO": "s-", "Ka": "x--", "MGo": "^-", "KaG": "+--"}
    for c in CONSTRUCTIONS:
        ax.loglog(h, sphere_err[c], styles.get(c, "o-"), label=c, ms=7, mfc="none")
    for p, style in ((3, ":"), (4, "--")):
        ref = [sphere_err["CTo" if p == 3 else "MGo"][-1] * (x / h[-1]) ** p for x in h]
        ax.loglog(h, ref, "k" + style, lw=0.8, label=f"h^{p}")
    ax.set_xlabel("h (relative edge length)")
    ax.set_ylabel("max |‖p‖ - 1|")
    ax.set_title("Sphere octant convergence (study Fig. 10)")
    ax.legend()
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(args.output, "convergence.png"), dpi=120)

    if not args.no_render:
        top = max(float(ex.point_array(t, "SphereError").max()) for t in finest.values())
        for c, tess in finest.items():
            ex.render(tess, os.path.join(args.output, f"octant_{c}.png"), "SphereError", (0.0, top),
                      colormap="rainbow", view=((2.2, 2.0, 1.8), (0.4, 0.4, 0.4)),
                      title=f"{c}, level {levels[-1]}: |‖p‖ - 1|")

    checks = ex.Checks()
    for c in CONSTRUCTIONS:
        o = ex.orders(sphere_err[c])
        checks.check(bool(np.all(np.diff(sphere_err[c]) < 0)), f"{c}: error decreases with every level")
        checks.check(o[-1] > bound[EXPECTED_ORDER[c]],
                     f"{c}: last observed order {o[-1]:.2f} > {bound[EXPECTED_ORDER[c]]}")
    checks.exit()


if __name__ == "__main__":
    main()
