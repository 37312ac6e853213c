#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""CTSplines against SciPy and Matplotlib on the mesh their users have, in one run.

The mesh: SciPy's Delaunay triangulation (qhull) of --points uniform random points of the unit
square, in qhull's numbering, with the exact values and gradients of z = sin 3x cos 2y. On it:

- ours:       vtkCloughTocherSplineFilter CTi (SciPy's element) and CTo (Matplotlib's), then
              vtkSplineParameterProbe on the CTi spline, one probe object for every call (it
              builds its spline, in a locality order, and its locator once and reuses them while
              the source is unchanged): first call, second call,
              later calls (positions and derivatives, and positions only);
- SciPy:      CloughTocher2DInterpolator(tri, z, maxiter=0) with .grad set to the exact gradients;
- Matplotlib: CubicTriInterpolator(kind='user', dz=exact), its TriFinder built beforehand (not
              counted).

Printed: construction time (best of --repeat), probe time for --queries points in sorted order
(rows of a square grid) and in random order (SciPy's random probe walks qhull's triangulation
from point to point: it is timed on --scipy-random-queries points and scaled), and the peak
resident memory each construction adds (Linux: /proc/self/clear_refs resets the high-water
mark), against our spline's size. Ratios are the peer's time (or memory) over ours: > 1 means
ours is faster (smaller). Everything runs in this process, back to back, on the same data;
CTSPLINES_NUM_THREADS (default 1 here) sets our threads, NumPy's code is single-threaded.

Each stage prints as it ends. At --points 2000000 (4e6 triangles) Matplotlib's construction adds
5.6 GB to the process and the probe stage alone peaked at 6.7 GB (2026-12-04).

Usage: PYTHONPATH=<build>/lib/python3.11/dist-packages /usr/bin/python3 delaunay_comparison.py
       [--points 500000] [--queries 1000000] [--repeat 3] [--stages construction,probe] [--quick]
"""
import argparse
import os
import resource
import sys
import time
import warnings

os.environ.setdefault("CTSPLINES_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.tri as mtri  # noqa: E402
from scipy.interpolate import CloughTocher2DInterpolator  # noqa: E402
from scipy.spatial import Delaunay  # noqa: E402

import ctsplines  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonCore import vtkPoints  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData  # noqa: E402

# Round-off on the random convex hull's sliver triangles reaches ~1e-8 (our CTo vs Matplotlib).
AGREEMENT_TOL = 1e-6
clock = time.perf_counter  # set from --clock in main (CLOCKS)


def user_seconds():
    """This process' user CPU time (all threads)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_utime


# --clock: (the function every timing reads, the name the header prints).
CLOCKS = {"wall": (time.perf_counter, "wall-clock"),
          "cpu": (time.process_time, "process CPU"),
          "user": (user_seconds, "user CPU")}


def best(fn, repeat):
    """(best wall-clock seconds, last result) of `repeat` calls."""
    t, result = float("inf"), None
    for _ in range(repeat):
        t0 = clock()
        result = fn()
        t = min(t, clock() - t0)
    return t, result


def status_bytes(field):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return 1024 * int(line.split()[1])
    return -1


def peak_extra(fn):
    """(peak resident bytes fn adds over what was resident before it, fn's result); -1 bytes
    when the high-water mark cannot be reset."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        return -1, fn()
    before = status_bytes("VmRSS")
    result = fn()
    return status_bytes("VmHWM") - before, result


def sine_cosine(uv):
    x, y = uv[:, 0], uv[:, 1]
    return np.sin(3 * x) * np.cos(2 * y), 3 * np.cos(3 * x) * np.cos(2 * y), -2 * np.sin(3 * x) * np.sin(2 * y)


def vtk_array(a, name=None, deep=True):
    arr = numpy_to_vtk(np.ascontiguousarray(a), deep=deep)
    if name:
        arr.SetName(name)
    return arr


def mesh_polydata(uv, z, zx, zy, triangles):
    n = len(uv)
    pd = vtkPolyData()
    pts = vtkPoints()
    pts.SetData(vtk_array(np.column_stack([uv, z])))
    pd.SetPoints(pts)
    cells = vtkCellArray()
    cells.SetData(
        numpy_to_vtkIdTypeArray(np.arange(0, 3 * len(triangles) + 1, 3, dtype=np.int64), deep=True),
        numpy_to_vtkIdTypeArray(np.ascontiguousarray(triangles, dtype=np.int64).ravel(), deep=True),
    )
    pd.SetPolys(cells)
    zeros, ones = np.zeros(n), np.ones(n)
    pd.GetPointData().AddArray(vtk_array(uv, "UV"))
    pd.GetPointData().AddArray(vtk_array(np.column_stack([ones, zeros, zx]), "dFdu"))
    pd.GetPointData().AddArray(vtk_array(np.column_stack([zeros, ones, zy]), "dFdv"))
    return pd


def query_polydata(q):
    pd = vtkPolyData()
    pts = vtkPoints()
    # The (u, v, 0) points wrapped without a copy (the VTK array keeps the NumPy one alive), as
    # a user probing NumPy queries would; the stacking is part of the timed call.
    pts.SetData(vtk_array(np.column_stack([q, np.zeros(len(q))]), deep=False))
    pd.SetPoints(pts)
    return pd


def build_ours(mesh, construction):
    f = ctsplines.vtkCloughTocherSplineFilter()
    f.SetInputData(mesh)
    f.SetConstruction(construction)
    f.SetSplitPointToBary()
    f.SetBoundaryModeToMidpoint()
    f.Update()
    out = f.GetOutput()
    if out.GetNumberOfCells() != 3 * mesh.GetNumberOfPolys():
        raise RuntimeError("vtkCloughTocherSplineFilter failed")
    return out


class Probe:
    """One vtkSplineParameterProbe for every call: the spline and its locator are built once."""

    def __init__(self, spline, derivatives=True):
        self.probe = ctsplines.vtkSplineParameterProbe()
        self.probe.SetSourceData(spline)
        self.probe.SetComputeDerivatives(derivatives)

    def __call__(self, q):
        self.probe.SetInputData(query_polydata(q))
        self.probe.Update()
        out = self.probe.GetOutput()
        z = vtk_to_numpy(out.GetPoints().GetData())[:, 2].copy()
        z[vtk_to_numpy(out.GetPointData().GetArray("vtkValidPointMask")) == 0] = np.nan
        return z


def build_scipy(tri, z, zx, zy):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # maxiter=0: "did not converge"; .grad is replaced below
        ip = CloughTocher2DInterpolator(tri, z, maxiter=0)
    ip.grad = np.column_stack([zx, zy])[:, None, :].copy()
    return ip


class Mesh:
    """The random Delaunay mesh, its function values and the queries."""

    def __init__(self, args):
        rng = np.random.default_rng(args.seed)
        self.uv = rng.random((args.points, 2))
        self.tri = Delaunay(self.uv)
        self.triangles = self.tri.simplices.astype(np.int64)
        self.z, self.zx, self.zy = sine_cosine(self.uv)
        side = int(round(np.sqrt(args.queries)))
        g = (np.arange(side) + 0.5) / side
        self.sorted_q = np.column_stack([np.tile(g, side), np.repeat(g, side)])  # rows of a grid
        self.random_q = rng.random((len(self.sorted_q), 2))
        self.polydata = mesh_polydata(self.uv, self.z, self.zx, self.zy, self.triangles)
        self.spline = None  # the CTi spline the construction stage leaves for the probes

    def matplotlib_build(self):
        """(seconds, interpolator): Matplotlib's construction, its TriFinder built before (not
        counted)."""
        triang = mtri.Triangulation(self.uv[:, 0], self.uv[:, 1], self.triangles)
        finder = triang.get_trifinder()
        t0 = clock()
        ip = mtri.CubicTriInterpolator(triang, self.z, kind="user", dz=(self.zx, self.zy),
                                       trifinder=finder)
        return clock() - t0, ip

    def scipy_build(self):
        return build_scipy(self.tri, self.z, self.zx, self.zy)


CTI, CTO = ctsplines.vtkCloughTocherSplineFilter.CTi, ctsplines.vtkCloughTocherSplineFilter.CTo


def ratio(peer, ours):
    # A time below the clock's resolution (user time of a --quick run) has no ratio.
    return f"{peer / ours:8.2f}" if ours > 0 else "-"


def print_rows(rows):
    print(f"\n{'stage':<34} {'ours s':>9} {'scipy s':>9} {'mpl s':>9} {'scipy/ours':>11} {'mpl/ours':>9}")
    for name, ours, s, m in rows:
        print(f"{name:<34} {ours:9.4f} {s:9.4f} {m:9.4f} {ratio(s, ours):>11} {ratio(m, ours):>9}")
    sys.stdout.flush()


def constructions(args, mesh, keep_spline):
    """Construction times and the peak memory each construction adds; printed. keep_spline:
    the CTi spline, built before the memory is measured, is left in mesh.spline for the probes
    (the order of earlier sessions' figures: the probe's first call comes after the memory
    runs)."""
    # Alternating ours and theirs so that load changes hit both, and reversing the order every
    # other round: a run's fresh pages are fast to touch only when another run freed them
    # moments before. On a VM that reports free memory to its host (virtio-balloon, 2 MiB
    # blocks), huge pages freed a few seconds earlier cost ~20x more to touch again; in a fixed
    # order, the run after Matplotlib's (CTi) always paid that.
    times = {k: float("inf") for k in ("CTi", "CTo", "scipy", "matplotlib")}
    runs = [("CTi", lambda: best(lambda: build_ours(mesh.polydata, CTI), 1)[0]),
            ("CTo", lambda: best(lambda: build_ours(mesh.polydata, CTO), 1)[0]),
            ("scipy", lambda: best(mesh.scipy_build, 1)[0]),
            ("matplotlib", lambda: mesh.matplotlib_build()[0])]
    for r in range(args.repeat):
        for name, run in runs if r % 2 == 0 else runs[::-1]:
            times[name] = min(times[name], run())
    # Our constructions above write their points into the blocks of the previous spline's points,
    # retained when it was freed (SetRetainedMemoryLimit); as a process's first construction, or
    # with nothing retained, every output page is a fresh one.
    filter_class = ctsplines.vtkCloughTocherSplineFilter
    limit = filter_class.GetRetainedMemoryLimit()
    filter_class.SetRetainedMemoryLimit(0)
    fresh = best(lambda: build_ours(mesh.polydata, CTI), args.repeat)[0]
    filter_class.SetRetainedMemoryLimit(limit)
    print_rows([("construction CTi", times["CTi"], times["scipy"], times["matplotlib"]),
                ("construction CTo", times["CTo"], times["scipy"], times["matplotlib"]),
                ("construction CTi, nothing retained", fresh, times["scipy"], times["matplotlib"])])
    spline = build_ours(mesh.polydata, CTI)
    spline_bytes = 1024 * spline.GetActualMemorySize()
    if keep_spline:
        mesh.spline = spline
    del spline
    def fresh_peak(construction):
        """As a process's first construction: nothing retained to write into."""
        ctsplines.vtkCloughTocherSplineFilter.ReleaseRetainedMemory()
        return peak_extra(lambda: build_ours(mesh.polydata, construction))[0]

    memory = {
        "CTi": fresh_peak(CTI),
        "CTo": fresh_peak(CTO),
        "scipy": peak_extra(mesh.scipy_build)[0],
        "matplotlib": peak_extra(lambda: mesh.matplotlib_build()[1])[0],
    }
    print(f"\npeak memory added by the construction [MB] (our CTi spline: {spline_bytes / 1e6:.0f} MB)")
    for name in ("CTi", "CTo", "scipy", "matplotlib"):
        print(f"  {name:<11} {memory[name] / 1e6:9.0f} MB   {memory[name] / spline_bytes:5.2f} x our spline"
              f"   {memory[name] / max(memory['CTi'], 1):5.2f} x ours (CTi)")
    sys.stdout.flush()


def probes(args, mesh):
    """Probe times, printed, and the checks that the three interpolants agree; returns the
    failed checks. Each peer's interpolator is freed before the next one is built (at 4e6
    triangles, Matplotlib's TriFinder and interpolator take 6 GB)."""
    # Ours: the first call builds the spline (in a locality order) and its locator, later calls
    # reuse them.
    spline, mesh.spline = mesh.spline, None  # this function's reference only: freed below
    if spline is None:
        spline = build_ours(mesh.polydata, CTI)
    probe = Probe(spline)
    t_first, _ = best(lambda: probe(mesh.sorted_q), 1)
    t_second, _ = best(lambda: probe(mesh.sorted_q), 1)
    t_sorted, ours_sorted = best(lambda: probe(mesh.sorted_q), args.repeat)
    positions = Probe(spline, derivatives=False)
    positions(mesh.sorted_q)
    positions(mesh.sorted_q)
    t_positions, ours_positions = best(lambda: positions(mesh.sorted_q), args.repeat)
    t_random, ours_random = best(lambda: probe(mesh.random_q), args.repeat)
    del probe, positions, spline
    cto_sorted = Probe(build_ours(mesh.polydata, CTO))(mesh.sorted_q)

    scipy_ip = mesh.scipy_build()
    s_sorted, scipy_sorted = best(lambda: scipy_ip(mesh.sorted_q), args.repeat)
    nr = min(args.scipy_random_queries, len(mesh.random_q))
    s_random = best(lambda: scipy_ip(mesh.random_q[:nr]), 1)[0] * len(mesh.random_q) / nr
    scipy_random = scipy_ip(mesh.random_q[:2000])
    del scipy_ip

    mpl_ip = mesh.matplotlib_build()[1]
    m_sorted, mpl_sorted = best(
        lambda: np.ma.filled(mpl_ip(mesh.sorted_q[:, 0], mesh.sorted_q[:, 1]), np.nan), args.repeat)
    m_random = best(lambda: mpl_ip(mesh.random_q[:, 0], mesh.random_q[:, 1]), args.repeat)[0]
    del mpl_ip

    print_rows([
        ("probe sorted (spline reused)", t_sorted, s_sorted, m_sorted),
        ("probe sorted, positions only", t_positions, s_sorted, m_sorted),
        ("probe sorted, first call", t_first, s_sorted, m_sorted),
        ("probe sorted, second call", t_second, s_sorted, m_sorted),
        ("probe random (spline reused)", t_random, s_random, m_random),
    ])
    print(f"(SciPy's random probe: {nr} points timed, scaled to {len(mesh.random_q)})")

    # The same interpolants: SciPy's is CTi, Matplotlib's is CTo (to round-off).
    failures = []
    for what, a, b in (("CTi - scipy, sorted", ours_sorted, scipy_sorted),
                       ("CTi - scipy, random", ours_random[:2000], scipy_random),
                       ("CTo - matplotlib, sorted", cto_sorted, mpl_sorted)):
        d = float(np.nanmax(np.abs(a - b)))
        ok = d <= AGREEMENT_TOL
        print(f"  [{'ok' if ok else 'FAIL'}] {what}: max |difference| {d:.2e}")
        if not ok:
            failures.append(what)
    same = np.array_equal(ours_positions, ours_sorted, equal_nan=True)
    print(f"  [{'ok' if same else 'FAIL'}] positions only: the same bits as with derivatives")
    if not same:
        failures.append("positions only")
    return failures


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--points", type=int, default=500000, help="random points (about 2x triangles)")
    ap.add_argument("--queries", type=int, default=1000000, help="probe points, sorted and random")
    ap.add_argument("--scipy-random-queries", type=int, default=20000,
                    help="SciPy's random probe is timed on this many points and scaled")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--clock", choices=tuple(CLOCKS), default="wall",
                    help="cpu: this process' CPU time (honest with one thread on a shared machine); "
                         "user: its user CPU time, without the kernel's zeroing of fresh pages "
                         "(steadier on a VM whose host takes freed memory back)")
    ap.add_argument("--stages", default="construction,probe",
                    help="construction (times and peak memory) and/or probe (times and agreement)")
    ap.add_argument("--quick", action="store_true", help="small sizes (smoke test)")
    args = ap.parse_args()
    global clock
    clock, clock_name = CLOCKS[args.clock]
    if args.quick:
        args.points, args.queries, args.scipy_random_queries, args.repeat = 2000, 10000, 2000, 1
    stages = set(args.stages.split(","))
    if not stages <= {"construction", "probe"}:
        ap.error(f"--stages: construction and/or probe, not {args.stages!r}")

    mesh = Mesh(args)
    with open("/proc/loadavg") as f:
        load = " ".join(f.read().split()[:3])
    print(f"{len(mesh.uv)} random points, {len(mesh.triangles)} triangles (SciPy's Delaunay, qhull's "
          f"order), z = sin 3x cos 2y with exact gradients; {len(mesh.sorted_q)} queries; best of "
          f"{args.repeat}")
    print(f"CTSplines threads {os.environ.get('CTSPLINES_NUM_THREADS')}, load average {load}, "
          f"{clock_name} time")
    sys.stdout.flush()
    if "construction" in stages:
        constructions(args, mesh, keep_spline="probe" in stages)
    failures = probes(args, mesh) if "probe" in stages else []
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
