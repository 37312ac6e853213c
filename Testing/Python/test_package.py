# SPDX-License-Identifier: GPL-3.0-or-later
"""The Python package: interoperation with `import vtk`, numpy helpers, facts measured through
Python (quadratic precision, interpolation), errors surfacing in Python."""
import subprocess
import sys
import unittest

import numpy as np
import vtk

import ctsplines
from ctsplines import arrays


def quadratic(x, y):
    z = 0.5 * x * x - 0.3 * x * y + 0.8 * y * y + 0.1 * x
    return z, x - 0.3 * y + 0.1, -0.3 * x + 1.6 * y


def grid(n):
    xs = np.linspace(0.0, 1.0, n + 1)
    x, y = np.meshgrid(xs, xs)
    xy = np.column_stack([x.ravel(), y.ravel()])
    tris = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            tris += [[a, a + 1, a + n + 2], [a, a + n + 2, a + n + 1]]
    return xy, np.array(tris)


class PackageTest(unittest.TestCase):
    def convert(self, mesh, construction="CTi"):
        f = ctsplines.vtkCloughTocherSplineFilter()
        getattr(f, "SetConstructionTo" + construction)()
        f.SetInputData(mesh)
        f.Update()
        return f.GetOutput()

    def test_import_leaves_numpy_alone(self):
        # numpy (half of the import time) loads with the helpers that use it, not with the
        # package: the command line and the filters do without.
        code = ("import sys, ctsplines; assert 'numpy' not in sys.modules, 'numpy imported'; "
                "ctsplines.functional_mesh; assert 'numpy' in sys.modules")
        subprocess.run([sys.executable, "-c", code], check=True)
        self.assertIs(ctsplines.mesh_from_arrays, arrays.mesh_from_arrays)
        with self.assertRaises(AttributeError):
            ctsplines.no_such_name  # noqa: B018

    def test_block_index_quotes_names_without_xml_sax(self):
        # The .vtm index names each block as written by ctsplines.io (characters XML must
        # escape included), and writing it leaves xml.sax and its urllib/email imports alone
        # (a quarter of a second of a small model's conversion).
        code = r"""
import os, sys, tempfile
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet, vtkMultiBlockDataSet, vtkPolyData
from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataReader
from ctsplines import io
names = ['a "b" & <c>', "tab\there\nline", "plain"]
blocks = vtkMultiBlockDataSet()
for i, name in enumerate(names):
    blocks.SetBlock(i, vtkPolyData())
    blocks.GetMetaData(i).Set(vtkCompositeDataSet.NAME(), name)
folder = tempfile.mkdtemp()
with io.VTKMessages() as messages:
    io.write(blocks, os.path.join(folder, "out.vtm"), messages)
assert "xml.sax" not in sys.modules and "urllib.request" not in sys.modules, "xml.sax imported"
reader = vtkXMLMultiBlockDataReader()
reader.SetFileName(os.path.join(folder, "out.vtm"))
reader.Update()
got = [reader.GetOutput().GetMetaData(i).Get(vtkCompositeDataSet.NAME()) for i in range(3)]
assert got == names, got
"""
        subprocess.run([sys.executable, "-c", code], check=True)

    def test_interoperates_with_vtk(self):
        xy, tris = grid(3)
        z, zx, zy = quadratic(xy[:, 0], xy[:, 1])
        mesh = ctsplines.functional_mesh(xy, tris, z, zx, zy)
        self.assertIsInstance(mesh, vtk.vtkPolyData)
        # A plain VTK filter upstream, ours downstream, a plain VTK filter after.
        clean = vtk.vtkPassThrough()
        clean.SetInputData(mesh)
        f = ctsplines.vtkCloughTocherSplineFilter()
        f.SetInputConnection(clean.GetOutputPort())
        geometry = vtk.vtkGeometryFilter()
        geometry.SetInputConnection(f.GetOutputPort())
        geometry.Update()
        self.assertIsInstance(f.GetOutput(), vtk.vtkUnstructuredGrid)
        self.assertEqual(f.GetOutput().GetNumberOfCells(), 3 * len(tris))
        self.assertEqual(f.GetOutput().GetCellType(0), vtk.VTK_BEZIER_TRIANGLE)

    def test_control_points_reproduce_a_quadratic(self):
        # Quadratic precision: every control point of the cubic spline of a quadratic lies on the
        # quadratic's own Bézier net, so the control points' z follow from their (x, y) by the
        # blossom; here checked through VTK's Bézier evaluation at the cells' centres.
        xy, tris = grid(4)
        z, zx, zy = quadratic(xy[:, 0], xy[:, 1])
        for construction in ("CTo", "CTi", "MGo", "MGi"):
            mesh = ctsplines.functional_mesh(
                xy, tris, z, zx, zy, edge_gradients=self.edge_gradients(xy, tris)
            )
            out = self.convert(mesh, construction)
            cell = vtk.vtkGenericCell()
            worst = 0.0
            for c in range(out.GetNumberOfCells()):
                out.GetCell(c, cell)
                x = [0.0, 0.0, 0.0]
                w = [0.0] * 10
                cell.EvaluateLocation(vtk.reference(0), [0.3, 0.2, 0.0], x, w)
                worst = max(worst, abs(x[2] - quadratic(x[0], x[1])[0]))
            self.assertLess(worst, 1e-13, construction)

    @staticmethod
    def edge_gradients(xy, tris):
        g = np.zeros((len(tris), 3, 2))
        for l in range(3):
            mid = 0.5 * (xy[tris[:, l]] + xy[tris[:, (l + 1) % 3]])
            _, gx, gy = quadratic(mid[:, 0], mid[:, 1])
            g[:, l, 0], g[:, l, 1] = gx, gy
        return g

    def test_vertex_control_points_interpolate(self):
        xy, tris = grid(3)
        z, zx, zy = quadratic(xy[:, 0], xy[:, 1])
        out = self.convert(ctsplines.functional_mesh(xy, tris, z, zx, zy))
        pts = arrays.points(out)
        # Vertex control points come first, one per input point.
        np.testing.assert_allclose(pts[: len(xy), :2], xy, atol=1e-15)
        np.testing.assert_allclose(pts[: len(xy), 2], z, atol=1e-15)
        conn = arrays.cells(out)
        self.assertEqual(conn.shape, (3 * len(tris), 10))

    def test_errors_reach_python(self):
        xy, tris = grid(2)
        z, zx, zy = quadratic(xy[:, 0], xy[:, 1])
        mesh = ctsplines.functional_mesh(xy, tris, z, zx, zy)
        mesh.GetPointData().RemoveArray("dFdv")
        f = ctsplines.vtkCloughTocherSplineFilter()
        f.SetInputData(mesh)
        messages = []
        f.AddObserver("ErrorEvent", lambda obj, ev: messages.append(ev))
        f.GetExecutive().AddObserver("ErrorEvent", lambda obj, ev: None)
        f.Update()
        self.assertTrue(messages)
        self.assertEqual(f.GetOutput().GetNumberOfCells(), 0)

    def test_helpers_check_shapes(self):
        xy, tris = grid(2)
        with self.assertRaises(ValueError):
            ctsplines.mesh_from_arrays(xy, tris[:, :2], np.zeros((9, 3)), np.zeros((9, 3)), np.zeros((9, 3)))
        with self.assertRaises(ValueError):
            ctsplines.mesh_from_arrays(xy, tris, np.zeros((8, 3)), np.zeros((9, 3)), np.zeros((9, 3)))


if __name__ == "__main__":
    unittest.main()
