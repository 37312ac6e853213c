# SPDX-License-Identifier: GPL-3.0-or-later
"""CTSplines: Clough-Tocher splines of parametrised triangle meshes, as VTK filters.

    import vtk                      # the same VTK: objects pass freely between both
    from ctsplines import vtkCloughTocherSplineFilter

The wrapped classes come from the C++ module CTSplines::Filters and, when the build found
OpenCASCADE, CTSplines::IOCAD (vtkCADFaceSampler, vtkWatertightSplineStitcher; check with
``ctsplines.HAS_IOCAD``).
"""
import importlib as _importlib
import importlib.util as _importlib_util
import os as _os

# Wrapped classes build on VTK's own Python modules: import them first so that both packages
# share one set of VTK types.
from vtkmodules import vtkCommonCore as _vtkCommonCore  # noqa: F401
from vtkmodules import vtkCommonDataModel as _vtkCommonDataModel  # noqa: F401
from vtkmodules import vtkCommonExecutionModel as _vtkCommonExecutionModel  # noqa: F401

from .CTSplinesFilters import *  # noqa: F401,F403

# CTSplinesIOCAD exists only in builds with OpenCASCADE. Looking for the module rather than
# catching ImportError keeps a broken one (a missing OCCT library) a visible error.
HAS_IOCAD = _importlib_util.find_spec(".CTSplinesIOCAD", __name__) is not None
if HAS_IOCAD:
    from .CTSplinesIOCAD import *  # noqa: F401,F403


def _use_threads():
    """The filters' loops run on their own pool of threads, one per core (CTSPLINES_NUM_THREADS,
    see Filters/CTSplinesSMP.h). VTK's global backend is left as it is: VTK 9.2's STDThread
    backend starts threads on every small vtkSMPTools call of VTK's own (array ranges in the
    writers), tens of thousands for a CAD model of many faces. With VTK_SMP_BACKEND_IN_USE or
    CTSPLINES_NUM_THREADS set, nothing changes (the filters follow VTK, or that count)."""
    if "VTK_SMP_BACKEND_IN_USE" in _os.environ or "CTSPLINES_NUM_THREADS" in _os.environ:
        return
    cores = len(_os.sched_getaffinity(0)) if hasattr(_os, "sched_getaffinity") else _os.cpu_count()
    _os.environ["CTSPLINES_NUM_THREADS"] = str(cores or 1)


_use_threads()

# numpy's helpers (arrays.py) load on first use: numpy is half of the package's import time, and
# neither the command line nor the filters need it.
_LAZY = {"functional_mesh": "arrays", "mesh_from_arrays": "arrays"}


def __getattr__(name):
    if name in _LAZY:
        return getattr(_importlib.import_module("." + _LAZY[name], __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))

__version__ = "0.1.0"
