#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Linear Kirchhoff-Love shells with the C1 Clough-Tocher spline space: the shell obstacle course.

Each benchmark's mid-surface is an analytic surface (cylinder, sphere in arc-length parameters)
sampled with exact first derivatives and mid-edge gradients on an n x n grid of the parameter
rectangle, converted by vtkCloughTocherSplineFilter (boundary mode GradientPerpendicular) with
its Bézier extraction; the spline is the geometry and each displacement component lives in the
spline space (ctsplines.shell). Symmetry planes and supports are imposed through the spline dofs
(ctsplines.shell.line_dofs).

  Scordelis-Lo roof   R 25, L 50, 40 deg, t 0.25, E 4.32e8, nu 0, self weight 90 per area;
                      quarter model; vertical displacement at the midpoint of the free edge
                      (reference 0.3006 thin shell, 0.3024 MacNeal-Harder).
  pinched cylinder    R 300, L 600, t 3, E 3e6, nu 0.3, rigid end diaphragms, two opposite unit
                      loads at mid-length; octant model; radial displacement under the load
                      (reference 1.8248e-5).
  pinched hemisphere  R 10, 18 deg hole, t 0.04, E 6.825e7, nu 0.3, four alternating radial
                      loads of 2 on the equator; quarter model; radial displacement under a load
                      (reference 0.0924; 0.094 MacNeal-Harder).

Prints, per benchmark and construction, the value, its ratio to the reference and the observed
order from three successive levels (p = log2(|q_h - q_h/2| / |q_h/2 - q_h/4|), independent of
the reference). With -o writes each benchmark's finest solution as a .vtu with a Displacement
point array on the Bézier control points (ParaView: Warp By Vector shows the deformed shell).
With --cad STEP the pinched hemisphere runs again on the quarter written to STEP by OpenCASCADE
and sampled by the CAD pipeline (vtkCADFaceSampler: an unstructured mesh of the face, refined by
MaxEdgeLength = 1/n of the diagonal, exact derivatives from the CAD surface). With
--cad-cylinder STEP the pinched cylinder runs on a CAD model of its octant with any number of
faces, each face's spline in its own parameters, joined by ctsplines.shell.FacePatches (shared
nodes, G1 at tangent joins), the conditions given as planes of the model. The test models are
written by `ctsplines_write_test_model --shape hemisphere_quarter|cylinder_octant_two_faces PATH`.

    /usr/bin/python3 Examples/Python/kirchhoff_love_shell.py [--quick] [-o DIR] [--levels 8,16]
        [--constructions CTi,KaG,MGi] [--benchmarks scordelis_lo,pinched_cylinder,pinched_hemisphere]
        [--cad hemisphere_quarter.step] [--cad-cylinder cylinder_octant_two_faces.step]
"""
import argparse
import math
import os
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from ctsplines import shell


@dataclass
class Benchmark:
    """A shell problem on the parameter rectangle [0, width] x [0, height].

    conditions: (axis, line value, component, 'trace' | 'normal') for shell.line_dofs;
    loads: (parameter point, force) point loads; pressure: force per area; probe: the parameter
    point and the direction whose displacement is measured; pinned: (parameter point, component)
    single unknowns held (a rigid motion the symmetry planes leave free)."""

    name: str
    surface: object
    width: float
    height: float
    thickness: float
    young: float
    poisson: float
    reference: float
    probe: tuple
    conditions: list
    loads: list = field(default_factory=list)
    pressure: tuple = None
    pinned: list = field(default_factory=list)
    levels: tuple = (4, 8, 16)
    quick_levels: tuple = (4, 8)
    mesher: object = None  # n -> parametrised mesh; None: the n x n grid of the rectangle
    solver: object = None  # (bench, n, construction, output) -> (unknowns, value, s); None: solve

    def mesh(self, n):
        if self.mesher is not None:
            return self.mesher(n)
        return shell.grid_mesh(n, n, (0.0, self.width), (0.0, self.height), self.surface)


def scordelis_lo():
    R, L = 25.0, 50.0
    w = R * math.radians(40.0)
    # u: arc length from the crown (symmetry x = 0), v: axial from mid-span (symmetry y = 0).
    cond = [(1, L / 2, 0, "trace"), (1, L / 2, 2, "trace"),  # rigid diaphragm at y = L/2
            (1, 0.0, 1, "trace"), (1, 0.0, 0, "normal"), (1, 0.0, 2, "normal"),
            (0, 0.0, 0, "trace"), (0, 0.0, 1, "normal"), (0, 0.0, 2, "normal")]
    return Benchmark("scordelis_lo", shell.cylinder(R), w, L / 2, 0.25, 4.32e8, 0.0, 0.3006,
                     ((w, 0.0), (0.0, 0.0, -1.0)), cond, pressure=(0.0, 0.0, -90.0),
                     levels=(4, 8, 16, 32), quick_levels=(4, 8))


def pinched_cylinder():
    R, L = 300.0, 600.0
    w = R * math.pi / 2
    cond = [(1, L / 2, 0, "trace"), (1, L / 2, 2, "trace"),  # rigid diaphragm
            (1, 0.0, 1, "trace"), (1, 0.0, 0, "normal"), (1, 0.0, 2, "normal"),
            (0, 0.0, 0, "trace"), (0, 0.0, 1, "normal"), (0, 0.0, 2, "normal"),
            (0, w, 2, "trace"), (0, w, 0, "normal"), (0, w, 1, "normal")]
    # The octant carries a quarter of the unit load at the crown (0, 0, R).
    return Benchmark("pinched_cylinder", shell.cylinder(R), w, L / 2, 3.0, 3e6, 0.3, 1.8248e-5,
                     ((0.0, 0.0), (0.0, 0.0, -1.0)), cond, loads=[((0.0, 0.0), (0.0, 0.0, -0.25))],
                     levels=(8, 16, 32), quick_levels=(8, 16))


def cad_faces(path, n):
    """The CAD pipeline's sampling (vtkCADFaceSampler) of the faces of a STEP/IGES model, with
    edges at most 1/n of the bounding-box diagonal: per face UV, exact dFdu, dFdv and mid-edge
    gradients from the CAD surface, GlobalNodeId on the shared boundary nodes."""
    from ctsplines import io

    messages = io.VTKMessages()
    sampler = io.cad_sampler(path, messages)
    sampler.SetMaxEdgeLength(1.0 / n)
    sampler.Update()
    errors = messages.take_errors()
    if errors:
        raise ValueError(f"{path}: {'; '.join(errors)}")
    faces = sampler.GetOutputDataObject(0)
    return [faces.GetBlock(i) for i in range(faces.GetNumberOfBlocks())]


def cad_face_mesher(path):
    """n -> the sampling of the one face of a STEP/IGES model (cad_faces)."""
    def mesh(n):
        faces = cad_faces(path, n)
        if len(faces) != 1:
            raise ValueError(f"{path}: expected one sampled face, got {len(faces)}")
        return faces[0]
    return mesh


# The pinched cylinder's octant conditions as planes of the model, so that they apply to any
# faces whose boundary lines lie there (shell.FacePatches.plane_dofs): (axis, value, component,
# condition). Symmetry planes x = 0, y = 0, z = 0; rigid diaphragm at y = L/2.
CYLINDER_PLANES = [(1, 300.0, 0, "trace"), (1, 300.0, 2, "trace"),
                   (1, 0.0, 1, "trace"), (1, 0.0, 0, "normal"), (1, 0.0, 2, "normal"),
                   (0, 0.0, 0, "trace"), (0, 0.0, 1, "normal"), (0, 0.0, 2, "normal"),
                   (2, 0.0, 2, "trace"), (2, 0.0, 0, "normal"), (2, 0.0, 1, "normal")]


def solve_cad_cylinder(path, n, construction, g1_threshold=10.0):
    """The pinched cylinder on a CAD model of its octant with any number of faces (the faces'
    splines joined by shell.FacePatches): (unknowns, radial displacement under the load,
    seconds, the model, its displacement dofs per face)."""
    start = time.time()
    bench = pinched_cylinder()
    model = shell.FacePatches(cad_faces(path, n), construction, bench.thickness, bench.young,
                              bench.poisson, g1_threshold)
    fixed = np.concatenate([model.plane_dofs(*c) for c in CYLINDER_PLANES])
    face, vertex = model.vertex_near((0.0, 0.0, 300.0))
    d = model.solve(model.point_load(face, vertex, (0.0, 0.0, -0.25)), fixed)
    value = float(-model.shells[face].vertex_displacement(d[face], vertex)[2])
    return model.n_unknowns, value, time.time() - start, model, d


def pinched_hemisphere(cad=None):
    """cad: optional STEP/IGES file holding the quarter as one spherical face in OCCT's
    parameters (u longitude 0..pi/2, v latitude 0..72 deg, radians)."""
    R = 10.0
    scale = 1.0 if cad else R  # the analytic surface uses arc-length parameters
    w, h = scale * math.pi / 2, scale * math.radians(72.0)
    # u: longitude from the plane y = 0, v: latitude from the equator to the 18 deg hole.
    cond = [(0, 0.0, 1, "trace"), (0, 0.0, 0, "normal"), (0, 0.0, 2, "normal"),
            (0, w, 0, "trace"), (0, w, 1, "normal"), (0, w, 2, "normal")]
    # Each load of 2 lies on a symmetry plane: the quarter carries half of it.
    return Benchmark("pinched_hemisphere", shell.sphere(R), w, h, 0.04, 6.825e7, 0.3, 0.0924,
                     ((0.0, 0.0), (1.0, 0.0, 0.0)), cond,
                     loads=[((0.0, 0.0), (1.0, 0.0, 0.0)), ((w, 0.0), (0.0, -1.0, 0.0))],
                     pinned=[((0.0, 0.0), 2)], levels=(8, 16, 32), quick_levels=(8, 16),
                     mesher=cad_face_mesher(cad) if cad else None)


def cad_cylinder_run(path, n, construction, output=None):
    """solve_cad_cylinder as a table row; with output, one .vtu per face with its Displacement."""
    unknowns, value, seconds, model, d = solve_cad_cylinder(path, n, construction)
    if output:
        for f, (face, df) in enumerate(zip(model.shells, d)):
            shell.write_displacement(face.grid, face.control_point_displacement(df), os.path.join(
                output, f"pinched_cylinder_cad_{construction}_{n}_face{f}.vtu"))
    return unknowns, value, seconds


BENCHMARKS = {b.__name__: b for b in (scordelis_lo, pinched_cylinder, pinched_hemisphere)}


def solve(bench, n, construction, output=None):
    """Solves one benchmark on the n x n grid: (unknowns, measured displacement, seconds)."""
    start = time.time()
    mesh = bench.mesh(n)
    n_vertices = mesh.GetNumberOfPoints()
    grid = shell.spline(mesh, construction)
    model = shell.Shell(grid, bench.thickness, bench.young, bench.poisson)
    ex = model.ex
    b = np.zeros(model.n_unknowns)
    if bench.pressure is not None:
        b += model.surface_load(bench.pressure)
    for uv, force in bench.loads:
        b += model.point_load(shell.vertex_at(ex, n_vertices, uv), force)
    fixed = [shell.line_dofs(ex, n_vertices, *c) for c in bench.conditions]
    fixed += [[3 * (3 * shell.vertex_at(ex, n_vertices, uv) + shell.VALUE) + c] for uv, c in bench.pinned]
    d = model.solve(model.stiffness(), b, np.concatenate(fixed))
    uv, direction = bench.probe
    value = float(model.vertex_displacement(d, shell.vertex_at(ex, n_vertices, uv)) @ direction)
    if output:
        shell.write_displacement(grid, model.control_point_displacement(d),
                                 os.path.join(output, f"{bench.name}_{construction}_{n}.vtu"))
    return model.n_unknowns, value, time.time() - start


def observed_orders(values):
    """Orders from successive differences of a sequence on halving meshes (None where the
    differences do not shrink or vanish)."""
    out = [None, None]
    for i in range(2, len(values)):
        d1, d2 = abs(values[i - 1] - values[i - 2]), abs(values[i] - values[i - 1])
        out.append(math.log2(d1 / d2) if d2 > 0 and d1 > d2 else None)
    return out


def table(bench, construction, levels, output=None):
    """Markdown rows of one convergence study and the list of values."""
    rows, values = [], []
    for n in levels:
        run = bench.solver or solve
        unknowns, value, seconds = run(bench, n, construction, output if n == levels[-1] else None)
        values.append(value)
        rows.append([n, unknowns, value, seconds])
    # Successive differences give an order only on halving meshes.
    halving = all(levels[i + 1] == 2 * levels[i] for i in range(len(levels) - 1))
    orders = observed_orders(values) if halving else [None] * len(values)
    lines = []
    for (n, unknowns, value, seconds), p in zip(rows, orders):
        lines.append(f"| {bench.name} | {construction} | {n} | {unknowns} | {value:.6g} | "
                     f"{value / bench.reference:.4f} | {'' if p is None else f'{p:.2f}'} | {seconds:.1f} |")
    return lines, values


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="the two coarsest levels only")
    ap.add_argument("-o", "--output", help="directory for the finest solutions (.vtu)")
    ap.add_argument("--constructions", default="CTi,KaG,MGi")
    ap.add_argument("--benchmarks", default=",".join(BENCHMARKS))
    ap.add_argument("--levels", help="grid sizes n (comma separated) instead of each benchmark's")
    ap.add_argument("--cad", metavar="STEP", help="also run the pinched hemisphere on this CAD model "
                    "of its quarter (one spherical face), sampled by the CAD pipeline")
    ap.add_argument("--cad-cylinder", metavar="STEP", help="also run the pinched cylinder on this CAD "
                    "model of its octant (any faces, joined by shell.FacePatches)")
    args = ap.parse_args(argv)
    names = args.benchmarks.split(",")
    unknown = [n for n in names if n not in BENCHMARKS]
    if unknown:
        ap.error(f"unknown benchmark(s) {unknown}; choose from {list(BENCHMARKS)}")
    if args.output:
        os.makedirs(args.output, exist_ok=True)
    print("| benchmark | space | n | unknowns | displacement | / reference | observed order | s |")
    print("|---|---|---|---|---|---|---|---|")
    runs = [BENCHMARKS[name]() for name in names]
    if args.cad:
        runs.append(pinched_hemisphere(args.cad))
        runs[-1].name = "pinched_hemisphere_cad"
    if args.cad_cylinder:
        runs.append(pinched_cylinder())
        runs[-1].name = "pinched_cylinder_cad"
        runs[-1].solver = lambda bench, n, construction, output: cad_cylinder_run(
            args.cad_cylinder, n, construction, output)
    for bench in runs:
        levels = tuple(map(int, args.levels.split(","))) if args.levels else (
            bench.quick_levels if args.quick else bench.levels)
        for construction in args.constructions.split(","):
            lines, _ = table(bench, construction, levels, args.output)
            print("\n".join(lines), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
