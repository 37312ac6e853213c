# SPDX-License-Identifier: GPL-3.0-or-later
"""`python3 -m ctsplines convert MODEL.step -o OUT.vtm`: the watertight CAD conversion from the
command line, on the box with a hole that CAD.WriteTestModel writes and on component8.step when
CAD.FetchModels could fetch it (both into $CTSPLINES_CAD_MODELS). Skipped without CTSplines::IOCAD
or without the models."""
import json
import os
import re
import shutil
import unittest

from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet
from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataReader, vtkXMLUnstructuredGridReader

import ctsplines
from cli_case import CommandLineCase

MODELS = os.environ.get("CTSPLINES_CAD_MODELS", "")


def model(name):
    path = os.path.join(MODELS, name)
    return path if MODELS and os.path.isfile(path) else None


def field(data, name):
    return data.GetFieldData().GetArray(name).GetValue(0)


@unittest.skipUnless(ctsplines.HAS_IOCAD, "ctsplines was built without CTSplines::IOCAD")
class CADCommandLineTest(CommandLineCase):
    def box(self):
        path = model("box_with_hole.step")
        if path is None:
            self.skipTest("box_with_hole.step not written (fixture CAD.WriteTestModel)")
        return path

    def convert_and_check(self, step, tolerance, *options):
        out = self.path("out.vtm")
        text = self.cli("convert", step, "--tolerance", str(tolerance), "-o", out,
                        *options).stdout
        # The naming: OUT.vtm with its block files in OUT/, the merged grid in OUT.vtu.
        self.assertTrue(os.path.isdir(self.path("out")), os.listdir(self.dir))
        reader = vtkXMLMultiBlockDataReader()
        reader.SetFileName(out)
        reader.Update()
        splines = reader.GetOutput()
        grid_reader = vtkXMLUnstructuredGridReader()
        grid_reader.SetFileName(self.path("out.vtu"))
        grid_reader.Update()
        merged = grid_reader.GetOutput()

        faces = int(re.search(r"\((\d+) faces, \d+ B-rep edges, (\d+) triangles", text).group(1))
        self.assertEqual(splines.GetNumberOfBlocks(), faces, text)
        self.assertGreater(merged.GetNumberOfCells(), 0)
        cells = sum(splines.GetBlock(f).GetNumberOfCells() for f in range(faces))
        # Merging shares interface control points; it keeps every Bézier triangle.
        self.assertEqual(merged.GetNumberOfCells(), cells)
        self.assertLess(merged.GetNumberOfPoints(),
                        sum(splines.GetBlock(f).GetNumberOfPoints() for f in range(faces)))
        # A closed solid: watertight, every interface exactly shared.
        self.assertEqual(field(merged, "NumberOfFreeEdges"), 0)
        self.assertEqual(field(merged, "NumberOfNonManifoldEdges"), 0)
        self.assertEqual(field(merged, "MaxC0Gap"), 0.0)
        self.assertIn("free edges: 0 (non-manifold edges: 0, 0 of them", text)
        self.assertIn("C0 gap: max 0.000e+00", text)
        # The faces are refined for the stitched spline (IM steps aside): within the tolerance.
        deviation = float(re.search(r"relative to the diagonal\): max (\S+),", text).group(1))
        self.assertLessEqual(deviation, tolerance * (1 if "--iterations" not in options else 2),
                             text)
        self.assertRegex(text, r"G1 angle across interfaces: max \S+ degrees; over the \d+ "
                               r"macro-edges where the CAD faces meet tangentially max \S+")
        for stage in ("read", "edges", "loops", "tangent planes", "faces", "splines", "stitch",
                      "merge", "deviation", "total"):
            self.assertRegex(text, rf"\b{stage} \d+\.\d{{3}}")
        return text

    def test_box_with_hole(self):
        text = self.convert_and_check(self.box(), 1e-3)
        self.assertIn("KaG, Bary, Midpoint, 0 iterations", text)  # the CAD defaults

    def test_options_and_stp_extension(self):
        stp = self.path("box.stp")
        shutil.copy(self.box(), stp)
        text = self.convert_and_check(stp, 1e-3, "--construction", "CTi", "--split-point", "Inc2",
                                      "--boundary-mode", "Perpendicular", "--iterations", "1",
                                      "--aspect-ratio", "20", "--max-edge-length", "0.2")
        self.assertIn("CTi, Inc2, Perpendicular, 1 iterations", text)

    def test_g1_options(self):
        # The options reach the sampler and the report; whether RestoreG1 restores G1 is tested
        # in C++ (CAD.CADConversion.RestoreG1AtAlmostTangentInterface, a kinked model).
        text = self.convert_and_check(self.box(), 1e-3, "--g1", "--g1-threshold", "5")
        self.assertIn("(tangent within 5 degrees, RestoreG1)", text)
        # The hole's seam is a tangent interface.
        tangent = re.search(r"(\d+) macro-edges where the CAD faces meet tangentially max (\S+),",
                            text)
        self.assertGreater(int(tangent.group(1)), 0, text)
        self.assertLess(float(tangent.group(2)), 0.1, text)
        # --g1 takes no value (the option after it is not mistaken for one); angles are checked.
        self.cli("convert", self.box(), "--g1", "-o", self.path("o.vtm"), "--tolerance", "1e-2")
        # G1 is the default (--g1 is its explicit form); --no-g1 turns it off.
        text = self.cli("convert", self.box(), "-o", self.path("o.vtm"), "--tolerance",
                        "1e-2").stdout
        self.assertIn("(tangent within 10 degrees, RestoreG1)", text)
        text = self.cli("convert", self.box(), "-o", self.path("o.vtm"), "--tolerance", "1e-2",
                        "--no-g1").stdout
        self.assertIn("(tangent within 10 degrees)", text)
        p = self.cli("convert", self.box(), "-o", self.path("o.vtm"), "--g1", "--no-g1", code=2)
        self.assertIn("not allowed with argument", p.stderr)
        p = self.cli("convert", self.box(), "-o", self.path("o.vtm"), "--g1-threshold", "200",
                     code=2)
        self.assertIn("not an angle in [0, 90]", p.stderr)

    def test_angular_tolerance(self):
        # The normal deviation is reported beside the positional one; --angular-tolerance
        # refines until the normals are within it (the hole's cylinder: 0.06 degrees without).
        def normals(text):
            found = re.search(r"normals: max (\S+) degrees, RMS (\S+)", text)
            self.assertIsNotNone(found, text)
            return float(found.group(1)), float(found.group(2))

        def triangles(text):
            return int(re.search(r"B-rep edges, (\d+) triangles", text).group(1))

        free = self.convert_and_check(self.box(), 1e-3)
        held = self.convert_and_check(self.box(), 1e-3, "--angular-tolerance", "0.02")
        self.assertGreater(normals(free)[0], 0.02, free)
        self.assertLessEqual(normals(held)[0], 0.02, held)
        self.assertLessEqual(normals(held)[1], normals(held)[0])
        self.assertIn("(angular tolerance 0.02)", held)
        self.assertGreater(triangles(held), triangles(free))
        p = self.cli("convert", self.box(), "-o", self.path("o.vtm"), "--angular-tolerance",
                     "-1", code=2)
        self.assertIn("not an angle in [0, 90]", p.stderr)

    def test_default_output_is_named_after_the_model(self):
        self.cli("convert", self.box(), "--tolerance", "1e-2")
        for name in ("box_with_hole.vtm", "box_with_hole.vtu"):
            self.assertTrue(os.path.isfile(self.path(name)), os.listdir(self.dir))

    def test_outputs_are_raw_lz4_and_the_index_is_vtks(self):
        # The outputs' data is raw binary, LZ4 compressed (zlib and base64 took longer than a
        # small model's conversion); the index is vtkXMLMultiBlockDataWriter's: one named
        # DataSet per face, its file in OUT/, the model's field data.
        text = self.convert_and_check(self.box(), 1e-2)
        for name in ("out.vtu", os.path.join("out", "out_0.vtu")):
            with open(self.path(name), "rb") as f:
                content = f.read()
            self.assertIn(b'compressor="vtkLZ4DataCompressor"', content, name)
            self.assertIn(b'<AppendedData encoding="raw">', content, name)
        reader = vtkXMLMultiBlockDataReader()
        reader.SetFileName(self.path("out.vtm"))
        reader.Update()
        splines = reader.GetOutput()
        faces = int(re.search(r"\((\d+) faces", text).group(1))
        with open(self.path("out.vtm"), encoding="utf-8") as f:
            files = re.findall(r'<DataSet index="(\d+)" name="[^"]*" file="out/out_(\d+)\.vtu"/>',
                               f.read())
        self.assertEqual(files, [(str(i), str(i)) for i in range(faces)])
        for i in range(faces):
            name = splines.GetBlock(i).GetFieldData().GetAbstractArray("FaceName").GetValue(0)
            self.assertEqual(splines.GetMetaData(i).Get(vtkCompositeDataSet.NAME()), name)
        diagonal = float(re.search(r"of the diagonal (\S+)\)", text).group(1))
        self.assertAlmostEqual(field(splines, "Diagonal"), diagonal, delta=1e-5 * diagonal)
        self.assertEqual(splines.GetFieldData().GetArray("StageTimes").GetNumberOfTuples(), 5)

    def test_component8(self):
        step = model("component8.step")
        if step is None:
            self.skipTest("component8.step not fetched (gmsh-doc unavailable)")
        text = self.convert_and_check(step, 1e-4)
        self.assertIn("(21 faces, 48 B-rep edges", text)

    def test_loose_faces_are_sewn(self):
        # A box's six faces, each with edges of its own (CAD.WriteTestModel.loose_box_faces).
        step = model("loose_box_faces.step")
        if step is None:
            self.skipTest("loose_box_faces.step not written (fixture CAD.WriteTestModel)")
        text = self.convert_and_check(step, 1e-4)
        self.assertRegex(text, r"healing: 12 edges sewn in \d+\.\d{3} s, 0 sliver faces removed")
        text = self.cli("convert", step, "-o", self.path("open.vtm"), "--no-sew").stdout
        self.assertIn("healing: 0 edges sewn (--no-sew)", text)
        free = int(re.search(r"free edges: (\d+)", text).group(1))
        self.assertGreater(free, 24, text)
        for option in ("--no-sew", "--no-fallback"):
            p = self.cli("convert", self.path("mesh.vtp"), self.path("s.vtu"), option, code=2)
            self.assertIn(f"{option} applies to CAD models", p.stderr)

    def test_occt_exception_is_named(self):
        # A face on which OpenCASCADE throws (CAD.WriteTestModel.offset_without_normal): the
        # error line names the face and the operation, beside OCCT's own text.
        step = model("offset_without_normal.step")
        if step is None:
            self.skipTest("offset_without_normal.step not written (fixture CAD.WriteTestModel)")
        p = self.cli("convert", step, "-o", self.path("o.vtm"), code=3)
        self.assertRegex(p.stderr, r"(?m)^error: ")
        self.assertIn("the bounding box of face 0", p.stderr)
        self.assertIn("evaluating its surface", p.stderr)
        self.assertIn("Geom_UndefinedValue", p.stderr)

    def test_errors(self):
        p = self.cli("convert", self.path("missing.step"), "-o", self.path("o.vtm"), code=3)
        self.assertIn("no such file", p.stderr)
        garbage = self.path("garbage.step")
        with open(garbage, "w") as f:
            f.write("this is not ISO-10303-21\n")
        p = self.cli("convert", garbage, "-o", self.path("o.vtm"), code=3)
        self.assertIn("cannot read", p.stderr)
        self.assertNoVTKNoise(p.stderr)
        box = self.box()
        p = self.cli("convert", box, "-o", self.path("o.vtu"), code=3)
        self.assertIn(".vtm", p.stderr)
        self.cli("convert", box, "-o", self.path("o.vtm"), "-c", "Quartic", code=2)
        self.cli("convert", box, "-o", self.path("o.vtm"), "--tolerance", "0", code=2)
        self.cli("convert", box, "-o", self.path("o.vtm"), "--tessellate", "2", code=2)
        self.cli("convert", box, self.path("a.vtm"), "-o", self.path("b.vtm"), code=2)
        mesh = self.path("mesh.vtp")
        self.cli("sample", mesh)
        p = self.cli("convert", mesh, self.path("s.vtu"), "--g1", code=2)
        self.assertIn("--g1 applies to CAD models", p.stderr)
        p = self.cli("convert", mesh, self.path("s.vtu"), "--no-g1", code=2)
        self.assertIn("--no-g1 applies to CAD models", p.stderr)

    def test_missing_output_folder_is_named_before_the_work(self):
        # The folder is checked first: the conversion (here: of a file that cannot be read)
        # does not run, and nothing is left behind.
        garbage = self.path("garbage.step")
        with open(garbage, "w") as f:
            f.write("this is not ISO-10303-21\n")
        missing = self.path("no/such/folder")
        for option in ("-o", "--summary-json"):
            args = ["convert", garbage, "-o", os.path.join(missing, "o.vtm")] if option == "-o" \
                else ["convert", garbage, "-o", self.path("o.vtm"), option,
                      os.path.join(missing, "s.json")]
            p = self.cli(*args, code=3)
            self.assertIn(f"folder {missing} does not exist", p.stderr, option)
            self.assertNotIn("cannot read", p.stderr, option)
        self.assertFalse(os.path.exists(self.path("o.vtm")))

    def test_malformed_files_are_clean_errors(self):
        # Each was a crash or a hang of OpenCASCADE before; now exit code 3 naming the file.
        with open(self.box()) as f:
            text = f.read()
        point = re.search(r"CARTESIAN_POINT\('',\(([^,]+),", text)
        cases = {
            "truncated.step": (text[: len(text) // 3], "cannot read"),
            "huge.step": (text[: point.start(1)] + "1.E400" + text[point.end(1):],
                          "out of the range of a double"),
            "nan.step": (text[: point.start(1)] + "NaN" + text[point.end(1):],
                         "'NaN' is not a number"),
            "empty.stp": ("", "the file is empty"),
        }
        for name, (content, message) in cases.items():
            path = self.path(name)
            with open(path, "w") as f:
                f.write(content)
            p = self.cli("convert", path, "-o", self.path("o.vtm"), code=3)
            self.assertIn(message, p.stderr, name)
            self.assertIn(name, p.stderr)
            self.assertNotIn("Traceback", p.stderr)

    def test_read_timeout(self):
        p = self.cli("convert", self.box(), "-o", self.path("o.vtm"), "--read-timeout", "1e-4",
                     code=3)
        self.assertIn("did not end within the read timeout of 0.0001 s", p.stderr)
        # 0: in this process, without a limit.
        self.cli("convert", self.box(), "-o", self.path("o.vtm"), "--tolerance", "1e-2",
                 "--read-timeout", "0")
        self.cli("convert", self.box(), "-o", self.path("o.vtm"), "--read-timeout", "-1", code=2)

    def test_crash_in_translation_is_an_error(self):
        step = model("component8.step")
        if step is None:
            self.skipTest("component8.step not fetched (gmsh-doc unavailable)")
        with open(step) as f:
            text = f.read()
        # An oriented edge that is its own edge: OCCT recurses until its stack overflows.
        changed = self.path("self_reference.step")
        with open(changed, "w") as f:
            f.write(re.sub(r"#179=ORIENTED_EDGE\([^;]*;", "#179=ORIENTED_EDGE('',*,*,#179,.T.);",
                           text))
        p = self.cli("convert", changed, "-o", self.path("o.vtm"), code=3)
        self.assertIn("OpenCASCADE's translation crashed", p.stderr)
        self.assertIn("self_reference.step", p.stderr)

    def test_summary_json(self):
        summary = self.path("s.json")
        text = self.cli("convert", self.box(), "-o", self.path("o.vtm"), "--tolerance", "1e-3",
                        "--summary-json", summary).stdout
        with open(summary) as f:
            s = json.load(f)  # strict JSON: unreported figures are null, never NaN
        self.assertEqual((s["exit_status"], s["error"], s["model"]), (0, None, self.box()))
        self.assertEqual(s["options"]["tolerance"], 1e-3)
        self.assertIn(f"({s['faces']} faces, {s['brep_edges']} B-rep edges", text)
        self.assertEqual((s["free_edges"], s["non_manifold_edges"], s["c0_gap"]), (0, 0, 0.0))
        self.assertLessEqual(s["max_deviation"], 1e-3)
        self.assertEqual([name for name, _ in s["stages"]][:2], ["read", "edges"])
        self.assertIn("g1_angle_tangent", s)
        # Where the largest deviations and the largest G1 angle at a tangent interface (the
        # hole's seam) are: a face and macro-triangle of the model, near the box.
        self.assertGreater(s["tangent_edges"], 0)
        for key in ("max_deviation_at", "max_normal_deviation_at", "g1_angle_tangent_at"):
            where = s[key]
            self.assertTrue(0 <= where["face"] < s["faces"], where)
            self.assertGreaterEqual(where["macro_triangle"], 0)
            self.assertLess(max(abs(x) for x in where["point"]), 10 * s["diagonal"], where)
            self.assertIn(f"face {where['face']}, macro-triangle {where['macro_triangle']}", text)
        # A failure writes the error the CLI prints and its exit status.
        garbage = self.path("garbage.step")
        with open(garbage, "w") as f:
            f.write("this is not ISO-10303-21\n")
        p = self.cli("convert", garbage, "-o", self.path("o.vtm"), "--summary-json", summary,
                     code=3)
        with open(summary) as f:
            s = json.load(f)
        self.assertEqual(s["exit_status"], 3)
        self.assertIn("cannot read", s["error"])
        self.assertIn(f"error: {s['error']}", p.stderr)
        self.assertNotIn("faces", s)
        mesh = self.path("mesh.vtp")
        self.cli("sample", mesh)
        p = self.cli("convert", mesh, self.path("m.vtu"), "--summary-json", summary, code=2)
        self.assertIn("--summary-json applies to CAD models", p.stderr)

    def test_help_explains_the_cad_options(self):
        out = self.cli("convert", "--help").stdout
        for text in ("--tolerance", "--angular-tolerance", "--aspect-ratio", "--max-edge-length",
                     "--g1", "--no-g1", "--g1-threshold", "--read-timeout", "--no-sew",
                     "--no-fallback", ".step",
                     "OUT.vtu", "-o"):
            self.assertIn(text, out)


if __name__ == "__main__":
    unittest.main()
