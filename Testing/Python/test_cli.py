# SPDX-License-Identifier: GPL-3.0-or-later
"""The command line `python3 -m ctsplines`, run as a subprocess on files it writes into a
temporary folder: outputs checked by reading them back, error paths by exit code and message."""
import os
import re
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLUnstructuredGridReader

from cli_case import CommandLineCase


def quadratic(p):
    x, y = p[:, 0], p[:, 1]
    return 0.5 * x * x - 0.3 * x * y + 0.8 * y * y + 0.1 * x


def read(path):
    r = vtkXMLUnstructuredGridReader() if path.endswith(".vtu") else vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def write_vtp(data, path):
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    w = vtkXMLPolyDataWriter()
    w.SetFileName(path)
    w.SetInputData(data)
    # VTK 9.2 cannot read appended data with string arrays back (the source's field data).
    w.SetDataModeToBinary()
    w.Write()


def points(data):
    return vtk_to_numpy(data.GetPoints().GetData())


class CommandLineTest(CommandLineCase):
    def sample_quadratic(self, name, r=4):
        path = self.path(name)
        out = self.cli("sample", path, "--surface", "Quadratic", "--domain", "Grid",
                       "--resolution", str(r)).stdout
        self.assertIn(f"{2 * r * r} triangles, {(r + 1) ** 2} points", out)
        return path

    def test_sample_convert_tessellate(self):
        r, level = 4, 3
        mesh = self.sample_quadratic("quad.vtp", r)
        spline, tess = self.path("quad.vtu"), self.path("tess.vtp")
        out = self.cli("convert", mesh, spline, "--tessellate", str(level), "--tessellation",
                       tess).stdout
        T = 2 * r * r
        grid = read(spline)
        self.assertEqual(grid.GetNumberOfCells(), 3 * T)
        self.assertIn(f"{3 * T} Bézier triangles of order 3", out)
        surface = read(tess)
        self.assertEqual(surface.GetNumberOfCells(), 3 * T * level * level)
        p = points(surface)
        self.assertLess(np.max(np.abs(p[:, 2] - quadratic(p))), 1e-12)
        # Summaries: the quadratic is reproduced, so C1 jumps vanish and the spline lies within
        # the quadratic's distance from its interpolating triangles.
        macro = re.search(r"macro\s+(\d+) edges\s+C0Gap (\S+)\s+C1Jump (\S+)", out)
        self.assertIsNotNone(macro, out)
        self.assertLess(float(macro.group(3)), 1e-12)
        self.assertRegex(out, r"distance to the input triangles: max \d\.\d+e-0[1-3]")

    def test_constructions_and_options(self):
        mesh = self.sample_quadratic("quad.vtp", 3)
        for construction, order in (("CTo", 3), ("MGi", 3), ("Kashyap", 3), ("Quartic", 4)):
            out = self.cli("convert", mesh, self.path(f"{construction}.vtu"), "-c",
                           construction, "--split-point", "Inc3", "--boundary-mode",
                           "GradientPerpendicular", "--iterations", "1", "--no-analysis").stdout
            self.assertIn(f"of order {order}", out)
            self.assertIn(f"{construction}, Inc3, GradientPerpendicular, 1 iterations", out)
            field = read(self.path(f"{construction}.vtu")).GetFieldData()
            names = [field.GetAbstractArray(i).GetValue(0)
                     for i in range(field.GetNumberOfArrays())
                     if field.GetAbstractArray(i).IsA("vtkStringArray")]
            self.assertIn(construction, names)

    def test_renamed_arrays(self):
        mesh = self.sample_quadratic("quad.vtp", 3)
        data = read(mesh)
        for old, new in (("UV", "params"), ("dFdu", "Xu"), ("dFdv", "Xv")):
            data.GetPointData().GetArray(old).SetName(new)
        data.GetPointData().SetActiveAttribute(-1, 3)  # no active texture coordinates (TCOORDS)
        renamed = self.path("renamed.vtp")
        write_vtp(data, renamed)
        p = self.cli("convert", renamed, self.path("a.vtu"), "--derivatives", "file", code=1)
        self.assertIn("UV", p.stderr)
        self.cli("convert", renamed, self.path("b.vtu"), "--uv-array", "params", "--du-array",
                 "Xu", "--dv-array", "Xv", "--derivatives", "file", "--no-analysis")

    def test_estimated_derivatives_reproduce_quadratics(self):
        mesh = self.sample_quadratic("quad.vtp", 5)
        self.cli("convert", mesh, self.path("est.vtu"), "--derivatives", "estimate",
                 "--tessellate", "3", "--no-analysis")
        p = points(read(self.path("est.vtp")))
        self.assertLess(np.max(np.abs(p[:, 2] - quadratic(p))), 1e-10)

    def test_obj_and_ply_with_texture_coordinates(self):
        for ext in ("obj", "ply"):
            mesh = self.sample_quadratic(f"quad.{ext}", 5)
            info = self.cli("info", mesh, code=1).stdout
            self.assertIn("valid input: no", info)
            self.assertIn("dFdu", info)
            self.assertIn("hint:", info)
            self.assertNoVTKNoise(info)
            p = self.cli("convert", mesh, self.path(f"{ext}.vtu"), "--tessellate", "2")
            self.assertIn("estimated dFdu and dFdv", p.stderr)
            q = points(read(self.path(f"{ext}.vtp")))
            # OBJ and PLY store single precision: the quadratic up to rounding.
            self.assertLess(np.max(np.abs(q[:, 2] - quadratic(q))), 1e-4)

    def test_info(self):
        mesh = self.sample_quadratic("quad.vtp", 3)
        out = self.cli("info", mesh).stdout
        self.assertIn("cells: 18 (18 Triangle)", out)
        self.assertIn("UV (2 x double) [texture coordinates]", out)
        self.assertIn("EdgeGradients (18 x double)", out)
        self.assertIn("Surface = Quadratic", out)
        self.assertIn("valid input: yes (CTi gives 54 Bézier triangles", out)
        self.cli("convert", mesh, self.path("s.vtu"), "--no-analysis")
        out = self.cli("info", self.path("s.vtu")).stdout
        self.assertIn("Bézier triangles of order 3", out)

    def test_bad_files(self):
        p = self.cli("convert", self.path("missing.vtp"), self.path("o.vtu"), code=3)
        self.assertIn("no such file", p.stderr)
        # Output folders are checked before the input is read (and before any work).
        for out in (["no/o.vtu"], ["o.vtu", "-t", "2", "--tessellation", "no/t.vtp"]):
            p = self.cli("convert", self.path("missing.vtp"), self.path(out[0]), *out[1:], code=3)
            self.assertIn("does not exist", p.stderr, out)
            self.assertNotIn("no such file", p.stderr, out)
        bad = self.path("bad.txt")
        with open(bad, "w") as f:
            f.write("hello\n")
        p = self.cli("info", bad, code=3)
        self.assertIn("unsupported format '.txt'", p.stderr)
        broken = self.path("broken.vtp")
        with open(broken, "w") as f:
            f.write("<VTKFile type='PolyData'><oops")
        p = self.cli("convert", broken, self.path("o.vtu"), code=3)
        self.assertIn("cannot read it", p.stderr)
        self.assertNoVTKNoise(p.stderr)
        mesh = self.sample_quadratic("quad.vtp", 2)
        p = self.cli("convert", mesh, self.path("o.png"), code=3)
        self.assertIn("cannot write", p.stderr)
        self.cli("convert", mesh, self.path("o.vtu"), "--iterations", "-1", code=2)
        self.cli("convert", mesh, self.path("o.vtu"), "-c", "Nope", code=2)

    def test_invalid_input_reports_the_filters_message(self):
        mesh = self.sample_quadratic("quad.vtp", 2)
        data = read(mesh)
        data.GetPointData().RemoveArray("dFdv")
        write_vtp(data, self.path("nodv.vtp"))
        p = self.cli("convert", self.path("nodv.vtp"), self.path("o.vtu"), "--derivatives",
                     "file", code=1)
        self.assertIn("is not valid input", p.stderr)
        self.assertIn("vtkCloughTocherSplineFilter: ", p.stderr)
        self.assertIn("dFdv", p.stderr)
        self.assertNoVTKNoise(p.stderr)
        self.assertFalse(os.path.exists(self.path("o.vtu")))
        p = self.cli("sample", self.path("s.vtp"), "--surface", "SphereOctant", "--domain",
                     "Grid", code=1)
        self.assertIn("vtkSampledSurfaceSource: ", p.stderr)
        self.assertNoVTKNoise(p.stderr)

    def test_progress(self):
        mesh = self.sample_quadratic("quad.vtp", 3)
        p = self.cli("convert", mesh, self.path("a.vtu"), "--tessellate", "2", "--progress",
                     "--no-analysis")
        self.assertRegex(p.stderr, r"spline\s+\[#+\] 100\.0%")
        self.assertRegex(p.stderr, r"tessellation\s+\[#+\] 100\.0%")
        p = self.cli("convert", mesh, self.path("b.vtu"), "--no-analysis")
        self.assertNotIn("%", p.stderr)  # not a terminal: no bar unless asked

    def test_help_explains_every_option(self):
        for command, options in (
                ("convert", ("--construction", "--split-point", "--boundary-mode",
                             "--iterations", "--uv-array", "--du-array", "--dv-array",
                             "--edge-gradients-array", "--derivatives", "--tessellate",
                             "--tessellation", "--reference", "--progress", "--no-analysis")),
                ("info", ("--construction", "--uv-array")),
                ("sample", ("--surface", "--domain", "--resolution", "--grid-diagonal",
                            "--seed", "--affine", "--translation")),
                ("demo", ("--output", "--construction", "--points", "--level", "--no-render"))):
            out = self.cli(command, "--help").stdout
            for option in options:
                self.assertIn(option, out, f"{command} --help")
        self.assertIn("Exit codes", self.cli("--help").stdout)

    def test_reference_error(self):
        coarse = self.sample_quadratic("coarse.vtp", 3)
        fine = self.sample_quadratic("fine.vtp", 9)
        out = self.cli("convert", coarse, self.path("c.vtu"), "--reference", fine).stdout
        m = re.search(r"error against \S+ \(parametric\): max (\S+)", out)
        self.assertIsNotNone(m, out)
        self.assertLess(float(m.group(1)), 1e-12)

    def test_demo_still_works(self):
        out = self.cli("demo", "--output", self.path("demo"), "--points", "20", "--level", "2",
                       "--no-render").stdout
        self.assertIn("spline: ", out)
        self.assertTrue(os.path.exists(self.path("demo/spline.vtu")))
        self.assertTrue(os.path.exists(self.path("demo/tessellation.vtp")))


if __name__ == "__main__":
    unittest.main()
