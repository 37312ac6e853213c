# SPDX-License-Identifier: GPL-3.0-or-later
"""What ParaView does after each Apply: its data information (ranges of every array, bounds).

Run by pvpython: paraview_information_benchmark.py PLUGIN [--points 707000] [--level 4]

Builds SampledSurfaceSource (Franke, RandomDelaunay) -> CloughTocherSplineFilter ->
BezierTriangleTessellator and prints, per stage, what Apply costs: UpdatePipeline and the data
information, with the ranges the filters store (CTSplinesArrayRanges.h). Then the data
information again (vtkPVDataInformation) after every array and the points are marked modified:
VTK computes every range itself, as it does for filters that store none, and the bounds.
Wall-clock seconds, one run each.
"""
import argparse
import time

from paraview import simple
from paraview.modules.vtkRemotingCore import vtkPVDataInformation
from vtkmodules.vtkCommonDataModel import vtkPointSet


def information_seconds(data):
    start = time.perf_counter()
    vtkPVDataInformation().CopyFromObject(data)
    return time.perf_counter() - start


def mark_modified(data):
    """Every array's stored ranges and the points' bounds become stale."""
    arrays = [data.GetPoints().GetData()] if isinstance(data, vtkPointSet) else []
    for attributes in (data.GetPointData(), data.GetCellData()):
        arrays += [attributes.GetArray(i) for i in range(attributes.GetNumberOfArrays())]
    for a in arrays:
        if a is not None:
            a.Modified()
    if isinstance(data, vtkPointSet):
        data.GetPoints().Modified()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("plugin", help="path of CTSplines.so")
    parser.add_argument("--points", type=int, default=707000,
                        help="random points of the source (about twice as many triangles)")
    parser.add_argument("--level", type=int, default=4, help="tessellation SubdivisionLevel")
    args = parser.parse_args()
    simple.LoadPlugin(args.plugin, remote=False)
    source = simple.SampledSurfaceSource(Surface="Franke", Domain="RandomDelaunay",
                                         Resolution=args.points, Seed=1)
    spline = simple.CloughTocherSplineFilter(Input=source)
    tessellator = simple.BezierTriangleTessellator(Input=spline, SubdivisionLevel=args.level)
    print("%-12s %10s %10s %10s %26s" % ("stage", "points", "cells", "apply",
                                         "information without stored"))
    for name, proxy in (("source", source), ("spline", spline), ("tessellator", tessellator)):
        start = time.perf_counter()
        proxy.UpdatePipeline()
        info = proxy.GetDataInformation()
        points, cells = info.GetNumberOfPoints(), info.GetNumberOfCells()
        apply = time.perf_counter() - start
        data = proxy.GetClientSideObject().GetOutputDataObject(0)
        mark_modified(data)
        computed = information_seconds(data)
        print("%-12s %10d %10d %9.2fs %25.2fs" % (name, points, cells, apply, computed))

if __name__ == "__main__":
    main()
