# SPDX-License-Identifier: GPL-3.0-or-later
"""Files and pipeline plumbing for the command line: reading meshes (VTP, VTU, VTK, OBJ, PLY) and
CAD models (STEP, IGES), writing results, collecting VTK's error messages and showing
progress."""
import os
import re
import sys

from vtkmodules.util import vtkConstants
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import (
    vtkCommand,
    vtkLogger,
    vtkOutputWindow,
    vtkStringOutputWindow,
)
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData


class InputError(Exception):
    """A file that is missing, of an unknown format or unreadable (exit code 3)."""


class FilterError(Exception):
    """A filter refused its input; the message is what it reported (exit code 1)."""


READ_FORMATS = (".vtp", ".vtu", ".vtk", ".obj", ".ply")
WRITE_FORMATS = (".vtp", ".vtu", ".vtk", ".obj", ".ply")
CAD_FORMATS = (".step", ".stp", ".iges", ".igs")

# "ERROR: In file.cxx, line 12\nvtkSomeClass (0x55d0...): the message\n\n"
_VTK_MESSAGE = re.compile(
    r"(?:ERROR|Warning): In [^\n]*, line \d+\n(?:\w+ \(0x[0-9a-fA-F]+\): )?(.*)", re.S)


def clean_vtk_message(text):
    """The message of a vtkErrorMacro/vtkWarningMacro text, without file, line and address."""
    m = _VTK_MESSAGE.match(text.strip())
    return (m.group(1) if m else text).strip()


class VTKMessages:
    """Collects the errors and warnings of the observed algorithms instead of printing them.

    vtkErrorMacro invokes ErrorEvent when the object has an observer, and prints to the output
    window otherwise; the observers below catch the algorithms' own messages. Everything else
    (the executive's 'returned failure for request' with its information dump, parser details)
    goes to a string output window and, for readers, may be asked for with details()."""

    def __init__(self):
        self.errors = []
        self.warnings = []
        self._window = vtkStringOutputWindow()
        self._previous = None
        self._verbosity = None

    def __enter__(self):
        self._previous = vtkOutputWindow.GetInstance()
        self._previous.Register(None)
        vtkOutputWindow.SetInstance(self._window)
        # vtkOutputWindow also logs through vtkLogger, which writes to stderr by itself.
        self._verbosity = vtkLogger.GetCurrentVerbosityCutoff()
        vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
        return self

    def __exit__(self, *exc):
        vtkOutputWindow.SetInstance(self._previous)
        self._previous.UnRegister(None)
        vtkLogger.SetStderrVerbosity(self._verbosity)
        return False

    def watch(self, algorithm):
        @calldata_type(vtkConstants.VTK_STRING)
        def on_error(obj, event, text):
            self.errors.append(f"{obj.GetClassName()}: {clean_vtk_message(text)}")

        @calldata_type(vtkConstants.VTK_STRING)
        def on_warning(obj, event, text):
            self.warnings.append(f"{obj.GetClassName()}: {clean_vtk_message(text)}")

        algorithm.AddObserver(vtkCommand.ErrorEvent, on_error)
        algorithm.AddObserver(vtkCommand.WarningEvent, on_warning)
        return algorithm

    def details(self):
        """Messages that reached the output window, minus the executive's failure reports."""
        out = []
        for block in re.split(r"\n\n+(?=ERROR|Warning)", self._window.GetOutput()):
            if not block.strip() or "returned failure for request" in block:
                continue
            out.append(clean_vtk_message(block))
        return out

    def take_errors(self):
        errors, self.errors = self.errors, []
        return errors


class Progress:
    """A progress bar on stderr driven by the algorithms' ProgressEvent."""

    def __init__(self, enabled, stream=None, width=30):
        self.stream = stream or sys.stderr
        self.enabled = enabled
        self.width = width
        self._last = None

    @staticmethod
    def wanted(flag, stream=None):
        """--progress / --no-progress, else on when stderr is a terminal."""
        if flag is not None:
            return flag
        stream = stream or sys.stderr
        return hasattr(stream, "isatty") and stream.isatty()

    def watch(self, algorithm, label):
        if not self.enabled:
            return algorithm

        def on_progress(obj, event):
            self.show(label, obj.GetProgress())

        algorithm.AddObserver(vtkCommand.ProgressEvent, on_progress)
        algorithm.AddObserver(vtkCommand.EndEvent, lambda obj, event: self.show(label, 1.0))
        return algorithm

    def show(self, label, fraction):
        fraction = min(max(fraction, 0.0), 1.0)
        key = (label, int(fraction * 100))
        if key == self._last:
            return
        self._last = key
        filled = int(round(fraction * self.width))
        bar = "#" * filled + "-" * (self.width - filled)
        end = "\n" if fraction >= 1.0 else ""
        self.stream.write(f"\r{label:<14} [{bar}] {fraction * 100:5.1f}%{end}")
        self.stream.flush()


def _extension(path):
    return os.path.splitext(path)[1].lower()


def _reader(path):
    ext = _extension(path)
    if ext == ".vtp":
        from vtkmodules.vtkIOXML import vtkXMLPolyDataReader as R
    elif ext == ".vtu":
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader as R
    elif ext == ".vtk":
        from vtkmodules.vtkIOLegacy import vtkDataSetReader as R
    elif ext == ".obj":
        from vtkmodules.vtkIOGeometry import vtkOBJReader as R
    elif ext == ".ply":
        from vtkmodules.vtkIOPLY import vtkPLYReader as R
    else:
        raise InputError(f"{path}: unsupported format '{ext or '(none)'}' "
                         f"(readable: {', '.join(READ_FORMATS)})")
    reader = R()
    reader.SetFileName(path)
    return reader


def is_cad(path):
    return _extension(path) in CAD_FORMATS


def _check_exists(path):
    if not os.path.exists(path):
        raise InputError(f"{path}: no such file")
    if os.path.isdir(path):
        raise InputError(f"{path}: is a directory")


def cad_sampler(path, messages):
    """A watched vtkCADFaceSampler for a STEP or IGES file (not yet updated). Raises InputError
    for a missing file or an unknown extension, and when this build has no CTSplines::IOCAD."""
    _check_exists(path)
    if not is_cad(path):
        raise InputError(f"{path}: not a CAD model (readable: {', '.join(CAD_FORMATS)})")
    from . import HAS_IOCAD

    if not HAS_IOCAD:
        raise InputError(f"{path}: this build of ctsplines has no CAD import (CTSplines::IOCAD "
                         "is built only when CMake finds OpenCASCADE)")
    from . import vtkCADFaceSampler

    sampler = messages.watch(vtkCADFaceSampler())
    sampler.SetFileName(path)
    return sampler


def read(path, messages):
    """Reads a data set; raises InputError for a missing, unknown or unreadable file."""
    _check_exists(path)
    reader = messages.watch(_reader(path))
    if _extension(path) == ".ply" and not reader.CanReadFile(path):
        raise InputError(f"{path}: not a PLY file")
    reader.Update()
    errors = messages.take_errors()
    failed = bool(errors) or (hasattr(reader, "GetErrorCode") and reader.GetErrorCode() != 0)
    data = reader.GetOutputDataObject(0)
    if failed or data is None:
        detail = "; ".join(dict.fromkeys(messages.details() + errors)) or "reader failed"
        raise InputError(f"{path}: cannot read it: {detail}")
    if data.GetNumberOfPoints() == 0 and os.path.getsize(path) > 0 and _extension(path) in (
            ".obj", ".ply", ".vtk"):
        # These readers may accept garbage silently and produce nothing.
        raise InputError(f"{path}: cannot read it: no points found")
    return data


def as_polydata(data):
    """The input of vtkCloughTocherSplineFilter is vtkPolyData: an unstructured grid's points,
    point, cell and field data are kept as they are, its 2D cells become polygons (cell ids
    unchanged). Raises InputError for cells that cannot be part of a surface mesh."""
    if data.IsA("vtkPolyData"):
        return data
    if not data.IsA("vtkUnstructuredGrid"):
        raise InputError(f"a {data.GetClassName()} is not a surface mesh")
    from vtkmodules.vtkCommonDataModel import vtkCellTypes

    for i in range(data.GetNumberOfCells()):
        t = data.GetCellType(i)
        if data.GetCell(i).GetCellDimension() != 2 or t not in (
                vtkConstants.VTK_TRIANGLE, vtkConstants.VTK_POLYGON, vtkConstants.VTK_QUAD):
            raise InputError(f"cell {i} is a {vtkCellTypes.GetClassNameFromTypeId(t)}; a "
                             "surface mesh of polygons (triangles) is expected")
    mesh = vtkPolyData()
    mesh.SetPoints(data.GetPoints())
    polys = vtkCellArray()
    if data.GetNumberOfCells():
        polys.SetData(data.GetCells().GetOffsetsArray(), data.GetCells().GetConnectivityArray())
    mesh.SetPolys(polys)
    mesh.GetPointData().ShallowCopy(data.GetPointData())
    mesh.GetCellData().ShallowCopy(data.GetCellData())
    mesh.GetFieldData().ShallowCopy(data.GetFieldData())
    return mesh


def check_output_folder(path):
    """Raises InputError when the folder `path` is to be written into does not exist; called
    before the work too, so that a typo costs no conversion."""
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        raise InputError(f"{path}: folder {directory} does not exist")


def write(data, path, messages):
    """Writes a data set by the file's extension. A spline (vtkUnstructuredGrid) only goes to
    .vtu or .vtk; polydata to any of WRITE_FORMATS (OBJ/PLY with the UV as texture
    coordinates); a multiblock data set only to .vtm. Raises InputError for an unknown extension,
    FilterError when writing fails."""
    ext = _extension(path)
    grid = data.IsA("vtkUnstructuredGrid")
    if data.IsA("vtkMultiBlockDataSet"):
        allowed = (".vtm",)
    else:
        allowed = (".vtu", ".vtk") if grid else WRITE_FORMATS
    if ext not in allowed:
        raise InputError(f"{path}: cannot write a {data.GetClassName()} as '{ext or '(none)'}' "
                         f"(use {', '.join(allowed)})")
    if ext == ".vtu" and not grid:
        from vtkmodules.vtkFiltersCore import vtkAppendFilter

        append = vtkAppendFilter()
        append.AddInputData(data)
        append.Update()
        data = append.GetOutput()
    if ext in (".obj", ".ply"):
        # OBJ and PLY keep only the active texture coordinates: make UV active on a copy.
        copy = data.NewInstance()
        copy.ShallowCopy(data)
        pd = copy.GetPointData()
        if pd.GetTCoords() is None and pd.GetArray("UV") is not None:
            pd.SetTCoords(pd.GetArray("UV"))
        if ext == ".ply" and pd.GetTCoords() is not None and not pd.GetTCoords().IsA(
                "vtkFloatArray"):
            # vtkPLYWriter takes float texture coordinates only (and crashes after saying so).
            from vtkmodules.vtkCommonCore import vtkFloatArray

            tcoords = vtkFloatArray()
            tcoords.DeepCopy(pd.GetTCoords())
            pd.SetTCoords(tcoords)
        data = copy
    check_output_folder(path)
    if ext == ".vtm" and _flat_blocks(data):
        return _write_blocks(data, path, messages)
    if ext == ".vtm":
        from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataWriter as W
    elif ext == ".vtp":
        from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter as W
    elif ext == ".vtu":
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter as W
    elif ext == ".vtk":
        from vtkmodules.vtkIOLegacy import vtkDataSetWriter as W
    elif ext == ".obj":
        from vtkmodules.vtkIOGeometry import vtkOBJWriter as W
    else:
        from vtkmodules.vtkIOPLY import vtkPLYWriter as W
    writer = messages.watch(W())
    writer.SetFileName(path)
    writer.SetInputData(data)
    if ext == ".ply":
        writer.SetFileTypeToBinary()
    elif ext in (".vtp", ".vtu", ".vtm"):
        _fast_xml(writer)
    _check_written(writer.Write(), path, messages)
    return path


def _check_written(ok, path, messages):
    errors = messages.take_errors()
    if not ok or errors:
        raise FilterError(f"{path}: cannot write it: {'; '.join(errors) or 'writer failed'}")


def _fast_xml(writer):
    """XML data as raw binary in the appended section, compressed with LZ4: zlib took more time
    than the conversion of a small model, base64 a quarter more. ParaView and VTK's readers
    read both, string arrays included."""
    writer.SetDataModeToAppended()
    writer.SetEncodeAppendedData(False)
    writer.SetCompressorTypeToLZ4()


def _flat_blocks(data):
    """A multiblock data set of data sets (or empty blocks): what _write_blocks writes."""
    for i in range(data.GetNumberOfBlocks()):
        block = data.GetBlock(i)
        if block is not None and not block.IsA("vtkDataSet"):
            return False
    return True


def _block_name(data, i):
    from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet

    meta = data.GetMetaData(i) if data.HasMetaData(i) else None
    key = vtkCompositeDataSet.NAME()
    return meta.Get(key) if meta is not None and meta.Has(key) else None


def _field_data_xml(data):
    """The <FieldData> element of a data object's field data (inline base64, uncompressed, as
    vtkXMLMultiBlockDataWriter puts it into a .vtm), or "" when it has none."""
    if data.GetFieldData().GetNumberOfArrays() == 0:
        return ""
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    holder = vtkPolyData()
    holder.GetFieldData().ShallowCopy(data.GetFieldData())
    writer = vtkXMLPolyDataWriter()
    writer.SetInputData(holder)
    writer.SetDataModeToBinary()
    writer.SetCompressorTypeToNone()
    writer.SetHeaderTypeToUInt64()
    writer.WriteToOutputStringOn()
    writer.Write()
    text = writer.GetOutputString()
    text = text.decode() if isinstance(text, bytes) else text
    start, end = text.find("    <FieldData>"), text.find("</FieldData>")
    if start < 0 or end < 0:
        return ""
    lines = text[start:end + len("</FieldData>")].split("\n")
    return "\n".join(line[2:] for line in lines) + "\n"


def _write_blocks(data, path, messages):
    """A multiblock data set of data sets in the layout of vtkXMLMultiBlockDataWriter: the index
    PATH (.vtm) naming one file per block in the folder named after it (OUT.vtm: OUT/OUT_0.vtu,
    ...) and holding the field data. VTK's writer opens a writer per block, which seeks and
    flushes the file at every array (a second per thousand blocks): here one writer per data
    type writes each block to memory, saved in one write."""
    from vtkmodules.vtkIOXML import vtkXMLDataObjectWriter

    stem = os.path.splitext(os.path.basename(path))[0]
    folder = os.path.join(os.path.dirname(path), stem)
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as e:
        raise FilterError(f"{folder}: cannot make the folder of the blocks: {e.strerror}") from None
    writers = {}
    entries = []
    for i in range(data.GetNumberOfBlocks()):
        block = data.GetBlock(i)
        name = _block_name(data, i)
        entry = f'    <DataSet index="{i}"'
        entry += "" if name is None else f" name={_xml_attribute(name)}"
        if block is None:
            entries.append(entry + "/>\n")
            continue
        kind = block.GetDataObjectType()
        if kind not in writers:
            writers[kind] = messages.watch(vtkXMLDataObjectWriter.NewWriter(kind))
            _fast_xml(writers[kind])
            writers[kind].WriteToOutputStringOn()
        writer = writers[kind]
        file = f"{stem}/{stem}_{len(entries)}.{writer.GetDefaultFileExtension()}"
        writer.SetInputData(block)
        _check_written(writer.Write(), os.path.join(folder, os.path.basename(file)), messages)
        text = writer.GetOutputString()
        _save(os.path.join(os.path.dirname(path), file),
              text if isinstance(text, bytes) else text.encode())
        entries.append(entry + f" file={_xml_attribute(file)}/>\n")
    order = "LittleEndian" if sys.byteorder == "little" else "BigEndian"
    _save(path, ('<?xml version="1.0"?>\n<VTKFile type="vtkMultiBlockDataSet" version="1.0" '
                 f'byte_order="{order}" header_type="UInt64">\n  <vtkMultiBlockDataSet>\n'
                 + "".join(entries) + "  </vtkMultiBlockDataSet>\n" + _field_data_xml(data)
                 + "</VTKFile>\n").encode())
    return path


_XML_ESCAPES = str.maketrans({"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;",
                              "\n": "&#10;", "\r": "&#13;", "\t": "&#9;"})


def _xml_attribute(value):
    """value as a double-quoted XML attribute value. Not xml.sax.saxutils.quoteattr: importing it
    brings urllib, http and email along, a quarter of a second of every small conversion."""
    return '"' + value.translate(_XML_ESCAPES) + '"'


def _save(path, content):
    try:
        with open(path, "wb") as f:
            f.write(content)
    except OSError as e:
        raise FilterError(f"{path}: cannot write it: {e.strerror}") from None
