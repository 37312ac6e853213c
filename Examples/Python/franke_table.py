#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Study Table 2: maximum error on Franke's function per construction and split point.

Franke's function (study eq. 27) is sampled with exact gradients (and exact mid-edge gradients
for MGo, MGi, KaG) on two triangulations of [0, 1]^2: the Delaunay triangulation of random points
(vtkSampledSurfaceSource RandomDelaunay) and a regular grid. Every construction (CTo CTi Fa FO Ka
MGo MGi, plus KaG, Kashyap and Quartic with 5 fairing rounds) and split point (Bary, Inc2, Inc3)
is converted, and the maximum error max |S(u, v) - F(u, v)| is measured against a dense exact
sampling of F (vtkApproximationErrorFilter, Parametric mode). Boundary mode: Midpoint (default).

Checks (exit nonzero on failure): every construction and split point reproduces a quadratic
(error < 1e-10 on the kernel's Quadratic surface, same meshes); every Franke error is finite and
below the error of the piecewise linear interpolant of the same vertices.

Writes franke_max_error.csv / .md and, when vtkBezierCurvatureFilter is available and not
--no-render, shaded and mean-curvature images of a few splines.

    xvfb-run -a /usr/bin/python3 Examples/Python/franke_table.py [--quick] [--output DIR]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np  # noqa: E402

import example_common as ex  # noqa: E402

CONSTRUCTIONS = ex.CONSTRUCTIONS  # every row of the construction table
SPLITS = ["Bary", "Inc2", "Inc3"]
FAIRING_ROUNDS = 5  # Kashyap and Quartic, as in the quartic paper


def iterations(c):
    return FAIRING_ROUNDS if c in ("Kashyap", "Quartic") else 0


def main():
    args = ex.parse_args("franke_table", __doc__.splitlines()[1])
    random_points = 40 if args.quick else 100
    grid = 6 if args.quick else 10
    dense = 60 if args.quick else 300
    domains = [("Delaunay", "RandomDelaunay", random_points), ("Grid", "Grid", grid)]
    checks = ex.Checks()

    reference = ex.source("Franke", "Grid", dense)
    quadratic_reference = ex.source("Quadratic", "Grid", dense // 3)
    header = ["construction", "split"] + [f"{d} ({n})" for d, _, n in domains]
    rows = []
    linear = {}
    for dname, domain, n in domains:
        # The piecewise linear interpolant of the same vertices: an upper bound any C1
        # interpolant with exact gradients should beat.
        linear[dname] = _linear_error(ex.source("Franke", domain, n), reference)
    worst_quadratic = 0.0
    for c in CONSTRUCTIONS:
        for s in SPLITS:
            row = [c, s]
            for dname, domain, n in domains:
                spl = ex.spline(ex.source("Franke", domain, n), c, s, iterations(c))
                _, v = ex.approximation_error(spl, reference, "Parametric")
                row.append(v["MaxError"])
                checks.check(np.isfinite(v["MaxError"]) and v["MaxError"] < linear[dname],
                             f"{c}/{s} on {dname}: {v['MaxError']:.4g} < linear {linear[dname]:.4g}")
                q = ex.spline(ex.source("Quadratic", domain, n), c, s, iterations(c))
                _, vq = ex.approximation_error(q, quadratic_reference, "Parametric")
                worst_quadratic = max(worst_quadratic, vq["MaxError"])
                checks.check(vq["MaxError"] < 1e-10, f"{c}/{s} on {dname}: quadratic reproduced "
                             f"({vq['MaxError']:.2e})")
            rows.append(row)
    rows.append(["piecewise linear", "-"] + [linear[d] for d, _, _ in domains])
    text = ex.write_tables(
        args.output, "franke_max_error", header, rows,
        title="Franke's function: maximum error (study Table 2)",
        notes=[f"Delaunay: {random_points} random interior points plus boundary points (seed 1); "
               f"Grid: {grid} x {grid} cells, forward diagonals. Error: max |S - F| at the "
               f"{(dense + 1) ** 2} points of a {dense} x {dense} grid. Kashyap and Quartic: "
               f"{FAIRING_ROUNDS} rounds. Largest error on quadratic data: {worst_quadratic:.2e}."])
    print(text)

    if not args.no_render:
        src = ex.source("Franke", "RandomDelaunay", random_points)
        for c in ("CTo", "FO", "Ka", "Quartic"):
            spl = ex.spline(src, c, "Bary", iterations(c))
            surface = ex.curvature(spl, 8)
            ex.render(surface, os.path.join(args.output, f"franke_{c}_shaded.png"), title=f"{c}")
            ex.render(surface, os.path.join(args.output, f"franke_{c}_mean_curvature.png"),
                      "Mean_Curvature", (-20.0, 20.0), title=f"{c}: mean curvature")
    checks.exit()


def _linear_error(src, reference):
    """max |L - F| of the piecewise linear interpolant L of the source's vertices, evaluated at
    the reference's parameters with barycentric interpolation (numpy, for the comparison row)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    mesh = src.GetOutput()
    uv = ex.point_array(mesh, "UV")
    z = ex.points(mesh)[:, 2]
    tri = vtk_to_numpy(mesh.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    ref = reference.GetOutput()
    q = ex.point_array(ref, "UV")
    fz = ex.points(ref)[:, 2]
    from matplotlib.tri import LinearTriInterpolator, Triangulation

    interp = LinearTriInterpolator(Triangulation(uv[:, 0], uv[:, 1], tri), z)
    lz = np.ma.filled(interp(q[:, 0], q[:, 1]), np.nan)
    return float(np.nanmax(np.abs(lz - fz)))


if __name__ == "__main__":
    main()
