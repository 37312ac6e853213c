# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared plumbing of the paper-reproduction examples: command line, output folder, tables,
pipelines built from the ctsplines filters, offscreen rendering. Imported by the examples next
to it (they put their own folder on sys.path)."""
import argparse
import csv
import os
import sys

import numpy as np

import ctsplines
import ctsplines.constructions
from ctsplines.arrays import point_array, points  # noqa: F401  (used by the examples)
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

# The study's cubic constructions CTo..KaG (those that take boundary curves, from the kernel's
# construction table).
CUBIC = ctsplines.constructions.stitched()
CONSTRUCTIONS = ctsplines.constructions.names()


def parse_args(name, description, extra=None):
    """--output (default ./ctsplines-output/examples/<name>), --quick, --no-render."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--output", default=os.path.join("ctsplines-output", "examples", name),
                   help="output folder (created)")
    p.add_argument("--quick", action="store_true",
                   help="small sizes for the smoke test; still asserts the claims")
    p.add_argument("--no-render", action="store_true", help="skip the PNG renderings")
    if extra:
        extra(p)
    args = p.parse_args()
    os.makedirs(args.output, exist_ok=True)
    return args


def source(surface, domain, resolution, diagonal="Forward", seed=1, affine=None):
    src = ctsplines.vtkSampledSurfaceSource()
    getattr(src, "SetSurfaceTo" + surface)()
    getattr(src, "SetDomainTo" + domain)()
    src.SetResolution(resolution)
    getattr(src, "SetGridDiagonalTo" + diagonal)()
    src.SetSeed(seed)
    if affine is not None:
        src.SetAffineMatrix(*affine)
    src.Update()
    return src


def spline(src, construction, split="Bary", iterations=0, boundary=None):
    f = ctsplines.vtkCloughTocherSplineFilter()
    f.SetInputConnection(src.GetOutputPort())
    getattr(f, "SetConstructionTo" + construction)()
    getattr(f, "SetSplitPointTo" + split)()
    if boundary:
        getattr(f, "SetBoundaryModeTo" + boundary)()
    f.SetIterations(iterations)
    f.Update()
    if f.GetOutput().GetNumberOfCells() == 0:
        raise RuntimeError(f"vtkCloughTocherSplineFilter failed ({construction}/{split})")
    return f


def tessellate(spl, level):
    t = ctsplines.vtkBezierTriangleTessellator()
    t.SetInputConnection(spl.GetOutputPort())
    t.SetSubdivisionLevel(level)
    t.Update()
    return t


def curvature(spl, level):
    """Exact curvatures of a spline (vtkBezierCurvatureFilter) on its tessellation at LEVEL."""
    f = ctsplines.vtkBezierCurvatureFilter()
    f.SetInputConnection(spl.GetOutputPort())
    f.SetSubdivisionLevel(level)
    f.Update()
    return f.GetOutput()


def approximation_error(spl, reference, mode="Parametric", level=8, reference_level=1):
    """Runs vtkApproximationErrorFilter; returns (output, dict of its field data values)."""
    f = ctsplines.vtkApproximationErrorFilter()
    f.SetInputConnection(spl.GetOutputPort())
    if hasattr(reference, "GetOutputPort"):
        f.SetReferenceConnection(reference.GetOutputPort())
    else:
        f.SetReferenceData(reference)
    getattr(f, "SetModeTo" + mode)()
    f.SetSubdivisionLevel(level)
    f.SetReferenceSampleLevel(reference_level)
    f.Update()
    out = f.GetOutput()
    fd = out.GetFieldData()
    if fd.GetArray("MaxError") is None:
        raise RuntimeError("vtkApproximationErrorFilter failed")
    # Numeric entries only: the spline's own field data (construction names) is passed along.
    values = {fd.GetArrayName(i): fd.GetArray(i).GetTuple1(0)
              for i in range(fd.GetNumberOfArrays()) if fd.GetArray(i) is not None}
    return out, values


def add_point_array(data, name, values):
    a = numpy_to_vtk(np.ascontiguousarray(values, dtype=np.float64), deep=True)
    a.SetName(name)
    data.GetPointData().AddArray(a)


def field_value(data, name):
    a = data.GetFieldData().GetArray(name)
    return None if a is None else a.GetValue(0)


def orders(errors):
    """Observed orders log2(e_l / e_{l+1}) of errors on meshes halved in size."""
    e = np.asarray(errors, dtype=float)
    return np.log2(e[:-1] / e[1:])


def write_tables(folder, stem, header, rows, title=None, notes=None):
    """rows: lists of cells (floats are formatted). Writes <stem>.csv and <stem>.md; returns the
    Markdown text."""
    def fmt(x):
        if isinstance(x, float):
            return f"{x:.4g}" if abs(x) >= 1e-3 or x == 0.0 else f"{x:.3e}"
        return str(x)

    with open(os.path.join(folder, stem + ".csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for r in rows:
            w.writerow([repr(x) if isinstance(x, float) else x for x in r])
    lines = []
    if title:
        lines += [f"## {title}", ""]
    lines.append("| " + " | ".join(header) + " |")
    lines.append("|" + "---|" * len(header))
    for r in rows:
        lines.append("| " + " | ".join(fmt(x) for x in r) + " |")
    if notes:
        lines += [""] + list(notes)
    text = "\n".join(lines) + "\n"
    with open(os.path.join(folder, stem + ".md"), "w") as fh:
        fh.write(text)
    return text


def render(surface, filename, array=None, scalar_range=None, colormap="diverging",
           view=((0.5, -2.0, 2.2), (0.5, 0.5, 0.2)), size=(800, 600), title=None):
    """Offscreen PNG of a vtkPolyData, shaded, optionally coloured by a point data array.
    colormap: "diverging" (blue-white-red), "gray" (reflection lines) or "rainbow". Needs an X
    display: run under xvfb-run -a on a headless machine."""
    import vtkmodules.vtkRenderingFreeType  # noqa: F401  (text)
    from ctsplines.demo import offscreen_window, write_png
    from vtkmodules.vtkCommonCore import vtkLookupTable
    from vtkmodules.vtkRenderingAnnotation import vtkScalarBarActor
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer, vtkTextActor

    mapper = vtkPolyDataMapper()
    mapper.SetInputData(surface)
    renderer = vtkRenderer()
    if array:
        lut = vtkLookupTable()
        lut.SetNumberOfTableValues(256)
        if colormap == "gray":
            lut.SetHueRange(0.0, 0.0)
            lut.SetSaturationRange(0.0, 0.0)
            lut.SetValueRange(0.1, 1.0)
        elif colormap == "diverging":
            lut.Build()
            for i in range(256):
                s = i / 255.0
                # blue (0.23, 0.30, 0.75) -> white -> red (0.71, 0.02, 0.15), linear in RGB
                a, b = ((0.23, 0.30, 0.75), (1, 1, 1)) if s < 0.5 else ((1, 1, 1), (0.71, 0.02, 0.15))
                t = s * 2 if s < 0.5 else (s - 0.5) * 2
                lut.SetTableValue(i, *[a[c] + t * (b[c] - a[c]) for c in range(3)], 1.0)
        else:
            lut.SetHueRange(0.667, 0.0)
        if colormap != "diverging":
            lut.Build()
        mapper.SetScalarModeToUsePointFieldData()
        mapper.SelectColorArray(array)
        mapper.SetLookupTable(lut)
        if scalar_range is None:
            scalar_range = surface.GetPointData().GetArray(array).GetRange()
        mapper.SetScalarRange(*scalar_range)
        mapper.ScalarVisibilityOn()
        if colormap != "gray":
            bar = vtkScalarBarActor()
            bar.SetLookupTable(lut)
            bar.SetTitle(array)
            bar.SetNumberOfLabels(5)
            bar.GetTitleTextProperty().SetColor(0, 0, 0)
            bar.GetLabelTextProperty().SetColor(0, 0, 0)
            bar.SetWidth(0.1)
            renderer.AddActor2D(bar)
    else:
        mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    if not array:
        actor.GetProperty().SetColor(0.85, 0.85, 0.8)
    renderer.AddActor(actor)
    renderer.SetBackground(1.0, 1.0, 1.0)
    if title:
        text = vtkTextActor()
        text.SetInput(title)
        text.GetTextProperty().SetColor(0, 0, 0)
        text.GetTextProperty().SetFontSize(18)
        text.SetPosition(10, size[1] - 30)
        renderer.AddActor2D(text)
    window = offscreen_window(renderer, size)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(*view[0])
    camera.SetFocalPoint(*view[1])
    camera.SetViewUp(0.0, 0.0, 1.0)
    renderer.ResetCamera()
    return write_png(window, filename)


def reflection_lines(surface, eye, stripes=12.0):
    """Adds the point array ReflectionLines (zebra stripes of light lines parallel to x in a plane
    above the surface, as the demo shows them) to a surface with Normals."""
    from ctsplines import vtkReflectionLinesFilter

    zebra = vtkReflectionLinesFilter()
    zebra.SetInputData(surface)
    zebra.SetEyePosition(*eye)
    zebra.SetLightPlaneOrigin(0.5, 0.5, 3.0)
    zebra.SetLightPlaneNormal(0.0, 0.0, 1.0)
    zebra.SetLightLineDirection(1.0, 0.0, 0.0)
    zebra.SetSpacing(24.0 / stripes)
    zebra.Update()
    return zebra.GetOutput()


class Checks:
    """Collects pass/fail of the claims an example asserts; exit() ends nonzero on failure."""

    def __init__(self):
        self.failed = []

    def check(self, ok, what):
        print(("PASS " if ok else "FAIL ") + what)
        if not ok:
            self.failed.append(what)

    def exit(self):
        if self.failed:
            print(f"{len(self.failed)} check(s) failed", file=sys.stderr)
            sys.exit(1)
        print("all checks passed")


def continuity(spl):
    """Jumps of a spline across its edges (vtkSplineContinuityFilter): dict with micro/macro
    C0, C1, C2 max and C2 mean, and the study's eq. 7 measure across macro-edges."""
    f = ctsplines.vtkSplineContinuityFilter()
    f.SetInputConnection(spl.GetOutputPort())
    f.Update()
    out = f.GetOutput()
    r = {}
    for kind in ("Macro", "Micro"):
        for m in ("C0Gap", "C1Jump", "C2Jump"):
            r[f"{kind}_{m}_Max"] = field_value(out, f"{kind}_{m}_Max")
        r[f"{kind}_C2Jump_Mean"] = field_value(out, f"{kind}_C2Jump_Mean")
    r["Macro_C2JumpEq7_Max"] = field_value(out, "Macro_C2JumpEq7_Max")
    r["Macro_C2JumpEq7_Mean"] = field_value(out, "Macro_C2JumpEq7_Mean")
    if r["Macro_C2Jump_Max"] is None:
        raise RuntimeError("vtkSplineContinuityFilter failed")
    return r
