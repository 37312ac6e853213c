# SPDX-License-Identifier: GPL-3.0-or-later
"""Bézier extraction from Python: the global matrix reproduces the control points, the export
format round-trips, and the Galerkin example converges at the spaces' rates."""
import json
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

    def test_json_round_trip(self):
        grid = franke_spline("MGi")
        ex = iga.Extraction(grid)
        sets = {"corner": [0, 1, 2]}
        for layout in ("coreform", "ctsplines"):
            with tempfile.TemporaryDirectory() as d:
                path = os.path.join(d, "spline.json")
                iga.export_json(grid, path, layout=layout, dof_sets=sets)
                back = iga.read_json(path)
            self.assertEqual(back["n_dofs"], ex.n_dofs, layout)
            np.testing.assert_array_equal(back["points"], ex.points)
            np.testing.assert_array_equal(back["uv"], ex.uv)
            np.testing.assert_array_equal(back["dofs"], ex.dofs)
            np.testing.assert_array_equal(back["dof_sets"]["corner"], [0, 1, 2])
            self.assertEqual(len(back["elements"]), len(ex.cell_points))
            for c, (ids, dofs, op) in enumerate(back["elements"]):
                np.testing.assert_array_equal(ids, ex.cell_points[c])
                k = len(dofs)
                np.testing.assert_array_equal(dofs, ex.cell_dofs[c, :k])
                # Bit-exact for the per-element layout; the global matrix of the ctsplines layout
                # stores each shared control point once, so the cells must agree on it.
                np.testing.assert_allclose(op, ex.operators[c, :, :k], rtol=0, atol=1e-13,
                                           err_msg=f"{layout} element {c}")
                np.testing.assert_allclose(op @ back["dofs"][dofs], back["points"][ids], atol=1e-12)

    def test_json_bad_input_is_reported(self):
        grid = franke_spline("CTi")
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "spline.json")
            with self.assertRaisesRegex(ValueError, "unknown layout"):
                iga.export_json(grid, path, layout="bext")
            with self.assertRaisesRegex(ValueError, "outside"):
                iga.export_json(grid, path, dof_sets={"bad": [10**9]})
            for layout in ("coreform", "ctsplines"):
                iga.export_json(grid, path, layout=layout)
                with open(path) as f:
                    data = json.load(f)
                if layout == "coreform":
                    data["elements"]["element_blocks"][5]["node_ids"][0] = 10**9
                else:
                    data["cell_dofs"][5][0] = 10**9
                with open(path, "w") as f:
                    json.dump(data, f)
                with self.assertRaisesRegex(ValueError, "element 5|malformed"):
                    iga.read_json(path)
            with open(path, "w") as f:
                f.write("{not json")
            with self.assertRaisesRegex(ValueError, "not JSON"):
                iga.read_json(path)
            iga.export_json(grid, path, layout="coreform")
            with open(path) as f:
                data = json.load(f)
            data["nodes"][0][3] = 0.5
            with open(path, "w") as f:
                json.dump(data, f)
            with self.assertRaisesRegex(ValueError, "rational"):
                iga.read_json(path)
            with open(path, "w") as f:
                json.dump({"format": "something else"}, f)
            with self.assertRaisesRegex(ValueError, "not a ctsplines-bezier-extraction"):
                iga.read_json(path)

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
