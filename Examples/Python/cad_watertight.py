# SPDX-License-Identifier: GPL-3.0-or-later
"""Watertight Clough-Tocher conversion of a CAD model (study section 4), one command:

    /usr/bin/python3 Examples/Python/cad_watertight.py model.step --tolerance 1e-4 --output DIR

Samples every B-rep face edge first (vtkCADFaceSampler), converts each face (KaG by default),
stitches the faces with C0 continuity (vtkWatertightSplineStitcher) and writes into DIR:
faces.vtm (the sampled triangle meshes), splines_unstitched.vtm (each face converted on its own),
splines_stitched.vtm, stitched.vtu (one grid, interface control points merged),
gaps_unstitched.png and gaps_stitched.png (every interface curve coloured by the gap between its
two sides, before and after stitching) and prints the stage
breakdown, counts, free edges, the C0 gap and the deviation from the CAD surfaces.
"""
import argparse
import os
import sys
import time

import numpy as np

from vtkmodules.vtkCommonCore import vtkIdTypeArray  # noqa: F401  (VTK types first)
from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataWriter, vtkXMLUnstructuredGridWriter
from vtkmodules.util.numpy_support import vtk_to_numpy

from ctsplines import (constructions, vtkCADFaceSampler, vtkCloughTocherSplineFilter,
                       vtkWatertightSplineStitcher)

CUBIC = constructions.stitched()  # the constructions a CAD model can be stitched with


def field(data, name, i=0):
    a = data.GetFieldData().GetArray(name)
    return a.GetComponent(i, 0) if a is not None else float("nan")


def boundary_cubics(faces, splines):
    """{(gid a, gid b): [(4x3 control points from a to b), ...]} over the boundary macro-edges of
    every face spline (a macro-edge used by one micro-cell of its face)."""
    out = {}
    for f in range(faces.GetNumberOfBlocks()):
        gid = vtk_to_numpy(faces.GetBlock(f).GetPointData().GetArray("GlobalNodeId"))
        grid = splines.GetBlock(f)
        pts = vtk_to_numpy(grid.GetPoints().GetData())
        cells = vtk_to_numpy(grid.GetCells().GetConnectivityArray()).reshape(-1, 10)
        # VTK order: corners 0, 1 are the macro-edge's ends, points 3, 4 lie on it.
        lo = np.minimum(cells[:, 0], cells[:, 1])
        hi = np.maximum(cells[:, 0], cells[:, 1])
        keys, counts = np.unique(np.stack([lo, hi], 1), axis=0, return_counts=True)
        once = {tuple(k) for k in keys[counts == 1]}
        for c in cells:
            if (min(c[0], c[1]), max(c[0], c[1])) not in once:
                continue
            a, b = gid[c[0]], gid[c[1]]
            order = [c[0], c[3], c[4], c[1]]
            if a > b:
                a, b, order = b, a, order[::-1]
            if a != b:
                out.setdefault((a, b), []).append(pts[order])
    return out


def interface_gaps(cubics):
    """One side's curve (9 points) and the largest distance between the sides of every
    interface (edges with two or more sides)."""
    s = np.linspace(0, 1, 9)
    basis = np.stack([(1 - s) ** 3, 3 * (1 - s) ** 2 * s, 3 * (1 - s) * s ** 2, s ** 3], 1)
    lines, gaps = [], []
    for sides in cubics.values():
        if len(sides) < 2:
            continue
        curves = [basis @ p for p in sides]
        gaps.append(max(np.linalg.norm(c - curves[0], axis=1).max() for c in curves[1:]))
        lines.append(curves[0])
    return np.array(lines).reshape(-1, 9, 3), np.array(gaps)


def gap_figure(path, title, faces, lines, gaps, diag, vmax):
    """The sampled faces in grey and every interface curve coloured by its gap (relative to the
    diagonal, floored at 1e-12 so that exact zeros show), on the same scale for every figure."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    fig = plt.figure(figsize=(5.6, 4.6))
    ax = fig.add_subplot(projection="3d")
    triangles = []
    for f in range(faces.GetNumberOfBlocks()):
        block = faces.GetBlock(f)
        pts = vtk_to_numpy(block.GetPoints().GetData())
        triangles.append(pts[vtk_to_numpy(block.GetPolys().GetConnectivityArray()).reshape(-1, 3)])
    ax.add_collection3d(Poly3DCollection(np.concatenate(triangles), facecolor=(0.8, 0.8, 0.8),
                                         edgecolor="none", alpha=0.25))
    norm = LogNorm(vmin=1e-12, vmax=vmax)
    rel = np.maximum(gaps / diag, 1e-12)
    curves = Line3DCollection(lines, cmap="turbo", norm=norm, linewidths=1.6)
    curves.set_array(rel)
    ax.add_collection3d(curves)
    lo, hi = lines.reshape(-1, 3).min(0), lines.reshape(-1, 3).max(0)
    centre, half = (lo + hi) / 2, (hi - lo).max() / 2
    for axis, c in zip("xyz", centre):
        getattr(ax, f"set_{axis}lim")(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_axis_off()
    ax.set_title(f"{title}\nmax interface gap {gaps.max() / diag:.2g} of the diagonal",
                 fontsize=10)
    fig.colorbar(curves, ax=ax, shrink=0.65, pad=0.02,
                 label="interface gap / diagonal (0 drawn at 1e-12)")
    fig.tight_layout()
    fig.savefig(path, dpi=90, bbox_inches="tight")
    plt.close(fig)


def write(obj, path, multiblock):
    w = vtkXMLMultiBlockDataWriter() if multiblock else vtkXMLUnstructuredGridWriter()
    w.SetFileName(path)
    w.SetInputData(obj)
    w.SetDataModeToAppended()
    w.Write()


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("model", help="STEP (.step, .stp) or IGES (.iges, .igs) file")
    p.add_argument("--tolerance", type=float, default=1e-4, help="relative to the diagonal")
    p.add_argument("--aspect-ratio", type=float, default=0.0, help="3D aspect bound, 0 = none")
    p.add_argument("--construction", default="KaG", choices=CUBIC)
    p.add_argument("--output", default=os.path.join("ctsplines-output", "cad_watertight"))
    p.add_argument("--g1", action="store_true",
                   help="G1 at the nodes and span midpoints of tangent interfaces (RestoreG1)")
    p.add_argument("--no-figures", action="store_true")
    args = p.parse_args()
    os.makedirs(args.output, exist_ok=True)

    t0 = time.perf_counter()
    sampler = vtkCADFaceSampler()
    sampler.SetFileName(args.model)
    sampler.SetTolerance(args.tolerance)
    sampler.SetAspectRatio(args.aspect_ratio)
    sampler.SetConstruction(constructions.value(args.construction))  # refined for the stitched spline
    sampler.SetRestoreG1(args.g1)
    sampler.Update()
    faces = sampler.GetOutput()
    if faces.GetNumberOfBlocks() == 0:
        print("cad_watertight: nothing read from", args.model, file=sys.stderr)
        return 1
    stitcher = vtkWatertightSplineStitcher()
    stitcher.SetInputConnection(sampler.GetOutputPort())
    stitcher.SetConstruction(constructions.value(args.construction))
    stitcher.SetSurfaceSource(sampler)
    stitcher.Update()
    total = time.perf_counter() - t0
    stitched = stitcher.GetOutputDataObject(0)
    merged = stitcher.GetOutputDataObject(1)

    # The same faces converted on their own, for the gaps before stitching.
    unstitched = stitched.NewInstance()
    unstitched.SetNumberOfBlocks(faces.GetNumberOfBlocks())
    for f in range(faces.GetNumberOfBlocks()):
        ct = vtkCloughTocherSplineFilter()
        ct.SetInputData(faces.GetBlock(f))
        ct.SetConstruction(constructions.value(args.construction))
        ct.Update()
        unstitched.SetBlock(f, ct.GetOutput())

    diag = field(faces, "Diagonal")
    triangles = sum(faces.GetBlock(f).GetNumberOfCells() for f in range(faces.GetNumberOfBlocks()))
    stages = [(name, field(faces, "StageTimes", i))
              for i, name in enumerate(("read", "edges", "loops", "tangent planes", "faces"))]
    stages += [(name, field(merged, "StageTimes", i))
               for i, name in enumerate(("splines", "stitch", "merge", "deviation"))]
    print(f"{os.path.basename(args.model)}: tolerance {args.tolerance:g} of the diagonal {diag:.4g}, "
          f"construction {args.construction}")
    print(f"  faces {faces.GetNumberOfBlocks()}, B-rep edges {field(faces, 'NumberOfBRepEdges'):.0f}, "
          f"vertices {field(faces, 'NumberOfBRepVertices'):.0f}, triangles {triangles}, "
          f"Bezier patches {merged.GetNumberOfCells()}, control points {merged.GetNumberOfPoints()}")
    print(f"  measured model gaps (absolute): vertices moved to their surfaces' mean "
          f"{field(faces, 'MaxVertexGap'):.3g}, between faces along edges "
          f"{field(faces, 'MaxEdgeGap'):.3g}")
    print(f"  free edges {field(merged, 'NumberOfFreeEdges'):.0f}, non-manifold edges "
          f"{field(merged, 'NumberOfNonManifoldEdges'):.0f}, max C0 gap {field(merged, 'MaxC0Gap'):g} "
          f"(before stitching {field(merged, 'MaxGapBeforeStitching'):.3g})")
    print(f"  deviation from the surfaces (relative): max {field(merged, 'MaxDeviation'):.3g}, "
          f"RMS {field(merged, 'RMSDeviation'):.3g}")
    print(f"  G1 angle [degrees]: max {field(merged, 'MaxG1Angle'):.3g} over all interfaces, "
          f"{field(merged, 'MaxG1AngleTangent'):.3g} over the "
          f"{field(merged, 'NumberOfTangentInterfaceEdges'):.0f} tangent ones")
    print("  stages [s]: " + ", ".join(f"{n} {t:.3f}" for n, t in stages) + f"; end to end {total:.3f}")

    write(faces, os.path.join(args.output, "faces.vtm"), True)
    write(unstitched, os.path.join(args.output, "splines_unstitched.vtm"), True)
    write(stitched, os.path.join(args.output, "splines_stitched.vtm"), True)
    write(merged, os.path.join(args.output, "stitched.vtu"), False)

    if not args.no_figures:
        import matplotlib
        matplotlib.use("Agg")

        before = interface_gaps(boundary_cubics(faces, unstitched))
        after = interface_gaps(boundary_cubics(faces, stitched))
        if len(after[1]) == 0:
            print("  no interfaces between faces: no gap figures")
        else:
            vmax = max(1e-3, before[1].max() / diag)
            gap_figure(os.path.join(args.output, "gaps_unstitched.png"),
                       "each face converted on its own", faces, *before, diag, vmax)
            gap_figure(os.path.join(args.output, "gaps_stitched.png"), "stitched (watertight)",
                       faces, *after, diag, vmax)
            print(f"  interface gaps before stitching: max {before[1].max() / diag:.3g}, "
                  f"after: max {after[1].max() / diag:.3g} ({len(after[1])} interface "
                  "macro-edges)")
    print("  written to", args.output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
