#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Study Fig. 5-6: polynomial precision on Farin's cubic.

Farin's cubic c(x, y) = (x - 0.3)^3 + x (y - 0.3)^2 - 0.1 x (study eq. 26) is sampled with exact
gradients and exact mid-edge gradients (vtkSampledSurfaceSource FarinCubic) on a regular grid and
on the Delaunay triangulation of random points of [0, 1]^2, and converted with every cubic
construction (CTo CTi Fa FO Ka MGo MGi KaG, split point Bary, boundary mode Midpoint) and with
CTi and Fa after 20 IM steps with boundary edges fixed by the exact mid-edge gradients.
"Gradient boundary" is boundary mode GradientToSplitPoint; KaG and MGi use it whatever the mode
(they have the boundary mid-edge gradients). CTi and Fa with that boundary and no IM are listed
too.
The error max |S(u, v) - c(u, v)| is measured against a dense exact sampling
(vtkApproximationErrorFilter, Parametric mode), over the whole domain and over the interior
macro-triangles (those with three neighbours: FO and Ka reproduce cubics there only, their
boundary edges use a quadratic-precision rule).

Checks (exit nonzero on failure): FO and Ka reproduce the cubic on interior triangles, KaG, MGo
and MGi everywhere (max error < 1e-10); CTo, CTi and Fa do not (> 1e-6); 20 IM steps with the
gradient boundary reduce the error of CTi and Fa more than 100-fold; the exact Gaussian and mean
curvatures (vtkBezierCurvatureFilter) of the splines that reproduce the cubic everywhere equal
the cubic's (relative 1e-6).

Writes farin_cubic.csv / .md and, unless --no-render, per domain and construction reflection
lines (reflect_<domain>_<c>.png), Gaussian and mean curvature with a common colour range
(gauss_<domain>_<c>.png, mean_<domain>_<c>.png), and a contact sheet like the study's Fig. 6
(farin_cubic_<domain>.png: reflection lines, then K and H over the parameter domain with the
macro-triangles drawn in).

    xvfb-run -a /usr/bin/python3 Examples/Python/farin_cubic.py [--quick] [--output DIR]
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np  # noqa: E402

import example_common as ex  # noqa: E402

QUADRATIC = ["CTo", "CTi", "Fa"]           # quadratic precision
INTERIOR_CUBIC = ["FO", "Ka"]              # cubic precision on interior triangles
CUBIC = ["MGo", "MGi", "KaG"]              # cubic precision everywhere (exact edge gradients)
IM_STEPS = 20
GRADIENT_BOUNDARY = "GradientToSplitPoint"
SHOWN = 10                                 # the first SHOWN variants are drawn
DOMAIN_TITLE = {"Grid": "grid", "Delaunay": "random Delaunay triangulation"}
EYE = (-1.5, -1.5, 2.5)  # every reflected ray reaches the light plane z = 3
VIEW = (EYE, (0.5, 0.5, 0.2))


def variants():
    """(label, construction, IM steps, boundary mode, precision) of every spline; the last two
    (no IM) are the baselines of the IM check."""
    out = [(c, c, 0, None, "quadratic") for c in QUADRATIC]
    out += [(c, c, 0, None, "cubic (interior)") for c in INTERIOR_CUBIC]
    out += [(c, c, 0, None, "cubic") for c in ("MGo", "MGi", "KaG")]
    out += [(f"{c} + IM {IM_STEPS}", c, IM_STEPS, GRADIENT_BOUNDARY, "cubic (limit)")
            for c in ("CTi", "Fa")]
    out += [(f"{c}, grad. boundary", c, 0, GRADIENT_BOUNDARY, "quadratic") for c in ("CTi", "Fa")]
    return out


def boundary_name(construction, boundary):
    if construction in ("CTo", "MGo"):
        return "- (local)"
    if construction in ("KaG", "MGi") and boundary is None:
        return GRADIENT_BOUNDARY + " (implied)"
    return boundary or "Midpoint"


def exact_curvatures(u, v):
    """Gaussian and mean curvature of the graph z = c(u, v), normal upwards, in the sign
    convention of vtkBezierCurvatureFilter (H > 0 where the surface bends away from the normal)."""
    cx = 3.0 * (u - 0.3) ** 2 + (v - 0.3) ** 2 - 0.1
    cy = 2.0 * u * (v - 0.3)
    cxx, cxy, cyy = 6.0 * (u - 0.3), 2.0 * (v - 0.3), 2.0 * u
    w2 = 1.0 + cx * cx + cy * cy
    gauss = (cxx * cyy - cxy * cxy) / (w2 * w2)
    mean = -((1.0 + cy * cy) * cxx - 2.0 * cx * cy * cxy + (1.0 + cx * cx) * cyy) / (2.0 * w2 ** 1.5)
    return gauss, mean


def interior_triangles(mesh):
    """Boolean mask of the triangles of a vtkPolyData whose three edges are shared."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    tri = vtk_to_numpy(mesh.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    edges = np.sort(np.stack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]], axis=1), axis=2)
    flat = edges.reshape(-1, 2)
    _, inverse, counts = np.unique(flat, axis=0, return_inverse=True, return_counts=True)
    return (counts[inverse.reshape(-1)].reshape(-1, 3) == 2).all(axis=1)


def errors(spl, reference, interior):
    """(max error over the domain, max error over interior macro-triangles)."""
    out, values = ex.approximation_error(spl, reference, "Parametric")
    err = ex.point_array(out, "Error")
    valid = ex.point_array(out, "vtkValidPointMask").astype(bool)
    macro = ex.point_array(out, "MacroTriangleId").astype(int)
    inside = valid & (macro >= 0)
    inside[inside] = interior[macro[inside]]
    return values["MaxError"], float(err[inside].max()) if inside.any() else float("nan")


def exact_surface(resolution):
    """A dense sampling of the cubic with Normals (for the reference reflection lines) and its
    exact curvatures."""
    src = ex.source("FarinCubic", "Grid", resolution)
    data = src.GetOutput()
    n = np.cross(ex.point_array(data, "dFdu"), ex.point_array(data, "dFdv"))
    ex.add_point_array(data, "Normals", n / np.linalg.norm(n, axis=1)[:, None])
    uv = ex.point_array(data, "UV")
    k, h = exact_curvatures(uv[:, 0], uv[:, 1])
    ex.add_point_array(data, "Gauss_Curvature", k)
    ex.add_point_array(data, "Mean_Curvature", h)
    return data


def contact_sheet(filename, title, columns, mesh, ranges):
    """columns: (label, reflection-line PNG, curvature vtkPolyData with UV). Three rows:
    reflection lines (the rendered PNGs, cropped), Gaussian and mean curvature over the parameter
    domain (tripcolor, common colour range per row) with the macro-triangles drawn in."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation
    from vtkmodules.util.numpy_support import vtk_to_numpy

    uv_mesh = ex.point_array(mesh, "UV")
    tri_mesh = vtk_to_numpy(mesh.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    n = len(columns)
    fig, axes = plt.subplots(3, n, figsize=(1.45 * n + 0.9, 4.6),
                             gridspec_kw={"height_ratios": [1.0, 1.0, 1.0]})
    rows = [("reflection lines", None), ("Gaussian curvature", "Gauss_Curvature"),
            ("mean curvature", "Mean_Curvature")]
    mappable = {}
    for j, (label, png, curv) in enumerate(columns):
        img = plt.imread(png)
        ink = np.where(img[..., :3].min(axis=2) < 0.97)
        if ink[0].size:
            img = img[ink[0].min():ink[0].max() + 1, ink[1].min():ink[1].max() + 1]
        axes[0, j].imshow(img)
        axes[0, j].set_title(label, fontsize=8)
        uv = ex.point_array(curv, "UV")
        tri = vtk_to_numpy(curv.GetPolys().GetConnectivityArray()).reshape(-1, 3)
        t = Triangulation(uv[:, 0], uv[:, 1], tri)
        for i, (_, array) in enumerate(rows[1:], start=1):
            lo, hi = ranges[array]
            m = axes[i, j].tripcolor(t, ex.point_array(curv, array), shading="gouraud",
                                     cmap="coolwarm", vmin=lo, vmax=hi, rasterized=True)
            mappable[array] = m
            axes[i, j].triplot(uv_mesh[:, 0], uv_mesh[:, 1], tri_mesh, color="k", lw=0.25)
            axes[i, j].set_aspect("equal")
    for ax in axes.flat:
        ax.set_xticks([])
        ax.set_yticks([])
        for s in ax.spines.values():
            s.set_visible(False)
    for i, (name, _) in enumerate(rows):
        axes[i, 0].set_ylabel(name, fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout(rect=(0.0, 0.0, 0.965, 0.96), w_pad=0.2, h_pad=0.3)
    for i, (_, array) in enumerate(rows[1:], start=1):
        box = axes[i, -1].get_position()
        cax = fig.add_axes([box.x1 + 0.006, box.y0, 0.008, box.height])
        cb = fig.colorbar(mappable[array], cax=cax)
        cb.ax.tick_params(labelsize=6)
    fig.savefig(filename, dpi=100)
    plt.close(fig)
    # 256 colours (Pillow comes with Matplotlib): a third of the size, no visible banding.
    from PIL import Image

    with Image.open(filename) as img:
        small = img.convert("RGB").quantize(256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    small.save(filename, optimize=True)


def main():
    args = ex.parse_args("farin_cubic", __doc__.splitlines()[1])
    grid = 4 if args.quick else 5
    random_points = 12 if args.quick else 20
    dense = 60 if args.quick else 200
    curvature_level = 6 if args.quick else 12
    tess_level = 8 if args.quick else 16
    domains = [("Grid", "Grid", grid), ("Delaunay", "RandomDelaunay", random_points)]
    reference = ex.source("FarinCubic", "Grid", dense)
    checks = ex.Checks()

    specs = variants()
    header = ["construction", "precision", "boundary", "IM"]
    for d, _, n in domains:
        header += [f"{d} ({n}) max", f"{d} interior max"]
    table = {label: [label, prec, boundary_name(c, boundary), steps]
             for label, c, steps, boundary, prec in specs}
    exact = exact_surface(100 if args.quick else 300)
    for dname, domain, n in domains:
        src = ex.source("FarinCubic", domain, n)
        mesh = src.GetOutput()
        interior = interior_triangles(mesh)
        print(f"{dname}: {mesh.GetNumberOfCells()} triangles, {int(interior.sum())} interior")
        err = {}
        curv = {}
        for i, (label, construction, steps, boundary, _) in enumerate(specs):
            spl = ex.spline(src, construction, iterations=steps, boundary=boundary)
            err[label] = errors(spl, reference, interior)
            table[label] += list(err[label])
            print(f"  {label:20s} max {err[label][0]:.3e}  interior {err[label][1]:.3e}")
            if (not args.no_render and i < SHOWN) or label in CUBIC:
                curv[label] = (spl, ex.curvature(spl, curvature_level))

        for c in QUADRATIC:
            checks.check(err[c][0] > 1e-6, f"{dname}: {c} does not reproduce the cubic ({err[c][0]:.2e})")
        for c in INTERIOR_CUBIC:
            checks.check(err[c][1] < 1e-10,
                         f"{dname}: {c} reproduces the cubic on interior triangles ({err[c][1]:.2e})")
        for c in CUBIC:
            checks.check(err[c][0] < 1e-10, f"{dname}: {c} reproduces the cubic ({err[c][0]:.2e})")
            out = curv[c][1]
            uv = ex.point_array(out, "UV")
            for array, value in zip(("Gauss_Curvature", "Mean_Curvature"),
                                    exact_curvatures(uv[:, 0], uv[:, 1])):
                dev = np.abs(ex.point_array(out, array) - value).max() / np.abs(value).max()
                checks.check(dev < 1e-6, f"{dname}: {c} {array} equals the cubic's (relative {dev:.1e})")
        for c in ("CTi", "Fa"):
            e0, e20 = err[f"{c}, grad. boundary"][0], err[f"{c} + IM {IM_STEPS}"][0]
            checks.check(e20 * 100 < e0, f"{dname}: {IM_STEPS} IM steps, gradient boundary, reduce the "
                         f"{c} error {e0 / e20:.3g}-fold ({e0:.2e} -> {e20:.2e})")

        if args.no_render:
            continue
        # Common colour range: the exact cubic's curvatures over [0, 1]^2, symmetric about 0
        # (white); the quadratic-precision splines overshoot it.
        ranges = {}
        for array in ("Gauss_Curvature", "Mean_Curvature"):
            top = float(np.abs(ex.point_array(exact, array)).max())
            ranges[array] = (-top, top)
        columns = []
        shown = [("exact cubic", exact)] + [(label, None) for label, *_ in specs[:SHOWN]]
        for label, data in shown:
            stem = f"{dname}_{label.replace(' + IM ', '_IM').replace(' ', '_')}"
            if data is None:
                surface = ex.tessellate(curv[label][0], tess_level).GetOutput()
                cdata = curv[label][1]
            else:
                surface, cdata = data, data
            reflect = os.path.join(args.output, f"reflect_{stem}.png")
            ex.render(ex.reflection_lines(surface, EYE, 16.0), reflect, "ReflectionLines", (-1.0, 1.0),
                      colormap="gray", view=VIEW, size=(500, 400))
            for array, short in (("Gauss_Curvature", "gauss"), ("Mean_Curvature", "mean")):
                ex.render(cdata, os.path.join(args.output, f"{short}_{stem}.png"), array,
                          ranges[array], view=VIEW, title=f"{label}, {dname}: {array.replace('_', ' ')}")
            columns.append((label, reflect, cdata))
        contact_sheet(os.path.join(args.output, f"farin_cubic_{dname}.png"),
                      f"Farin's cubic on the {DOMAIN_TITLE[dname]} ({mesh.GetNumberOfCells()} "
                      "triangles, Bary split): reflection lines, Gaussian and mean curvature",
                      columns, mesh, ranges)

    rows = [table[label] for label, *_ in specs]
    text = ex.write_tables(
        args.output, "farin_cubic", header, rows,
        title="Farin's cubic: max |S - c| per construction (study Fig. 5-6, Table 1 precision)",
        notes=[f"Grid: {grid} x {grid} cells, forward diagonals; Delaunay: {random_points} random "
               "interior points plus boundary points (seed 1); split point Bary. Error at the "
               f"{(dense + 1) ** 2} points of a {dense} x {dense} grid; interior: points in "
               "macro-triangles with three neighbours. Grad. boundary: boundary mode "
               f"{GRADIENT_BOUNDARY} (exact boundary mid-edge gradients)."])
    print(text)
    checks.exit()


if __name__ == "__main__":
    main()
