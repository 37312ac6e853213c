# SPDX-License-Identifier: GPL-3.0-or-later
"""Kirchhoff-Love shells on geometry converted by the CAD pipeline: the pinched hemisphere on its
quarter written to STEP by OpenCASCADE (one spherical face), and the pinched cylinder on its
octant as two tangent cylindrical faces with their own parameters, joined by
shell.FacePatches (shared nodes, G1 at the tangent join). The models are written at test time
by the CADShellModels fixture into $CTSPLINES_CAD_MODELS; skipped without them."""
import os
import sys
import unittest

import numpy as np

from ctsplines import shell

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "Examples", "Python"))
import kirchhoff_love_shell as kls  # noqa: E402

MODELS = os.environ.get("CTSPLINES_CAD_MODELS", "")
HEMISPHERE = os.path.join(MODELS, "hemisphere_quarter.step")
CYLINDER = os.path.join(MODELS, "cylinder_octant_two_faces.step")


def have(path):
    try:
        from ctsplines import vtkCADFaceSampler  # noqa: F401
    except ImportError:
        return False
    return bool(MODELS) and os.path.exists(path)


@unittest.skipUnless(have(HEMISPHERE), "needs CTSplines::IOCAD and hemisphere_quarter.step (CADShellModels)")
class CADHemisphereTest(unittest.TestCase):
    def test_pinched_hemisphere_on_the_step_face(self):
        bench = kls.pinched_hemisphere(HEMISPHERE)
        coarse, fine = (kls.solve(bench, n, "KaG")[1] for n in (8, 16))
        # Converges to the analytic runs' 0.09350 (KaG, MGi, n = 32; docs/iga.md): measured
        # 0.09066 and 0.09341; 1.1 % above the 0.0924 reference.
        self.assertTrue(coarse < fine, (coarse, fine))
        self.assertAlmostEqual(fine / 0.09350, 1.0, delta=0.003)
        self.assertAlmostEqual(fine / 0.0924, 1.0, delta=0.015)


@unittest.skipUnless(have(CYLINDER), "needs CTSplines::IOCAD and cylinder_octant_two_faces.step (CADShellModels)")
class TwoFaceCylinderTest(unittest.TestCase):
    """The two faces meet at theta = 45 deg; the second's parameters are (90 deg - theta, -y)."""

    @classmethod
    def setUpClass(cls):
        cls.faces = {n: kls.cad_faces(CYLINDER, n) for n in (4, 16)}

    def model(self, n, construction="KaG", threshold=10.0):
        bench = kls.pinched_cylinder()
        return shell.FacePatches(self.faces[n], construction, bench.thickness, bench.young, bench.poisson,
                                 threshold)

    def test_one_numbering_with_shared_nodes(self):
        model = self.model(4)
        self.assertEqual(len(model.shells), 2)
        shared_nodes = np.intersect1d(*model.node_ids)
        self.assertGreaterEqual(len(shared_nodes), 3)
        self.assertEqual(model.joins, {"tangent": len(shared_nodes), "crease": 0,
                                       "tangent_edges": len(shared_nodes) - 1})
        self.assertEqual(len(model.shared_edges), len(shared_nodes) - 1)
        # Per shared node: one value and two gradient dofs; per shared edge one edge dof.
        stacked = model.T.shape[0]
        self.assertEqual(model.T.shape[1], stacked - 3 * len(shared_nodes) - len(model.shared_edges))

    def test_coupled_space_is_c1_across_the_join(self):
        for construction in ("CTi", "KaG", "MGi"):
            model = self.model(4, construction)
            r = np.random.default_rng(7).standard_normal(model.n_unknowns)
            dofs = model.stacked_dofs(r)
            (gap, value, grad), samples = model.interface_jumps(dofs)
            self.assertEqual(samples, 5 * len(model.shared_edges))
            self.assertLess(gap, 1e-9, construction)  # the faces' splines meet (affine transition)
            self.assertLess(value, 1e-12, construction)
            self.assertLess(grad, 1e-10, construction)
        # Treated as a crease (threshold 0) the join is a hinge: C0, the gradient jumps.
        model = self.model(4, "KaG", threshold=0.0)
        self.assertEqual(model.joins["tangent"], 0)
        r = np.random.default_rng(7).standard_normal(model.n_unknowns)
        dofs = model.stacked_dofs(r)
        (_, value, grad), _ = model.interface_jumps(dofs)
        self.assertLess(value, 1e-12)
        # Random dofs: d/du (u in radians) is 1/R of d/dv in 3D, so the free cross-edge
        # derivative jumps by about 1/R of the largest gradient (measured 3.2e-3).
        self.assertGreater(grad, 1e-3)

    def test_rigid_motions_are_in_the_kernel(self):
        for threshold in (10.0, 0.0):
            model = self.model(4, "KaG", threshold)
            K = model.stiffness()
            R = model.rigid_motions()
            stacked = np.concatenate([s.rigid_motions() for s in model.shells])
            # The coupled space holds each face's rigid motions, and they cost no energy.
            self.assertLess(np.abs(model.T3 @ R - stacked).max() / np.abs(stacked).max(), 1e-10)
            self.assertLess(np.abs(K @ (R / np.abs(R).max(axis=0))).max() / abs(K).max(), 1e-10)
            other = np.random.default_rng(2).standard_normal(model.n_unknowns)  # not rigid: costs energy
            self.assertGreater(np.abs(K @ other).max() / abs(K).max(), 1e-3)

    def test_pinched_cylinder_on_two_faces(self):
        unknowns, value, _, model, dofs = kls.solve_cad_cylinder(CYLINDER, 16, "KaG")
        # Analytic one-face octant, KaG, 16 x 16 grid: 1.78133e-5 (docs/iga.md); measured 1.77025e-5
        # here (0.970 of 1.8248e-5).
        self.assertAlmostEqual(value / 1.78133e-5, 1.0, delta=0.015)
        self.assertAlmostEqual(value / 1.8248e-5, 1.0, delta=0.04)
        (gap, jump, grad), _ = model.interface_jumps(dofs)
        self.assertLess(jump, 1e-12)
        self.assertLess(grad, 1e-10)
        # Joined as a hinge the interface carries no bending moment: the crown deflects more, if
        # only a little this far (235, about 8 sqrt(R t)) from the load (measured 1.0027).
        bench = kls.pinched_cylinder()
        hinge = shell.FacePatches(self.faces[16], "KaG", bench.thickness, bench.young, bench.poisson, 0.0)
        fixed = np.concatenate([hinge.plane_dofs(*c) for c in kls.CYLINDER_PLANES])
        f, v = hinge.vertex_near((0.0, 0.0, 300.0))
        d = hinge.solve(hinge.point_load(f, v, (0, 0, -0.25)), fixed)
        self.assertGreater(-d[f][3 * v][2] / value, 1.001)

    def test_bad_input(self):
        bench = kls.pinched_cylinder()
        mesh = shell.grid_mesh(2, 2, (0.0, 1.0), (0.0, 1.0), shell.cylinder(300.0))
        with self.assertRaisesRegex(ValueError, "face 0 has no point array GlobalNodeId"):
            shell.FacePatches([mesh], "KaG", 3.0, 3e6, 0.3)
        model = self.model(4)
        with self.assertRaisesRegex(ValueError, "no face boundary line lies in the plane"):
            model.plane_dofs(0, 100.0, 0, "trace")
        with self.assertRaisesRegex(ValueError, "no face has a vertex"):
            model.vertex_near((1.0, 2.0, 3.0))
        # Only the diaphragm: the octant can still slide along y.
        fixed = np.concatenate([model.plane_dofs(*c) for c in kls.CYLINDER_PLANES[:2]])
        with self.assertRaisesRegex(ValueError, "rigid-body motion free"):
            model.solve(np.zeros(model.T3.shape[0]), fixed)
        del bench


BOX = os.path.join(MODELS, "box_with_hole.step")


@unittest.skipUnless(have(BOX), "needs CTSplines::IOCAD and box_with_hole.step (CADTestModel)")
class CreasedModelTest(unittest.TestCase):
    """The box with a through-hole: seven faces, creases along straight and circular edges,
    corners of three faces, a seamed cylinder."""

    def test_creases_keep_rigid_motions_and_c0(self):
        model = shell.FacePatches(kls.cad_faces(BOX, 4), "KaG", 0.01, 1e4, 0.3)
        self.assertEqual(len(model.shells), 7)
        self.assertGreater(model.joins["crease"], 100)
        self.assertGreater(model.joins["tangent"], 0)  # the seam's copies of a node
        K, R = model.stiffness(), model.rigid_motions()
        stacked = np.concatenate([s.rigid_motions() for s in model.shells])
        # Crease ties along the B-rep edges' tangents (EdgeCurvePoints): exact for rigid motions.
        self.assertLess(np.abs(model.T3 @ R - stacked).max() / np.abs(stacked).max(), 1e-10)
        self.assertLess(np.abs(K @ (R / np.abs(R).max(axis=0))).max() / abs(K).max(), 1e-10)
        # C0 up to the faces' own gap on the circular edges (each face's boundary cubic lives in its
        # parameters): measured position gap 4.7e-5 (diagonal 2.5), value jump 3.8e-5 relative.
        (gap, value, _), _ = model.interface_jumps(
            model.stacked_dofs(np.random.default_rng(3).standard_normal(model.n_unknowns)))
        self.assertLess(gap, 1e-4)
        self.assertLess(value, 1e-4)


if __name__ == "__main__":
    unittest.main()
