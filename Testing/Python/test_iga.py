# SPDX-License-Identifier: GPL-3.0-or-later
"""Bézier extraction from Python: the global matrix reproduces the control points, the export
format round-trips, and the Galerkin example converges at the spaces' rates."""
import os
import sys
import tempfile
import unittest

import numpy as np

import ctsplines
from ctsplines import arrays, iga

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Examples", "Python"))


def franke_spline(construction, extraction=True):
    src = ctsplines.vtkSampledSurfaceSource()
    src.SetSurfaceToFranke()
    src.SetDomainToRandomDelaunay()
    src.SetResolution(40)
    ct = ctsplines.vtkCloughTocherSplineFilter()
    ct.SetInputConnection(src.GetOutputPort())
    getattr(ct, "SetConstructionTo" + construction)()
    ct.SetBoundaryModeToGradientToSplitPoint()
    ct.SetComputeBezierExtraction(extraction)
    ct.Update()
    return ct.GetOutput()


class ExtractionTest(unittest.TestCase):
    def test_global_matrix_reproduces_control_points(self):
        for construction in ("CTo", "CTi", "Ka", "KaG", "MGo", "MGi"):
            grid = franke_spline(construction)
            ex = iga.Extraction(grid)
            M = ex.global_matrix()
            np.testing.assert_allclose(M @ ex.dofs, arrays.points(grid), atol=1e-12, err_msg=construction)
            # Partition of unity: value dofs to one.
            n_vertices = (ex.n_dofs - np.count_nonzero(ex.edge_dofs[:, 2] >= 0)) // 3
            ones = np.zeros(ex.n_dofs)
            ones[0 : 3 * n_vertices : 3] = 1.0
            np.testing.assert_allclose(M @ ones, 1.0, atol=1e-13, err_msg=construction)

    def test_export_round_trip(self):
        grid = franke_spline("KaG")
        ex = iga.Extraction(grid)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "spline.ctx")
            iga.export(grid, path)
            back = iga.read(path)
        self.assertEqual(back["n_dofs"], ex.n_dofs)
        np.testing.assert_array_equal(back["points"], ex.points)
        for (ids, dofs, op), c in zip(back["elements"], range(len(ex.cell_points))):
            np.testing.assert_array_equal(ids, ex.cell_points[c])
            k = len(dofs)
            np.testing.assert_array_equal(op, ex.operators[c, :, :k])
            # Each element reproduces its control points from the degrees of freedom.
            np.testing.assert_allclose(op @ ex.dofs[dofs], ex.points[ids], atol=1e-12)

    def test_missing_extraction_is_reported(self):
        with self.assertRaises(ValueError):
            iga.Extraction(franke_spline("CTi", extraction=False))

    def test_galerkin_convergence_orders(self):
        import iga_poisson_biharmonic

        with tempfile.TemporaryDirectory() as d:
            self.assertEqual(iga_poisson_biharmonic.main(["--quick", "--output", d]), 0)
            self.assertTrue(os.path.exists(os.path.join(d, "convergence.md")))


if __name__ == "__main__":
    unittest.main()
