# SPDX-License-Identifier: GPL-3.0-or-later
"""A real distributed run of the spline filter, checked against the serial spline.

    mpirun -np N pvbatch --force-offscreen-rendering distributed.py PLUGIN --ranks N
        [--redistribution D3|RedistributeDataSet] [--points 1500]

PYTHONPATH must name the build tree's (or the installed) ctsplines package: rank 0 runs the
serial reference with the plain VTK classes. Pipeline, on every rank:

    SampledSurfaceSource (random Delaunay Franke; ParaView runs it on rank 0 only, it does not
    split itself into pieces) -> SerialIds (every triangle's serial index as the GlobalIds
    attribute) -> redistribution -> [GhostCellsGenerator] -> ToPolyData -> CloughTocherSplineFilter

The redistribution outputs vtkUnstructuredGrid while the spline filter takes vtkPolyData;
ParaView's surface filter would drop the ghost triangles, so ToPolyData converts the piece as it
is and also measures, per rank, how many rings of ghost triangles (cells sharing a point, VTK's
ghost levels) actually arrived around the piece's own ones. D3 builds ghost cells on request;
RedistributeDataSet does not, so a GhostCellsGenerator (BuildIfRequired) follows it. D3 is the
default because RedistributeDataSet moves cells as XML with appended raw data, which the
ParaView 5.11 XML reader fails to parse with the libexpat of Debian 12's security updates
("not well-formed (invalid token)" and silently empty pieces).

For CTi, Ka with 2 IM steps and the Quartic scheme with 2 rounds, the gathered pieces (Fetch)
must hold every serial micro-triangle exactly once, keyed by (MacroTriangleGlobalId,
MicroTriangleId), with every control point within 1e-12 of the bounding-box diagonal of the
serial one. Exits 1 with a message per failure; prints the figures."""
import argparse
import sys
import time

import numpy as np
from paraview import servermanager
import paraview.simple as simple
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkParallelCore import vtkMultiProcessController

from pieces import TO_POLYDATA

parser = argparse.ArgumentParser()
parser.add_argument("plugin")
parser.add_argument("--ranks", type=int, required=True, help="expected number of MPI ranks")
parser.add_argument("--redistribution", choices=["D3", "RedistributeDataSet"], default="D3")
parser.add_argument("--points", type=int, default=1500, help="random interior points")
parser.add_argument("--seed", type=int, default=11)
args = parser.parse_args()

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message, flush=True)


controller = vtkMultiProcessController.GetGlobalController()
ranks = controller.GetNumberOfProcesses() if controller else 1
if ranks != args.ranks:
    # pvbatch without MPI, or mpirun starting independent serial copies.
    print(f"FAIL: pvbatch sees {ranks} MPI ranks, expected {args.ranks}", flush=True)
    sys.exit(1)

import ctsplines  # noqa: E402  (after ParaView: both share ParaView's VTK)

simple.LoadPlugin(args.plugin, remote=False)

# Runs on every rank (ParaView executes the programmable filters where the data is).
SERIAL_IDS = """
import numpy as np
from vtkmodules.vtkCommonCore import vtkIdTypeArray
from vtkmodules.util.numpy_support import vtk_to_numpy
inp = self.GetInputDataObject(0, 0)
out = self.GetOutputDataObject(0)
out.ShallowCopy(inp)
ids = vtkIdTypeArray()
ids.SetName("SerialCellId")
ids.SetNumberOfTuples(inp.GetNumberOfCells())
vtk_to_numpy(ids)[:] = np.arange(inp.GetNumberOfCells())
out.GetCellData().SetGlobalIds(ids)
"""

# The conversion, then what arrived on each rank (rings of ghost triangles), gathered to rank 0.
TO_POLYDATA_WITH_STATISTICS = TO_POLYDATA + """
import numpy as np
from vtkmodules.vtkCommonCore import vtkIntArray
from vtkmodules.vtkCommonDataModel import vtkDataSetAttributes
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline as SDDP
from vtkmodules.vtkParallelCore import vtkMultiProcessController
from vtkmodules.util.numpy_support import vtk_to_numpy
n = ug.GetNumberOfCells()
owned = ghost = rings = unreached = 0
bad = 0
if n:
    bad = int((vtk_to_numpy(ug.GetCellTypesArray()) != 5).sum())  # VTK_TRIANGLE
    # The redistribution keeps the array but not necessarily its GlobalIds role.
    if pd.GetCellData().GetGlobalIds() is None and pd.GetCellData().GetArray("SerialCellId"):
        pd.GetCellData().SetGlobalIds(pd.GetCellData().GetArray("SerialCellId"))
    conn = vtk_to_numpy(ug.GetCells().GetConnectivityArray()).reshape(-1, 3)
    flags = ug.GetCellGhostArray()
    isghost = np.zeros(n, bool) if flags is None else (
        vtk_to_numpy(flags) & vtkDataSetAttributes.DUPLICATECELL) != 0
    owned, ghost = int((~isghost).sum()), int(isghost.sum())
    # Rings of ghost triangles around the own ones: grow by cells sharing a point.
    reached = ~isghost
    while True:
        marked = np.zeros(ug.GetNumberOfPoints(), bool)
        marked[conn[reached].ravel()] = True
        grown = marked[conn].any(axis=1)
        if grown.sum() == reached.sum():
            break
        reached, rings = grown, rings + 1
    unreached = int((~reached).sum())
info = self.GetOutputInformation(0)
levels = info.Get(SDDP.UPDATE_NUMBER_OF_GHOST_LEVELS()) if info.Has(
    SDDP.UPDATE_NUMBER_OF_GHOST_LEVELS()) else 0
mine = vtkIntArray()
for v in (owned, ghost, rings, unreached, levels, bad):
    mine.InsertNextValue(v)
gathered = vtkIntArray()
gathered.SetName("PieceStats")
controller = vtkMultiProcessController.GetGlobalController()
if controller is not None and controller.GetNumberOfProcesses() > 1:
    controller.Gather(mine, gathered, 0)
else:
    gathered.DeepCopy(mine)
gathered.SetName("PieceStats")
pd.GetFieldData().AddArray(gathered)
"""

def keyed_control_points(grid, id_array):
    """(macro id * 3 + micro id, control points (cells x points per cell x 3)), by key."""
    n = grid.GetNumberOfCells()
    if n == 0:
        return np.zeros(0, np.int64), np.zeros((0, 0, 3))
    cells = grid.GetCells()
    offsets = vtk_to_numpy(cells.GetOffsetsArray())
    size = int(offsets[1] - offsets[0])
    check(bool((np.diff(offsets) == size).all()), f"{id_array}: cells of different orders")
    conn = vtk_to_numpy(cells.GetConnectivityArray()).reshape(n, size)
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(np.float64)[conn]
    macro = grid.GetCellData().GetArray(id_array)
    micro = grid.GetCellData().GetArray("MicroTriangleId")
    if macro is None or micro is None:
        check(False, f"output lacks {id_array} or MicroTriangleId")
        return np.zeros(0, np.int64), np.zeros((0, size, 3))
    key = vtk_to_numpy(macro).astype(np.int64) * 3 + vtk_to_numpy(micro).astype(np.int64)
    order = np.argsort(key, kind="stable")
    return key[order], points[order]


def main():
    # Local names: on rank 0 ParaView runs the programmable filters' scripts in __main__, after
    # "from ...numpy_interface.algorithms import *" (which shadows sum, max, abs, ...).
    surface = dict(Surface="Franke", Domain="RandomDelaunay", Resolution=args.points, Seed=args.seed)
    source = simple.SampledSurfaceSource(**surface)
    ids = simple.ProgrammableFilter(Input=source, Script=SERIAL_IDS)
    if args.redistribution == "D3":
        pieces = simple.D3(Input=ids)
    else:
        pieces = simple.RedistributeDataSet(Input=ids, GenerateGlobalCellIds=0)
        # Ghost layers only as many as downstream asks for (the spline filter's request).
        pieces = simple.GhostCellsGenerator(Input=pieces, BuildIfRequired=1)
    poly = simple.ProgrammableFilter(Input=pieces, OutputDataSetType="vtkPolyData",
                                     Script=TO_POLYDATA_WITH_STATISTICS)
    spline = simple.CloughTocherSplineFilter(Input=poly)

    reference_source = ctsplines.vtkSampledSurfaceSource()
    reference_source.SetSurfaceToFranke()
    reference_source.SetDomainToRandomDelaunay()
    reference_source.SetResolution(args.points)
    reference_source.SetSeed(args.seed)
    reference_source.Update()
    mesh = reference_source.GetOutput()
    bounds = mesh.GetBounds()
    diagonal = float(np.linalg.norm(np.subtract(bounds[1::2], bounds[0::2])))
    print(f"{ranks} ranks, {args.redistribution}: {mesh.GetNumberOfCells()} triangles, "
          f"{mesh.GetNumberOfPoints()} points, bounding-box diagonal {diagonal:.4g}", flush=True)


    cases = [("CTi", 0), ("Ka", 2), ("Quartic", 2)]
    rows = []
    for construction, iterations in cases:
        label = f"{construction}+{iterations}" if iterations else construction
        spline.Construction = construction
        spline.Iterations = iterations
        start = time.perf_counter()
        spline.UpdatePipeline()
        parallel_seconds = time.perf_counter() - start
        # Fetch(spline) appends the pieces with vtkReductionFilter; with ParaView 5.11 here it
        # returned rank 0's piece only, so fetch each rank's piece and join the keyed arrays.
        pieces_out = [servermanager.Fetch(spline, rank) for rank in range(ranks)]

        reference = ctsplines.vtkCloughTocherSplineFilter()
        reference.SetInputConnection(reference_source.GetOutputPort())
        reference.SetConstruction(getattr(ctsplines.vtkCloughTocherSplineFilter, construction))
        reference.SetIterations(iterations)
        start = time.perf_counter()
        reference.Update()
        serial_seconds = time.perf_counter() - start
        required = reference.GetRequiredGhostLevels()

        # What the pieces looked like when the spline filter last ran (gathered on rank 0).
        stats = poly.GetClientSideObject().GetOutputDataObject(0).GetFieldData().GetArray(
            "PieceStats")
        stats = vtk_to_numpy(stats).reshape(-1, 6) if stats is not None else np.zeros((0, 6), int)
        check(len(stats) == ranks, f"{label}: piece statistics from {len(stats)} of {ranks} ranks")
        for rank, (owned, ghost, rings, unreached, levels, bad) in enumerate(stats):
            print(f"  {label} rank {rank}: {owned} own triangles, {ghost} ghost triangles in "
                  f"{rings} rings (requested {levels}, the filter needs {required})", flush=True)
            check(bad == 0, f"{label} rank {rank}: {bad} cells that are not triangles")
            check(levels >= required, f"{label} rank {rank}: upstream was asked for {levels} ghost "
                  f"levels, the filter needs {required}")
            check(unreached == 0, f"{label} rank {rank}: {unreached} ghost triangles not connected "
                  "to the piece (interface points not shared)")
            if ranks > 1:
                check(owned > 0, f"{label} rank {rank}: empty piece")
                check(rings >= required, f"{label} rank {rank}: {rings} rings of ghost triangles "
                      f"arrived, the filter needs {required}")
        check(int(stats[:, 0].sum()) == mesh.GetNumberOfCells(),
              f"{label}: the pieces own {int(stats[:, 0].sum())} triangles, the mesh has "
              f"{mesh.GetNumberOfCells()}")

        serial_key, serial_points = keyed_control_points(reference.GetOutput(), "MacroTriangleId")
        keyed = [keyed_control_points(p, "MacroTriangleGlobalId") for p in pieces_out
                 if p.GetNumberOfCells()]
        dist_key = np.concatenate([k for k, _ in keyed])
        dist_points = np.concatenate([p for _, p in keyed])
        order = np.argsort(dist_key, kind="stable")
        dist_key, dist_points = dist_key[order], dist_points[order]
        gathered_cells = int(np.sum([p.GetNumberOfCells() for p in pieces_out]))
        duplicates = int((np.diff(dist_key) == 0).sum()) if len(dist_key) else 0
        check(duplicates == 0, f"{label}: {duplicates} micro-triangles output by more than one rank")
        unique_key, first = np.unique(dist_key, return_index=True)
        missing = np.setdiff1d(serial_key, unique_key)
        extra = np.setdiff1d(unique_key, serial_key)
        check(len(missing) == 0, f"{label}: {len(missing)} serial micro-triangles missing, "
              f"e.g. (macro, micro) {[(int(k) // 3, int(k) % 3) for k in missing[:5]]}")
        check(len(extra) == 0, f"{label}: {len(extra)} micro-triangles not in the serial spline")
        deviation = float("nan")
        if len(missing) == 0 and len(extra) == 0 and serial_points.shape == dist_points[first].shape:
            deviation = float(np.abs(dist_points[first] - serial_points).max()) / diagonal
            check(deviation <= 1e-12, f"{label}: control points differ from the serial spline by "
                  f"{deviation:.3g} of the bounding-box diagonal (tolerance 1e-12)")
        rows.append((label, required, len(serial_key), gathered_cells, deviation,
                     parallel_seconds, serial_seconds))

    print(f"\n{'case':<10}{'ghosts':>7}{'serial cells':>14}{'gathered':>10}{'max dev/diag':>14}"
          f"{'pvbatch s':>11}{'serial s':>10}")
    for label, required, nserial, ngathered, deviation, tpar, tser in rows:
        print(f"{label:<10}{required:>7}{nserial:>14}{ngathered:>10}{deviation:>14.3g}"
              f"{tpar:>11.3f}{tser:>10.3f}")
    if failures:
        print(f"\n{len(failures)} failure(s) with {ranks} ranks", flush=True)
        sys.exit(1)
    print(f"\nOK: {ranks} ranks reproduce the serial spline", flush=True)


main()
