# SPDX-License-Identifier: GPL-3.0-or-later
"""Run by pvpython or pvbatch: plugin_pipeline.py PLUGIN SOURCE_DIR.

PLUGIN is the path of CTSplines.so, or "autoload" when PV_PLUGIN_PATH names its folder (then
ParaView loads it at start-up and no LoadPlugin is needed).
Checks that every class of CTSplines::Filters has a proxy whose properties are all documented,
and runs SampledSurfaceSource -> CloughTocherSplineFilter -> BezierTriangleTessellator ->
BezierCurvatureFilter -> SplineContinuityFilter on a quadratic, which the CTi construction
reproduces exactly: counts follow the layout formulas, the tessellation lies on the quadratic,
the Gaussian curvature is the quadratic's and the spline is C1 across every edge."""
import glob
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
from paraview import servermanager
import paraview.simple as simple
from vtkmodules.util.numpy_support import vtk_to_numpy

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


plugin, source_dir = sys.argv[1], sys.argv[2]
if plugin != "autoload":
    # Without ns the new proxies become functions of paraview.simple itself.
    simple.LoadPlugin(plugin, remote=False)
pxm = servermanager.ProxyManager()

# Every public class (Filters/vtk*.h) has a proxy named after it, in the CT Splines menu, with
# documentation on the proxy and on every property.
classes = sorted(os.path.basename(h)[:-2] for h in glob.glob(os.path.join(source_dir, "Filters",
                                                                           "vtk*.h")))
xml_dir = os.path.join(source_dir, "module", "paraview", "CTSplines")
for cls in classes:
    name = cls[3:]
    proxy = pxm.GetPrototypeProxy("filters", name) or pxm.GetPrototypeProxy("sources", name)
    check(proxy is not None, f"no proxy {name} for {cls}")
    path = os.path.join(xml_dir, cls + ".xml")
    check(os.path.exists(path), f"no {path}")
    if not os.path.exists(path):
        continue
    root = ET.parse(path).getroot()
    for sp in root.iter("SourceProxy"):
        check(sp.get("class") == cls and sp.get("name") == name, f"{path}: names {sp.attrib}")
        check(sp.find("Documentation") is not None, f"{name}: no documentation")
        check(sp.find("Hints/ShowInMenu[@category='CT Splines']") is not None,
              f"{name}: not in the CT Splines menu")
        for prop in sp:
            if prop.tag.endswith("Property"):
                check(prop.find("Documentation") is not None,
                      f"{name}.{prop.get('name')}: no documentation")

# Quadratic z = 0.5 x^2 - 0.3 x y + 0.8 y^2 + 0.1 x on an r x r grid.
r, level = 4, 4
source = simple.SampledSurfaceSource(Surface="Quadratic", Domain="Grid", Resolution=r)
spline = simple.CloughTocherSplineFilter(Input=source, Construction="CTi")
check(spline.UVArray == "UV" and spline.DuArray == "dFdu" and spline.DvArray == "dFdv"
      and spline.EdgeGradientsArray == "EdgeGradients",
      f"array defaults {spline.UVArray} {spline.DuArray} {spline.DvArray} "
      f"{spline.EdgeGradientsArray}")
tess = simple.BezierTriangleTessellator(Input=spline, SubdivisionLevel=level)

mesh = servermanager.Fetch(source)
bezier = servermanager.Fetch(spline)
surface = servermanager.Fetch(tess)
T, V = 2 * r * r, (r + 1) ** 2
E = 3 * r * r + 2 * r
check(mesh.GetNumberOfCells() == T and mesh.GetNumberOfPoints() == V,
      f"input {mesh.GetNumberOfCells()} cells {mesh.GetNumberOfPoints()} points")
# Cubic CT: per macro-triangle 3 micro-triangles; control points: vertices, 2 per macro-edge,
# and 10 inside each macro-triangle (6 on micro-edges, the split point, 3 micro interiors).
check(bezier.GetNumberOfCells() == 3 * T, f"spline cells {bezier.GetNumberOfCells()}")
check(bezier.GetNumberOfPoints() == V + 2 * E + 10 * T,
      f"control points {bezier.GetNumberOfPoints()} != {V + 2 * E + 10 * T}")
# Tessellation of the micro-triangle mesh (V + T vertices, E + 3T edges, 3T faces).
Vb, Eb, Tb = V + T, E + 3 * T, 3 * T
check(surface.GetNumberOfCells() == Tb * level * level, f"tessellation cells "
      f"{surface.GetNumberOfCells()}")
expected_points = Vb + Eb * (level - 1) + Tb * (level - 1) * (level - 2) // 2
check(surface.GetNumberOfPoints() == expected_points,
      f"tessellation points {surface.GetNumberOfPoints()} != {expected_points}")
p = vtk_to_numpy(surface.GetPoints().GetData())
x, y = p[:, 0], p[:, 1]
z = 0.5 * x * x - 0.3 * x * y + 0.8 * y * y + 0.1 * x
err = np.max(np.abs(p[:, 2] - z))
check(err < 1e-12, f"quadratic not reproduced: {err}")

# SplineParameterProbe at the grid's own points gives the quadratic too.
probe = simple.SplineParameterProbe(Input=source, Source=spline)
probed = servermanager.Fetch(probe)
q = vtk_to_numpy(probed.GetPoints().GetData())
err = np.max(np.abs(q[:, 2] - (0.5 * q[:, 0] ** 2 - 0.3 * q[:, 0] * q[:, 1] + 0.8 * q[:, 1] ** 2
                               + 0.1 * q[:, 0])))
check(err < 1e-12, f"probe off the quadratic: {err}")

if hasattr(simple, "BezierCurvatureFilter"):
    curv = simple.BezierCurvatureFilter(Input=spline, SubdivisionLevel=level)
    c = servermanager.Fetch(curv)
    cp = vtk_to_numpy(c.GetPoints().GetData())
    K = vtk_to_numpy(c.GetPointData().GetArray("Gauss_Curvature"))
    fx = cp[:, 0] - 0.3 * cp[:, 1] + 0.1
    fy = -0.3 * cp[:, 0] + 1.6 * cp[:, 1]
    exact = (1.0 * 1.6 - 0.3 ** 2) / (1 + fx * fx + fy * fy) ** 2
    err = np.max(np.abs(K - exact))
    check(err < 1e-9, f"Gaussian curvature off by {err}")
    check(c.GetNumberOfCells() == Tb * level * level, "curvature cells")

if hasattr(simple, "SplineContinuityFilter"):
    cont = simple.SplineContinuityFilter(Input=spline)
    lines = servermanager.Fetch(cont)
    check(lines.GetNumberOfCells() == Eb, f"continuity edges {lines.GetNumberOfCells()} != {Eb}")
    kind = vtk_to_numpy(lines.GetCellData().GetArray("EdgeKind"))
    c1 = vtk_to_numpy(lines.GetCellData().GetArray("C1Jump"))
    g1 = vtk_to_numpy(lines.GetCellData().GetArray("G1Angle"))
    check(np.sum(kind == 2) == 4 * r, f"boundary edges {np.sum(kind == 2)}")
    check(np.sum(kind == 1) == 3 * T, f"micro-edges {np.sum(kind == 1)}")
    check(np.max(c1) < 1e-12, f"C1 jump {np.max(c1)}")
    # Degrees from acos of unit normals' dot product: ~1e-6 is rounding.
    check(np.max(g1) < 1e-4, f"G1 angle {np.max(g1)}")

print(f"{len(classes)} classes checked, {len(failures)} failures")
sys.exit(1 if failures else 0)
