# SPDX-License-Identifier: GPL-3.0-or-later
"""The kernel's construction table (Filters/Kernel/Constructions.h, docs/constructions.md), read
through the wrapped vtkCloughTocherSplineFilter: names, values and what each construction can
do. Lists of constructions anywhere in the package come from here."""
from .CTSplinesFilters import vtkCloughTocherSplineFilter as _F


def names():
    """All constructions, in value order (the values SetConstruction takes)."""
    return [_F.GetConstructionName(i) for i in range(_F.GetNumberOfConstructions())]


def value(name):
    """The value of a construction by name; ValueError for an unknown name."""
    v = _F.GetConstructionValue(name)
    if v < 0:
        raise ValueError(f"unknown construction {name!r}: one of {', '.join(names())}")
    return v


def degree(name):
    """Degree of the output Bézier triangles (3 or 4)."""
    return _F.GetConstructionDegree(value(name))


def summary(name):
    return _F.GetConstructionSummary(value(name))


def stitched():
    """The constructions a CAD model can be converted with (they take prescribed boundary
    curves): the study's cubic constructions CTo..KaG."""
    return [n for i, n in enumerate(names()) if _F.GetConstructionCanBeStitched(i)]


def with_bezier_extraction():
    """The constructions whose spline space has a Bézier extraction (ComputeBezierExtraction)."""
    return [n for i, n in enumerate(names()) if _F.GetConstructionHasBezierExtraction(i)]
