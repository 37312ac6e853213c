#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""A converted CAD model shown with per-face colours and reflection lines.

The STEP/IGES model is converted as `python3 -m ctsplines convert` does it (ctsplines.cad:
vtkCADFaceSampler and vtkWatertightSplineStitcher, KaG, tolerance 1e-4 of the diagonal), the
merged watertight grid is tessellated (vtkBezierTriangleTessellator, crease points split so that
every face keeps its own exact normals, cell data FaceId copied to the triangles) and
vtkReflectionLinesFilter adds reflection lines of light lines in a plane above the model, seen
from the camera.

Checks (exit nonzero on failure): the merged grid has no free and no non-manifold edge and a C0
gap of 0; every triangle of the tessellation carries the FaceId of a face of the model and every
face has triangles; the point normals of every planar face (all its Bezier control points in one
plane) are within 1 degree of the plane's normal (crease points are split: each face gets its own
normal there); on every planar face the filter's reflection lines are those of a plane mirror
(computed from the mirrored eye) to 1 % of the stripe spacing.

Writes into --output: model.vtm / model.vtu (the conversion) and, unless --no-render,
face_colours.png and reflection_lines.png (each rendered at twice the size) and both side by side
in cad_reflection_lines.png (1400 x 560).

The default model is as1-tu-203.stp from Debian's gmsh-doc package, looked up in
$CTSPLINES_CAD_MODELS and build/IOCAD/Testing/models/; the ctest fixture fetches it there:

    ctest --test-dir build -R CAD.FetchModels
    xvfb-run -a /usr/bin/python3 Examples/Python/cad_reflection_lines.py [MODEL] [--quick]

--quick tessellates at level 3 and, without as1-tu-203.stp, uses box_with_hole.step (written by
`ctest --test-dir build -R CAD.WriteTestModel`).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import numpy as np  # noqa: E402

import example_common as ex  # noqa: E402
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy  # noqa: E402

DEFAULT_MODEL = "as1-tu-203.stp"
QUICK_FALLBACK = "box_with_hole.step"
MODEL_FOLDERS = [os.environ.get("CTSPLINES_CAD_MODELS", ""),
                 os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "build",
                              "IOCAD", "Testing", "models")]
MAX_PLANAR_ANGLE = 1.0  # degrees
MAX_STRIPE_SHIFT = 0.01  # of the stripe spacing
SIZE = (700, 560)       # per view in the side-by-side picture
SUPERSAMPLING = 2       # the views are rendered this many times larger (--quick: 1)
LIGHT_LINES = np.array([1.0, 0.0, 0.0])
SLATE = (0.7, 0.75, 0.86, 1.0)  # points that reflect no light line


def find_model(quick):
    """The default model's path, or None."""
    for name in [DEFAULT_MODEL] + ([QUICK_FALLBACK] if quick else []):
        for folder in MODEL_FOLDERS:
            path = os.path.join(folder, name)
            if folder and os.path.isfile(path):
                return path
    return None


def convert(model, folder):
    """The CLI's CAD conversion with its defaults; returns the summary (a dict) and a reader of
    the merged grid."""
    from ctsplines import cad, constructions
    from ctsplines.io import Progress, VTKMessages
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    options = {"tolerance": 1e-4, "aspect_ratio": 0.0, "max_edge_length": 0.0,
               "construction": constructions.value("KaG"), "split_point": 0, "boundary_mode": 0,
               "iterations": 0}
    with VTKMessages() as messages:
        summary = cad.convert(model, os.path.join(folder, "model.vtm"), options, messages,
                              Progress(False))
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(summary["merged"])
    reader.Update()
    return summary, reader


def face_cells(grid):
    """The point ids of the merged grid's cells (all Bezier triangles of one order), one row
    each."""
    connectivity = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    return connectivity.reshape(grid.GetNumberOfCells(), -1)


def planar_faces(grid):
    """{FaceId: unit normal} of the faces whose Bezier control points all lie in one plane (to
    1e-10 of the diagonal)."""
    xyz = vtk_to_numpy(grid.GetPoints().GetData())
    cells = face_cells(grid)
    face = vtk_to_numpy(grid.GetCellData().GetArray("FaceId"))
    diagonal = np.linalg.norm(np.ptp(xyz, axis=0))
    planes = {}
    for f in np.unique(face):
        p = xyz[np.unique(cells[face == f])]
        _, s, vt = np.linalg.svd(p - p.mean(axis=0), full_matrices=False)
        if s[-1] / np.sqrt(len(p)) < 1e-10 * diagonal:
            planes[int(f)] = vt[-1]
    return planes


def normal_angles(surface, planes):
    """Per planar face the largest angle (degrees) between a point normal of its triangles and
    the plane (either orientation)."""
    normals = vtk_to_numpy(surface.GetPointData().GetNormals())
    tri = vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    face = vtk_to_numpy(surface.GetCellData().GetArray("FaceId"))
    angles = {}
    for f, n in planes.items():
        cosine = np.abs(normals[np.unique(tri[face == f])] @ n)
        angles[f] = float(np.degrees(np.arccos(np.clip(cosine.min(), 0.0, 1.0))))
    return angles


def face_graph_colours(grid, count):
    """{FaceId: colour index < count}: greedy colouring of the faces' adjacency (faces sharing
    a control point of the merged grid), so that neighbouring faces differ."""
    cells = face_cells(grid)
    face = vtk_to_numpy(grid.GetCellData().GetArray("FaceId")).astype(np.int64)
    pairs = np.unique(np.stack([cells.ravel(), np.repeat(face, cells.shape[1])], axis=1), axis=0)
    starts = np.flatnonzero(np.r_[True, pairs[1:, 0] != pairs[:-1, 0]])
    sizes = np.diff(np.r_[starts, len(pairs)])
    neighbours = {int(f): set() for f in np.unique(face)}
    for s, n in zip(starts[sizes > 1], sizes[sizes > 1]):
        shared = pairs[s:s + n, 1]
        for f in shared:
            neighbours[int(f)].update(int(g) for g in shared if g != f)
    colour = {}
    for f in sorted(neighbours, key=lambda f: -len(neighbours[f])):
        used = {colour[g] for g in neighbours[f] if g in colour}
        # Start from a colour of the face's own (not always the first free one): all colours
        # get used.
        free = [(f + k) % count for k in range(count) if (f + k) % count not in used]
        colour[f] = free[0] if free else f % count
    return colour


def with_face_colours(surface, grid):
    """A copy of the surface with cell scalars FaceColour: a categorical colour per FaceId
    (matplotlib's tab10 without its grey), neighbouring faces in different colours."""
    from matplotlib import colormaps

    # tab10 without its grey, lightened a little: the headlight darkens oblique faces.
    tab10 = np.delete(np.asarray(colormaps["tab10"].colors), 7, axis=0)
    palette = ((0.75 * tab10 + 0.25) * 255).round().astype(np.uint8)
    colour = face_graph_colours(grid, len(palette))
    face = vtk_to_numpy(surface.GetCellData().GetArray("FaceId")).astype(np.int64)
    lookup = np.zeros(face.max() + 1, dtype=np.int64)
    lookup[list(colour)] = list(colour.values())
    coloured = type(surface)()
    coloured.ShallowCopy(surface)
    scalars = numpy_to_vtk(palette[lookup[face]], deep=True)
    scalars.SetName("FaceColour")
    coloured.GetCellData().SetScalars(scalars)
    return coloured


def view(surface):
    """(eye, light plane origin, spacing): the camera looks at the model from the front right,
    above it; the light lines lie in a horizontal plane above the model, parallel to x."""
    b = np.asarray(surface.GetBounds()).reshape(3, 2)
    centre, extent = b.mean(axis=1), b[:, 1] - b[:, 0]
    diagonal = np.linalg.norm(extent)
    eye = centre + diagonal * np.array([0.9, -1.4, 1.1])
    light = centre + np.array([0.0, 0.0, extent[2] / 2 + diagonal])
    return eye, light, diagonal / 20.0


def reflection_lines(surface, eye, light, spacing):
    from ctsplines import vtkReflectionLinesFilter

    zebra = vtkReflectionLinesFilter()
    zebra.SetInputData(surface)
    zebra.SetEyePosition(*eye)
    zebra.SetLightPlaneOrigin(*light)
    zebra.SetLightPlaneNormal(0.0, 0.0, 1.0)
    zebra.SetLightLineDirection(*LIGHT_LINES)
    zebra.SetSpacing(spacing)
    zebra.Update()
    return zebra.GetOutput()


def check_mirrors(checks, surface, planes, eye, light, spacing):
    """On every planar face the filter's ReflectionLineParameter is a plane mirror's: the
    stripes are displaced by less than MAX_STRIPE_SHIFT of their spacing."""
    xyz = vtk_to_numpy(surface.GetPoints().GetData())
    tri = vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    face = vtk_to_numpy(surface.GetCellData().GetArray("FaceId"))
    parameter = ex.point_array(surface, "ReflectionLineParameter")
    print(f"reflection lines: {np.isfinite(parameter).mean():.0%} of the points reflect a light "
          f"line (spacing {spacing:.3g})")
    worst, mismatched, reflecting = 0.0, 0, 0
    for f, n in planes.items():
        ids = np.unique(tri[face == f])
        expected = mirror_parameter(xyz[ids], n, xyz[ids[0]], eye, light)
        got = parameter[ids]
        mismatched += int((np.isfinite(got) != np.isfinite(expected)).sum())
        both = np.isfinite(got) & np.isfinite(expected)
        reflecting += int(both.sum())
        if both.any():
            worst = max(worst, float(np.abs(got[both] - expected[both]).max()) / spacing)
    checks.check(reflecting > 0 and mismatched == 0 and worst < MAX_STRIPE_SHIFT,
                 f"planar faces reflect as plane mirrors: {reflecting} points, stripes shifted by "
                 f"at most {worst:.2g} of their spacing (< {MAX_STRIPE_SHIFT:g}), {mismatched} "
                 "points disagree on reflecting a light line at all")


def mirror_parameter(points, plane_normal, plane_point, eye, light):
    """ReflectionLineParameter of points of a plane mirror, from the mirrored eye: the line from
    the eye's mirror image through x meets the light plane (z = light z) where the reflected ray
    does (NaN where the reflected ray points away from it)."""
    n = plane_normal / np.linalg.norm(plane_normal)
    mirrored = eye - 2.0 * np.dot(eye - plane_point, n) * n
    r = points - mirrored
    lam = (light[2] - points[:, 2]) / r[:, 2]
    hit = points + lam[:, None] * r
    m = np.cross((0.0, 0.0, 1.0), LIGHT_LINES)
    out = (hit - light) @ (m / np.linalg.norm(m))
    out[~(lam >= 0)] = np.nan
    return out


def light_panel(surface, share=0.95):
    """The part (lo, hi) of the light plane, across the lines, that the central `share` of the
    reflecting surface area mirrors. Beyond such a light panel the surface reflects no line:
    grazing reflections reach far out in the plane, and a thin cylinder would mirror all of its
    stripes within a few pixels."""
    xyz = vtk_to_numpy(surface.GetPoints().GetData())
    tri = vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    parameter = ex.point_array(surface, "ReflectionLineParameter")
    edges = xyz[tri[:, 1:]] - xyz[tri[:, :1]]
    area = np.linalg.norm(np.cross(edges[:, 0], edges[:, 1]), axis=1)
    value = parameter[tri].mean(axis=1)
    keep = np.isfinite(value)
    order = np.argsort(value[keep])
    cumulative = np.cumsum(area[keep][order]) / area[keep].sum()
    lo, hi = np.searchsorted(cumulative, [(1.0 - share) / 2, (1.0 + share) / 2])
    return value[keep][order][lo], value[keep][order][min(hi, len(order) - 1)]


def stripes(panel, spacing, table=4096):
    """A grey lookup table over the light panel: black and white bands (a sharpened
    cos(2 pi parameter / spacing)), light slate outside the panel and where no light line is
    reflected (NaN). Rendered with the parameter interpolated per pixel: the per-point
    ReflectionLines value would alias across the large triangles of planar faces."""
    from vtkmodules.vtkCommonCore import vtkLookupTable

    lo, hi = panel
    t = np.linspace(lo, hi, table)
    grey = 0.1 + 0.85 * np.clip(0.5 + 1.2 * np.cos(2.0 * np.pi * t / spacing), 0.0, 1.0)
    lut = vtkLookupTable()
    lut.SetNumberOfTableValues(table)
    lut.SetTableRange(lo, hi)
    for i, g in enumerate(grey):
        lut.SetTableValue(i, g, g, g, 1.0)
    lut.SetNanColor(*SLATE)
    lut.SetBelowRangeColor(*SLATE)
    lut.SetAboveRangeColor(*SLATE)
    lut.UseBelowRangeColorOn()
    lut.UseAboveRangeColorOn()
    return lut


def render(surface, filename, eye, scale, lut=None):
    """PNG of the surface, lit, camera at the eye: coloured by its cell scalars (FaceColour),
    or with a lookup table by the point data ReflectionLineParameter."""
    from ctsplines.demo import render_actor
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

    mapper = vtkPolyDataMapper()
    mapper.SetInputData(surface)
    if lut is None:
        mapper.SetColorModeToDirectScalars()
        mapper.SetScalarModeToUseCellData()
    else:
        mapper.SetScalarModeToUsePointFieldData()
        mapper.SelectColorArray("ReflectionLineParameter")
        mapper.SetLookupTable(lut)
        mapper.UseLookupTableScalarRangeOn()
        mapper.InterpolateScalarsBeforeMappingOn()
    actor = vtkActor()
    actor.SetMapper(mapper)
    if lut is None:
        actor.GetProperty().SetAmbient(0.15)
        actor.GetProperty().SetDiffuse(0.85)
        actor.GetProperty().SetSpecular(0.25)
        actor.GetProperty().SetSpecularPower(30.0)
    else:
        # Half unlit: the stripes are the light; shading only shows the faces' shapes.
        actor.GetProperty().SetAmbient(0.3)
        actor.GetProperty().SetDiffuse(0.7)
    return render_actor(actor, surface, filename, eye, [scale * n for n in SIZE])


def side_by_side(left, right, filename, shrink):
    """The two views next to each other, each shrunk by averaging shrink x shrink pixels
    (supersampling: smooth stripe edges)."""
    import matplotlib.pyplot as plt

    views = []
    for path in (left, right):
        image = plt.imread(path)[..., :3]
        h, w = image.shape[0] // shrink, image.shape[1] // shrink
        blocks = image[:h * shrink, :w * shrink].reshape(h, shrink, w, shrink, 3)
        views.append(blocks.mean(axis=(1, 3)))
    plt.imsave(filename, np.concatenate(views, axis=1))


def main():
    def extra(p):
        p.add_argument("model", nargs="?",
                       help=f"STEP or IGES file (default: {DEFAULT_MODEL} from gmsh-doc)")

    args = ex.parse_args("cad_reflection_lines", __doc__.splitlines()[0], extra)
    import ctsplines

    if not ctsplines.HAS_IOCAD:
        print("cad_reflection_lines: ctsplines was built without OpenCASCADE (CTSplines::IOCAD)",
              file=sys.stderr)
        return 2
    model = args.model or find_model(args.quick)
    if model is None:
        print(f"cad_reflection_lines: {DEFAULT_MODEL} not found in $CTSPLINES_CAD_MODELS or "
              "build/IOCAD/Testing/models/. Fetch it (from Debian's gmsh-doc) with\n"
              "    ctest --test-dir build -R CAD.FetchModels\n"
              "or give a STEP/IGES file on the command line.", file=sys.stderr)
        return 2
    level = 3 if args.quick else 6
    checks = ex.Checks()

    from ctsplines.io import FilterError, InputError

    try:
        summary, reader = convert(model, args.output)
    except (InputError, FilterError) as e:
        print(f"cad_reflection_lines: {e}", file=sys.stderr)
        return 1
    grid = reader.GetOutput()
    print(f"{os.path.basename(model)}: {summary['faces']} faces, {summary['patches']} patches, "
          f"{summary['bezier_triangles']} Bezier triangles")
    checks.check(summary["free_edges"] == 0 and summary["non_manifold_edges"] == 0,
                 f"merged grid: {summary['free_edges']} free and {summary['non_manifold_edges']} "
                 "non-manifold edges (0)")
    checks.check(summary["c0_gap"] == 0.0, f"merged grid: C0 gap {summary['c0_gap']:g} (0)")

    # Crease points split (SplitSharpEdges, the default): each face keeps its own normals.
    surface = ex.tessellate(reader, level).GetOutput()
    face = surface.GetCellData().GetArray("FaceId")
    ids = vtk_to_numpy(face) if face is not None else np.array([], dtype=np.int64)
    grid_ids = np.unique(vtk_to_numpy(grid.GetCellData().GetArray("FaceId")))
    checks.check(len(ids) == surface.GetNumberOfCells() and np.isin(ids, grid_ids).all()
                 and np.array_equal(np.unique(ids), grid_ids)
                 and len(grid_ids) == summary["faces"],
                 f"tessellation (level {level}): each of its {surface.GetNumberOfCells()} "
                 f"triangles has the FaceId of one of the {summary['faces']} faces, every face "
                 "has triangles")
    planes = planar_faces(grid)
    angles = normal_angles(surface, planes)
    worst = max(angles.values(), default=float("nan"))
    checks.check(len(planes) > 0 and worst < MAX_PLANAR_ANGLE,
                 f"{len(planes)} planar faces: point normals at most {worst:.2g} degrees off "
                 f"their plane (< {MAX_PLANAR_ANGLE:g})")

    eye, light, spacing = view(surface)
    surface = reflection_lines(surface, eye, light, spacing)
    check_mirrors(checks, surface, planes, eye, light, spacing)
    if not args.no_render:
        scale = 1 if args.quick else SUPERSAMPLING
        colours = render(with_face_colours(surface, grid),
                         os.path.join(args.output, "face_colours.png"), eye, scale)
        zebra = render(surface, os.path.join(args.output, "reflection_lines.png"), eye, scale,
                       stripes(light_panel(surface), spacing))
        both = os.path.join(args.output, "cad_reflection_lines.png")
        side_by_side(colours, zebra, both, scale)
        print("written", both)
    checks.exit()
    return 0


if __name__ == "__main__":
    sys.exit(main())
