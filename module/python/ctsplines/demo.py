# SPDX-License-Identifier: GPL-3.0-or-later
"""The main job on a built-in default: sample, convert, tessellate, write, render."""
import os

# Registers the OpenGL implementations of mappers and windows; it must precede the creation of any
# rendering object (importing it needs no display).
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

from . import (
    vtkBezierTriangleTessellator,
    vtkCloughTocherSplineFilter,
    vtkReflectionLinesFilter,
    vtkSampledSurfaceSource,
)


def run(output="ctsplines-output", construction="KaG", points=300, level=8, render=True):
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
    # Zebra stripes: reflections of light lines parallel to x in a plane above the surface, seen
    # from the eye; they kink wherever the surface is not curvature continuous.
    eye = (0.5, -2.5, 3.0)
    zebra = vtkReflectionLinesFilter()
    zebra.SetInputConnection(tess.GetOutputPort())
    zebra.SetEyePosition(*eye)
    zebra.SetLightPlaneOrigin(0.5, 0.5, 3.0)
    zebra.SetLightPlaneNormal(0.0, 0.0, 1.0)
    zebra.SetLightLineDirection(1.0, 0.0, 0.0)
    zebra.SetSpacing(4.0)
    zebra.Update()
    surface = zebra.GetOutput()

    from .io import VTKMessages, write

    paths = {
        "spline": os.path.join(output, "spline.vtu"),
        "tessellation": os.path.join(output, "tessellation.vtp"),
    }
    messages = VTKMessages()
    write(spline.GetOutput(), paths["spline"], messages)
    write(surface, paths["tessellation"], messages)
    if render:
        paths["image"] = os.path.join(output, "spline.png")
        render_png(surface, "ReflectionLines", paths["image"], eye)
    return paths


def fit_view(renderer, window, surface, fill=0.92, rounds=3):
    """Pan and zoom so that the surface's projection fills `fill` of the image (ResetCamera fits
    the bounding sphere, which leaves a flat surface small). Perspective makes each round an
    approximation, hence a few rounds."""
    camera = renderer.GetActiveCamera()
    pts = surface.GetPoints()
    step = max(1, pts.GetNumberOfPoints() // 5000)
    samples = [pts.GetPoint(i) for i in range(0, pts.GetNumberOfPoints(), step)]
    width, height = window.GetSize()
    for _ in range(rounds):
        window.Render()
        xs, ys = [], []
        for p in samples:
            renderer.SetWorldPoint(p[0], p[1], p[2], 1.0)
            renderer.WorldToDisplay()
            x, y, _ = renderer.GetDisplayPoint()
            xs.append(x)
            ys.append(y)
        focal = camera.GetFocalPoint()
        renderer.SetWorldPoint(focal[0], focal[1], focal[2], 1.0)
        renderer.WorldToDisplay()
        depth = renderer.GetDisplayPoint()[2]
        renderer.SetDisplayPoint((min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2, depth)
        renderer.DisplayToWorld()
        w = renderer.GetWorldPoint()
        shift = [w[i] / w[3] - focal[i] for i in range(3)]
        position = camera.GetPosition()
        camera.SetFocalPoint(*[focal[i] + shift[i] for i in range(3)])
        camera.SetPosition(*[position[i] + shift[i] for i in range(3)])
        camera.Zoom(fill * min(width / (max(xs) - min(xs)), height / (max(ys) - min(ys))))
        renderer.ResetCameraClippingRange()


def offscreen_window(renderer, size):
    """An offscreen render window showing `renderer` (needs an X display: run under xvfb-run on a
    headless machine)."""
    from vtkmodules.vtkRenderingCore import vtkRenderWindow

    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.AddRenderer(renderer)
    window.SetSize(*size)
    return window


def write_png(window, filename):
    """Renders the window and writes it to a PNG file, then releases the window."""
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(filename)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    window.Finalize()
    return filename


def render_png(surface, array, filename, eye, size=(900, 700)):
    """Offscreen rendering (needs an X display: run under xvfb-run on a headless machine)."""
    from vtkmodules.vtkCommonCore import vtkLookupTable
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

    lut = vtkLookupTable()
    lut.SetNumberOfTableValues(256)
    lut.SetHueRange(0.0, 0.0)
    lut.SetSaturationRange(0.0, 0.0)
    lut.SetValueRange(0.1, 1.0)
    lut.SetNanColor(0.55, 0.6, 0.75, 1.0)  # points that reflect no light line
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
    render_actor(actor, surface, filename, eye, size)


def render_actor(actor, surface, filename, eye, size):
    """PNG of one actor on white, seen from the eye towards the centre of the surface's bounds
    (z up) and zoomed to fill the image (needs an X display: run under xvfb-run on a headless
    machine). Returns the filename."""
    from vtkmodules.vtkRenderingCore import vtkRenderer

    renderer = vtkRenderer()
    renderer.AddActor(actor)
    renderer.SetBackground(1.0, 1.0, 1.0)
    window = offscreen_window(renderer, size)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(*eye)
    bounds = surface.GetBounds()
    camera.SetFocalPoint(*[(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)])
    camera.SetViewUp(0.0, 0.0, 1.0)
    renderer.ResetCamera()
    fit_view(renderer, window, surface)
    return write_png(window, filename)
