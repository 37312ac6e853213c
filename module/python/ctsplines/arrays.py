# SPDX-License-Identifier: GPL-3.0-or-later
"""numpy helpers: build the filters' input from arrays and read results back as arrays."""
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData


def _named(array, name):
    a = numpy_to_vtk(np.ascontiguousarray(array, dtype=np.float64), deep=True)
    a.SetName(name)
    return a


def mesh_from_arrays(uv, triangles, f, fu, fv, edge_gradients=None):
    """A parametrised triangle mesh for vtkCloughTocherSplineFilter.

    uv: #V by 2 parameter values; triangles: #T by 3 vertex ids; f, fu, fv: #V by 3 positions and
    derivatives; edge_gradients: optional #T by 18 (local edges (p0,p1), (p1,p2), (p2,p0); f_u
    then f_v at each edge midpoint)."""
    uv = np.asarray(uv, dtype=np.float64)
    triangles = np.asarray(triangles, dtype=np.int64)
    f = np.asarray(f, dtype=np.float64)
    if uv.ndim != 2 or uv.shape[1] != 2:
        raise ValueError(f"uv must be #V by 2, got shape {uv.shape}")
    if triangles.ndim != 2 or triangles.shape[1] != 3:
        raise ValueError(f"triangles must be #T by 3, got shape {triangles.shape}")
    for name, a in (("f", f), ("fu", fu), ("fv", fv)):
        if np.shape(a) != (uv.shape[0], 3):
            raise ValueError(f"{name} must be #V by 3 = ({uv.shape[0]}, 3), got {np.shape(a)}")
    mesh = vtkPolyData()
    points = vtkPoints()
    points.SetData(_named(f, "Points"))
    mesh.SetPoints(points)
    n = triangles.shape[0]
    offsets = numpy_to_vtkIdTypeArray(np.arange(0, 3 * n + 1, 3, dtype=np.int64), deep=True)
    conn = numpy_to_vtkIdTypeArray(triangles.ravel().astype(np.int64), deep=True)
    cells = vtkCellArray()
    cells.SetData(offsets, conn)
    mesh.SetPolys(cells)
    pd = mesh.GetPointData()
    pd.AddArray(_named(uv, "UV"))
    pd.AddArray(_named(fu, "dFdu"))
    pd.AddArray(_named(fv, "dFdv"))
    if edge_gradients is not None:
        eg = np.asarray(edge_gradients, dtype=np.float64)
        if eg.shape != (n, 18):
            raise ValueError(f"edge_gradients must be #T by 18 = ({n}, 18), got {eg.shape}")
        mesh.GetCellData().AddArray(_named(eg, "EdgeGradients"))
    return mesh


def functional_mesh(xy, triangles, z, zx, zy, edge_gradients=None):
    """The functional case z = f(x, y): U = (x, y), f = (x, y, z), f_u = (1, 0, z_x),
    f_v = (0, 1, z_y). edge_gradients: optional #T by 3 by 2 (z_x, z_y at each edge midpoint)."""
    xy = np.asarray(xy, dtype=np.float64)
    n = xy.shape[0]
    f = np.column_stack([xy, z])
    fu = np.column_stack([np.ones(n), np.zeros(n), zx])
    fv = np.column_stack([np.zeros(n), np.ones(n), zy])
    eg = None
    if edge_gradients is not None:
        g = np.asarray(edge_gradients, dtype=np.float64).reshape(-1, 3, 2)
        eg = np.zeros((g.shape[0], 3, 6))
        eg[:, :, 0] = 1.0
        eg[:, :, 2] = g[:, :, 0]
        eg[:, :, 4] = 1.0
        eg[:, :, 5] = g[:, :, 1]
        eg = eg.reshape(-1, 18)
    return mesh_from_arrays(xy, triangles, f, fu, fv, eg)


def points(data):
    """Points of any vtkPointSet as a #P by 3 array."""
    return vtk_to_numpy(data.GetPoints().GetData())


def _attribute_array(attributes, name, what):
    a = attributes.GetArray(name)
    if a is None:
        raise KeyError(f"no {what} array '{name}'")
    return vtk_to_numpy(a)


def point_array(data, name):
    """A point-data array by name as numpy (KeyError when missing)."""
    return _attribute_array(data.GetPointData(), name, "point data")


def cells(grid):
    """Connectivity of a grid whose cells all have the same size, as #C by n point ids."""
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray())
    sizes = np.diff(offsets)
    if len(sizes) and not np.all(sizes == sizes[0]):
        raise ValueError("cells of different sizes")
    return conn.reshape(len(sizes), -1) if len(sizes) else conn.reshape(0, 0)


def cell_array(data, name):
    """A cell-data array by name as numpy (KeyError when missing)."""
    return _attribute_array(data.GetCellData(), name, "cell data")


def field_values(data):
    """Field data of a data object as {name: numpy array or str} (strings for string arrays)."""
    fd = data.GetFieldData()
    out = {}
    for i in range(fd.GetNumberOfArrays()):
        a = fd.GetAbstractArray(i)
        if a.IsA("vtkStringArray"):
            out[a.GetName()] = a.GetValue(0) if a.GetNumberOfValues() == 1 else [
                a.GetValue(j) for j in range(a.GetNumberOfValues())]
        else:
            out[a.GetName()] = vtk_to_numpy(a)
    return out


def triangles(polydata):
    """The polygons of a vtkPolyData of triangles (a tessellation) as #T by 3 point ids."""
    polys = polydata.GetPolys()
    offsets = vtk_to_numpy(polys.GetOffsetsArray())
    if len(offsets) > 1 and not np.all(np.diff(offsets) == 3):
        raise ValueError("polygons that are not triangles")
    return vtk_to_numpy(polys.GetConnectivityArray()).reshape(-1, 3)

