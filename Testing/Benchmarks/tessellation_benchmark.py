# SPDX-License-Identifier: GPL-3.0-or-later
"""Triangles needed for a chordal error: vtkBezierTriangleTessellator's adaptive mode against its
uniform mode, on the demo's spline (Franke's function on 300 random points, KaG) and on converted
CAD models (STEP files given on the command line, e.g. gmsh-doc's component8.step).

For each relative tolerance the adaptive tessellation is measured, then the smallest uniform
level whose measured error is as small. The error of a tessellation is the largest distance from
the points of a dense reference tessellation (uniform, level --reference) to its triangles
(vtkDistancePolyDataFilter), relative to the bounding-box diagonal: one measure for both modes.

  python3 Testing/Benchmarks/tessellation_benchmark.py [MODEL.step ...] [--reference 24]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersGeneral import vtkDistancePolyDataFilter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

import ctsplines

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Examples",
                                "Python"))
import example_common as ex  # noqa: E402


def demo_spline():
    """The demo's spline (`python3 -m ctsplines demo`: seed 1, KaG)."""
    return ex.spline(ex.source("Franke", "RandomDelaunay", 300), "KaG").GetOutput()


def cad_spline(step, folder):
    out = os.path.join(folder, "model.vtm")
    subprocess.run([sys.executable, "-m", "ctsplines", "convert", step, "-o", out], check=True,
                   capture_output=True)
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(folder, "model.vtu"))
    reader.Update()
    return reader.GetOutput()


def tessellate(spline, level, chordal=0.0):
    t = ctsplines.vtkBezierTriangleTessellator()
    t.SetInputData(spline)
    t.SetSubdivisionLevel(level)
    t.SetChordalTolerance(chordal)
    t.SetSplitSharpEdges(False)
    start = time.perf_counter()
    t.Update()
    return t.GetOutput(), time.perf_counter() - start


def error(mesh, reference_points, diagonal):
    samples = vtkPolyData()
    samples.SetPoints(vtkPoints())
    samples.GetPoints().SetData(numpy_to_vtk(reference_points, deep=True))
    vertices = vtkCellArray()  # the filter wants cells
    ids = np.arange(len(reference_points), dtype=np.int64)
    vertices.SetData(numpy_to_vtkIdTypeArray(np.arange(len(ids) + 1, dtype=np.int64), deep=True),
                     numpy_to_vtkIdTypeArray(ids, deep=True))
    samples.SetVerts(vertices)
    distance = vtkDistancePolyDataFilter()
    distance.SetInputData(0, samples)
    distance.SetInputData(1, mesh)
    distance.SignedDistanceOff()
    distance.ComputeSecondDistanceOff()
    distance.Update()
    d = vtk_to_numpy(distance.GetOutput().GetPointData().GetArray("Distance"))
    return float(np.abs(d).max()) / diagonal


def compare(name, spline, tolerances, reference_level, max_level):
    diagonal = spline.GetLength()
    reference, _ = tessellate(spline, reference_level)
    points = vtk_to_numpy(reference.GetPoints().GetData())
    # Points inside the reference's triangles too (its vertices lie on every coarser mesh's
    # lattice for levels dividing it): the centroids.
    tri = vtk_to_numpy(reference.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    samples = np.vstack([points, points[tri].mean(axis=1)])
    rng = np.random.default_rng(5)
    if len(samples) > 100000:
        samples = samples[rng.choice(len(samples), 100000, replace=False)]
    print(f"\n{name}: {spline.GetNumberOfCells()} Bezier triangles, reference level "
          f"{reference_level} ({len(samples)} sample points)")
    print("| tolerance | adaptive triangles | adaptive error | time | uniform level | "
          "uniform triangles | uniform error | uniform / adaptive |")
    print("|---|---|---|---|---|---|---|---|")
    uniform_errors = {}
    for tol in tolerances:
        adaptive, seconds = tessellate(spline, max_level, tol)
        e_adaptive = error(adaptive, samples, diagonal)
        level = 1
        while True:
            if level not in uniform_errors:
                mesh, _ = tessellate(spline, level)
                uniform_errors[level] = (error(mesh, samples, diagonal), mesh.GetNumberOfCells())
            if uniform_errors[level][0] <= e_adaptive or level >= reference_level // 2:
                break  # (at reference / 2 the reference cannot tell: marked with ">=")
            level += 1
        e_uniform, n_uniform = uniform_errors[level]
        capped = ">= " if e_uniform > e_adaptive else ""
        print(f"| {tol:.0e} | {adaptive.GetNumberOfCells():,} | {e_adaptive:.2e} | "
              f"{seconds:.2f} s | {capped}{level} | {capped}{n_uniform:,} | {e_uniform:.2e} | "
              f"{capped}{n_uniform / adaptive.GetNumberOfCells():.2f} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("models", nargs="*", help="STEP/IGES models to convert and compare")
    parser.add_argument("--reference", type=int, default=24, help="level of the reference")
    parser.add_argument("--max-level", type=int, default=16, help="adaptive mode's largest level")
    parser.add_argument("--tolerances", type=float, nargs="+", default=[1e-3, 3e-4, 1e-4])
    args = parser.parse_args()
    compare("demo spline (Franke, 300 random points, KaG)", demo_spline(), args.tolerances,
            args.reference, args.max_level)
    for step in args.models:
        with tempfile.TemporaryDirectory() as folder:
            compare(os.path.basename(step), cad_spline(step, folder), args.tolerances,
                    args.reference, args.max_level)


if __name__ == "__main__":
    main()
