# SPDX-License-Identifier: GPL-3.0-or-later
"""Watertight conversion of a STEP or IGES model for ``python3 -m ctsplines convert``:
vtkCADFaceSampler -> vtkWatertightSplineStitcher, outputs written, numbers gathered."""
import os
import time

from .io import FilterError, InputError, cad_sampler, write

# Errors of vtkCADFaceSampler that mean the file itself could not be used (exit code 3: also a
# malformed file on which OpenCASCADE's translation crashed or did not end within the read
# timeout); the others (an edge without pcurve, a face that cannot be meshed) are the model's
# (exit code 1).
_READ_ERRORS = ("cannot read", "unknown CAD file extension", "no faces in")


def output_paths(output):
    """OUT.vtm (per-face splines; VTK puts the block files into the folder OUT/) and OUT.vtu
    (the merged watertight grid) for an output OUT.vtm."""
    stem, ext = os.path.splitext(output)
    if ext.lower() != ".vtm":
        raise InputError(f"{output}: the per-face splines of a CAD model are a multiblock "
                         "data set, written as .vtm")
    return output, stem + ".vtu"


def _field(data, name, i=0):
    a = data.GetFieldData().GetArray(name)
    return a.GetComponent(i, 0) if a is not None else float("nan")


def _worst_cell(merged, field):
    """Where a maximum is (field data `field` names the merged grid's cell): face, macro-triangle
    and the centre of the cell's corners; None when the field is absent (no deviation measured,
    no tangent interface)."""
    a = merged.GetFieldData().GetArray(field)
    if a is None or merged.GetNumberOfCells() == 0:
        return None
    c = int(a.GetValue(0))
    cd = merged.GetCellData()
    ids = merged.GetCell(c).GetPointIds()
    corners = [merged.GetPoint(ids.GetId(i)) for i in range(3)]  # VTK lists the corners first
    return {"face": int(cd.GetArray("FaceId").GetValue(c)),
            "macro_triangle": int(cd.GetArray("MacroTriangleId").GetValue(c)),
            "point": [sum(p[k] for p in corners) / 3 for k in range(3)]}


def _gap_faces(faces, tolerance):
    """(block index, name, gap relative to the diagonal) of the faces whose surface lies farther
    than half the tolerance from the edge curves they share (the model's own gap): the sampler
    holds those to twice the gap."""
    diagonal = _field(faces, "Diagonal")
    out = []
    for f in range(faces.GetNumberOfBlocks()):
        gap = _field(faces.GetBlock(f), "MaxGap") / diagonal
        if 2 * gap > tolerance:
            name = faces.GetBlock(f).GetFieldData().GetAbstractArray("FaceName")
            out.append((f, name.GetValue(0) if name is not None else f"Face {f}", gap))
    return out


def _fallback_faces(splines):
    """(block index, construction) of the faces built with another construction than the one
    asked for: the sampler's FallbackConstructions, where that one could not get within the
    tolerance."""
    out = []
    for f in range(splines.GetNumberOfBlocks()):
        fd = splines.GetBlock(f).GetFieldData()
        if fd.GetArray("FallbackConstruction") is not None:
            out.append((f, fd.GetAbstractArray("Construction").GetValue(0)))
    return out


def _update(algorithm, messages):
    ok = algorithm.GetExecutive().Update()
    errors = list(dict.fromkeys(messages.take_errors()))
    return ok and not errors, errors


def convert(model, output, options, messages, progress):
    """Samples, converts and stitches MODEL; writes OUTPUT (.vtm) and the merged .vtu beside
    it. options: tolerance, angular_tolerance (degrees, 0 for none), aspect_ratio,
    max_edge_length, construction, split_point, boundary_mode, iterations (ints for the
    enumerations), g1 (RestoreG1, default True), g1_threshold (degrees), read_timeout (seconds; 0
    reads in this process), sew (default True: sew the faces on reading), fallback (default True:
    a face the construction cannot bring within the tolerance takes another, see
    vtkCADFaceSampler::FallbackConstructions). Returns the summary as
    a dict: max_deviation, rms_deviation relative to the diagonal, max_normal_deviation,
    rms_normal_deviation in degrees (not at poles nor at the cusp_nodes, where the face's
    boundary curves touch and the spline's normal is undefined), gap_faces (the faces whose own edge curves lie farther from
    them than half the tolerance: (index, name, relative gap), held to twice the gap),
    fallback_faces ((index, construction name) of the faces built with a fallback),
    max_deviation_at, max_normal_deviation_at, g1_angle_tangent_at (face, macro_triangle and
    point of the worst cell, or None), ..."""
    splines_path, merged_path = output_paths(output)
    sampler = cad_sampler(model, messages)  # InputError first when the build has no IOCAD
    from . import vtkWatertightSplineStitcher

    progress.watch(sampler, "sample faces")
    sampler.SetTolerance(options["tolerance"])
    sampler.SetAngularTolerance(options.get("angular_tolerance", 0.0))
    sampler.SetAspectRatio(options["aspect_ratio"])
    sampler.SetMaxEdgeLength(options.get("max_edge_length", 0.0))
    # Refine the faces for the spline the stitcher will make.
    sampler.SetConstruction(options["construction"])
    sampler.SetSplitPoint(options["split_point"])
    sampler.SetBoundaryMode(options["boundary_mode"])
    sampler.SetRestoreG1(bool(options.get("g1", True)))
    sampler.SetG1Threshold(options.get("g1_threshold", 10.0))
    sampler.SetReadTimeout(options.get("read_timeout", 120.0))
    sampler.SetSew(bool(options.get("sew", True)))
    sampler.SetFallbackConstructions(bool(options.get("fallback", True)))
    # The face blocks only feed the stitcher: their ranges would be a third of a many-face
    # model's peak memory (vtkCADFaceSampler::CacheArrayRanges).
    sampler.SetCacheArrayRanges(False)
    start = time.perf_counter()
    ok, errors = _update(sampler, messages)
    if not ok:
        detail = "\n  ".join(errors or ["the sampler failed"])
        if any(e.split(": ", 1)[-1].startswith(_READ_ERRORS) for e in errors):
            raise InputError(f"{model}: cannot read it:\n  {detail}")
        raise FilterError(f"{model} cannot be sampled:\n  {detail}")
    faces = sampler.GetOutputDataObject(0)

    stitcher = messages.watch(vtkWatertightSplineStitcher())
    progress.watch(stitcher, "splines")
    stitcher.SetInputConnection(sampler.GetOutputPort())
    stitcher.SetConstruction(options["construction"])
    stitcher.SetSplitPoint(options["split_point"])
    stitcher.SetBoundaryMode(options["boundary_mode"])
    stitcher.SetIterations(options["iterations"])
    stitcher.SetSurfaceSource(sampler)  # for the deviation from the CAD surfaces
    ok, errors = _update(stitcher, messages)
    if not ok:
        raise FilterError(f"{model}: the faces cannot be stitched:\n  "
                          + "\n  ".join(errors or ["the stitcher failed"]))
    total = time.perf_counter() - start
    splines = stitcher.GetOutputDataObject(0)
    merged = stitcher.GetOutputDataObject(1)

    write(splines, splines_path, messages)
    write(merged, merged_path, messages)

    n = faces.GetNumberOfBlocks()
    stages = [(name, _field(faces, "StageTimes", i))
              for i, name in enumerate(("read", "edges", "loops", "tangent planes", "faces"))]
    stages += [(name, _field(merged, "StageTimes", i))
               for i, name in enumerate(("splines", "stitch", "merge", "deviation"))]
    return {
        "splines": splines_path,
        "merged": merged_path,
        "faces": n,
        "triangles": sum(faces.GetBlock(f).GetNumberOfCells() for f in range(n)),
        "brep_edges": int(_field(faces, "NumberOfBRepEdges")),
        "diagonal": _field(faces, "Diagonal"),
        "patches": int(_field(merged, "NumberOfMacroTriangles")),
        "bezier_triangles": merged.GetNumberOfCells(),
        "control_points": merged.GetNumberOfPoints(),
        "free_edges": int(_field(merged, "NumberOfFreeEdges")),
        "non_manifold_edges": int(_field(merged, "NumberOfNonManifoldEdges")),
        "extra_non_manifold_edges": int(_field(merged, "NumberOfExtraNonManifoldEdges")),
        "c0_gap": _field(merged, "MaxC0Gap"),
        "gap_before": _field(merged, "MaxGapBeforeStitching"),
        "max_deviation": _field(merged, "MaxDeviation"),
        "rms_deviation": _field(merged, "RMSDeviation"),
        "max_normal_deviation": _field(merged, "MaxNormalDeviation"),
        "max_deviation_at": _worst_cell(merged, "MaxDeviationCell"),
        "max_normal_deviation_at": _worst_cell(merged, "MaxNormalDeviationCell"),
        "rms_normal_deviation": _field(merged, "RMSNormalDeviation"),
        "cusp_nodes": int(_field(merged, "NumberOfCuspNodes")),
        "gap_faces": _gap_faces(faces, options["tolerance"]),
        "fallback_faces": _fallback_faces(splines),
        "edge_gap": _field(faces, "MaxEdgeGap"),
        "sewn_edges": int(_field(faces, "NumberOfSewnEdges")),
        "removed_faces": int(_field(faces, "NumberOfRemovedFaces")),
        "collapsed_edges": int(_field(faces, "NumberOfCollapsedEdges")),
        "sewing_time": _field(faces, "SewingTime"),
        "g1_angle": _field(merged, "MaxG1Angle"),
        "g1_angle_tangent": _field(merged, "MaxG1AngleTangent"),
        "g1_angle_tangent_mean": _field(merged, "MeanG1AngleTangent"),
        "g1_angle_tangent_at": _worst_cell(merged, "MaxG1AngleTangentCell"),
        "tangent_edges": int(_field(merged, "NumberOfTangentInterfaceEdges")),
        "stages": stages,
        "total": total,
    }
