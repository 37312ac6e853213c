# SPDX-License-Identifier: GPL-3.0-or-later
"""Cost of VTK's SMP backend on many small filter calls, and threads created.

VTK 9.2's STDThread backend starts and joins a new set of threads on every vtkSMPTools::For call
that it splits. The module's loops (Filters/CTSplinesSMP.h) run serially below a grain size and
otherwise on a pool of threads started once
(CTSPLINES_NUM_THREADS, else VTK's count). This program prints, for
three settings:

- Sequential: VTK's Sequential backend, the module following it (1 thread);
- STDThread: VTK's STDThread backend with --threads, the module following it;
- default: what the Python package sets on import: VTK's backend untouched (Sequential here),
  the module on --threads threads (in the CLI runs: one per core);

these figures:

- the wall time of --calls small spline filter calls (and tessellator, probe) on a
  --triangles-triangle mesh, best of --repeat;
- the threads created by those calls (clone/clone3 system calls counted by strace, in a child
  process; "n/a" without strace);
- optionally the CLI conversion of CAD models (`python3 -m ctsplines convert`, writing included)
  under each backend (VTK_SMP_BACKEND_IN_USE), best of --repeat, with its thread count.

  /usr/bin/python3 Testing/Benchmarks/smp_overhead_benchmark.py [MODEL.step ...]
      [--calls 1000] [--triangles 50] [--repeat 5] [--threads 2]

The large-loop side (2 threads against 1 at 1e6 triangles) is ctsplines_benchmark's:
  ctsplines_benchmark --sizes 1e6 --threads 2 --stages spline,tessellate,probe
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

import ctsplines
from vtkmodules.vtkCommonCore import vtkSMPTools
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkCommonCore import vtkPoints

STAGES = ("spline", "tessellate", "probe")


def small_mesh(triangles, seed=1):
    """A functional mesh of about `triangles` triangles: a regular grid of the unit square
    (two triangles per cell), z = sin(3x) cos(2y)."""
    k = max(1, int(round(np.sqrt(triangles / 2.0))))
    g = np.linspace(0.0, 1.0, k + 1)
    x, y = np.meshgrid(g, g, indexing="ij")
    xy = np.column_stack([x.ravel(), y.ravel()])
    tri = []
    for i in range(k):
        for j in range(k):
            a, b = i * (k + 1) + j, (i + 1) * (k + 1) + j
            tri += [(a, b, b + 1), (a, b + 1, a + 1)]
    z = np.sin(3 * xy[:, 0]) * np.cos(2 * xy[:, 1])
    zx = 3 * np.cos(3 * xy[:, 0]) * np.cos(2 * xy[:, 1])
    zy = -2 * np.sin(3 * xy[:, 0]) * np.sin(2 * xy[:, 1])
    return ctsplines.functional_mesh(xy, np.array(tri), z, zx, zy)


def probe_points(n=200, seed=2):
    rng = np.random.default_rng(seed)
    uv = rng.uniform(0.0, 1.0, (n, 2))
    pts = vtkPoints()
    pts.SetDataTypeToDouble()
    for u, v in uv:
        pts.InsertNextPoint(u, v, 0.0)
    pd = vtkPolyData()
    pd.SetPoints(pts)
    return pd


def pipeline(mesh):
    """The three filters, connected: spline -> tessellator (level 4), spline -> probe."""
    spline = ctsplines.vtkCloughTocherSplineFilter()
    spline.SetInputData(mesh)
    tess = ctsplines.vtkBezierTriangleTessellator()
    tess.SetInputConnection(spline.GetOutputPort())
    tess.SetSubdivisionLevel(4)
    probe = ctsplines.vtkSplineParameterProbe()
    probe.SetInputData(probe_points())
    probe.SetSourceConnection(spline.GetOutputPort())
    return {"spline": spline, "tessellate": tess, "probe": probe}


def run_calls(filters, stage, calls):
    """calls executions of one stage (its upstream is up to date; only this filter re-runs)."""
    f = filters[stage]
    f.Update()
    t0 = time.perf_counter()
    for _ in range(calls):
        f.Modified()
        f.Update()
    return time.perf_counter() - t0


MODES = ("Sequential", "STDThread", "default")


def set_backend(mode, threads):
    """VTK's backend and the module's thread count of a mode (see the description)."""
    backend = "STDThread" if mode == "STDThread" else "Sequential"
    if not vtkSMPTools.SetBackend(backend):
        sys.exit(f"VTK has no {backend} SMP backend")
    vtkSMPTools.Initialize(threads if backend == "STDThread" else 1)
    if mode == "default":
        os.environ["CTSPLINES_NUM_THREADS"] = str(threads)
    else:
        os.environ.pop("CTSPLINES_NUM_THREADS", None)


def mode_environment(mode, threads):
    """The environment giving a CLI run that mode."""
    env = dict(os.environ, VTK_SMP_MAX_THREADS=str(threads))
    env.pop("VTK_SMP_BACKEND_IN_USE", None)
    env.pop("CTSPLINES_NUM_THREADS", None)
    if mode != "default":
        env["VTK_SMP_BACKEND_IN_USE"] = mode
    return env


def child(args):
    """In a child process (under strace): the calls of one stage under one backend."""
    set_backend(args.backend, args.threads)
    filters = pipeline(small_mesh(args.triangles))
    run_calls(filters, args.stage, args.calls)


def strace_clones(cmd, env=None):
    """Threads created by a command: clone/clone3 calls counted by strace -f (None without it)."""
    if shutil.which("strace") is None:
        return None
    with tempfile.NamedTemporaryFile("r", suffix=".txt") as log:
        subprocess.run(["strace", "-f", "-c", "-o", log.name, "-e", "trace=clone,clone3"] + cmd,
                       check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        text = log.read()
    total = 0
    for line in text.splitlines():
        m = re.match(r"\s*[\d.]+\s+[\d.]+\s+\d+\s+(\d+)\s+(?:\d+\s+)?(clone3?)\s*$", line)
        if m:
            total += int(m.group(1))
    return total


def small_calls(args):
    filters = pipeline(small_mesh(args.triangles))
    n = filters["spline"].GetInputDataObject(0, 0).GetNumberOfCells()
    print(f"{args.calls} calls per stage on a {n}-triangle mesh, best of {args.repeat} "
          f"(spread: worst/best), STDThread with {args.threads} threads")
    print(f"{'stage':<11} {'mode':<11} {'ms/call':>9} {'spread':>7} {'threads':>8}")
    best = {}
    for stage in STAGES:
        for backend in MODES:
            set_backend(backend, args.threads)
            times = [run_calls(filters, stage, args.calls) for _ in range(args.repeat)]
            clones = strace_clones([sys.executable, os.path.abspath(__file__), "--child",
                                    "--backend", backend, "--stage", stage, "--calls",
                                    str(args.calls), "--triangles", str(args.triangles),
                                    "--threads", str(args.threads)])
            best[stage, backend] = min(times)
            print(f"{stage:<11} {backend:<11} {1e3 * min(times) / args.calls:9.3f} "
                  f"{max(times) / min(times):7.2f} {'n/a' if clones is None else clones:>8}")
        print(f"{stage:<11} STDThread/Sequential: "
              f"{best[stage, 'STDThread'] / best[stage, 'Sequential']:.2f}, default/Sequential: "
              f"{best[stage, 'default'] / best[stage, 'Sequential']:.2f}")


def cad_conversions(args):
    print(f"\nCLI conversion (writing included), best of {args.repeat}")
    print(f"{'model':<28} {'mode':<11} {'s':>7} {'spread':>7} {'threads':>8}")
    with tempfile.TemporaryDirectory() as folder:
        for model in args.models:
            for backend in MODES:
                env = mode_environment(backend, args.threads)
                cmd = [sys.executable, "-m", "ctsplines", "convert", model, "-o",
                       os.path.join(folder, "out.vtm")]
                times = []
                for _ in range(args.repeat):
                    t0 = time.perf_counter()
                    subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL)
                    times.append(time.perf_counter() - t0)
                clones = strace_clones(cmd, env)
                print(f"{os.path.basename(model):<28} {backend:<11} {min(times):7.3f} "
                      f"{max(times) / min(times):7.2f} {'n/a' if clones is None else clones:>8}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("models", nargs="*", help="STEP/IGES models for the CLI conversion")
    p.add_argument("--calls", type=int, default=1000)
    p.add_argument("--triangles", type=int, default=50)
    p.add_argument("--repeat", type=int, default=5)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--backend", default="STDThread", choices=MODES, help=argparse.SUPPRESS)
    p.add_argument("--stage", default="spline", choices=STAGES, help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.child:
        child(args)
        return
    small_calls(args)
    if args.models:
        cad_conversions(args)


if __name__ == "__main__":
    main()
