# SPDX-License-Identifier: GPL-3.0-or-later
"""Strong scaling of the spline filter in pvbatch (a measurement, not a test).

    VTK_SMP_BACKEND_IN_USE=Sequential mpirun -np N pvbatch scaling.py PLUGIN \
        [--resolution 224 500] [--repeats 3]

(as root in a container add --allow-run-as-root, --oversubscribe for more ranks than cores, and
OMPI_MCA_btl=self,vader.) Franke's function on the Resolution x Resolution grid (2 R^2
triangles: 224 -> 1.0e5, 500 -> 5.0e5, 707 -> 1.0e6) is made on rank 0, distributed by D3 with
the ghost levels the filter asks for, converted to vtkPolyData, and splined with CTi and with Ka
plus one IM step. A first spline filter brings the pipeline up to date for its ghost-level
request (the "distribute" column: D3, ghost cells, conversion and that first spline); then fresh
filters with the same settings re-execute alone, and the best of --repeats of their
UpdatePipeline wall times on rank 0 is reported ("spline"). UpdatePipeline returns after every
rank has finished (ParaView gathers the data information), so it is the slowest piece's time.
The Sequential backend keeps one thread per rank, so that ranks are the only parallelism."""
import argparse
import builtins
import time

import paraview.simple as simple
from vtkmodules.vtkCommonCore import vtkSMPTools
from vtkmodules.vtkParallelCore import vtkMultiProcessController

from pieces import TO_POLYDATA

parser = argparse.ArgumentParser()
parser.add_argument("plugin")
parser.add_argument("--resolution", type=int, nargs="+", default=[224, 500])
parser.add_argument("--repeats", type=int, default=3)
args = parser.parse_args()

controller = vtkMultiProcessController.GetGlobalController()
ranks = controller.GetNumberOfProcesses() if controller else 1
simple.LoadPlugin(args.plugin, remote=False)



def main():
    # Local names, builtins.min: on rank 0 ParaView runs the programmable filter's script in
    # __main__ after "from ...numpy_interface.algorithms import *" (shadows min, sum, ...).
    print(f"{ranks} ranks, SMP backend {vtkSMPTools.GetBackend()} "
          f"({vtkSMPTools.GetEstimatedNumberOfThreads()} threads on rank 0)", flush=True)
    rows = []
    for resolution in args.resolution:
        source = simple.SampledSurfaceSource(Surface="Franke", Domain="Grid",
                                             Resolution=resolution)
        pieces = simple.D3(Input=source)
        poly = simple.ProgrammableFilter(Input=pieces, OutputDataSetType="vtkPolyData",
                                         Script=TO_POLYDATA)
        triangles = 2 * resolution * resolution
        for construction, iterations in (("CTi", 0), ("Ka", 1)):
            label = construction + ("+IM" * iterations)
            settings = dict(Input=poly, Construction=construction, Iterations=iterations)
            first = simple.CloughTocherSplineFilter(**settings)
            start = time.perf_counter()
            first.UpdatePipeline()
            distribute = time.perf_counter() - start
            best = float("inf")
            for _ in range(args.repeats):
                spline = simple.CloughTocherSplineFilter(**settings)
                start = time.perf_counter()
                spline.UpdatePipeline()
                best = builtins.min(best, time.perf_counter() - start)
                cells = spline.GetDataInformation().GetNumberOfCells()
                simple.Delete(spline)
            simple.Delete(first)
            if cells != 3 * triangles:
                print(f"WARNING: {label}: {cells} micro-triangles, expected {3 * triangles}")
            rows.append((triangles, label, distribute, best))
            print(f"  {triangles} triangles {label}: distribute {distribute:.3f} s, "
                  f"spline {best:.3f} s", flush=True)
        for proxy in (poly, pieces, source):
            simple.Delete(proxy)
    print(f"\n{'ranks':>5}{'triangles':>11}  {'case':<7}{'distribute s':>13}{'spline s':>10}")
    for triangles, label, distribute, best in rows:
        print(f"{ranks:>5}{triangles:>11}  {label:<7}{distribute:>13.3f}{best:>10.3f}")


main()
