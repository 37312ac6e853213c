# SPDX-License-Identifier: GPL-3.0-or-later
"""ctsplines.io's own .vtu writer of multiblock blocks (_grid_file, used by _write_blocks for the
CLI's per-face splines): what VTK's reader reads back is what was written, bit for bit, with and
without LZ4; what it cannot write goes to VTK's writer."""
import os
import tempfile
import unittest

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import (
    vtkBitArray,
    vtkCharArray,
    vtkDoubleArray,
    vtkFloatArray,
    vtkIdList,
    vtkIdTypeArray,
    vtkIntArray,
    vtkLongArray,
    vtkLongLongArray,
    vtkPoints,
    vtkShortArray,
    vtkSignedCharArray,
    vtkSOADataArrayTemplate,
    vtkStringArray,
    vtkUnsignedCharArray,
    vtkUnsignedIntArray,
    vtkUnsignedLongLongArray,
    vtkUnsignedShortArray,
)
from vtkmodules.vtkCommonDataModel import (
    VTK_BEZIER_TRIANGLE,
    VTK_HEXAHEDRON,
    VTK_TRIANGLE,
    VTK_VERTEX,
    vtkCompositeDataSet,
    vtkDataSetAttributes,
    vtkMultiBlockDataSet,
    vtkPolyData,
    vtkUnstructuredGrid,
)
from vtkmodules.vtkIOXML import (
    vtkXMLMultiBlockDataReader,
    vtkXMLUnstructuredGridReader,
    vtkXMLUnstructuredGridWriter,
)

from ctsplines import io

NUMERIC = (vtkCharArray, vtkSignedCharArray, vtkUnsignedCharArray, vtkShortArray,
           vtkUnsignedShortArray, vtkIntArray, vtkUnsignedIntArray, vtkLongArray,
           vtkLongLongArray, vtkUnsignedLongLongArray, vtkIdTypeArray, vtkFloatArray,
           vtkDoubleArray)
NAMES = ("plain", 'quote " and <tag> & amp', "tab\there, newline\nthere", "ünïcödé ∂")


def numeric(cls, name, tuples, components, rng):
    a = cls()
    a.SetName(name)
    a.SetNumberOfComponents(components)
    a.SetNumberOfTuples(tuples)
    values = vtk_to_numpy(a) if tuples else None
    if values is not None:
        if np.issubdtype(values.dtype, np.integer):
            info = np.iinfo(values.dtype)
            values[...] = rng.integers(info.min, info.max, values.shape, dtype=values.dtype,
                                       endpoint=True)
        else:
            values[...] = rng.standard_normal(values.shape)
            values.flat[0] = np.nan
            if values.size > 1:
                values.flat[1] = -np.inf
    return a


def strings(name, values):
    a = vtkStringArray()
    a.SetName(name)
    for v in values:
        a.InsertNextValue(v)
    return a


def grid(rng, points=40, cells=True):
    """An unstructured grid of a Bézier triangle, a hexahedron, triangles and vertices, with every
    numeric VTK type and strings in its point, cell and field data, attribute designations,
    component names and awkward names."""
    g = vtkUnstructuredGrid()
    p = vtkPoints()
    p.SetDataTypeToDouble()
    p.SetNumberOfPoints(points)
    vtk_to_numpy(p.GetData())[...] = rng.standard_normal((points, 3))
    g.SetPoints(p)
    g.Allocate(8)
    if cells:
        g.InsertNextCell(VTK_BEZIER_TRIANGLE, 10, list(range(10)))
        g.InsertNextCell(VTK_HEXAHEDRON, 8, list(range(10, 18)))
        g.InsertNextCell(VTK_TRIANGLE, 3, [18, 19, 20])
        g.InsertNextCell(VTK_VERTEX, 1, [points - 1])
    n = g.GetNumberOfCells()
    for data, tuples in ((g.GetPointData(), points), (g.GetCellData(), n)):
        for k, cls in enumerate(NUMERIC):
            data.AddArray(numeric(cls, f"{NAMES[k % len(NAMES)]} {cls.__name__}", tuples,
                                  1 + k % 3, rng))
        data.AddArray(strings("labels", [f"item {i} <&>" for i in range(tuples)]))
    uv = numeric(vtkDoubleArray, "UV", points, 2, rng)
    g.GetPointData().SetTCoords(uv)
    normals = numeric(vtkFloatArray, "Normals", points, 3, rng)
    normals.SetComponentName(0, "n_x")
    normals.SetComponentName(2, 'n "z"')
    g.GetPointData().SetNormals(normals)
    ids = numeric(vtkIdTypeArray, "ids", points, 1, rng)
    g.GetPointData().SetGlobalIds(ids)
    degrees = numeric(vtkIntArray, "HigherOrderDegrees", n, 3, rng)
    g.GetCellData().SetHigherOrderDegrees(degrees)
    g.GetCellData().SetScalars(g.GetCellData().GetArray(0))
    fd = g.GetFieldData()
    fd.AddArray(numeric(vtkIdTypeArray, "FaceId", 1, 1, rng))
    fd.AddArray(numeric(vtkDoubleArray, "MaxGap", 1, 1, rng))
    fd.AddArray(numeric(vtkDoubleArray, "Empty", 0, 3, rng))
    fd.AddArray(strings("FaceName", ["Face 7 <&> ünï"]))
    fd.AddArray(strings("Several", ["", "two", "", "four\nlines"]))
    return g


def plain_names(g):
    """A copy of g whose arrays and components have plain names: VTK's writer does not escape
    them in its XML."""
    plain = g.NewInstance()
    plain.DeepCopy(g)
    for data in (plain.GetPointData(), plain.GetCellData(), plain.GetFieldData()):
        for i in range(data.GetNumberOfArrays()):
            array = data.GetAbstractArray(i)
            array.SetName(f"array {i}")
            for c in range(array.GetNumberOfComponents() if array.HasAComponentName() else 0):
                array.SetComponentName(c, f"component {c}")
    return plain


def read_vtu(path):
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


class GridFileTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.rng = np.random.default_rng(7)

    def tearDown(self):
        self.dir.cleanup()

    def round_trip(self, g):
        """g written by _grid_file and read back, and as VTK's writer's file reads back."""
        content = io._grid_file(g)
        self.assertIsNotNone(content)
        path = os.path.join(self.dir.name, "g.vtu")
        with open(path, "wb") as f:
            f.write(content)
        writer = vtkXMLUnstructuredGridWriter()
        writer.SetInputData(plain_names(g))
        writer.SetFileName(os.path.join(self.dir.name, "vtk.vtu"))
        writer.SetDataModeToBinary()  # VTK 9.2 reads its appended string arrays back empty
        writer.Write()
        return read_vtu(path), read_vtu(writer.GetFileName())

    def assertSameArrays(self, a, b, vtks, where):
        """b holds a's arrays, values bit for bit, of the types VTK's reader gives VTK's
        writer's file (vtks: it reads char as signed char, long as long long)."""
        self.assertEqual(a.GetNumberOfArrays(), b.GetNumberOfArrays(), where)
        for i in range(a.GetNumberOfArrays()):
            x = a.GetAbstractArray(i)
            y = b.GetAbstractArray(i)
            name = f"{where} {x.GetName()!r}"
            self.assertEqual(x.GetName(), y.GetName(), name)
            self.assertEqual(vtks.GetAbstractArray(i).GetDataType(), y.GetDataType(), name)
            self.assertEqual(x.GetDataTypeSize(), y.GetDataTypeSize(), name)
            self.assertEqual(x.GetNumberOfComponents(), y.GetNumberOfComponents(), name)
            self.assertEqual(x.GetNumberOfTuples(), y.GetNumberOfTuples(), name)
            for c in range(x.GetNumberOfComponents()):
                self.assertEqual(x.GetComponentName(c), y.GetComponentName(c), name)
            if x.IsA("vtkStringArray"):
                self.assertEqual([x.GetValue(k) for k in range(x.GetNumberOfValues())],
                                 [y.GetValue(k) for k in range(y.GetNumberOfValues())], name)
            elif x.GetNumberOfValues():
                self.assertEqual(vtk_to_numpy(x).tobytes(), vtk_to_numpy(y).tobytes(), name)
        if a.IsA("vtkDataSetAttributes"):
            for kind in range(vtkDataSetAttributes.NUM_ATTRIBUTES):
                x, y = a.GetAbstractAttribute(kind), b.GetAbstractAttribute(kind)
                self.assertEqual(x and x.GetName(), y and y.GetName(),
                                 f"{where} {vtkDataSetAttributes.GetAttributeTypeAsString(kind)}")

    def assertSameGrid(self, g, back):
        h, vtks = back
        self.assertEqual(g.GetNumberOfPoints(), h.GetNumberOfPoints())
        self.assertEqual(g.GetNumberOfCells(), h.GetNumberOfCells())
        self.assertEqual(vtk_to_numpy(g.GetPoints().GetData()).tobytes(),
                         vtk_to_numpy(h.GetPoints().GetData()).tobytes())
        for get in (lambda x: x.GetCells().GetConnectivityArray(),
                    lambda x: x.GetCells().GetOffsetsArray()):
            self.assertEqual(vtk_to_numpy(get(g)).tolist(), vtk_to_numpy(get(h)).tolist())
        self.assertEqual([g.GetCellType(c) for c in range(g.GetNumberOfCells())],
                         [h.GetCellType(c) for c in range(h.GetNumberOfCells())])
        self.assertSameArrays(g.GetPointData(), h.GetPointData(), vtks.GetPointData(),
                              "point data")
        self.assertSameArrays(g.GetCellData(), h.GetCellData(), vtks.GetCellData(), "cell data")
        self.assertSameArrays(g.GetFieldData(), h.GetFieldData(), vtks.GetFieldData(),
                              "field data")

    def test_read_back_bit_for_bit_with_lz4_and_raw(self):
        g = grid(self.rng)
        self.assertIsNotNone(io._lz4_block, "python3-lz4 is a dependency (setup.sh)")
        lz4 = self.round_trip(g)
        self.assertSameGrid(g, lz4)
        with open(os.path.join(self.dir.name, "g.vtu"), "rb") as f:
            self.assertIn(b'compressor="vtkLZ4DataCompressor"', f.read(400))
        saved, io._lz4_block = io._lz4_block, None
        try:
            raw = self.round_trip(g)
        finally:
            io._lz4_block = saved
        self.assertSameGrid(g, raw)

    def test_empty_grids_and_32_bit_cells(self):
        self.assertSameGrid(g := grid(self.rng, points=0, cells=False), self.round_trip(g))
        g = grid(self.rng, cells=False)  # points without cells
        self.assertSameGrid(g, self.round_trip(g))
        g = grid(self.rng)
        cells = g.GetCells()
        if cells.IsStorage64Bit():
            cells.ConvertTo32BitStorage()
        self.assertSameGrid(g, self.round_trip(g))

    def test_what_it_cannot_write_goes_to_vtks_writer(self):
        polyhedron = vtkUnstructuredGrid()
        polyhedron.SetPoints(vtkPoints())
        for p in ((0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)):
            polyhedron.GetPoints().InsertNextPoint(p)
        stream = vtkIdList()  # a tetrahedron as a polyhedron: 4 faces of 3 points
        for i in (4, 3, 0, 2, 1, 3, 0, 1, 3, 3, 1, 2, 3, 3, 2, 0, 3):
            stream.InsertNextId(i)
        polyhedron.InsertNextCell(42, stream)  # VTK_POLYHEDRON
        bits = plain_names(grid(self.rng))
        flags = vtkBitArray()
        flags.SetName("bits")
        flags.SetNumberOfTuples(bits.GetNumberOfPoints())
        for k in range(bits.GetNumberOfPoints()):
            flags.SetValue(k, k % 3 == 0)
        bits.GetPointData().AddArray(flags)
        soa = grid(self.rng)
        split = vtkSOADataArrayTemplate['float64']()  # written through VTK's AOS copy
        split.SetName("soa")
        split.SetNumberOfComponents(2)
        split.SetNumberOfTuples(soa.GetNumberOfPoints())
        split.Fill(0.25)
        soa.GetPointData().AddArray(split)
        polydata = vtkPolyData()
        polydata.SetPoints(polyhedron.GetPoints())
        blocks = {"polyhedron": polyhedron, "bits": bits, "soa": soa,
                  "plain": grid(self.rng), "polydata": polydata}
        for name in ("polyhedron", "bits", "polydata"):
            self.assertIsNone(io._grid_file(blocks[name]), name)
        # In a multiblock: VTK's writer writes those, ours the others; all read back.
        mb = vtkMultiBlockDataSet()
        for i, (name, block) in enumerate(blocks.items()):
            mb.SetBlock(i, block)
            mb.GetMetaData(i).Set(vtkCompositeDataSet.NAME(), name)
        mb.SetBlock(len(blocks), None)
        path = os.path.join(self.dir.name, "m.vtm")

        class Messages:
            def watch(self, writer):
                return writer

            def take_errors(self):
                return []

        io._write_blocks(mb, path, Messages())
        r = vtkXMLMultiBlockDataReader()
        r.SetFileName(path)
        r.Update()
        back = r.GetOutput()
        self.assertEqual(back.GetNumberOfBlocks(), len(blocks) + 1)
        for i, name in enumerate(blocks):
            self.assertEqual(back.GetMetaData(i).Get(vtkCompositeDataSet.NAME()), name)
        vtks = self.round_trip(blocks["plain"])[1]
        self.assertSameGrid(blocks["plain"], (back.GetBlock(3), vtks))
        for i, name in ((1, "bits"), (2, "soa")):
            a = blocks[name].GetPointData().GetArray(name)
            b = back.GetBlock(i).GetPointData().GetArray(name)
            self.assertEqual([a.GetValue(k) for k in range(a.GetNumberOfValues())],
                             [b.GetValue(k) for k in range(b.GetNumberOfValues())], name)
        self.assertEqual(back.GetBlock(0).GetCellType(0), 42)
        self.assertIsNone(back.GetBlock(len(blocks)))
        self.assertTrue(os.path.isfile(os.path.join(self.dir.name, "m", "m_4.vtp")))


if __name__ == "__main__":
    unittest.main()
