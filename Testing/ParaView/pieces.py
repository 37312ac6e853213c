# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared by distributed.py and scaling.py (imported from the scripts' folder).

TO_POLYDATA is the script of a ProgrammableFilter (output vtkPolyData) after the redistribution:
the pieces are vtkUnstructuredGrid, the spline filter takes vtkPolyData, and ParaView's surface
filter would drop the ghost triangles, so the piece is converted as it is. It leaves `ug` (the
input piece) and `pd` (the output) for scripts that append to it."""

TO_POLYDATA = """
from vtkmodules.vtkCommonDataModel import vtkCellArray
ug = self.GetInputDataObject(0, 0)
pd = self.GetOutputDataObject(0)
if ug.GetNumberOfCells():
    pd.SetPoints(ug.GetPoints())
    polys = vtkCellArray()
    polys.SetData(ug.GetCells().GetOffsetsArray(), ug.GetCells().GetConnectivityArray())
    pd.SetPolys(polys)
    pd.GetPointData().ShallowCopy(ug.GetPointData())
    pd.GetCellData().ShallowCopy(ug.GetCellData())
"""
