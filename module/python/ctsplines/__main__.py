# SPDX-License-Identifier: GPL-3.0-or-later
"""Command line of CTSplines: ``python3 -m ctsplines {demo,convert,info,sample} ...``.

``demo`` converts the built-in default (Franke's function sampled on a Delaunay triangulation of
seeded random points, with exact gradients) into a cubic Clough-Tocher spline and writes the
Bézier spline (.vtu), its tessellation (.vtp) and a rendered PNG with reflection lines.
``convert`` turns a parametrised triangle mesh from a file into a spline, or a STEP/IGES model
into per-face splines stitched watertight; ``info`` summarises a file and tells whether it is
valid conversion input, ``sample`` writes a mesh of a test surface.

Exit codes: 0 success, 1 the filter rejected the input (its messages are printed), 2 bad command
line, 3 a file is missing, of an unknown format or unreadable.
"""
import argparse
import os
import sys

EXIT_INVALID = 1
EXIT_FILE = 3


def _demo(args):
    from . import demo

    paths = demo.run(
        output=args.output,
        construction=args.construction,
        points=args.points,
        level=args.level,
        render=not args.no_render,
    )
    for kind, path in paths.items():
        print(f"{kind}: {os.path.abspath(path)}")
    return 0


def _names(getter, lo, hi):
    return [getter(i) for i in range(lo, hi + 1)]


def _spline_choices():
    from . import vtkCloughTocherSplineFilter as F

    f = F()
    return (
        _names(F.GetConstructionName, f.GetConstructionMinValue(), f.GetConstructionMaxValue()),
        _names(F.GetSplitPointName, f.GetSplitPointMinValue(), f.GetSplitPointMaxValue()),
        _names(F.GetBoundaryModeName, f.GetBoundaryModeMinValue(), f.GetBoundaryModeMaxValue()),
    )


def _source_choices():
    from . import vtkSampledSurfaceSource as S

    s = S()
    return (
        _names(S.GetSurfaceName, s.GetSurfaceMinValue(), s.GetSurfaceMaxValue()),
        _names(S.GetDomainName, s.GetDomainMinValue(), s.GetDomainMaxValue()),
    )


GRID_DIAGONALS = ["Forward", "Backward", "Alternating"]


def _has(name):
    from . import CTSplinesFilters

    return hasattr(CTSplinesFilters, name)


def _run(algorithm, messages, what):
    """Updates an algorithm; its reported errors become a FilterError."""
    from .io import FilterError

    ok = algorithm.GetExecutive().Update()
    errors = list(dict.fromkeys(messages.take_errors()))
    if errors or not ok:
        raise FilterError(f"{what}:\n  " + "\n  ".join(errors or ["the filter failed"]))
    return algorithm.GetOutputDataObject(0)


def _describe_array(a):
    kind = a.GetDataTypeAsString()
    return f"{a.GetName()} ({a.GetNumberOfComponents()} x {kind})"


def _uv_of(mesh, name):
    """The parameter values the filter would use: the named array, else the texture coords."""
    pd = mesh.GetPointData()
    uv = pd.GetArray(name) if name else None
    if uv is None:
        uv = pd.GetTCoords()
    return uv if uv is not None and uv.GetNumberOfComponents() == 2 else None


DERIVATIVE_METHODS = {"local-quadratic": "LocalQuadratic", "minimum-energy": "MinimumEnergy"}
_DERIVATIVE_NOTES = {"LocalQuadratic": "local quadratic least squares: exact for quadratic surfaces",
                     "MinimumEnergy": "minimum bending energy: exact for planes"}


def _estimate_derivatives(spline, mesh, args):
    """Sets the spline filter's DerivativeEstimation from --derivatives and --derivative-method
    (the filter estimates dFdu, dFdv when the mesh lacks them); returns the mesh to convert:
    for --derivatives estimate a shallow copy without the file's derivative arrays."""
    if args.derivatives == "file":
        spline.SetDerivativeEstimationToNone()
        return mesh
    spline.SetDerivativeEstimation(getattr(spline, DERIVATIVE_METHODS[args.derivative_method]))
    if args.derivatives == "estimate":
        out = mesh.NewInstance()
        out.ShallowCopy(mesh)
        for name in (args.du_array, args.dv_array):
            out.GetPointData().RemoveArray(name)
        return out
    return mesh


def _log_estimated_derivatives(result, args, log):
    from .arrays import field_values

    method = field_values(result).get("DerivativeEstimation", "None")
    if method != "None":
        log(f"note: estimated {args.du_array} and {args.dv_array} from the positions "
            f"({_DERIVATIVE_NOTES[method]})")


def _needs_derivatives(mesh, args):
    pd = mesh.GetPointData()
    return pd.GetArray(args.du_array) is None or pd.GetArray(args.dv_array) is None


def _configure_spline(spline, args):
    spline.SetConstruction(args._choices[0].index(args.construction))
    spline.SetSplitPoint(args._choices[1].index(args.split_point))
    spline.SetBoundaryMode(args._choices[2].index(args.boundary_mode))
    spline.SetIterations(args.iterations)
    spline.SetUVArrayName(args.uv_array)
    spline.SetDuArrayName(args.du_array)
    spline.SetDvArrayName(args.dv_array)
    spline.SetEdgeGradientsArrayName(args.edge_gradients_array)


def _print_continuity(spline_output, messages, progress):
    from . import vtkSplineContinuityFilter
    from .arrays import field_values

    cont = messages.watch(vtkSplineContinuityFilter())
    progress.watch(cont, "continuity")
    cont.SetInputData(spline_output)
    fields = field_values(_run(cont, messages, "continuity analysis failed"))
    print("continuity (largest Rule A jumps per edge kind; G1 angle in degrees):")
    for kind in ("Macro", "Micro", "Boundary", "Interface"):
        count = int(fields.get(f"{kind}_EdgeCount", [0])[0])
        if count == 0:
            continue
        values = "  ".join(
            f"{m} {float(fields[f'{kind}_{m}_Max'][0]):.3e}"
            for m in ("C0Gap", "C1Jump", "C2Jump", "G1Angle") if f"{kind}_{m}_Max" in fields)
        print(f"  {kind.lower():<9} {count:>8} edges  {values}")


def _print_error(spline_output, reference, label, level, messages, progress):
    from . import vtkApproximationErrorFilter
    from .arrays import field_values

    err = messages.watch(vtkApproximationErrorFilter())
    progress.watch(err, "error")
    err.SetInputData(spline_output)
    err.SetReferenceData(reference)
    parametric = _uv_of(reference, "UV") is not None and label != "input"
    if parametric:
        err.SetModeToParametric()
    else:
        err.SetModeToMeshDistance()
        err.SetSubdivisionLevel(level)
    f = field_values(_run(err, messages, "error analysis failed"))
    what = ("distance to the input triangles" if label == "input" else
            f"error against {label} ({'parametric' if parametric else 'mesh distance'})")
    print(f"{what}: max {float(f['MaxError'][0]):.3e} (relative "
          f"{float(f['RelativeMaxError'][0]):.3e}), RMS {float(f['RMSError'][0]):.3e} (relative "
          f"{float(f['RelativeRMSError'][0]):.3e})")


def _cell_summary(data):
    from vtkmodules.vtkCommonDataModel import vtkCellTypes

    counts = {}
    for i in range(data.GetNumberOfCells()):
        t = data.GetCellType(i)
        counts[t] = counts.get(t, 0) + 1
    return {vtkCellTypes.GetClassNameFromTypeId(t).replace("vtk", ""): n
            for t, n in sorted(counts.items())}


def _bezier_order(data):
    """Orders of the VTK_BEZIER_TRIANGLE cells (n from (n+1)(n+2)/2 points)."""
    from vtkmodules.vtkCommonDataModel import VTK_BEZIER_TRIANGLE

    orders = set()
    for i in range(data.GetNumberOfCells()):
        if data.GetCellType(i) != VTK_BEZIER_TRIANGLE:
            return None
        m = data.GetCell(i).GetNumberOfPoints()
        n = int(round(((8 * m + 1) ** 0.5 - 3) / 2))
        orders.add(n)
    return sorted(orders) if orders else None


def _cad_usage(args):
    """Checks the options of a CAD conversion; argparse's error() exits with 2."""
    from . import constructions

    cubic = constructions.stitched()
    if args.construction not in cubic:
        args._parser.error(f"a CAD model takes one of the cubic constructions {', '.join(cubic)}"
                           " (the faces are stitched through their cubic boundary curves)")
    for option, value in (("--tessellate", args.tessellate), ("--tessellation", args.tessellation),
                          ("--reference", args.reference)):
        if value is not None:
            args._parser.error(f"{option} applies to meshes, not to CAD models")


def _json_value(value):
    """NaN (a figure the filters did not report) as null, tuples as lists: strict JSON."""
    if isinstance(value, float) and value != value:
        return None
    if isinstance(value, (list, tuple)):
        return [_json_value(v) for v in value]
    return value


def _write_cad_summary(args, options, result, warnings, error=None):
    """--summary-json: every figure of the conversion (cad.convert's dict), the options, the
    warnings and the exit status; on error the message the CLI prints after `error:`."""
    import json

    summary = {"model": args.input, "options": options,
               "warnings": list(dict.fromkeys(warnings)),
               "exit_status": 0 if error is None else _error_status(error),
               "error": None if error is None else str(error)}
    if error is not None and not isinstance(error, _expected_errors()):
        summary["error"] = f"uncaught {type(error).__name__}: {error}"
    for key, value in (result or {}).items():
        summary[key] = _json_value(value)
    try:
        with open(args.summary_json, "w", encoding="utf-8") as f:
            json.dump(summary, f, indent=1)
            f.write("\n")
    except OSError as e:  # the conversion's own outcome (and exit code) stays what it was
        print(f"warning: cannot write the summary {args.summary_json}: {e.strerror}",
              file=sys.stderr)


def _place(where):
    """A worst cell of the merged grid (cad.convert's *_at): face, macro-triangle, point."""
    x, y, z = where["point"]
    return (f"face {where['face']}, macro-triangle {where['macro_triangle']}, near "
            f"({x:.6g}, {y:.6g}, {z:.6g})")


def _convert_cad(args):
    from . import cad
    from .io import Progress, VTKMessages, check_output_folder

    _cad_usage(args)
    output = args.output or os.path.splitext(os.path.basename(args.input))[0] + ".vtm"
    for path in (output, args.summary_json):
        if path:
            check_output_folder(path)
    options = {
        "tolerance": 1e-4 if args.tolerance is None else args.tolerance,
        "angular_tolerance": args.angular_tolerance or 0.0,
        "aspect_ratio": args.aspect_ratio or 0.0,
        "max_edge_length": args.max_edge_length or 0.0,
        "construction": args._choices[0].index(args.construction),
        "split_point": args._choices[1].index(args.split_point),
        "boundary_mode": args._choices[2].index(args.boundary_mode),
        "iterations": args.iterations,
        "g1": args.g1 is not False,
        "g1_threshold": 10.0 if args.g1_threshold is None else args.g1_threshold,
        "read_timeout": args.read_timeout,
        "sew": not args.no_sew,
        "fallback": not args.no_fallback,
    }
    progress = Progress(Progress.wanted(args.progress))
    with VTKMessages() as messages:
        try:
            r = cad.convert(args.input, output, options, messages, progress)
        except BaseException as e:
            if args.summary_json and not isinstance(e, KeyboardInterrupt):
                _write_cad_summary(args, options, None, messages.warnings, e)
            raise
        for w in dict.fromkeys(messages.warnings):
            print(f"warning: {w}", file=sys.stderr)
    if args.summary_json:
        _write_cad_summary(args, options, r, messages.warnings)
    d = r["diagonal"]
    print(f"model: {args.input} ({r['faces']} faces, {r['brep_edges']} B-rep edges, "
          f"{r['triangles']} triangles; tolerance {options['tolerance']:g} of the diagonal "
          f"{d:.6g})")
    print(f"splines: {r['splines']} (one block per face, {args.construction}, "
          f"{args.split_point}, {args.boundary_mode}, {args.iterations} iterations)")
    print(f"watertight: {r['merged']} ({r['patches']} patches, {r['bezier_triangles']} Bézier "
          f"triangles, {r['control_points']} control points)")
    print(f"free edges: {r['free_edges']} (non-manifold edges: {r['non_manifold_edges']}, "
          f"{r['extra_non_manifold_edges']} of them not on a B-rep edge of 3 or more faces)")
    print(f"healing: {r['sewn_edges']} edges sewn"
          + (f" in {r['sewing_time']:.3f} s" if r["sewing_time"] > 0 else "")
          + ("" if options["sew"] else " (--no-sew)")
          + f", {r['removed_faces']} sliver faces removed, {r['collapsed_edges']} edges "
          "collapsed")
    print(f"C0 gap: max {r['c0_gap']:.3e} (relative {r['c0_gap'] / d:.3e}); before stitching "
          f"{r['gap_before']:.3e} (relative {r['gap_before'] / d:.3e})")
    print(f"deviation from the CAD surfaces (relative to the diagonal): max "
          f"{r['max_deviation']:.3e}, RMS {r['rms_deviation']:.3e}; normals: max "
          f"{r['max_normal_deviation']:.3g} degrees, RMS {r['rms_normal_deviation']:.3g}"
          + (f", undefined at {r['cusp_nodes']} cusp nodes (boundary curves touching)"
             if r["cusp_nodes"] else "")
          + (f" (angular tolerance {options['angular_tolerance']:g})"
             if options["angular_tolerance"] else ""))
    for what, where, array in (("deviation", r["max_deviation_at"], "Deviation"),
                               ("normal deviation", r["max_normal_deviation_at"],
                                "NormalDeviation")):
        if where:
            print(f"largest {what}: {_place(where)} (cell data {array} of {r['merged']})")
    for f, name, gap in r["gap_faces"]:
        print(f"model gap: face {f} ({name}) lies {gap:.3e} of the diagonal from its shared "
              f"edge curves, more than half the tolerance: held to {2 * gap:.3e} there")
    if r["fallback_faces"]:
        print(f"fallback constructions: {len(r['fallback_faces'])} face(s) that "
              f"{args.construction} could not bring within the tolerance built with another: "
              + ", ".join(f"face {f} {c}" for f, c in r["fallback_faces"]))
    print(f"G1 angle across interfaces: max {r['g1_angle']:.3g} degrees; over the "
          f"{r['tangent_edges']} macro-edges where the CAD faces meet tangentially max "
          f"{r['g1_angle_tangent']:.3g}, mean {r['g1_angle_tangent_mean']:.3g}"
          + f" (tangent within {options['g1_threshold']:g} degrees"
          + (", RestoreG1)" if options["g1"] else ")"))
    if r["g1_angle_tangent_at"]:
        print(f"largest G1 angle at a tangent interface: {_place(r['g1_angle_tangent_at'])} (the "
              "cell on one side of the macro-edge)")
    print("time [s]: " + ", ".join(f"{name} {t:.3f}" for name, t in r["stages"])
          + f"; total {r['total']:.3f}")
    return 0


def _convert(args):
    from . import vtkBezierTriangleTessellator, vtkCloughTocherSplineFilter
    from .io import Progress, VTKMessages, as_polydata, check_output_folder, is_cad, read, write

    if args.output_option is not None:
        if args.output is not None and args.output != args.output_option:
            args._parser.error("give the output once: as OUTPUT or with -o")
        args.output = args.output_option
    if is_cad(args.input):
        if args.construction is None:
            args.construction = "KaG"  # the stitcher's and the study's choice
        return _convert_cad(args)
    if args.output is None:
        args._parser.error("the output spline is required for a mesh (OUTPUT or -o)")
    for option, value in (("--tolerance", args.tolerance),
                          ("--angular-tolerance", args.angular_tolerance),
                          ("--aspect-ratio", args.aspect_ratio),
                          ("--max-edge-length", args.max_edge_length),
                          ("--g1" if args.g1 else "--no-g1", args.g1),
                          ("--g1-threshold", args.g1_threshold),
                          ("--summary-json", args.summary_json),
                          ("--no-sew", args.no_sew or None),
                          ("--no-fallback", args.no_fallback or None)):
        if value is not None:
            args._parser.error(f"{option} applies to CAD models (.step, .stp, .iges, .igs)")
    if args.construction is None:
        args.construction = "CTi"
    for path in (args.output, args.tessellation):
        if path:
            check_output_folder(path)

    log = lambda text: print(text, file=sys.stderr)  # noqa: E731
    progress = Progress(Progress.wanted(args.progress))
    with VTKMessages() as messages:
        mesh = as_polydata(read(args.input, messages))
        reference = None
        if args.reference:
            reference = as_polydata(read(args.reference, messages))

        spline = messages.watch(vtkCloughTocherSplineFilter())
        progress.watch(spline, "spline")
        _configure_spline(spline, args)
        spline.SetInputData(_estimate_derivatives(spline, mesh, args))
        result = _run(spline, messages, f"{args.input} is not valid input")
        _log_estimated_derivatives(result, args, log)
        write(result, args.output, messages)
        orders = _bezier_order(result) or ["?"]
        print(f"spline: {args.output} ({result.GetNumberOfCells()} Bézier triangles of order "
              f"{', '.join(map(str, orders))}, {result.GetNumberOfPoints()} control points; "
              f"{mesh.GetNumberOfCells()} input triangles, {args.construction}, "
              f"{args.split_point}, {args.boundary_mode}, {args.iterations} iterations)")

        if args.tessellate is not None:
            tess = messages.watch(vtkBezierTriangleTessellator())
            progress.watch(tess, "tessellation")
            tess.SetSubdivisionLevel(args.tessellate)
            tess.SetUVArrayName(args.uv_array)
            tess.SetInputData(result)
            surface = _run(tess, messages, "tessellation failed")
            path = args.tessellation or os.path.splitext(args.output)[0] + ".vtp"
            write(surface, path, messages)
            print(f"tessellation: {path} ({surface.GetNumberOfCells()} triangles, "
                  f"{surface.GetNumberOfPoints()} points, level {args.tessellate})")

        if not args.no_analysis:
            if _has("vtkSplineContinuityFilter"):
                _print_continuity(result, messages, progress)
            if _has("vtkApproximationErrorFilter"):
                level = args.tessellate or 4
                if reference is not None:
                    _print_error(result, reference, args.reference, level, messages, progress)
                else:
                    _print_error(result, mesh, "input", level, messages, progress)
        for w in dict.fromkeys(messages.warnings):
            log(f"warning: {w}")
    return 0


def _info(args):
    from . import vtkCloughTocherSplineFilter
    from .io import VTKMessages, as_polydata, read

    with VTKMessages() as messages:
        data = read(args.file, messages)
        print(f"file: {args.file} ({data.GetClassName()})")
        print(f"points: {data.GetNumberOfPoints()}")
        cells = _cell_summary(data)
        print(f"cells: {data.GetNumberOfCells()}"
              + (f" ({', '.join(f'{n} {t}' for t, n in cells.items())})" if cells else ""))
        for label, attrs in (("point data", data.GetPointData()),
                             ("cell data", data.GetCellData())):
            names = [_describe_array(attrs.GetAbstractArray(i))
                     for i in range(attrs.GetNumberOfArrays())]
            tcoords = attrs.GetTCoords() if label == "point data" else None
            if tcoords is not None and tcoords.GetName():
                names = [n + (" [texture coordinates]" if n.startswith(tcoords.GetName() + " (")
                              else "") for n in names]
            print(f"{label}: {', '.join(names) if names else '(none)'}")
        fd = data.GetFieldData()
        fields = []
        for i in range(fd.GetNumberOfArrays()):
            a = fd.GetAbstractArray(i)
            if a.IsA("vtkStringArray") and a.GetNumberOfValues() == 1:
                fields.append(f"{a.GetName()} = {a.GetValue(0)}")
            else:
                fields.append(_describe_array(a))
        if fields:
            print(f"field data: {', '.join(fields)}")

        orders = _bezier_order(data)
        if orders:
            print(f"spline: Bézier triangles of order {', '.join(map(str, orders))} (the output "
                  "of convert, not conversion input)")
            return 0
        try:
            mesh = as_polydata(data)
        except Exception as e:  # an InputError for volume cells: not a surface at all
            print(f"valid input: no\n  {e}")
            return EXIT_INVALID
        spline = messages.watch(vtkCloughTocherSplineFilter())
        _configure_spline(spline, args)
        spline.SetInputData(mesh)
        spline.Update()
        errors = messages.take_errors()
        if errors:
            print("valid input: no")
            for e in dict.fromkeys(errors):
                print(f"  {e}")
            if _needs_derivatives(mesh, args) and _uv_of(mesh, args.uv_array) is not None:
                print(f"  hint: the file has parameter values but no {args.du_array}/"
                      f"{args.dv_array}; `convert` estimates them (--derivatives auto)")
            return EXIT_INVALID
        out = spline.GetOutput()
        print(f"valid input: yes ({args.construction} gives {out.GetNumberOfCells()} Bézier "
              f"triangles, {out.GetNumberOfPoints()} control points)")
    return 0


def _sample(args):
    from . import vtkSampledSurfaceSource
    from .io import Progress, VTKMessages, write

    surfaces, domains = _source_choices()
    progress = Progress(Progress.wanted(args.progress))
    with VTKMessages() as messages:
        source = messages.watch(vtkSampledSurfaceSource())
        progress.watch(source, "sample")
        source.SetSurface(surfaces.index(args.surface))
        source.SetDomain(domains.index(args.domain))
        if args.resolution is not None:
            source.SetResolution(args.resolution)
        source.SetGridDiagonal(GRID_DIAGONALS.index(args.grid_diagonal))
        source.SetSeed(args.seed)
        source.SetAffineMatrix(*args.affine)
        source.SetAffineTranslation(*args.translation)
        mesh = _run(source, messages, "cannot sample the surface")
        write(mesh, args.output, messages)
    print(f"sample: {args.output} ({args.surface} on {args.domain}: "
          f"{mesh.GetNumberOfCells()} triangles, {mesh.GetNumberOfPoints()} points)")
    return 0


def _add_spline_options(p, choices, cad=False):
    constructions, splits, boundaries = choices
    g = p.add_argument_group("spline construction")
    # convert resolves None: CTi for meshes, KaG for CAD models.
    g.add_argument("--construction", "-c", default=None if cad else "CTi", choices=constructions,
                   help="how the central control points are fixed: CTo and MGo are local; CTi, "
                   "Fa, FO, Ka, MGi and KaG read the neighbours (MG and KaG need the "
                   "EdgeGradients cell data); Kashyap is Kashyap's cubic fairing scheme; "
                   "Quartic is Fang and Mann's quartic scheme (default "
                   + ("CTi for meshes, KaG for CAD models, which take CTo to KaG only)" if cad
                      else "%(default)s)"))
    g.add_argument("--split-point", default="Bary", choices=splits,
                   help="the point splitting every triangle into three: barycentre or one of "
                   "two incentre rules (default %(default)s)")
    g.add_argument("--boundary-mode", default="Midpoint", choices=boundaries,
                   help="rule for boundary edges of the constructions that read neighbours; "
                   "the Gradient modes need EdgeGradients (default %(default)s)")
    g.add_argument("--iterations", "-n", type=_non_negative, default=0,
                   help="iterative C2 minimisation steps after the construction; for Kashyap "
                   "and Quartic, fairing rounds (default %(default)s)")
    a = p.add_argument_group("input arrays")
    a.add_argument("--uv-array", default="UV",
                   help="2-component point data of parameter values; without it the texture "
                   "coordinates are used, as OBJ and PLY files have them (default %(default)s)")
    a.add_argument("--du-array", default="dFdu",
                   help="3-component point data of derivatives dF/du (default %(default)s)")
    a.add_argument("--dv-array", default="dFdv",
                   help="3-component point data of derivatives dF/dv (default %(default)s)")
    a.add_argument("--edge-gradients-array", default="EdgeGradients",
                   help="18-component cell data of mid-edge gradients (default %(default)s)")


def _non_negative(text):
    value = int(text)
    if value < 0:
        raise argparse.ArgumentTypeError(f"{value} is negative")
    return value


def _positive(text):
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} is not positive")
    return value


def _tolerance(text):
    value = float(text)
    if not 1e-9 <= value <= 1:  # vtkCADFaceSampler's range; it would clamp silently
        raise argparse.ArgumentTypeError(f"{text} is not between 1e-9 and 1")
    return value


def _angle(text):
    value = float(text)
    if not 0 <= value <= 90:
        raise argparse.ArgumentTypeError(f"{text} is not an angle in [0, 90] degrees")
    return value


def _non_negative_float(text):
    value = float(text)
    if not value >= 0:
        raise argparse.ArgumentTypeError(f"{text} is negative")
    return value


def _progress_option(p):
    p.add_argument("--progress", dest="progress", action="store_true", default=None,
                   help="show a progress bar on stderr (default: when stderr is a terminal)")
    p.add_argument("--no-progress", dest="progress", action="store_false",
                   help="never show the progress bar")


def build_parser():
    parser = argparse.ArgumentParser(
        prog="python3 -m ctsplines",
        description="Clough-Tocher splines of parametrised triangle meshes (VTK).",
        epilog="Exit codes: 0 success, 1 invalid input (the filter's messages are printed), "
        "2 bad command line, 3 missing, unknown or unreadable file.",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    choices = _spline_choices()
    _add_demo_command(sub, choices)
    _add_convert_command(sub, choices)
    _add_info_command(sub, choices)
    _add_sample_command(sub)
    return parser


def _add_demo_command(sub, choices):
    demo = sub.add_parser(
        "demo",
        help="convert the built-in default surface and write .vtu, .vtp and .png",
        description="Converts Franke's function on a Delaunay triangulation of seeded random "
        "points into a cubic C1 Clough-Tocher spline; writes the Bézier spline (spline.vtu), its "
        "tessellation (tessellation.vtp) and a PNG with reflection lines (spline.png).",
    )
    demo.add_argument("--output", "-o", default="ctsplines-output", help="output folder")
    demo.add_argument(
        "--construction",
        default="KaG",
        choices=choices[0],
        help="Clough-Tocher construction (default KaG, the study's recommendation)",
    )
    demo.add_argument("--points", type=int, default=300, help="random interior samples")
    demo.add_argument("--level", type=int, default=8, help="tessellation segments per cell edge")
    demo.add_argument("--no-render", action="store_true", help="skip the PNG")
    demo.set_defaults(func=_demo)


def _add_convert_command(sub, choices):
    convert = sub.add_parser(
        "convert",
        help="convert a parametrised triangle mesh file into a Bézier spline (.vtu), or a "
        "STEP/IGES model into watertight per-face splines (.vtm + .vtu)",
        description="Reads a triangle mesh whose points carry parameter values (point data UV, "
        "or texture coordinates as in OBJ and PLY files) and, ideally, first derivatives dFdu, "
        "dFdv; converts it into a Clough-Tocher spline of Bézier triangles and writes it as "
        "VTU. Missing derivatives are estimated from the positions (see --derivatives). Prints "
        "the continuity across the cell edges and the distance to the input triangles (or the "
        "error against --reference). "
        "A CAD model (.step, .stp, .iges, .igs) is sampled face by face, edge first "
        "(--tolerance), every face converted and the faces stitched with C0 continuity: "
        "`-o OUT.vtm` writes the per-face splines to OUT.vtm (one block per B-rep face; VTK "
        "keeps the block files in the folder OUT/) and the merged watertight grid to OUT.vtu "
        "(default OUT: the model's name in the current folder). Prints faces, triangles, "
        "patches, free edges, the C0 gap, the deviation from the CAD surfaces and the time per "
        "stage.",
    )
    convert.add_argument("input", help="input mesh: .vtp, .vtu, .vtk, .obj or .ply; or a CAD "
                         "model: .step, .stp, .iges or .igs")
    convert.add_argument("output", nargs="?",
                         help="the spline, .vtu (or legacy .vtk); for a CAD model the per-face "
                         "splines, .vtm (the merged grid goes to the same name with .vtu)")
    convert.add_argument("--output", "-o", dest="output_option", metavar="OUTPUT",
                         help="the same as the positional OUTPUT")
    _add_spline_options(convert, choices, cad=True)
    _add_cad_options(convert)
    convert.add_argument("--derivatives", choices=["auto", "file", "estimate"], default="auto",
                         help="auto: use the file's derivative arrays, estimate them when "
                         "missing; file: only the file's (missing ones are an error); "
                         "estimate: always estimate, ignoring the file's (default %(default)s)")
    convert.add_argument("--derivative-method", choices=list(DERIVATIVE_METHODS),
                         default="local-quadratic",
                         help="how derivatives are estimated: local-quadratic fits a quadratic "
                         "over each vertex's neighbour rings (exact for quadratic surfaces, "
                         "affine invariant); minimum-energy minimises the spline's bending "
                         "energy per coordinate (exact for planes, smoother, global) "
                         "(default %(default)s)")
    out = convert.add_argument_group("outputs and analysis")
    out.add_argument("--tessellate", "-t", type=_positive, metavar="LEVEL",
                     help="also write the tessellation with LEVEL segments per cell edge "
                     "(LEVEL^2 triangles per Bézier triangle)")
    out.add_argument("--tessellation", metavar="PATH",
                     help="where the tessellation goes (default: OUTPUT with .vtp)")
    out.add_argument("--reference", metavar="FILE",
                     help="report the error against this surface: parametric when it has UV "
                     "(e.g. a finer `sample` of the same surface), else mesh distance")
    out.add_argument("--no-analysis", action="store_true",
                     help="skip the continuity and error summaries")
    _progress_option(convert)
    convert.set_defaults(func=_convert, _choices=choices, _parser=convert)


def _add_cad_options(convert):
    """The convert command's options for CAD models."""
    cad = convert.add_argument_group("CAD models (.step, .stp, .iges, .igs)")
    cad.add_argument("--tolerance", type=_tolerance, metavar="REL",
                     help="error bound of the edge and face sampling, relative to the model's "
                     "bounding-box diagonal (default 1e-4)")
    cad.add_argument("--angular-tolerance", type=_angle, metavar="DEG",
                     help="bound on the angle between the spline's normals and the CAD "
                     "surfaces' (like OpenCASCADE's angular deflection): edges and faces are "
                     "refined until it holds; 0 for none (default 0: the tolerance alone)")
    cad.add_argument("--aspect-ratio", type=_non_negative_float, metavar="RATIO",
                     help="bound on the 3D aspect ratio of the sampled triangles (1 is "
                     "equilateral); 0 for none (default 0)")
    cad.add_argument("--max-edge-length", type=_non_negative_float, metavar="REL",
                     help="bound on the 3D length of triangle edges and edge spans, relative to "
                     "the diagonal (with --aspect-ratio, meets the bound next to the boundary "
                     "too); 0 for none (default 0)")
    g1 = cad.add_mutually_exclusive_group()
    g1.add_argument("--g1", dest="g1", action="store_true", default=None,
                    help="make interfaces where the CAD faces meet tangentially G1 (within 0.1 "
                    "degrees, the deviation within the tolerance): one tangent plane at every "
                    "boundary node and span midpoint there, spans split where needed (default)")
    g1.add_argument("--no-g1", dest="g1", action="store_false",
                    help="leave the tangent interfaces as the faces' own data make them (the G1 "
                    "angle is still measured)")
    cad.add_argument("--g1-threshold", type=_angle, metavar="DEGREES",
                     help="largest angle between the faces' normals for an interface to count as "
                     "tangent (default 10)")
    cad.add_argument("--no-sew", action="store_true",
                     help="keep the file's topology: by default faces whose free edges lie within "
                     "the tolerance of each other are sewn on reading (IGES surface models, STEP "
                     "files of loose faces), also across removed sliver faces of no width; "
                     "openings it leaves (missing faces) stay open, each described in a warning")
    cad.add_argument("--no-fallback", action="store_true",
                     help="build every face with --construction: by default a face it cannot "
                     "bring within the tolerance where no point can go in (a domain narrowing to "
                     "a wedge as wide as its triangles) is built with the stitchable construction "
                     "that gets closest, said in a warning and in the summary")
    cad.add_argument("--read-timeout", type=_non_negative_float, metavar="SECONDS", default=120.0,
                     help="OpenCASCADE translates the file in a separate process, which is "
                     "abandoned after this time (a malformed file on which it loops or crashes is "
                     "then an error, exit code 3); 0 translates in this process without a limit "
                     "(default %(default)g)")
    cad.add_argument("--summary-json", metavar="PATH",
                     help="also write the summary as JSON: every figure printed and more (keys "
                     "of the conversion's result), the options, the warnings, exit_status and, "
                     "on failure, error (the message printed after `error:`)")


def _add_info_command(sub, choices):
    info = sub.add_parser(
        "info",
        help="summarise a mesh or spline file and check it is valid conversion input",
        description="Prints the cells, point, cell and field data of a file and whether "
        "convert accepts it: the spline filter runs on it and its messages are printed. Exits "
        "with 1 when the file is not valid input.",
    )
    info.add_argument("file", help=".vtp, .vtu, .vtk, .obj or .ply")
    _add_spline_options(info, choices)
    info.set_defaults(func=_info, _choices=choices)


def _add_sample_command(sub):
    surfaces, domains = _source_choices()
    sample = sub.add_parser(
        "sample",
        help="write a mesh sampled from an analytic test surface (vtkSampledSurfaceSource)",
        description="Samples a test surface with exact positions, derivatives dFdu, dFdv, "
        "parameter values UV and mid-edge gradients EdgeGradients, and writes the mesh. VTP, "
        "VTU and VTK keep every array; OBJ and PLY keep positions and UV (as texture "
        "coordinates) only.",
    )
    sample.add_argument("output", help="output mesh: .vtp, .vtu, .vtk, .obj or .ply")
    sample.add_argument("--surface", "-s", default="Franke", choices=surfaces,
                        help="Plane, Quadratic, FarinCubic, Franke and SineWave are functions "
                        "z = f(u, v) over the unit square; SphereOctant is the rational quartic "
                        "sphere octant (default %(default)s)")
    sample.add_argument("--domain", "-d", default="RandomDelaunay", choices=domains,
                        help="Grid (unit square, not for SphereOctant), EquilateralTriangle "
                        "(midpoint refinement) or RandomDelaunay (default %(default)s)")
    sample.add_argument("--resolution", "-r", type=int,
                        help="Grid: cells per side; EquilateralTriangle: refinement level "
                        "(4^level triangles); RandomDelaunay: random interior points "
                        "(default 100)")
    sample.add_argument("--grid-diagonal", default="Forward", choices=GRID_DIAGONALS,
                        help="diagonal splitting the grid cells (default %(default)s)")
    sample.add_argument("--seed", type=_non_negative, default=1,
                        help="seed of the random points (default %(default)s)")
    sample.add_argument("--affine", type=float, nargs=4, default=[1.0, 0.0, 0.0, 1.0],
                        metavar=("A00", "A01", "A10", "A11"),
                        help="matrix A of the reparameterisation U' = A U + t, row-major "
                        "(default identity)")
    sample.add_argument("--translation", type=float, nargs=2, default=[0.0, 0.0],
                        metavar=("TX", "TY"), help="translation t (default 0 0)")
    _progress_option(sample)
    sample.set_defaults(func=_sample)


def _expected_errors():
    from .io import FilterError, InputError

    return (InputError, FilterError)


def _error_status(e):
    """The exit code of an error: EXIT_FILE for a file, EXIT_INVALID for the input (1 also for
    an uncaught exception, as Python exits with a traceback)."""
    from .io import InputError

    return EXIT_FILE if isinstance(e, InputError) else EXIT_INVALID


def main(argv=None):
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except _expected_errors() as e:
        print(f"error: {e}", file=sys.stderr)
        return _error_status(e)
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
