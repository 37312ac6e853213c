# SPDX-License-Identifier: GPL-3.0-or-later
"""The spline filter on input that is already partitioned, against one rank (a measurement).

    /usr/bin/python3 partitioned_scaling.py prepare DIR [--points 500000] [--pieces 2]
        [--ghost-levels 2]
    VTK_SMP_BACKEND_IN_USE=Sequential CTSPLINES_NUM_THREADS=1 \
        mpirun -np N pvbatch partitioned_scaling.py run PLUGIN DIR [--repeats 3] [--no-d3]

    VTK_SMP_BACKEND_IN_USE=Sequential CTSPLINES_NUM_THREADS=1 \
        mpirun -np N pvbatch --symmetric partitioned_scaling.py ranks DIR [--repeats 3]

(as root in a container add --allow-run-as-root and OMPI_MCA_btl=self,vader.)
`prepare` (PYTHONPATH: the ctsplines package, for nothing but the benchmark's mesh; SciPy)
makes issue 12's mesh: qhull's Delaunay triangulation of --points uniform random points of the
unit square in qhull's numbering, z = sin 3x cos 2y with its exact gradients (the arrays UV,
dFdu, dFdv of Testing/Benchmarks/delaunay_comparison.py). It writes DIR/whole.vtu and
DIR/pieces.pvtu: --pieces pieces of contiguous Morton ranges of the triangles' centroids, each
with --ghost-levels rings of ghost triangles (cells sharing a point, marked DUPLICATECELL in
vtkGhostType), so that a rank reads its piece and the ghosts the spline filter asks for (CTi:
2 rings) without any redistribution.

`run` measures on every rank count, one thread per rank:
- partitioned: with 1 rank whole.vtu, with N > 1 ranks pieces.pvtu (N must equal --pieces);
  the read alone, then the spline filter (CTi, fresh filters on the read data, best of
  --repeats; UpdatePipeline returns when every rank has finished, so it is the slowest piece);
- D3 (N > 1): whole.vtu read on rank 0, redistributed by D3; the first spline filter after it
  brings D3 up to date with the ghost rings requested ("distribute", D3 and ghosts included),
  and its cost of its own is that minus the spline time.
`ranks` (PYTHONPATH: the ctsplines package; the VTK classes without ParaView's proxies) gives
each rank's own CPU and wall time, for a machine shared with other work: the read, D3 of
whole.vtu read on rank 0 with the ghost rings (N > 1, vtkPDistributedDataFilter, what the D3
proxy runs), and the spline filter on the piece read and on D3's piece. "first" is the first
spline of the process (fresh pages: the kernel zeroes them), "best" the best of --repeats.
Every spline's cell count must be 3 × the triangles: a piece built without its ghost rings
would still have them, but the serial comparison of Testing/ParaView/distributed.py is the
correctness test; this script only checks counts."""
import argparse
import builtins
import os
import sys
import time


def parse():
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers(dest="mode", required=True)
    prep = sub.add_parser("prepare")
    prep.add_argument("dir")
    prep.add_argument("--points", type=float, default=5e5)
    prep.add_argument("--pieces", type=int, default=2)
    prep.add_argument("--ghost-levels", type=int, default=2)
    prep.add_argument("--seed", type=int, default=1)
    run = sub.add_parser("run")
    run.add_argument("plugin")
    run.add_argument("dir")
    run.add_argument("--repeats", type=int, default=3)
    run.add_argument("--no-d3", action="store_true", help="skip the D3 route")
    ranks = sub.add_parser("ranks")
    ranks.add_argument("dir")
    ranks.add_argument("--repeats", type=int, default=3)
    return parser.parse_args()


def morton_order(xy):
    """Triangle order by the Morton key of their centroids (16 bits per coordinate)."""
    import numpy as np

    q = np.clip((xy - xy.min(0)) / np.ptp(xy, 0).clip(1e-300) * 65535, 0, 65535).astype(np.uint64)
    key = np.zeros(len(xy), dtype=np.uint64)
    for bit in range(16):
        key |= ((q[:, 0] >> bit) & 1) << np.uint64(2 * bit)
        key |= ((q[:, 1] >> bit) & 1) << np.uint64(2 * bit + 1)
    return np.argsort(key, kind="stable")


def ghost_rings(triangles, owned, levels, n_points):
    """Cells within `levels` rings (sharing a point) of the owned ones, and the owned mask."""
    import numpy as np
    from scipy.sparse import csr_matrix

    n = len(triangles)
    incidence = csr_matrix(
        (np.ones(3 * n, dtype=np.int8), triangles.ravel(), np.arange(0, 3 * n + 1, 3)),
        shape=(n, n_points))
    keep = owned.copy()
    for _ in range(levels):
        touched = incidence.T @ keep.astype(np.int8) > 0
        keep |= incidence @ touched.astype(np.int8) > 0
    return keep


def write_piece(path, uv, z, zx, zy, triangles, ghost):
    """One .vtu of the triangles (points renumbered to those used) with vtkGhostType."""
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid, VTK_TRIANGLE
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter
    from vtkmodules.util.numpy_support import numpy_to_vtkIdTypeArray

    used, local = np.unique(triangles, return_inverse=True)
    local = local.reshape(-1, 3)

    def array(a, name=None, deep=True):
        arr = numpy_to_vtk(np.ascontiguousarray(a), deep=deep)
        if name:
            arr.SetName(name)
        return arr

    ug = vtkUnstructuredGrid()
    pts = vtkPoints()
    pts.SetData(array(np.column_stack([uv[used], z[used]])))
    ug.SetPoints(pts)
    cells = vtkCellArray()
    cells.SetData(
        numpy_to_vtkIdTypeArray(np.arange(0, 3 * len(local) + 1, 3, dtype=np.int64), deep=True),
        numpy_to_vtkIdTypeArray(local.astype(np.int64).ravel(), deep=True))
    ug.SetCells(VTK_TRIANGLE, cells)
    m = len(used)
    zeros, ones = np.zeros(m), np.ones(m)
    ug.GetPointData().AddArray(array(uv[used], "UV"))
    ug.GetPointData().AddArray(array(np.column_stack([ones, zeros, zx[used]]), "dFdu"))
    ug.GetPointData().AddArray(array(np.column_stack([zeros, ones, zy[used]]), "dFdv"))
    # D3 merges the points it receives by global id, else by position with a tolerance that
    # fuses close random points into degenerate triangles.
    ids = numpy_to_vtkIdTypeArray(used.astype(np.int64), deep=True)
    ids.SetName("GlobalPointIds")
    ug.GetPointData().SetGlobalIds(ids)
    if ghost is not None:
        ug.GetCellData().AddArray(array(ghost.astype(np.uint8), "vtkGhostType"))
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(path)
    writer.SetInputData(ug)
    writer.SetDataModeToAppended()
    writer.EncodeAppendedDataOff()
    writer.SetCompressorTypeToNone()
    if not writer.Write():
        sys.exit(f"error: cannot write {path}")


PVTU = """<?xml version="1.0"?>
<VTKFile type="PUnstructuredGrid" version="1.0" byte_order="LittleEndian">
  <PUnstructuredGrid GhostLevel="{levels}">
    <PPointData GlobalIds="GlobalPointIds">
      <PDataArray type="Float64" Name="UV" NumberOfComponents="2"/>
      <PDataArray type="Float64" Name="dFdu" NumberOfComponents="3"/>
      <PDataArray type="Float64" Name="dFdv" NumberOfComponents="3"/>
      <PDataArray type="Int64" Name="GlobalPointIds"/>
    </PPointData>
    <PCellData>
      <PDataArray type="UInt8" Name="vtkGhostType"/>
    </PCellData>
    <PPoints>
      <PDataArray type="Float64" NumberOfComponents="3"/>
    </PPoints>
{pieces}  </PUnstructuredGrid>
</VTKFile>
"""


def prepare(args):
    import numpy as np
    from scipy.spatial import Delaunay

    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Benchmarks"))
    from delaunay_comparison import sine_cosine

    os.makedirs(args.dir, exist_ok=True)
    rng = np.random.default_rng(args.seed)
    uv = rng.random((int(args.points), 2))
    triangles = Delaunay(uv).simplices.astype(np.int64)
    z, zx, zy = sine_cosine(uv)
    write_piece(os.path.join(args.dir, "whole.vtu"), uv, z, zx, zy, triangles, None)
    order = morton_order(uv[triangles].mean(axis=1))
    lines = []
    for p, chunk in enumerate(np.array_split(order, args.pieces)):
        owned = np.zeros(len(triangles), dtype=bool)
        owned[chunk] = True
        keep = ghost_rings(triangles, owned, args.ghost_levels, len(uv))
        name = f"piece_{p}.vtu"
        # vtkDataSetAttributes::DUPLICATECELL = 1
        write_piece(os.path.join(args.dir, name), uv, z, zx, zy, triangles[keep],
                    np.where(owned[keep], 0, 1))
        lines.append(f'    <Piece Source="{name}"/>\n')
        print(f"piece {p}: {len(chunk)} triangles + {keep.sum() - len(chunk)} ghosts")
    with open(os.path.join(args.dir, "pieces.pvtu"), "w") as f:
        f.write(PVTU.format(levels=args.ghost_levels, pieces="".join(lines)))
    print(f"{len(triangles)} triangles, {len(uv)} points in {args.dir}")


def timed(fn):
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def best_spline(simple, source, repeats):
    """Best UpdatePipeline wall time of fresh CTi filters on `source`, and their cell count."""
    best, cells = float("inf"), 0
    for _ in range(repeats):
        spline = simple.CloughTocherSplineFilter(Input=source, Construction="CTi")
        best = builtins.min(best, timed(spline.UpdatePipeline))
        cells = spline.GetDataInformation().GetNumberOfCells()
        simple.Delete(spline)
    return best, cells


def run(args):
    import paraview.simple as simple
    from vtkmodules.vtkParallelCore import vtkMultiProcessController

    controller = vtkMultiProcessController.GetGlobalController()
    ranks = controller.GetNumberOfProcesses() if controller else 1
    simple.LoadPlugin(args.plugin, remote=False)
    whole = simple.XMLUnstructuredGridReader(FileName=[os.path.join(args.dir, "whole.vtu")])
    whole.UpdatePipeline()
    triangles = whole.GetDataInformation().GetNumberOfCells()
    print(f"\n{'ranks':>5}{'triangles':>11}  {'route':<12}{'read/D3 s':>10}{'spline s':>10}")
    failed = False

    def report(route, before, seconds, cells):
        nonlocal failed
        print(f"{ranks:>5}{triangles:>11}  {route:<12}{before:>10.3f}{seconds:>10.3f}", flush=True)
        if cells != 3 * triangles:
            print(f"FAIL: {route}: {cells} micro-triangles, expected {3 * triangles}", flush=True)
            failed = True

    if ranks == 1:
        source = whole
        read = timed(lambda: simple.XMLUnstructuredGridReader(
            FileName=[os.path.join(args.dir, "whole.vtu")]).UpdatePipeline())
    else:
        source = simple.XMLPartitionedUnstructuredGridReader(
            FileName=[os.path.join(args.dir, "pieces.pvtu")])
        read = timed(source.UpdatePipeline)
    spline, cells = best_spline(simple, source, args.repeats)
    report("partitioned", read, spline, cells)
    if ranks > 1 and not args.no_d3:
        d3 = simple.D3(Input=whole)
        first = simple.CloughTocherSplineFilter(Input=d3, Construction="CTi")
        distribute = timed(first.UpdatePipeline)
        again, cells = best_spline(simple, d3, args.repeats)
        report("D3", distribute - again, again, cells)
    if failed:
        sys.exit(1)


def clocks(fn):
    """CPU and wall seconds of fn() on this rank."""
    cpu, wall = time.process_time(), time.perf_counter()
    fn()
    return time.process_time() - cpu, time.perf_counter() - wall


def ranks_mode(args):
    import numpy as np
    from ctsplines import vtkCloughTocherSplineFilter
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkIdTypeArray
    from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid
    from vtkmodules.vtkFiltersParallelGeometry import vtkPDistributedDataFilter
    from vtkmodules.vtkIOXML import vtkXMLPUnstructuredGridReader, vtkXMLUnstructuredGridReader
    from vtkmodules.vtkParallelCore import vtkCommunicator, vtkMultiProcessController

    controller = vtkMultiProcessController.GetGlobalController()
    rank, n = controller.GetLocalProcessId(), controller.GetNumberOfProcesses()
    levels = vtkCloughTocherSplineFilter().GetRequiredGhostLevels()
    lines = []

    def spline(route, data):
        """First and best CPU/wall of fresh CTi filters on data; checks the cell count."""
        ghosts = data.GetCellData().GetArray("vtkGhostType")
        owned = data.GetNumberOfCells() - (np.count_nonzero(vtk_to_numpy(ghosts)) if ghosts else 0)
        times, cells = [], 0
        for _ in range(args.repeats):
            f = vtkCloughTocherSplineFilter()
            f.SetConstruction(vtkCloughTocherSplineFilter.CTi)
            f.SetInputData(data)
            controller.Barrier()
            times.append(clocks(lambda: f.UpdatePiece(rank, n, 0)))
            cells = f.GetOutput().GetNumberOfCells()
            del f
        best = builtins.min(times)
        lines.append(f"{rank:>5}{data.GetNumberOfCells():>10}  {route + ' spline':<19}"
                     f"{times[0][0]:>7.3f}{times[0][1]:>7.3f}{best[0]:>7.3f}{best[1]:>7.3f}")
        if cells != 3 * owned:
            lines.append(f"FAIL: rank {rank}, {route}: {cells} micro-triangles, expected {3 * owned}")
        return cells

    def stage(route, data, seconds):
        lines.append(f"{rank:>5}{data.GetNumberOfCells():>10}  {route:<19}"
                     f"{seconds[0]:>7.3f}{seconds[1]:>7.3f}")

    reader = vtkXMLUnstructuredGridReader() if n == 1 else vtkXMLPUnstructuredGridReader()
    reader.SetFileName(os.path.join(args.dir, "whole.vtu" if n == 1 else "pieces.pvtu"))
    stage("read", reader.GetOutput(), clocks(lambda: reader.UpdatePiece(rank, n, levels)))
    total = [spline("partitioned", reader.GetOutput())]
    if n > 1:
        whole = vtkUnstructuredGrid()
        if rank == 0:
            single = vtkXMLUnstructuredGridReader()
            single.SetFileName(os.path.join(args.dir, "whole.vtu"))
            single.Update()
            whole = single.GetOutput()
        d3 = vtkPDistributedDataFilter()
        d3.SetController(controller)
        d3.SetInputData(whole)
        controller.Barrier()
        stage("D3", d3.GetOutput(), clocks(lambda: d3.UpdatePiece(rank, n, levels)))
        total.append(spline("D3", d3.GetOutput()))
    for route, cells in zip(["partitioned", "D3"], total):
        mine, summed = vtkIdTypeArray(), vtkIdTypeArray()
        mine.InsertNextValue(cells)
        controller.AllReduce(mine, summed, vtkCommunicator.SUM_OP)
        if rank == 0 and n > 1:
            lines.append(f"      {route}: {summed.GetValue(0)} micro-triangles on {n} ranks")
    if rank == 0:
        print(f"\n{'rank':>5}{'cells':>10}  {'stage':<19}{'cpu':>7}{'wall':>7}{'cpu':>7}{'wall':>7}"
              f"  (seconds; spline: first, then best of {args.repeats})")
    for r in range(n):
        if r == rank:
            print("\n".join(lines), flush=True)
        controller.Barrier()
    if any(line.startswith("FAIL") for line in lines):
        sys.exit(1)


if __name__ == "__main__":
    arguments = parse()
    {"prepare": prepare, "run": run, "ranks": ranks_mode}[arguments.mode](arguments)
