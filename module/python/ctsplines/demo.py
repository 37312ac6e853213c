# SPDX-License-Identifier: GPL-3.0-or-later
"""The main job on a built-in default: sample, convert, tessellate, write, render."""
import os

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

from . import (
    vtkBezierTriangleTessellator,
    vtkCloughTocherSplineFilter,
    vtkSampledSurfaceSource,
)


def reflection_line_scalars(points, normals, eye, stripes=12.0):
    """Zebra stripes: the direction of the eye ray reflected at the surface, measured as an angle
    about the x-axis; equal angles form the reflection lines of light lines parallel to x."""
    d = points - np.asarray(eye)[None, :]
    d /= np.linalg.norm(d, axis=1)[:, None]
    r = d - 2.0 * np.sum(d * normals, axis=1)[:, None] * normals
    angle = np.arctan2(r[:, 1], r[:, 2])
    return np.sin(stripes * angle)


def run(output="ctsplines-output", construction="CTi", points=300, level=8, render=True):
    os.makedirs(output, exist_ok=True)
    source = vtkSampledSurfaceSource()
    source.SetSurfaceToFranke()
    source.SetDomainToRandomDelaunay()
    source.SetResolution(points)
    source.SetSeed(1)

    spline = vtkCloughTocherSplineFilter()
    spline.SetInputConnection(source.GetOutputPort())
    getattr(spline, "SetConstructionTo" + construction)()

    tess = vtkBezierTriangleTessellator()
    tess.SetInputConnection(spline.GetOutputPort())
    tess.SetSubdivisionLevel(level)
    tess.Update()
    surface = tess.GetOutput()

    pts = vtk_to_numpy(surface.GetPoints().GetData())
    nrm = vtk_to_numpy(surface.GetPointData().GetArray("Normals"))
    eye = (0.5, -2.5, 3.0)
    stripes = numpy_to_vtk(reflection_line_scalars(pts, nrm, eye), deep=True)
    stripes.SetName("ReflectionLines")
    surface.GetPointData().AddArray(stripes)

    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter, vtkXMLUnstructuredGridWriter

    paths = {
        "spline": os.path.join(output, "spline.vtu"),
        "tessellation": os.path.join(output, "tessellation.vtp"),
    }
    w = vtkXMLUnstructuredGridWriter()
    w.SetFileName(paths["spline"])
    w.SetInputConnection(spline.GetOutputPort())
    w.Write()
    w2 = vtkXMLPolyDataWriter()
    w2.SetFileName(paths["tessellation"])
    w2.SetInputData(surface)
    w2.Write()
    if render:
        paths["image"] = os.path.join(output, "spline.png")
        render_png(surface, "ReflectionLines", paths["image"], eye)
    return paths


def render_png(surface, array, filename, eye, size=(900, 700)):
    """Offscreen rendering (needs an X display: run under xvfb-run on a headless machine)."""
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (registers the OpenGL backend)
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.vtkRenderingCore import (
        vtkActor,
        vtkPolyDataMapper,
        vtkRenderer,
        vtkRenderWindow,
        vtkWindowToImageFilter,
    )
    from vtkmodules.vtkCommonCore import vtkLookupTable

    lut = vtkLookupTable()
    lut.SetNumberOfTableValues(256)
    lut.SetHueRange(0.0, 0.0)
    lut.SetSaturationRange(0.0, 0.0)
    lut.SetValueRange(0.1, 1.0)
    lut.Build()
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(surface)
    mapper.SetScalarModeToUsePointFieldData()
    mapper.SelectColorArray(array)
    mapper.SetLookupTable(lut)
    mapper.SetScalarRange(-1.0, 1.0)
    mapper.ScalarVisibilityOn()
    actor = vtkActor()
    actor.SetMapper(mapper)
    renderer = vtkRenderer()
    renderer.AddActor(actor)
    renderer.SetBackground(1.0, 1.0, 1.0)
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.AddRenderer(renderer)
    window.SetSize(*size)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(*eye)
    camera.SetFocalPoint(0.5, 0.5, 0.4)
    camera.SetViewUp(0.0, 0.0, 1.0)
    renderer.ResetCamera()
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(filename)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    window.Finalize()
