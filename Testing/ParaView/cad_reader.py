# SPDX-License-Identifier: GPL-3.0-or-later
"""Run by pvpython: cad_reader.py PLUGIN SOURCE_DIR MODELS_DIR.

The CAD part of the plugin: vtkCADFaceSampler and vtkWatertightSplineStitcher have documented
proxies, File -> Open picks the sampler for .step/.stp/.iges/.igs (OpenDataFile goes through the
same reader factory), and sampler -> stitcher on a closed model gives a watertight grid: no free
edges, C0 gap exactly 0, deviation from the CAD surfaces near the tolerance. MODELS_DIR holds
box_with_hole.step (CAD.WriteTestModel) and, when CAD.FetchModels could fetch it,
component8.step; a missing model is skipped."""
import os
import sys
import xml.etree.ElementTree as ET

from paraview import servermanager
import paraview.simple as simple

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


plugin, source_dir, models = sys.argv[1:4]
simple.LoadPlugin(plugin, remote=False)
pxm = servermanager.ProxyManager()

xml_dir = os.path.join(source_dir, "module", "paraview", "CTSplines", "IOCAD")
for cls, group in (("vtkCADFaceSampler", "sources"), ("vtkWatertightSplineStitcher", "filters")):
    name = cls[3:]
    check(pxm.GetPrototypeProxy(group, name) is not None, f"no proxy {group}/{name}")
    root = ET.parse(os.path.join(xml_dir, cls + ".xml")).getroot()
    for sp in root.iter("SourceProxy"):
        check(sp.get("class") == cls and sp.get("name") == name, f"{cls}.xml: {sp.attrib}")
        check(sp.find("Documentation") is not None, f"{name}: no documentation")
        for prop in sp:
            if prop.tag.endswith("Property"):
                check(prop.find("Documentation") is not None,
                      f"{name}.{prop.get('name')}: no documentation")
        if group == "sources":
            factory = sp.find("Hints/ReaderFactory")
            check(factory is not None and set(factory.get("extensions").split())
                  == {"step", "stp", "iges", "igs"}, f"{name}: reader factory {factory}")
        else:
            check(sp.find("Hints/ShowInMenu[@category='CT Splines']") is not None,
                  f"{name}: not in the CT Splines menu")


def field(data, name):
    a = data.GetFieldData().GetArray(name)
    return a.GetValue(0) if a is not None else float("nan")


def convert(path, tolerance, faces=None):
    reader = simple.OpenDataFile(path)
    check(reader is not None and reader.GetXMLName() == "CADFaceSampler",
          f"{path}: opened by {reader.GetXMLName() if reader else None}")
    if reader is None:
        return
    reader.Tolerance = tolerance
    stitcher = simple.WatertightSplineStitcher(Input=reader, SurfaceSource=reader)
    check(stitcher.Construction == "KaG" and stitcher.BoundaryMode == "Midpoint",
          f"defaults {stitcher.Construction} {stitcher.BoundaryMode}")
    sampled = servermanager.Fetch(reader)
    splines = servermanager.Fetch(stitcher, idx=0)
    merged = servermanager.Fetch(stitcher, idx=1)
    n = sampled.GetNumberOfBlocks()
    name = os.path.basename(path)
    if faces is not None:
        check(n == faces, f"{name}: {n} faces")
    check(splines.GetNumberOfBlocks() == n, f"{name}: {splines.GetNumberOfBlocks()} spline blocks")
    triangles = sum(sampled.GetBlock(f).GetNumberOfCells() for f in range(n))
    check(merged.GetNumberOfCells() == 3 * triangles,
          f"{name}: {merged.GetNumberOfCells()} Bezier triangles for {triangles} triangles")
    check(field(merged, "NumberOfMacroTriangles") == triangles, f"{name}: macro-triangles")
    check(field(merged, "NumberOfFreeEdges") == 0,
          f"{name}: {field(merged, 'NumberOfFreeEdges')} free edges")
    check(field(merged, "NumberOfNonManifoldEdges") == 0, f"{name}: non-manifold edges")
    check(field(merged, "MaxC0Gap") == 0.0, f"{name}: C0 gap {field(merged, 'MaxC0Gap')}")
    deviation = field(merged, "MaxDeviation")
    check(deviation < 10 * tolerance, f"{name}: deviation {deviation}")
    print(f"{name}: {n} faces, {triangles} triangles, free edges "
          f"{field(merged, 'NumberOfFreeEdges'):.0f}, C0 gap {field(merged, 'MaxC0Gap')}, "
          f"max deviation {deviation:.3g}")
    simple.Delete(stitcher)
    simple.Delete(reader)


box = os.path.join(models, "box_with_hole.step")
check(os.path.isfile(box), f"{box} missing (fixture CAD.WriteTestModel)")
if os.path.isfile(box):
    convert(box, 1e-3, faces=7)
component8 = os.path.join(models, "component8.step")
if os.path.isfile(component8):
    convert(component8, 1e-4, faces=21)
else:
    print("component8.step not fetched (gmsh-doc unavailable): skipped")

print(f"{len(failures)} failures")
sys.exit(1 if failures else 0)
