#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Compare ctsplines with SciPy's and Matplotlib's cubic Clough-Tocher interpolants.

All three get the same data: one Delaunay triangulation of scattered points in [0, 1]^2 (SciPy's,
of the vertices that vtkSampledSurfaceSource sampled) and the exact values and gradients of a
functional surface (Franke's by default) at the vertices:

- ours:       vtkCloughTocherSplineFilter (CTi and CTo) + vtkSplineParameterProbe
- SciPy:      scipy.interpolate.CloughTocher2DInterpolator, .grad overwritten with the exact
              gradients (its own global gradient estimate is skipped with maxiter=0)
- Matplotlib: matplotlib.tri.CubicTriInterpolator(kind='user', dz=(zx, zy)) (reduced HCT)

All are C1 piecewise cubics on the Clough-Tocher split; their edge conditions are documented
differently, so the pairwise differences are reported. The script asserts the following and exits
nonzero otherwise:

- each interpolant reproduces the vertex values (to 1e-12);
- with data from a quadratic (the kernel's Quadratic surface) all three reproduce it, so they agree
  with each other at random points to 1e-10;
- measured, then asserted: SciPy's interpolant is our CTi (Bary split, Midpoint boundary) and
  Matplotlib's is our CTo, to round-off (1e-11), on the same triangulation and gradients.

Usage: PYTHONPATH=<build>/lib/python3.11/dist-packages /usr/bin/python3 benchmark_scipy.py
       [--quick] [--points N] [--queries M] [--seed S] [--repeat R]
"""
import argparse
import os
import sys
import time
import warnings

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.tri as mtri  # noqa: E402
from scipy.interpolate import CloughTocher2DInterpolator  # noqa: E402
from scipy.spatial import Delaunay  # noqa: E402

import ctsplines  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints, vtkSMPTools  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData  # noqa: E402

VERTEX_TOL = 1e-12
QUADRATIC_TOL = 1e-10
IDENTITY_TOL = 1e-11


def best_time(fn, repeat):
    """(best wall-clock seconds, result of the last call) of `repeat` calls."""
    best, result = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - t0)
    return best, result


def sample(surface, points, seed):
    """Vertices of a RandomDelaunay mesh of [0,1]^2 with exact values and gradients."""
    src = ctsplines.vtkSampledSurfaceSource()
    src.SetSurface(surface)
    src.SetDomainToRandomDelaunay()
    src.SetResolution(points)
    src.SetSeed(seed)
    src.Update()
    out = src.GetOutput()
    if out.GetNumberOfPoints() == 0:
        raise RuntimeError("vtkSampledSurfaceSource failed")
    pd = out.GetPointData()
    uv = vtk_to_numpy(pd.GetArray("UV")).copy()
    F = vtk_to_numpy(out.GetPoints().GetData()).copy()
    Fu = vtk_to_numpy(pd.GetArray("dFdu")).copy()
    Fv = vtk_to_numpy(pd.GetArray("dFdv")).copy()
    return uv, F, Fu, Fv


def mesh_polydata(uv, F, Fu, Fv, triangles):
    """The filter's input: our own triangles (SciPy's) with the sampled point data."""
    pd = vtkPolyData()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(F), deep=True))
    pd.SetPoints(pts)
    nT = len(triangles)
    cells = vtkCellArray()
    cells.SetData(
        numpy_to_vtkIdTypeArray(np.arange(0, 3 * nT + 1, 3, dtype=np.int64), deep=True),
        numpy_to_vtkIdTypeArray(np.ascontiguousarray(triangles, dtype=np.int64).ravel(), deep=True),
    )
    pd.SetPolys(cells)
    for name, arr in (("UV", uv), ("dFdu", Fu), ("dFdv", Fv)):
        a = numpy_to_vtk(np.ascontiguousarray(arr), deep=True)
        a.SetName(name)
        pd.GetPointData().AddArray(a)
    return pd


def query_polydata(q):
    pd = vtkPolyData()
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.column_stack([q, np.zeros(len(q))]), deep=True))
    pd.SetPoints(pts)
    return pd


class Ours:
    """vtkCloughTocherSplineFilter + vtkSplineParameterProbe."""

    def __init__(self, mesh, construction):
        self.mesh, self.construction = mesh, construction
        self.spline = None

    def build(self):
        f = ctsplines.vtkCloughTocherSplineFilter()
        f.SetInputData(self.mesh)
        f.SetConstruction(self.construction)
        f.SetSplitPointToBary()
        f.SetBoundaryModeToMidpoint()
        f.Update()
        self.spline = f.GetOutput()
        if self.spline.GetNumberOfCells() == 0:
            raise RuntimeError("vtkCloughTocherSplineFilter failed")
        return self

    def __call__(self, q):
        probe = ctsplines.vtkSplineParameterProbe()
        probe.SetInputData(query_polydata(q))
        probe.SetSourceData(self.spline)
        probe.Update()
        out = probe.GetOutput()
        if out.GetNumberOfPoints() != len(q):
            raise RuntimeError("vtkSplineParameterProbe failed")
        z = vtk_to_numpy(out.GetPoints().GetData())[:, 2].copy()
        valid = vtk_to_numpy(out.GetPointData().GetArray("vtkValidPointMask"))
        z[valid == 0] = np.nan
        return z


class Scipy:
    def __init__(self, tri, z, zx, zy):
        self.tri, self.z, self.grad = tri, z, np.column_stack([zx, zy])[:, None, :]

    def build(self):
        with warnings.catch_warnings():
            # maxiter=0 skips the global gradient estimate we overwrite anyway; SciPy warns that
            # it "did not converge".
            warnings.simplefilter("ignore")
            self.ip = CloughTocher2DInterpolator(self.tri, self.z, maxiter=0)
        self.ip.grad = self.grad.copy()
        return self

    def __call__(self, q):
        return self.ip(q)


class Mpl:
    def __init__(self, uv, triangles, z, zx, zy):
        self.uv, self.triangles, self.z, self.dz = uv, triangles, z, (zx, zy)

    def build(self):
        triang = mtri.Triangulation(self.uv[:, 0], self.uv[:, 1], self.triangles)
        self.ip = mtri.CubicTriInterpolator(triang, self.z, kind="user", dz=self.dz)
        triang.get_trifinder()  # built lazily otherwise: count it as construction
        return self

    def __call__(self, q):
        return np.ma.filled(self.ip(q[:, 0], q[:, 1]), np.nan)


def setup(surface, points, seed):
    uv, F, Fu, Fv = sample(surface, points, seed)
    z, zx, zy = F[:, 2], Fu[:, 2], Fv[:, 2]
    # Functional surfaces: F = (u, v, z), f_u = (1, 0, z_x), f_v = (0, 1, z_y).
    assert np.array_equal(F[:, :2], uv) and np.all(Fu[:, :2] == [1, 0]) and np.all(Fv[:, :2] == [0, 1])
    tri = Delaunay(uv)
    triangles = tri.simplices.astype(np.int64)
    a = uv[triangles]
    area = 0.5 * np.cross(a[:, 1] - a[:, 0], a[:, 2] - a[:, 0])
    info = dict(
        vertices=len(uv),
        triangles=len(triangles),
        unused=len(uv) - len(np.unique(triangles)),
        min_area=np.abs(area).min(),
    )
    # Our filter takes any orientation; keep SciPy's triangles as they are.
    interpolants = {
        "ours CTi": Ours(mesh_polydata(uv, F, Fu, Fv, triangles), ctsplines.vtkCloughTocherSplineFilter.CTi),
        "ours CTo": Ours(mesh_polydata(uv, F, Fu, Fv, triangles), ctsplines.vtkCloughTocherSplineFilter.CTo),
        "scipy": Scipy(tri, z, zx, zy),
        "matplotlib": Mpl(uv, triangles, z, zx, zy),
    }
    return uv, z, info, interpolants


def max_pairwise(values):
    names = list(values)
    rows = []
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            rows.append((a, b, float(np.nanmax(np.abs(values[a] - values[b])))))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="small sizes (smoke test)")
    ap.add_argument("--points", type=int, default=100000, help="random interior vertices")
    ap.add_argument("--queries", type=int, default=1000000, help="random evaluation points")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--repeat", type=int, default=3, help="runs per timing; the best is reported")
    args = ap.parse_args()
    if args.quick:
        args.points, args.queries, args.repeat = 300, 5000, 1
    if not hasattr(ctsplines, "vtkSplineParameterProbe"):
        print("ctsplines has no vtkSplineParameterProbe: cannot evaluate our spline", file=sys.stderr)
        return 1
    # The filters' loops run on the package's pool (CTSPLINES_NUM_THREADS, set on import); say
    # what ran.
    print(f"CTSplines threads {os.environ.get('CTSPLINES_NUM_THREADS', 'as VTK')}, "
          f"VTK SMP backend {vtkSMPTools.GetBackend()}")

    failures = []

    def check(ok, what):
        print(f"  [{'ok' if ok else 'FAIL'}] {what}")
        if not ok:
            failures.append(what)

    rng = np.random.default_rng(args.seed)
    q = rng.random((args.queries, 2))

    # 1. Franke: timings and differences.
    uv, z, info, ips = setup(ctsplines.vtkSampledSurfaceSource.Franke, args.points, args.seed)
    print(
        f"\nFranke, {info['vertices']} vertices, {info['triangles']} triangles (SciPy's Delaunay), "
        f"{args.queries} random query points, best of {args.repeat}"
    )
    check(info["unused"] == 0 and info["min_area"] > 0, f"triangulation uses every vertex, min area {info['min_area']:.3g}")
    print(f"\n  {'interpolant':<12} {'build s':>10} {'eval s':>10} {'total s':>10} {'build tri/s':>13} {'eval pts/s':>13}")
    times, at_queries = {}, {}
    for name, ip in ips.items():
        tb, _ = best_time(ip.build, args.repeat)
        te, values = best_time(lambda: ip(q), args.repeat)
        times[name] = (tb, te)
        at_queries[name] = values
        print(
            f"  {name:<12} {tb:10.4f} {te:10.4f} {tb + te:10.4f} {info['triangles'] / tb:13.4g} "
            f"{args.queries / te:13.4g}"
        )
    ours = times["ours CTi"]
    print("\n  throughput ratios (ours CTi / other, >1 = ours faster):")
    for other in ("scipy", "matplotlib"):
        t = times[other]
        print(
            f"    vs {other:<10} evaluation {t[1] / ours[1]:7.2f}x   construction+evaluation "
            f"{(t[0] + t[1]) / (ours[0] + ours[1]):7.2f}x"
        )
    print("\n  max |difference| at the query points:")
    for a, b, d in max_pairwise(at_queries):
        print(f"    {a:<10} - {b:<10} {d:.3e}")
    for name, values in at_queries.items():
        check(np.all(np.isfinite(values)), f"{name}: finite at every query point in [0,1]^2")
    # Measured, and asserted because it pins the edge conditions down: SciPy's element is CTi
    # with the Midpoint boundary, Matplotlib's reduced HCT is CTo (to round-off, Bary split).
    for a, b in (("ours CTi", "scipy"), ("ours CTo", "matplotlib")):
        d = float(np.nanmax(np.abs(at_queries[a] - at_queries[b])))
        check(d <= IDENTITY_TOL, f"{a} and {b} are the same interpolant: {d:.2e}")

    # Interpolation error against the exact function: the vertices of an independent random mesh.
    uv_test, F_test, _, _ = sample(ctsplines.vtkSampledSurfaceSource.Franke, max(100, args.queries // 50), args.seed + 1000)
    print(f"\n  max |error| against Franke at {len(uv_test)} independent points:")
    for name, ip in ips.items():
        print(f"    {name:<10} {np.nanmax(np.abs(ip(uv_test) - F_test[:, 2])):.3e}")

    # Vertex data are reproduced exactly by every interpolant.
    print("\n  at the vertices:")
    at_vertices = {name: ip(uv) for name, ip in ips.items()}
    for name, values in at_vertices.items():
        err = float(np.max(np.abs(values - z)))
        check(err <= VERTEX_TOL, f"{name} reproduces the vertex values: max error {err:.2e}")
    d = float(np.max(np.abs(at_vertices["ours CTi"] - at_vertices["scipy"])))
    check(d <= VERTEX_TOL, f"ours CTi and scipy agree at the vertices: {d:.2e}")

    # 2. Quadratic data: quadratic precision of all three.
    nq = min(args.points, 2000)
    uvq, zq, _, ipq = setup(ctsplines.vtkSampledSurfaceSource.Quadratic, nq, args.seed + 1)
    qq = q[: min(len(q), 20000)]
    print(f"\nQuadratic, {len(uvq)} vertices, {len(qq)} query points:")
    values = {name: ip.build()(qq) for name, ip in ipq.items()}
    for a, b, d in max_pairwise(values):
        check(d <= QUADRATIC_TOL, f"{a} - {b}: {d:.2e}")
    # And they reproduce the quadratic itself, sampled exactly at an independent point set.
    uv_test, F_test, _, _ = sample(ctsplines.vtkSampledSurfaceSource.Quadratic, 2000, args.seed + 2000)
    for name, ip in ipq.items():
        err = float(np.nanmax(np.abs(ip(uv_test) - F_test[:, 2])))
        check(err <= QUADRATIC_TOL, f"{name} reproduces the quadratic: {err:.2e}")

    if failures:
        print(f"\n{len(failures)} check(s) failed", file=sys.stderr)
        return 1
    print("\nall checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
