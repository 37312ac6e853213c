# SPDX-License-Identifier: GPL-3.0-or-later
"""The main job's picture: `python3 -m ctsplines demo` renders a PNG that shows the surface (run
under xvfb-run by ctest)."""
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader


class RenderTest(unittest.TestCase):
    def test_demo_image_shows_the_surface(self):
        with tempfile.TemporaryDirectory() as d:
            p = subprocess.run(
                [sys.executable, "-m", "ctsplines", "demo", "--output", d, "--points", "60", "--level", "4"],
                capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            reader = vtkPNGReader()
            reader.SetFileName(os.path.join(d, "spline.png"))
            reader.Update()
            image = reader.GetOutput()
            rgb = vtk_to_numpy(image.GetPointData().GetScalars())[:, :3].astype(float)
        self.assertEqual(image.GetDimensions()[:2], (900, 700))
        # White background plus a surface drawn in grey stripes: not one colour, and a good part
        # of the picture is not background.
        surface = np.any(rgb < 250, axis=1)
        self.assertGreater(surface.mean(), 0.2)
        self.assertLess(surface.mean(), 0.98)
        self.assertGreater(rgb[surface].std(), 20.0)


if __name__ == "__main__":
    unittest.main()
