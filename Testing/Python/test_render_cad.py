# SPDX-License-Identifier: GPL-3.0-or-later
"""Display-grade tessellation of converted CAD models: the planar faces of the box with a hole
(written by CAD.WriteTestModel) and of as1-tu-203.stp (gmsh-doc, when CAD.FetchModels could fetch
it) carry no point normal more than 1 degree off their plane, and render uniformly shaded. Both
fail with SplitSharpEdges off, where the points of creases and corners share one normal.
Needs an X display (ctest fixture Display) and CTSplines::IOCAD."""
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

import ctsplines

MODELS = os.environ.get("CTSPLINES_CAD_MODELS", "")


def model(name):
    path = os.path.join(MODELS, name)
    return path if MODELS and os.path.isfile(path) else None


def convert(step, folder):
    """The CLI's defaults; returns the merged watertight grid."""
    out = os.path.join(folder, "model.vtm")
    p = subprocess.run([sys.executable, "-m", "ctsplines", "convert", step, "-o", out],
                       capture_output=True, text=True)
    if p.returncode != 0:
        raise AssertionError(p.stdout + p.stderr)
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(os.path.join(folder, "model.vtu"))
    reader.Update()
    return reader.GetOutput()


def tessellate(grid, split=True, level=6):
    t = ctsplines.vtkBezierTriangleTessellator()
    t.SetInputData(grid)
    t.SetSubdivisionLevel(level)
    t.SetSplitSharpEdges(split)
    t.Update()
    return t.GetOutput()


def planar_faces(surface):
    """{face id: (unit plane normal, point ids)} for the faces whose points lie in a plane."""
    xyz = vtk_to_numpy(surface.GetPoints().GetData())
    tri = vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    face = vtk_to_numpy(surface.GetCellData().GetArray("FaceId"))
    diagonal = np.linalg.norm(xyz.max(axis=0) - xyz.min(axis=0))
    planes = {}
    for f in np.unique(face):
        ids = np.unique(tri[face == f])
        centred = xyz[ids] - xyz[ids].mean(axis=0)
        _, s, vt = np.linalg.svd(centred, full_matrices=False)
        if s[2] / np.sqrt(len(ids)) < 1e-10 * diagonal:
            planes[int(f)] = (vt[2], ids)
    return planes


def worst_normal_angle(surface, planes):
    """Largest angle (degrees) between a point normal of a planar face and the face's plane
    normal (either orientation of the plane)."""
    normals = vtk_to_numpy(surface.GetPointData().GetNormals())
    worst = 0.0
    for normal, ids in planes.values():
        cosine = np.clip(np.abs(normals[ids] @ normal), 0.0, 1.0)
        worst = max(worst, float(np.degrees(np.arccos(cosine.min()))))
    return worst


def render(surface, colour_by_face, size=(500, 500)):
    """RGB image of the surface: shaded (one directional headlight, no specular) or flat, each
    face in its own colour and without lighting (the face mask)."""
    from ctsplines.demo import offscreen_window
    from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer,
                                             vtkWindowToImageFilter)

    mapper = vtkPolyDataMapper()
    actor = vtkActor()
    data = surface
    if colour_by_face:
        face = vtk_to_numpy(surface.GetCellData().GetArray("FaceId")).astype(np.int64)
        rgb = np.stack([(face + 1) * 37 % 251, (face + 1) * 91 % 241, (face + 1) * 53 % 239], axis=1)
        data = type(surface)()
        data.ShallowCopy(surface)
        colours = numpy_to_vtk(rgb.astype(np.uint8), deep=True)
        colours.SetName("FaceColour")
        data.GetCellData().SetScalars(colours)
        mapper.SetColorModeToDirectScalars()
        mapper.SetScalarModeToUseCellData()
        actor.GetProperty().LightingOff()
    else:
        mapper.ScalarVisibilityOff()
        actor.GetProperty().SetColor(0.8, 0.8, 0.8)
        actor.GetProperty().SetSpecular(0.0)
    mapper.SetInputData(data)
    actor.SetMapper(mapper)
    renderer = vtkRenderer()
    renderer.AddActor(actor)
    renderer.SetBackground(0, 0, 0)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(1.0, -1.6, 1.3)
    camera.SetFocalPoint(0.0, 0.0, 0.0)
    camera.SetViewUp(0, 0, 1)
    renderer.ResetCamera()
    window = offscreen_window(renderer, size)
    window.SetMultiSamples(0)
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    image = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)
    window.Finalize()
    return image.reshape(size[1], size[0], 3), data if colour_by_face else None


def shading_spread(surface, planes):
    """Largest spread (max - min grey level) of the shaded image over the pixels of one planar
    face, away from its outline (pixels whose 3 x 3 neighbourhood shows the same face)."""
    mask, coloured = render(surface, True)
    shaded, _ = render(surface, False)
    face = vtk_to_numpy(surface.GetCellData().GetArray("FaceId")).astype(np.int64)
    key = mask[..., 0] * 65536 + mask[..., 1] * 256 + mask[..., 2]
    inner = np.ones(key.shape, bool)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            inner &= np.roll(np.roll(key, dy, axis=0), dx, axis=1) == key
    worst, pixels = 0, 0
    for f in planes:
        r, g, b = (f + 1) * 37 % 251, (f + 1) * 91 % 241, (f + 1) * 53 % 239
        where = inner & (key == r * 65536 + g * 256 + b)
        if where.sum() < 50:
            continue  # hidden or seen edge-on
        grey = shaded[where].mean(axis=1)
        worst = max(worst, float(grey.max() - grey.min()))
        pixels += int(where.sum())
    return worst, pixels


@unittest.skipUnless(ctsplines.HAS_IOCAD, "ctsplines was built without CTSplines::IOCAD")
class CADTessellationTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.TemporaryDirectory()
        cls.models = {}
        for name in ("box_with_hole.step", "as1-tu-203.stp"):
            path = model(name)
            if path:
                sub = os.path.join(cls.folder.name, name)
                os.makedirs(sub)
                cls.models[name] = convert(path, sub)

    @classmethod
    def tearDownClass(cls):
        cls.folder.cleanup()

    def grids(self):
        if "box_with_hole.step" not in self.models:
            self.skipTest("box_with_hole.step not written (fixture CAD.WriteTestModel)")
        return self.models.items()

    def test_planar_faces_have_their_plane_normal(self):
        for name, grid in self.grids():
            with self.subTest(model=name):
                split = tessellate(grid)
                planes = planar_faces(split)
                self.assertGreaterEqual(len(planes), 6 if name.startswith("box") else 60)
                self.assertLess(worst_normal_angle(split, planes), 1.0)
                # Watertight all the same: split points keep their coordinates, so the
                # tessellation has the same set of positions as the conforming one.
                merged = tessellate(grid, split=False)
                a = np.unique(vtk_to_numpy(split.GetPoints().GetData()), axis=0)
                b = np.unique(vtk_to_numpy(merged.GetPoints().GetData()), axis=0)
                self.assertTrue(np.array_equal(a, b))
                # The old conforming mesh: corner and crease points share one normal.
                self.assertGreater(worst_normal_angle(merged, planar_faces(merged)), 30.0)

    def test_planar_faces_render_uniformly(self):
        for name, grid in self.grids():
            with self.subTest(model=name):
                split = tessellate(grid)
                planes = planar_faces(split)
                spread, pixels = shading_spread(split, planes)
                self.assertGreater(pixels, 5000)
                self.assertLessEqual(spread, 3.0)
                spread_merged, _ = shading_spread(tessellate(grid, split=False), planes)
                self.assertGreater(spread_merged, 20.0)


if __name__ == "__main__":
    unittest.main()
