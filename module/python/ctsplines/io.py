# SPDX-License-Identifier: GPL-3.0-or-later
"""Files and pipeline plumbing for the command line: reading meshes (VTP, VTU, VTK, OBJ, PLY) and
CAD models (STEP, IGES), writing results, collecting VTK's error messages and showing
progress."""
import os
import re
import struct
import sys

from vtkmodules.util import vtkConstants
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import (
    vtkCommand,
    vtkLogger,
    vtkOutputWindow,
    vtkStringOutputWindow,
)
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkDataSetAttributes, vtkPolyData


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
    ...) and holding the field data. Unstructured grids are written by _grid_file (VTK's writer
    spent 1.2-1.6 ms a block in its pipeline and information objects: 2 s of a 1,474-face
    model's conversion); other blocks by one VTK writer per data type, to memory, saved in one
    write (VTK's own multiblock writer seeks and flushes the file at every array)."""
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
        content = _grid_file(block)
        if content is not None:
            file = f"{stem}/{stem}_{len(entries)}.vtu"
        else:
            kind = block.GetDataObjectType()
            if kind not in writers:
                writers[kind] = messages.watch(vtkXMLDataObjectWriter.NewWriter(kind))
                _fast_xml(writers[kind])
                writers[kind].WriteToOutputStringOn()
            writer = writers[kind]
            file = f"{stem}/{stem}_{len(entries)}.{writer.GetDefaultFileExtension()}"
            writer.SetInputData(block)
            _check_written(writer.Write(), os.path.join(folder, os.path.basename(file)), messages)
            content = writer.GetOutputString()
            content = content if isinstance(content, bytes) else content.encode()
        _save(os.path.join(os.path.dirname(path), file), content)
        entries.append(entry + f" file={_xml_attribute(file)}/>\n")
    _save(path, ('<?xml version="1.0"?>\n<VTKFile type="vtkMultiBlockDataSet" version="1.0" '
                 f'byte_order="{_BYTE_ORDER}" header_type="UInt64">\n  <vtkMultiBlockDataSet>\n'
                 + "".join(entries) + "  </vtkMultiBlockDataSet>\n" + _field_data_xml(data)
                 + "</VTKFile>\n").encode())
    return path


_BYTE_ORDER = "LittleEndian" if sys.byteorder == "little" else "BigEndian"

try:  # VTK's LZ4 blocks are LZ4's raw block format (python3-lz4; without it, uncompressed)
    from lz4.block import compress as _lz4_block
except ImportError:
    _lz4_block = None

# VTK's XML type names by VTK type: (signed, integer), as VTK's writer has them (char as Int8);
# the size comes from the array.
_XML_WORDS = {vtkConstants.VTK_CHAR: (True, True), vtkConstants.VTK_SIGNED_CHAR: (True, True),
              vtkConstants.VTK_UNSIGNED_CHAR: (False, True), vtkConstants.VTK_SHORT: (True, True),
              vtkConstants.VTK_UNSIGNED_SHORT: (False, True), vtkConstants.VTK_INT: (True, True),
              vtkConstants.VTK_UNSIGNED_INT: (False, True), vtkConstants.VTK_LONG: (True, True),
              vtkConstants.VTK_UNSIGNED_LONG: (False, True),
              vtkConstants.VTK_LONG_LONG: (True, True),
              vtkConstants.VTK_UNSIGNED_LONG_LONG: (False, True),
              vtkConstants.VTK_ID_TYPE: (True, True), vtkConstants.VTK_FLOAT: (True, False),
              vtkConstants.VTK_DOUBLE: (True, False)}


# The XML attributes naming a vtkDataSetAttributes' active arrays (Scalars, Vectors, Normals, ...).
_ATTRIBUTE_NAMES = [vtkDataSetAttributes.GetAttributeTypeAsString(kind)
                    for kind in range(vtkDataSetAttributes.NUM_ATTRIBUTES)]


class _AppendedData:
    """The raw appended section of a VTK XML file (header_type UInt64): each array's bytes after
    its size, or, compressed (vtkLZ4DataCompressor), after the header [blocks, block size, last
    partial block size, compressed sizes], the whole array one block."""

    def __init__(self):
        self.parts = []
        self.offset = 0

    def add(self, payload):
        """payload's offset in the section, where it is stored."""
        start = self.offset
        if _lz4_block is None:
            head = struct.pack("<Q", len(payload))
        elif payload:
            size = len(payload)
            payload = _lz4_block(payload, store_size=False)
            head = struct.pack("<4Q", 1, size, 0, len(payload))
        else:
            head = struct.pack("<3Q", 0, 1 << 15, 0)
        self.parts += (head, payload)
        self.offset += len(head) + len(payload)
        return start


def _array_element(array, data, indent, name=None, tuples=False, skip=0):
    """array's XML element, its data (but its first skip values) added to data (_AppendedData);
    None for an array VTK's writer must write (bit and variant arrays, arrays without a buffer).
    Other layouts (SOA) come through VTK's buffer, a copy of their values in AOS order."""
    label = _xml_attribute((array.GetName() or "") if name is None else name)
    if array.IsA("vtkStringArray"):
        payload = b"".join(array.GetValue(i).encode() + b"\0"
                           for i in range(array.GetNumberOfValues()))
        return (f'{indent}<Array type="String" Name={label} NumberOfTuples='
                f'"{array.GetNumberOfTuples()}" format="appended" offset="{data.add(payload)}"/>\n')
    word = _XML_WORDS.get(array.GetDataType()) if array.IsA("vtkDataArray") else None
    if word is None:
        return None
    try:
        view = memoryview(array) if array.GetNumberOfValues() > skip else None
        payload = b"" if view is None else bytes(view[skip:] if skip else view)
    except (TypeError, ValueError, NotImplementedError):
        return None
    bits = 8 * array.GetDataTypeSize()
    kind = f"{'' if word[0] else 'U'}Int{bits}" if word[1] else f"Float{bits}"
    element = f'{indent}<DataArray type="{kind}"'
    element += ' IdType="1"' if array.GetDataType() == vtkConstants.VTK_ID_TYPE else ""
    element += f" Name={label}"
    components = array.GetNumberOfComponents()
    if components != 1:
        element += f' NumberOfComponents="{components}"'
    for c in range(components if array.HasAComponentName() else 0):
        if array.GetComponentName(c):
            element += f" ComponentName{c}={_xml_attribute(array.GetComponentName(c))}"
    if tuples:
        element += f' NumberOfTuples="{array.GetNumberOfTuples()}"'
    return element + f' format="appended" offset="{data.add(payload)}"/>\n'


def _arrays_xml(arrays, tag, data, indent, tuples=False):
    """The <tag> element of a vtkFieldData (or vtkDataSetAttributes, with its attribute
    designations: Scalars=..., Normals=...); "" without arrays, None if one needs VTK's writer."""
    count = arrays.GetNumberOfArrays()
    if count == 0:
        return ""
    designations = ""
    if arrays.IsA("vtkDataSetAttributes"):
        indices = [-1] * len(_ATTRIBUTE_NAMES)
        arrays.GetAttributeIndices(indices)
        for kind, index in enumerate(indices):
            active = arrays.GetAbstractArray(index) if index >= 0 else None
            if active is not None and active.GetName():
                designations += f" {_ATTRIBUTE_NAMES[kind]}={_xml_attribute(active.GetName())}"
    elements = [_array_element(arrays.GetAbstractArray(i), data, indent + "  ", tuples=tuples)
                for i in range(count)]
    if None in elements:
        return None
    return f"{indent}<{tag}{designations}>\n" + "".join(elements) + f"{indent}</{tag}>\n"


def _grid_file(grid):
    """A vtkUnstructuredGrid as the bytes of a .vtu file (VTK XML 1.0, raw appended data, LZ4 when
    python3-lz4 is there) that VTK's reader reads back bit for bit: its field, point and cell data
    with their attribute designations and component names, points and cells. Array information
    keys (VTK's cached ranges) are not written. None when VTK's writer must write it: another
    data type, polyhedra, points missing, an array not of one contiguous block."""
    if not grid.IsA("vtkUnstructuredGrid") or grid.GetFaces() is not None \
            or grid.GetPoints() is None or grid.GetCells() is None:  # (no cell array: VTK 9.1)
        return None
    data = _AppendedData()
    parts = [_arrays_xml(grid.GetFieldData(), "FieldData", data, "    ", tuples=True),
             f'    <Piece NumberOfPoints="{grid.GetNumberOfPoints()}" '
             f'NumberOfCells="{grid.GetNumberOfCells()}">\n',
             _arrays_xml(grid.GetPointData(), "PointData", data, "      "),
             _arrays_xml(grid.GetCellData(), "CellData", data, "      "),
             "      <Points>\n",
             _array_element(grid.GetPoints().GetData(), data, "        ", "Points"),
             "      </Points>\n      <Cells>\n"]
    cells = grid.GetCells()
    types = grid.GetCellTypesArray()
    if types is None:
        from vtkmodules.vtkCommonCore import vtkUnsignedCharArray

        types = vtkUnsignedCharArray()
    parts += [_array_element(cells.GetConnectivityArray(), data, "        ", "connectivity"),
              # VTK's XML lists each cell's end: the offsets without their leading 0.
              _array_element(cells.GetOffsetsArray(), data, "        ", "offsets", skip=1),
              _array_element(types, data, "        ", "types"),
              "      </Cells>\n    </Piece>\n"]
    if None in parts:
        return None
    compressor = "" if _lz4_block is None else ' compressor="vtkLZ4DataCompressor"'
    head = (f'<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" '
            f'byte_order="{_BYTE_ORDER}" header_type="UInt64"{compressor}>\n  <UnstructuredGrid>\n'
            + "".join(parts) + '  </UnstructuredGrid>\n  <AppendedData encoding="raw">\n   _')
    return b"".join([head.encode(), *data.parts, b"\n  </AppendedData>\n</VTKFile>\n"])


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
