# SPDX-License-Identifier: GPL-3.0-or-later
"""The construction table is the one list of constructions: the ParaView XML enumerations, the
CLI's choices, the CAD classes' limits, docs/constructions.md and the filter's facts agree
with it."""
import os
import re
import unittest
import xml.etree.ElementTree as ET

import numpy as np

import ctsplines
from ctsplines import arrays, constructions
from ctsplines.io import VTKMessages

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
XML = os.path.join(ROOT, "module", "paraview", "CTSplines")


def enumeration(xml, proxy_property="Construction"):
    """(value, text) pairs and the default of an IntVectorProperty's enumeration."""
    for prop in ET.parse(xml).getroot().iter("IntVectorProperty"):
        if prop.get("name") == proxy_property:
            entries = [(int(e.get("value")), e.get("text")) for e in prop.iter("Entry")]
            return entries, int(prop.get("default_values"))
    raise AssertionError(f"{xml} has no {proxy_property} property")


class ConstructionTableTest(unittest.TestCase):
    def test_spline_filter_xml_lists_every_construction(self):
        entries, default = enumeration(os.path.join(XML, "vtkCloughTocherSplineFilter.xml"))
        self.assertEqual(entries, list(enumerate(constructions.names())))
        self.assertEqual(default, ctsplines.vtkCloughTocherSplineFilter().GetConstruction())

    def test_cad_xmls_list_the_stitchable_constructions(self):
        for name in ("vtkCADFaceSampler.xml", "vtkWatertightSplineStitcher.xml"):
            entries, default = enumeration(os.path.join(XML, "IOCAD", name))
            self.assertEqual([t for _, t in entries], constructions.stitched(), name)
            self.assertEqual([v for v, _ in entries], [constructions.value(t) for _, t in entries])
            self.assertEqual(default, constructions.value("KaG"), name)

    def test_cli_offers_every_construction(self):
        from ctsplines.__main__ import _spline_choices

        self.assertEqual(_spline_choices()[0], constructions.names())

    def test_docs_describe_every_construction(self):
        with open(os.path.join(ROOT, "docs", "constructions.md"), encoding="utf-8") as f:
            rows = re.findall(r"^\| `(\w+)` \|", f.read(), flags=re.M)
        self.assertEqual(rows, constructions.names())

    def test_facts(self):
        self.assertEqual(constructions.degree("Quartic"), 4)
        self.assertEqual(constructions.degree("KaG"), 3)
        self.assertNotIn("Kashyap", constructions.stitched())
        self.assertNotIn("Quartic", constructions.with_bezier_extraction())
        self.assertIn("KaG", constructions.stitched())
        with self.assertRaises(ValueError):
            constructions.value("Farin")

    @unittest.skipUnless(ctsplines.HAS_IOCAD, "built without OpenCASCADE")
    def test_cad_classes_refuse_what_they_cannot_stitch(self):
        for cls in (ctsplines.vtkCADFaceSampler, ctsplines.vtkWatertightSplineStitcher):
            obj = cls()
            with VTKMessages() as messages:
                messages.watch(obj)
                obj.SetConstruction(constructions.value("CTi"))
                obj.SetConstruction(constructions.value("Kashyap"))
            self.assertEqual(obj.GetConstruction(), constructions.value("CTi"), cls.__name__)
            self.assertEqual(len(messages.errors), 1, cls.__name__)
            self.assertIn("Kashyap", messages.errors[0])

    def test_boundary_curves_are_refused_by_name(self):
        xy = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], float)
        tris = np.array([[0, 1, 3], [0, 3, 2]])
        zero = np.zeros(len(xy))
        f = ctsplines.vtkCloughTocherSplineFilter()
        f.SetConstructionToKashyap()
        f.SetBoundaryCurvePointsArrayName("Curves")
        f.SetInputData(arrays.functional_mesh(xy, tris, zero, zero, zero))
        with VTKMessages() as messages:
            messages.watch(f)
            f.Update()
        seen = messages.errors
        self.assertEqual(len(seen), 1)
        # The message names the construction and the ones that do take curves, from the table.
        self.assertIn("Kashyap does not take prescribed boundary curves", seen[0])
        self.assertIn(", ".join(constructions.stitched()), seen[0])


if __name__ == "__main__":
    unittest.main()
