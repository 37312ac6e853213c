// SPDX-License-Identifier: GPL-3.0-or-later
// STEP/IGES reading for CADModel::Read: pre-check of the file's numbers, OCCT's translation and
// healing (in a child process with a time limit, or in this process), the shape sent back.
#include "CADFileReading.h"

#include "CADBRepSampling.h"
#include "CADFaceMesher.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepGProp.hxx>
#include <BRepLib_FindSurface.hxx>
#include <BRep_Builder.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRep_Tool.hxx>
#include <BRepTools.hxx>
#include <BinTools.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <Geom2dAPI_Interpolate.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom_Surface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <Interface_Check.hxx>
#include <Interface_CheckIterator.hxx>
#include <Interface_InterfaceModel.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <OSD.hxx>
#include <Precision.hxx>
#include <STEPControl_Reader.hxx>
#include <ShapeAnalysis_FreeBounds.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <ShapeBuild_ReShape.hxx>
#include <ShapeFix_Face.hxx>
#include <StepRepr_RepresentationItem.hxx>
#include <TColStd_HArray1OfReal.hxx>
#include <TColgp_HArray1OfPnt2d.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <NCollection_DataMap.hxx>
#include <TopTools_DataMapOfShapeShape.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ShapeMapHasher.hxx>
#include <TopoDS_Iterator.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>
#include <TransferBRep.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Vec2d.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace ctcad
{

std::string Number(double v)
{
  std::ostringstream s;
  s << v;
  return s.str();
}

namespace
{
enum class Format
{
  Unknown,
  STEP,
  IGES
};

Format FormatOf(const std::string& fileName)
{
  std::string name = fileName;
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  auto endsWith = [&](const std::string& e) {
    return name.size() >= e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0;
  };
  if (endsWith(".step") || endsWith(".stp"))
  {
    return Format::STEP;
  }
  return endsWith(".iges") || endsWith(".igs") ? Format::IGES : Format::Unknown;
}

std::string Prefix(Format format, const std::string& fileName)
{
  return std::string("cannot read ") + (format == Format::STEP ? "STEP" : "IGES") + " file " + fileName + ": ";
}

const char* StatusName(IFSelect_ReturnStatus status)
{
  switch (status)
  {
    case IFSelect_RetVoid:
      return "nothing read (RetVoid)";
    case IFSelect_RetDone:
      return "done";
    case IFSelect_RetError:
      return "error in the data (RetError)";
    case IFSelect_RetFail:
      return "failure (RetFail)";
    default:
      return "stopped (RetStop)";
  }
}

/// "face 3 (NAME)" or "face 3" when the entity has no useful name.
std::string FaceLabel(int i, const std::string& name)
{
  const bool useful = !name.empty() && name != "NONE" && name != "''";
  return "face " + std::to_string(i) + (useful ? " (" + name + ")" : std::string());
}

/// Why `token` (a real, or a word in a real's place) cannot be a coordinate, or "". Beyond 1e100
/// no model's numbers go, and OCCT's geometry overflows (its healing can then loop for ever).
std::string BadNumber(const std::string& token)
{
  std::string upper = token;
  std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return std::toupper(c); });
  const std::size_t sign = upper.find_first_not_of("+-");
  const std::string word = sign == std::string::npos ? upper : upper.substr(sign);
  if (word == "NAN" || word == "INF" || word == "INFINITY")
  {
    return "'" + token + "' is not a number";
  }
  if (word.empty() || !(std::isdigit(static_cast<unsigned char>(word[0])) || word[0] == '.'))
  {
    return "";
  }
  std::replace(upper.begin(), upper.end(), 'D', 'E'); // IGES exponents
  const double value = std::strtod(upper.c_str(), nullptr);
  if (!std::isfinite(value))
  {
    return "the number " + token + " is out of the range of a double";
  }
  return std::abs(value) > 1e100 ? "the number " + token + " is beyond 1e100 in magnitude (no model's is)" : "";
}

/// The STEP entity (as "#123") of the statement that starts at `start`.
std::string EntityAt(const std::string& text, std::size_t start)
{
  while (start < text.size() && std::isspace(static_cast<unsigned char>(text[start])))
  {
    ++start;
  }
  const std::size_t end = text.find_first_of("=;(", start);
  if (start >= text.size() || text[start] != '#' || end == std::string::npos || end - start > 24)
  {
    return "";
  }
  std::string id = text.substr(start, end - start);
  id.erase(id.find_last_not_of(" \t\r\n") + 1);
  return ", entity " + id;
}

/// Every real of a STEP file's text must be a finite double within 1e100 (OCCT reads 1e400 as
/// infinity and builds geometry from it), and no NaN or Inf may stand where a real would.
/// Strings and comments are skipped; tokens that follow an identifier character, '#' or '.' are
/// parts of names, references or enumerations.
bool CheckStepNumbers(const std::string& text, std::string& error)
{
  int line = 1;
  std::size_t statement = 0;
  const std::size_t n = text.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    const char c = text[i];
    if (c == '\n')
    {
      ++line;
    }
    else if (c == '\'')
    {
      const std::size_t close = text.find('\'', i + 1);
      line += static_cast<int>(std::count(text.begin() + i, close == std::string::npos ? text.end() : text.begin() + close, '\n'));
      i = close == std::string::npos ? n : close;
    }
    else if (c == '/' && i + 1 < n && text[i + 1] == '*')
    {
      const std::size_t close = text.find("*/", i + 2);
      line += static_cast<int>(std::count(text.begin() + i, close == std::string::npos ? text.end() : text.begin() + close, '\n'));
      i = close == std::string::npos ? n : close + 1;
    }
    else if (c == ';')
    {
      statement = i + 1;
    }
    else if (std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.')
    {
      const char prev = i > 0 ? text[i - 1] : ' ';
      if (std::isalnum(static_cast<unsigned char>(prev)) || prev == '_' || prev == '#' || prev == '.')
      {
        continue;
      }
      // The token: a real (sign, digits, point, exponent) or a word.
      std::size_t end = i + 1;
      while (end < n && (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '.' || text[end] == '_' ||
                          ((text[end] == '+' || text[end] == '-') && (text[end - 1] == 'E' || text[end - 1] == 'e'))))
      {
        ++end;
      }
      const std::string token = text.substr(i, std::min<std::size_t>(end - i, 40));
      const std::string bad = BadNumber(token);
      if (!bad.empty())
      {
        error = "line " + std::to_string(line) + EntityAt(text, statement) + ": " + bad;
        return false;
      }
      i = end - 1;
    }
  }
  return true;
}
/// The reals of an IGES file's global and parameter sections (free format before the last 16
/// columns of a line; Hollerith strings nH... skipped) must be finite doubles, "1.5D3" included.
bool CheckIgesNumbers(const std::string& text, std::string& error)
{
  int line = 0;
  for (std::size_t start = 0; start < text.size();)
  {
    std::size_t end = text.find('\n', start);
    end = end == std::string::npos ? text.size() : end;
    std::string row = text.substr(start, end - start);
    start = end + 1;
    ++line;
    row.erase(row.find_last_not_of("\r") + 1);
    const char section = row.size() >= 8 ? row[row.size() - 8] : ' ';
    if (row.size() < 17 || (section != 'P' && section != 'G'))
    {
      continue;
    }
    const std::string data = row.substr(0, row.size() - 16);
    for (std::size_t i = 0; i < data.size();)
    {
      const std::size_t token = data.find_first_not_of(" ", i);
      if (token == std::string::npos)
      {
        break;
      }
      std::size_t j = token;
      while (j < data.size() && std::isdigit(static_cast<unsigned char>(data[j])))
      {
        ++j;
      }
      if (j > token && j < data.size() && data[j] == 'H')
      {
        i = j + 1 + std::strtoul(data.c_str() + token, nullptr, 10); // Hollerith
        i = data.find_first_of(",;", std::min(i, data.size()));
        i = i == std::string::npos ? data.size() : i + 1;
        continue;
      }
      j = data.find_first_of(",;", token);
      j = j == std::string::npos ? data.size() : j;
      std::string value = data.substr(token, j - token);
      value.erase(value.find_last_not_of(" ") + 1);
      i = j + 1;
      const std::string bad = BadNumber(value);
      if (!bad.empty())
      {
        const std::string entry = section == 'P' ? row.substr(row.size() - 16, 8) : std::string();
        const std::size_t digits = entry.find_first_not_of(" 0");
        error = std::string(section == 'P' ? "parameter data" : "global section") + " line " +
          std::to_string(line) +
          (section == 'P' && digits != std::string::npos
              ? " (directory entry " + entry.substr(digits) + ")"
              : std::string()) +
          ": " + bad;
        return false;
      }
    }
  }
  return true;
}
} // namespace

bool CheckFileNumbers(const std::string& fileName, std::string& error)
{
  const Format format = FormatOf(fileName);
  std::ifstream in(fileName, std::ios::binary);
  if (!in)
  {
    error = Prefix(format, fileName) + std::strerror(errno);
    return false;
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
  {
    error = Prefix(format, fileName) + "the file is empty";
    return false;
  }
  std::string detail;
  if (format == Format::STEP ? !CheckStepNumbers(text, detail) : !CheckIgesNumbers(text, detail))
  {
    error = Prefix(format, fileName) + detail;
    return false;
  }
  return true;
}

namespace
{
/// Rebuilds r.Shape from `healed` as a compound of its faces in the file's order: the faces
/// that replaced original face i (`image` of it, explored for faces; null when it was removed)
/// take its place and its name; faces of `healed` that replace none come last, unnamed. Faces
/// keep their orientation in `healed`; the sampling needs faces and their shared edges only.
void KeepFaceOrder(ShapeRead& r, const TopTools_IndexedMapOfShape& original, const TopoDS_Shape& healed,
  const std::function<TopoDS_Shape(const TopoDS_Shape&)>& image)
{
  TopTools_IndexedMapOfShape healedMap;
  TopExp::MapShapes(healed, TopAbs_FACE, healedMap);
  std::vector<char> used(healedMap.Extent(), 0);
  std::vector<std::string> names;
  BRep_Builder builder;
  TopoDS_Compound faces;
  builder.MakeCompound(faces);
  auto take = [&](int j, const std::string& name) {
    if (j > 0 && !used[j - 1])
    {
      used[j - 1] = 1;
      builder.Add(faces, healedMap(j));
      names.push_back(name);
    }
  };
  for (int i = 1; i <= original.Extent(); ++i)
  {
    const TopoDS_Shape replacement = image(original(i));
    for (TopExp_Explorer fx(replacement, TopAbs_FACE); !replacement.IsNull() && fx.More(); fx.Next())
    {
      take(healedMap.FindIndex(fx.Current()), r.FaceNames[i - 1]);
    }
  }
  for (int j = 1; j <= healedMap.Extent(); ++j)
  {
    take(j, std::string());
  }
  r.Shape = faces;
  r.FaceNames = names;
}

/// Faces on closed surfaces bounded by closed wires but without a seam edge (e.g. a cylinder's
/// lateral face between two circles) have pcurves that are open curves in the parameter plane:
/// ShapeFix_Face::FixMissingSeam joins the wires by a seam edge. OCCT's readers do so in their
/// own healing (FixShape, on by default), which can be configured away or fail: this repeats
/// that one fix on the faces that still need it. Names follow their faces.
bool FixMissingSeams(ShapeRead& r, const std::string& prefix, std::string& error)
{
  TopTools_IndexedMapOfShape faceMap;
  TopExp::MapShapes(r.Shape, TopAbs_FACE, faceMap);
  const Handle(ShapeBuild_ReShape) context = new ShapeBuild_ReShape;
  std::string failure;
  for (int i = 1; i <= faceMap.Extent(); ++i)
  {
    const TopoDS_Face& F = TopoDS::Face(faceMap(i));
    const bool ok = RunGuarded(
      [&] {
        const BRepAdaptor_Surface S(F, Standard_False);
        int wires = 0;
        bool seam = false;
        for (TopExp_Explorer wx(F, TopAbs_WIRE); wx.More(); wx.Next())
        {
          ++wires;
        }
        for (TopExp_Explorer ex(F, TopAbs_EDGE); ex.More() && !seam; ex.Next())
        {
          seam = BRep_Tool::IsClosed(TopoDS::Edge(ex.Current()), F);
        }
        if (seam || wires < 2 || (!S.IsUClosed() && !S.IsVClosed()))
        {
          return;
        }
        const Handle(ShapeFix_Face) fix = new ShapeFix_Face(F);
        fix->SetContext(context);
        if (fix->FixMissingSeam())
        {
          if (!context->IsRecorded(F))
          {
            context->Replace(F, fix->Face());
          }
          ++r.Healing.SeamsAdded;
        }
      },
      failure);
    if (!ok)
    {
      error = prefix + "healing " + FaceLabel(i - 1, r.FaceNames[i - 1]) +
        " (ShapeFix_Face::FixMissingSeam): " + failure;
      return false;
    }
  }
  if (r.Healing.SeamsAdded == 0)
  {
    return true;
  }
  const bool ok = RunGuarded(
    [&] {
      const TopoDS_Shape healed = context->Apply(r.Shape);
      KeepFaceOrder(r, faceMap, healed, [&](const TopoDS_Shape& f) { return context->Value(f); });
    },
    failure);
  if (!ok)
  {
    error = prefix + "healing: applying the missing seams (ShapeBuild_ReShape::Apply): " + failure;
    return false;
  }
  return true;
}

/// "an edge of face 3 (NAME) and face 5" for edge E (faceMap and edgeFaces of the shape).
std::string EdgeOfFaces(const TopoDS_Shape& E, const TopTools_IndexedMapOfShape& faceMap,
  const TopTools_IndexedDataMapOfShapeListOfShape& edgeFaces, const std::vector<std::string>& names)
{
  std::string faces;
  const int k = edgeFaces.FindIndex(E);
  if (k > 0)
  {
    for (const TopoDS_Shape& F : edgeFaces(k))
    {
      const int i = faceMap.FindIndex(F);
      faces += (faces.empty() ? "" : " and ") + (i > 0 ? FaceLabel(i - 1, names[i - 1]) : std::string("a face"));
    }
  }
  return faces.empty() ? std::string("a free edge") : "an edge of " + faces;
}

/// Width of a face as 2 area / perimeter (a strip of width w: w; a disc of radius r: r).
double FaceWidth(const TopoDS_Shape& F)
{
  GProp_GProps area, perimeter;
  BRepGProp::SurfaceProperties(F, area);
  BRepGProp::LinearProperties(F, perimeter);
  // A face without edges (natural bounds) is no sliver.
  return perimeter.Mass() > 0 ? 2 * std::abs(area.Mass()) / perimeter.Mass() : HUGE_VAL;
}

/// One warning for many shapes of one kind: the count, the first few named, then "...".
class NamedList
{
public:
  void Add(const std::string& item)
  {
    if (++this->Count <= 4)
    {
      this->Items += (this->Items.empty() ? "" : "; ") + item;
    }
  }
  int Size() const { return this->Count; }
  std::string Text() const { return this->Items + (this->Count > 4 ? "; ..." : ""); }

private:
  int Count = 0;
  std::string Items;
};

/// Sliver faces (thinner than `tol`: zero-area faces, strips of no width) have an empty
/// parameter domain or one the face meshing cannot triangulate, and lie within `tol` of their
/// neighbours: with `remove` they are removed (a warning names them), and the sewing that
/// follows joins the neighbours across them. Returns the number of edges shorter than
/// `shortEdge` (named in a warning: the sampling follows them; the sewing collapses those whose
/// ends it merges).
int RemoveSlivers(ShapeRead& r, double tol, double shortEdge, bool sew, bool remove)
{
  TopTools_IndexedMapOfShape faceMap;
  TopTools_IndexedDataMapOfShapeListOfShape edgeFaces;
  TopExp::MapShapes(r.Shape, TopAbs_FACE, faceMap);
  const Handle(ShapeBuild_ReShape) context = new ShapeBuild_ReShape;
  NamedList slivers;
  for (int i = 1; i <= faceMap.Extent(); ++i)
  {
    const double width = remove ? FaceWidth(faceMap(i)) : HUGE_VAL;
    if (width < tol && faceMap.Extent() - slivers.Size() > 1)
    {
      context->Remove(faceMap(i));
      slivers.Add(FaceLabel(i - 1, r.FaceNames[i - 1]) + " " + Number(width) + " wide");
    }
  }
  if (slivers.Size() > 0)
  {
    r.Healing.RemovedFaces = slivers.Size();
    r.Warnings.push_back(std::to_string(slivers.Size()) + " sliver face(s) thinner than " + Number(tol) +
      " (width = 2 area / perimeter; a thousandth of the tolerance) removed" +
      (sew ? ", their neighbours sewn across them: " : ": ") + slivers.Text());
    const TopoDS_Shape healed = context->Apply(r.Shape);
    KeepFaceOrder(r, faceMap, healed, [&](const TopoDS_Shape& f) { return context->Value(f); });
    faceMap.Clear();
    TopExp::MapShapes(r.Shape, TopAbs_FACE, faceMap);
  }
  TopExp::MapShapesAndAncestors(r.Shape, TopAbs_EDGE, TopAbs_FACE, edgeFaces);
  NamedList shortEdges;
  for (int k = 1; k <= edgeFaces.Extent(); ++k)
  {
    const TopoDS_Edge& E = TopoDS::Edge(edgeFaces.FindKey(k));
    if (BRep_Tool::Degenerated(E))
    {
      continue;
    }
    GProp_GProps length;
    BRepGProp::LinearProperties(E, length);
    if (length.Mass() < shortEdge)
    {
      shortEdges.Add(EdgeOfFaces(E, faceMap, edgeFaces, r.FaceNames) + " " + Number(length.Mass()) + " long");
    }
  }
  if (shortEdges.Size() > 0)
  {
    r.Warnings.push_back(std::to_string(shortEdges.Size()) + " edge(s) shorter than half the tolerance (" +
      Number(shortEdge) + "), sampled as they are (within a thousandth of the tolerance: "
      "collapsed into one vertex): " + shortEdges.Text());
  }
  return shortEdges.Size();
}

/// The shape's free edges: on one face only, neither degenerated nor a seam.
int CountFreeEdges(const TopoDS_Shape& shape)
{
  TopTools_IndexedDataMapOfShapeListOfShape edgeFaces;
  TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, edgeFaces);
  int free = 0;
  for (int k = 1; k <= edgeFaces.Extent(); ++k)
  {
    const TopoDS_Edge& E = TopoDS::Edge(edgeFaces.FindKey(k));
    const TopTools_ListOfShape& faces = edgeFaces(k);
    free += faces.Extent() == 1 && !BRep_Tool::Degenerated(E) && !BRep_Tool::IsClosed(E, TopoDS::Face(faces.First()));
  }
  return free;
}

/// The sewing makes degenerated edges of the edges whose ends it merges (the ends of a removed
/// sliver, edges shorter than the tolerance between free edges), on faces that have no pole there: those edges are dropped from
/// their wires (the loops join the pcurve ends on either side, within the tolerance). The
/// sewing rebuilds the faces' own pole edges too: a degenerated edge is a pole when its sewn
/// face's original had a degenerated edge within `tol` (`poles`: per sewn face, those points).
/// Faces rebuilt are recorded in `rebuilt` (sewn face -> its replacement).
TopoDS_Shape DropCollapsedEdges(const TopoDS_Shape& sewn, const TopTools_IndexedMapOfShape& sewnFaces,
  const std::vector<std::vector<gp_Pnt>>& poles, double tol, TopTools_DataMapOfShapeShape& rebuilt)
{
  const std::vector<gp_Pnt> none;
  const std::vector<gp_Pnt>* facePoles = &none;
  auto collapsed = [&](const TopoDS_Shape& E) {
    if (!BRep_Tool::Degenerated(TopoDS::Edge(E)))
    {
      return false;
    }
    const gp_Pnt p = BRep_Tool::Pnt(TopExp::FirstVertex(TopoDS::Edge(E)));
    return std::none_of(facePoles->begin(), facePoles->end(), [&](const gp_Pnt& q) { return p.Distance(q) <= tol; });
  };
  BRep_Builder builder;
  TopoDS_Compound faces;
  builder.MakeCompound(faces);
  for (TopExp_Explorer fx(sewn, TopAbs_FACE); fx.More(); fx.Next())
  {
    const TopoDS_Shape& F = fx.Current();
    const int k = sewnFaces.FindIndex(F);
    facePoles = k > 0 ? &poles[k - 1] : &none;
    bool drop = false;
    for (TopExp_Explorer ex(F, TopAbs_EDGE); ex.More() && !drop; ex.Next())
    {
      drop = collapsed(ex.Current());
    }
    if (!drop)
    {
      builder.Add(faces, F);
      continue;
    }
    // Built forward, then given F's orientation (the builder reverses what it adds to a reversed
    // shape).
    const TopoDS_Shape forward = F.Oriented(TopAbs_FORWARD);
    TopoDS_Shape face = forward.EmptyCopied();
    for (TopoDS_Iterator wi(forward); wi.More(); wi.Next())
    {
      TopoDS_Shape wire = wi.Value().Oriented(TopAbs_FORWARD).EmptyCopied();
      for (TopoDS_Iterator ei(wi.Value().Oriented(TopAbs_FORWARD)); ei.More(); ei.Next())
      {
        if (!collapsed(ei.Value()))
        {
          builder.Add(wire, ei.Value());
        }
      }
      builder.Add(face, wire.Oriented(wi.Value().Orientation()));
    }
    face.Orientation(F.Orientation());
    rebuilt.Bind(F, face);
    builder.Add(faces, face);
  }
  return faces;
}

/// The edges of `sewn` that `cleaned` no longer has (the collapsed ones DropCollapsedEdges dropped).
int CountCollapsed(const TopoDS_Shape& sewn, const TopoDS_Shape& cleaned)
{
  TopTools_IndexedMapOfShape before, after;
  TopExp::MapShapes(sewn, TopAbs_EDGE, before);
  TopExp::MapShapes(cleaned, TopAbs_EDGE, after);
  return before.Extent() - after.Extent();
}

/// The largest distance between edge E's 3D curve and face F's surface over E's pcurve on F, at
/// the same parameters (SameParameter edges), at 65 points: a pcurve that jumps by a period
/// within one span (a closed surface) goes round the surface between two of them.
double PCurveDeviation(const TopoDS_Edge& E, const TopoDS_Face& F)
{
  double a = 0, b = 0;
  const Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(E, F, a, b);
  const BRepAdaptor_Curve curve(E);
  const BRepAdaptor_Surface surface(F, Standard_False);
  double d = 0;
  for (int i = 0; i <= 64; ++i)
  {
    const double t = a + (b - a) * i / 64;
    const gp_Pnt2d uv = pc->Value(t);
    d = std::max(d, surface.Value(uv.X(), uv.Y()).Distance(curve.Value(t)));
  }
  return d;
}

/// The shift by whole periods that brings parameter point `to` nearest to `from`.
gp_Vec2d PeriodShift(const gp_Pnt2d& from, const gp_Pnt2d& to, const std::array<double, 2>& period)
{
  return gp_Vec2d(
    WholePeriods(from.X() - to.X(), period[0]), WholePeriods(from.Y() - to.Y(), period[1]));
}

/// E's 3D curve projected on F's surface (ShapeAnalysis_Surface, each point from the previous
/// one) at 65 parameters, unwrapped across the periods, and interpolated at those parameters.
Handle(Geom2d_Curve) ProjectedPCurve(const TopoDS_Edge& E, const TopoDS_Face& F)
{
  TopLoc_Location loc;
  const Handle(Geom_Surface) S = BRep_Tool::Surface(F, loc);
  const Handle(ShapeAnalysis_Surface) projector = new ShapeAnalysis_Surface(S);
  const gp_Trsf toSurface = loc.Transformation().Inverted();
  const BRepAdaptor_Curve curve(E);
  const double a = curve.FirstParameter(), b = curve.LastParameter();
  const std::array<double, 2> period = SurfacePeriods(*S);
  const int n = 64;
  const Handle(TColgp_HArray1OfPnt2d) points = new TColgp_HArray1OfPnt2d(1, n + 1);
  const Handle(TColStd_HArray1OfReal) params = new TColStd_HArray1OfReal(1, n + 1);
  gp_Pnt2d prev;
  for (int i = 0; i <= n; ++i)
  {
    const double t = a + (b - a) * i / n;
    const gp_Pnt P = curve.Value(t).Transformed(toSurface);
    gp_Pnt2d uv = i == 0 ? projector->ValueOfUV(P, Precision::Confusion())
                         : projector->NextValueOfUV(prev, P, Precision::Confusion());
    if (i > 0)
    {
      uv.SetXY(uv.XY() - PeriodShift(uv, prev, period).XY());
    }
    points->SetValue(i + 1, uv);
    params->SetValue(i + 1, t);
    prev = uv;
  }
  Geom2dAPI_Interpolate interpolation(points, params, Standard_False, Precision::PConfusion());
  interpolation.Perform();
  if (!interpolation.IsDone())
  {
    return Handle(Geom2d_Curve)();
  }
  return Handle(Geom2d_Curve)(interpolation.Curve().get());
}

/// The parameter point where oriented edge E, whose pcurve pc runs over [a, b], starts (end:
/// ends).
gp_Pnt2d OrientedEnd(const TopoDS_Edge& E, const Handle(Geom2d_Curve)& pc, double a, double b, bool end)
{
  return pc->Value((E.Orientation() == TopAbs_REVERSED) != end ? b : a);
}

/// The parameter point where oriented edge E starts (end: ends) on F.
gp_Pnt2d PCurveEnd(const TopoDS_Edge& E, const TopoDS_Face& F, bool end)
{
  double a = 0, b = 0;
  const Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(E, F, a, b);
  return OrientedEnd(E, pc, a, b, end);
}

/// Edges whose pcurve on a face was replaced, and the pcurve they were read with.
using ReadPCurves = NCollection_DataMap<TopoDS_Shape, Handle(Geom2d_Curve), TopTools_ShapeMapHasher>;

/// The reprojected edges of one wire of F (in `fixed`) moved by whole periods so that each
/// starts where the edge before it in the wire ends, from an edge that kept its pcurve.
void ConnectReprojected(const TopoDS_Wire& W, const TopoDS_Face& F, const ReadPCurves& fixed)
{
  TopoDS_Edge broken;
  const std::vector<TopoDS_Edge> chain = WireEdges(W, F, broken);
  const std::size_t n = chain.size();
  std::size_t anchor = 0;
  while (anchor < n && fixed.IsBound(chain[anchor]))
  {
    ++anchor;
  }
  anchor %= std::max<std::size_t>(n, 1);
  const BRepAdaptor_Surface S(F, Standard_False);
  const std::array<double, 2> period = SurfacePeriods(S);
  for (std::size_t i = 1; i < n; ++i)
  {
    const TopoDS_Edge& E = chain[(anchor + i) % n];
    if (!fixed.IsBound(E))
    {
      continue;
    }
    const gp_Pnt2d from = PCurveEnd(chain[(anchor + i - 1) % n], F, true);
    const gp_Pnt2d start = PCurveEnd(E, F, false);
    const gp_Vec2d shift = PeriodShift(from, start, period);
    if (shift.SquareMagnitude() > 0)
    {
      double a = 0, b = 0;
      const Handle(Geom2d_Curve) moved =
        Handle(Geom2d_Curve)::DownCast(BRep_Tool::CurveOnSurface(E, F, a, b)->Translated(shift));
      BRep_Builder().UpdateEdge(E, moved, F, BRep_Tool::Tolerance(E));
    }
  }
}

/// The largest step in (u, v) from an edge's pcurve end to the next edge's start over F's
/// wires, to the nearest copy across the surface's periods (edges without a pcurve skipped).
double MaxWireGapUV(const TopoDS_Face& F)
{
  const BRepAdaptor_Surface S(F, Standard_False);
  const std::array<double, 2> period = SurfacePeriods(S);
  auto hasPCurve = [&F](const TopoDS_Edge& E) {
    double a = 0, b = 0;
    return !BRep_Tool::CurveOnSurface(E, F, a, b).IsNull();
  };
  double gap = 0;
  for (TopExp_Explorer wx(F, TopAbs_WIRE); wx.More(); wx.Next())
  {
    TopoDS_Edge broken;
    const std::vector<TopoDS_Edge> chain = WireEdges(TopoDS::Wire(wx.Current()), F, broken);
    for (std::size_t i = 0; i < chain.size(); ++i)
    {
      const TopoDS_Edge& next = chain[(i + 1) % chain.size()];
      if (!hasPCurve(chain[i]) || !hasPCurve(next))
      {
        continue;
      }
      const gp_Pnt2d end = PCurveEnd(chain[i], F, true), start = PCurveEnd(next, F, false);
      const gp_Vec2d step = gp_Vec2d(start, end) - PeriodShift(end, start, period);
      gap = std::max(gap, std::hypot(step.X(), step.Y()));
    }
  }
  return gap;
}

/// Pcurves off their edge's 3D curve by more than `tol` (where the edge is SameParameter: the
/// 3D curve is the edge) are replaced by its projection when that is at most half as far, and
/// moved by periods to join their wire. OCCT's STEP reader computes pcurves by projection and
/// raises the edge tolerance over what its projection misses: on surfaces of revolution it can
/// run the wrong way round (NXP_MPL115A1, faces off by 8 % of the diagonal), on a cylinder jump
/// by the period inside one span (the toroid inductors of Bourns 8100: the wire then seems to go
/// round the surface). A face whose wires its projections leave open in (u, v) keeps its
/// pcurves: where the surface barely moves across (u, v) near a vertex, the projections of its
/// edges land apart there (TQFP-64_14x14mm_P0.8mm: 0.13 apart on faces 13.5 wide, whose splines
/// then folded). The edges are changed in place. Returns the number replaced; the faces are
/// named in a warning.
int ReprojectPCurves(ShapeRead& r, double tol)
{
  TopTools_IndexedMapOfShape faceMap;
  TopExp::MapShapes(r.Shape, TopAbs_FACE, faceMap);
  int replaced = 0, named = 0;
  std::string faces;
  for (int i = 1; i <= faceMap.Extent(); ++i)
  {
    const TopoDS_Face F = TopoDS::Face(faceMap(i).Oriented(TopAbs_FORWARD));
    ReadPCurves fixed; // the edges replaced on F, with the pcurves they were read with
    double gapBefore = -1; // the wires' largest gap in (u, v) before any replacement
    for (TopExp_Explorer ex(F, TopAbs_EDGE); ex.More(); ex.Next())
    {
      const TopoDS_Edge& E = TopoDS::Edge(ex.Current());
      double a = 0, b = 0;
      if (BRep_Tool::Degenerated(E) || BRep_Tool::IsClosed(E, F) || !BRep_Tool::SameParameter(E) ||
        !BRep_Tool::SameRange(E) || BRep_Tool::Curve(E, a, b).IsNull() ||
        BRep_Tool::CurveOnSurface(E, F, a, b).IsNull() || fixed.IsBound(E))
      {
        continue;
      }
      const double before = PCurveDeviation(E, F);
      if (before <= tol)
      {
        continue;
      }
      const Handle(Geom2d_Curve) old = BRep_Tool::CurveOnSurface(E, F, a, b);
      const Handle(Geom2d_Curve) projected = ProjectedPCurve(E, F);
      if (projected.IsNull())
      {
        continue;
      }
      gapBefore = gapBefore < 0 ? MaxWireGapUV(F) : gapBefore;
      BRep_Builder().UpdateEdge(E, projected, F, BRep_Tool::Tolerance(E));
      if (PCurveDeviation(E, F) > 0.5 * before)
      {
        BRep_Builder().UpdateEdge(E, old, F, BRep_Tool::Tolerance(E));
        continue;
      }
      fixed.Bind(E, old);
    }
    if (fixed.IsEmpty())
    {
      continue;
    }
    for (TopExp_Explorer wx(F, TopAbs_WIRE); wx.More(); wx.Next())
    {
      ConnectReprojected(TopoDS::Wire(wx.Current()), F, fixed);
    }
    double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
    BRepTools::UVBounds(F, u0, u1, v0, v1);
    if (MaxWireGapUV(F) > 2 * gapBefore + 1e-6 * std::hypot(u1 - u0, v1 - v0))
    {
      for (ReadPCurves::Iterator it(fixed); it.More(); it.Next())
      {
        const TopoDS_Edge& E = TopoDS::Edge(it.Key());
        BRep_Builder().UpdateEdge(E, it.Value(), F, BRep_Tool::Tolerance(E));
      }
      continue;
    }
    replaced += fixed.Extent();
    faces += ++named > 4 ? (named == 5 ? ", ..." : "")
                         : (faces.empty() ? "" : ", ") + FaceLabel(i - 1, r.FaceNames[i - 1]);
  }
  if (replaced > 0)
  {
    r.Warnings.push_back(std::to_string(replaced) + " pcurve(s) off their edge by more than the " +
      "tolerance (" + Number(tol) + ") replaced by the edge's projection on " + faces);
  }
  return replaced;
}

/// How far F's surface strays from degenerated edge E's vertex along E's pcurve (17 points).
double DegeneratedEdgeSpan(const TopoDS_Edge& E, const TopoDS_Face& F)
{
  double a = 0, b = 0;
  const Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(E, F, a, b);
  if (pc.IsNull())
  {
    return 0;
  }
  const BRepAdaptor_Surface surface(F, Standard_False);
  const gp_Pnt V = BRep_Tool::Pnt(TopExp::FirstVertex(E));
  double d = 0;
  for (int i = 0; i <= 16; ++i)
  {
    const gp_Pnt2d uv = pc->Value(a + (b - a) * i / 16);
    d = std::max(d, surface.Value(uv.X(), uv.Y()).Distance(V));
  }
  return d;
}

/// One edge of a wire as it runs on a face: its pcurve for that orientation, moved.
struct WireStep
{
  TopoDS_Edge Edge;
  Handle(Geom2d_Curve) PCurve;
  double First = 0, Last = 0;
  bool Moved = false;
  gp_Pnt2d End(bool last) const { return OrientedEnd(this->Edge, this->PCurve, this->First, this->Last, last); }
};

/// The edges of wire `chain` of F without `dropped` ones, each pcurve moved by whole periods to
/// start where the one before it ends. Empty unless they close up in (u, v) within `tol2d` and
/// span at most one period in each periodic direction.
std::vector<WireStep> JoinedWithout(const std::vector<TopoDS_Edge>& chain, const TopoDS_Face& F,
  const std::function<bool(const TopoDS_Edge&)>& dropped, const std::array<double, 2>& period, double tol2d)
{
  std::vector<WireStep> steps;
  double lo[2] = { HUGE_VAL, HUGE_VAL }, hi[2] = { -HUGE_VAL, -HUGE_VAL };
  for (const TopoDS_Edge& E : chain)
  {
    if (dropped(E))
    {
      continue;
    }
    WireStep step{ E, Handle(Geom2d_Curve)(), 0, 0, false };
    step.PCurve = BRep_Tool::CurveOnSurface(E, F, step.First, step.Last);
    if (step.PCurve.IsNull())
    {
      return {};
    }
    if (!steps.empty())
    {
      const gp_Vec2d shift = PeriodShift(steps.back().End(true), step.End(false), period);
      if (shift.SquareMagnitude() > 0)
      {
        step.PCurve = Handle(Geom2d_Curve)::DownCast(step.PCurve->Translated(shift));
        step.Moved = true;
      }
    }
    for (int i = 0; i <= 8; ++i)
    {
      const gp_Pnt2d uv = step.PCurve->Value(step.First + (step.Last - step.First) * i / 8);
      for (int k = 0; k < 2; ++k)
      {
        lo[k] = std::min(lo[k], uv.Coord(k + 1));
        hi[k] = std::max(hi[k], uv.Coord(k + 1));
      }
    }
    steps.push_back(step);
  }
  const bool closed = !steps.empty() && steps.back().End(true).Distance(steps.front().End(false)) <= tol2d;
  for (int k = 0; k < 2 && closed; ++k)
  {
    if (period[k] > 0 && hi[k] - lo[k] > period[k] + tol2d)
    {
      return {};
    }
  }
  return closed ? steps : std::vector<WireStep>();
}

/// The pcurve of the step of `wires` that runs along oriented edge E (null if none does; a valid
/// face runs along each oriented edge once).
Handle(Geom2d_Curve) StepPCurve(const std::vector<std::vector<WireStep>>& wires, const TopoDS_Edge& E)
{
  for (const std::vector<WireStep>& wire : wires)
  {
    for (const WireStep& step : wire)
    {
      if (step.Edge.IsEqual(E))
      {
        return step.PCurve;
      }
    }
  }
  return Handle(Geom2d_Curve)();
}

/// F rebuilt on its surface from `wires`, whose moved pcurves replace the edges' ones on F (a
/// seam edge's two at once).
TopoDS_Face FaceWithWires(const TopoDS_Face& F, const std::vector<std::vector<WireStep>>& wires)
{
  BRep_Builder builder;
  for (const std::vector<WireStep>& wire : wires)
  {
    for (const WireStep& step : wire)
    {
      const TopoDS_Edge& E = step.Edge;
      if (!step.Moved)
      {
        continue;
      }
      if (!BRep_Tool::IsClosed(E, F))
      {
        builder.UpdateEdge(E, step.PCurve, F, BRep_Tool::Tolerance(E));
        continue;
      }
      // A seam: its pcurve for the other orientation, moved too if the wire moved it.
      const bool forward = E.Orientation() != TopAbs_REVERSED;
      const TopoDS_Edge other = TopoDS::Edge(E.Reversed());
      Handle(Geom2d_Curve) otherCurve = StepPCurve(wires, other);
      double a = 0, b = 0;
      otherCurve = otherCurve.IsNull() ? BRep_Tool::CurveOnSurface(other, F, a, b) : otherCurve;
      builder.UpdateEdge(E, forward ? step.PCurve : otherCurve, forward ? otherCurve : step.PCurve,
        F, BRep_Tool::Tolerance(E));
    }
  }
  TopLoc_Location location;
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(F, location);
  TopoDS_Face rebuilt;
  builder.MakeFace(rebuilt, surface, location, BRep_Tool::Tolerance(F));
  for (const std::vector<WireStep>& wire : wires)
  {
    TopoDS_Wire W;
    builder.MakeWire(W);
    for (const WireStep& step : wire)
    {
      builder.Add(W, step.Edge);
    }
    W.Closed(Standard_True);
    builder.Add(rebuilt, W);
  }
  return rebuilt;
}

} // namespace

/// Degenerated edges along which the surface does not stay at their vertex (by more than
/// `tol`) are dropped, and the other edges' pcurves moved by whole periods to join. OCCT's STEP
/// reader, projecting the edges of a face without pcurves, can put a closed circle's pcurve a
/// period off on a surface of revolution and close the wire with degenerated edges a period
/// long, which run along circles (BatteryHolder_Keystone_2462_2xAA: the wire then went twice
/// round its fillet, u over 4 pi, and the face's spline strayed 0.27 of the diagonal). The face
/// is rebuilt on its surface from those wires where each then closes within one period, else
/// kept and named in a warning. Returns the number of edges dropped.
int DropFalseDegeneratedEdges(ShapeRead& r, double tol)
{
  TopTools_IndexedMapOfShape faceMap;
  TopExp::MapShapes(r.Shape, TopAbs_FACE, faceMap);
  const Handle(ShapeBuild_ReShape) context = new ShapeBuild_ReShape;
  int dropped = 0;
  std::string fixedFaces, keptFaces;
  for (int i = 1; i <= faceMap.Extent(); ++i)
  {
    const TopoDS_Face F = TopoDS::Face(faceMap(i).Oriented(TopAbs_FORWARD));
    const auto isFalse = [&](const TopoDS_Edge& E) {
      return BRep_Tool::Degenerated(E) && DegeneratedEdgeSpan(E, F) > tol;
    };
    std::vector<std::vector<TopoDS_Edge>> chains;
    int count = 0;
    for (TopExp_Explorer wx(F, TopAbs_WIRE); wx.More(); wx.Next())
    {
      TopoDS_Edge broken;
      chains.push_back(WireEdges(TopoDS::Wire(wx.Current()), F, broken));
      count += static_cast<int>(std::count_if(chains.back().begin(), chains.back().end(), isFalse));
    }
    if (count == 0)
    {
      continue;
    }
    const BRepAdaptor_Surface S(F, Standard_False);
    const std::array<double, 2> period = SurfacePeriods(S);
    double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
    BRepTools::UVBounds(F, u0, u1, v0, v1);
    std::vector<std::vector<WireStep>> wires;
    for (const std::vector<TopoDS_Edge>& chain : chains)
    {
      wires.push_back(JoinedWithout(chain, F, isFalse, period, 1e-7 * std::hypot(u1 - u0, v1 - v0)));
    }
    std::string& list = std::all_of(wires.begin(), wires.end(),
                          [](const std::vector<WireStep>& w) { return !w.empty(); })
      ? fixedFaces
      : keptFaces;
    list += (list.empty() ? "" : ", ") + FaceLabel(i - 1, r.FaceNames[i - 1]);
    if (&list == &keptFaces)
    {
      continue;
    }
    context->Replace(F, FaceWithWires(F, wires));
    dropped += count;
  }
  if (!keptFaces.empty())
  {
    r.Warnings.push_back("degenerated edges along which the surface moves by more than " +
      Number(tol) + " kept on " + keptFaces + ": their wires do not close without them");
  }
  if (dropped == 0)
  {
    return 0;
  }
  const TopoDS_Shape healed = context->Apply(r.Shape);
  KeepFaceOrder(r, faceMap, healed, [&](const TopoDS_Shape& f) { return context->Value(f); });
  r.Warnings.push_back(std::to_string(dropped) + " degenerated edge(s) along which the surface " +
    "moves by more than " + Number(tol) + " dropped, the wires joined by whole periods, on " +
    fixedFaces);
  return dropped;
}

namespace
{

/// Sews free edges that lie within `tol` of each other (BRepBuilderAPI_Sewing, manifold, with
/// the cutting of free edges at each other's vertices; OCCT's own minimal tolerance, so that no
/// edge of the model is taken for a degenerated one). OCCT's stored tolerances understate the
/// real gaps between faces, so the conversion's tolerance is the sewing's: gaps within it are
/// below what the conversion resolves. Edges whose ends the sewing merges collapse (the ends of a
/// removed sliver). Faces keep their names and the file's order.
void SewFaces(ShapeRead& r, double tol)
{
  TopTools_IndexedMapOfShape faceMap;
  TopExp::MapShapes(r.Shape, TopAbs_FACE, faceMap);
  const auto start = std::chrono::steady_clock::now();
  BRepBuilderAPI_Sewing sewing(tol);
  sewing.Load(r.Shape);
  sewing.Perform();
  r.Healing.SewingSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const TopoDS_Shape sewn = sewing.SewedShape();
  if (sewn.IsNull())
  {
    r.Warnings.push_back("the sewing (BRepBuilderAPI_Sewing) gave no shape: the file's topology is kept");
    return;
  }
  r.Healing.SewingTolerance = tol;
  r.Healing.SewnEdges = sewing.NbContigousEdges();
  if (r.Healing.SewnEdges == 0 && sewing.NbDeletedFaces() == 0)
  {
    return; // nothing sewn: the faces stay exactly as they were
  }
  auto sewnImage = [&](const TopoDS_Shape& f) {
    return sewing.IsModifiedSubShape(f) ? sewing.ModifiedSubShape(f) : f;
  };
  TopTools_IndexedMapOfShape sewnFaces;
  std::vector<std::vector<gp_Pnt>> poles;
  for (int i = 1; i <= faceMap.Extent(); ++i)
  {
    const TopoDS_Shape image = sewnImage(faceMap(i));
    for (TopExp_Explorer fx(image, TopAbs_FACE); !image.IsNull() && fx.More(); fx.Next())
    {
      const int k = sewnFaces.Add(fx.Current());
      poles.resize(std::max<std::size_t>(poles.size(), k));
      for (TopExp_Explorer ex(faceMap(i), TopAbs_EDGE); ex.More(); ex.Next())
      {
        if (BRep_Tool::Degenerated(TopoDS::Edge(ex.Current())))
        {
          poles[k - 1].push_back(BRep_Tool::Pnt(TopExp::FirstVertex(TopoDS::Edge(ex.Current()))));
        }
      }
    }
  }
  TopTools_DataMapOfShapeShape rebuilt;
  const TopoDS_Shape cleaned = DropCollapsedEdges(sewn, sewnFaces, poles, tol, rebuilt);
  r.Healing.CollapsedEdges = rebuilt.Extent() > 0 ? CountCollapsed(sewn, cleaned) : 0;
  const std::vector<std::string> names = r.FaceNames;
  KeepFaceOrder(r, faceMap, cleaned, [&](const TopoDS_Shape& f) {
    const TopoDS_Shape s = sewnImage(f);
    return !s.IsNull() && rebuilt.IsBound(s) ? rebuilt(s) : s;
  });
  for (int i = 0; i < sewing.NbDeletedFaces(); ++i)
  {
    const int f = faceMap.FindIndex(sewing.DeletedFace(i + 1));
    r.Warnings.push_back((f > 0 ? FaceLabel(f - 1, names[f - 1]) : std::string("a face")) +
      " is smaller than the tolerance in every direction: removed by the sewing");
    ++r.Healing.RemovedFaces;
  }
}

/// One pass of the healing: slivers removed (with `removeSlivers`), then, with Sew and where
/// there are free edges, free edges sewn. Returns false with
/// `failure` when OCCT failed (r is then partly healed). freeAfter: the free edges left.
bool HealPass(ShapeRead& r, const HealingOptions& options, double tol, int freeBefore, bool removeSlivers,
  int& freeAfter, std::string& failure)
{
  // Zero-area faces and strips of no width (thinner than a thousandth of the tolerance) go:
  // thin faces the face meshing can triangulate stay, with the model's topology around them
  // (removing them moves the neighbours' shared edges by up to their width).
  return RunGuarded(
    [&] {
      RemoveSlivers(r, 1e-3 * tol, 0.5 * tol, options.Sew, removeSlivers);
      if (options.Sew && (freeBefore > 0 || r.Healing.RemovedFaces > 0))
      {
        SewFaces(r, tol);
      }
      freeAfter = CountFreeEdges(r.Shape);
    },
    failure);
}

/// "face 3 (NAME), face 7, ... (12 faces)": the faces of the edges of `wire`, at most 8 named.
std::string FacesAround(const TopoDS_Shape& wire, const TopTools_IndexedMapOfShape& faceMap,
  const TopTools_IndexedDataMapOfShapeListOfShape& edgeFaces, const std::vector<std::string>& names)
{
  std::vector<int> faces;
  for (TopExp_Explorer ex(wire, TopAbs_EDGE); ex.More(); ex.Next())
  {
    const int k = edgeFaces.FindIndex(ex.Current());
    for (const TopoDS_Shape& F : k > 0 ? edgeFaces(k) : TopTools_ListOfShape())
    {
      faces.push_back(faceMap.FindIndex(F));
    }
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  std::string text;
  for (std::size_t j = 0; j < faces.size() && j < 8; ++j)
  {
    text += (j > 0 ? ", " : "") +
      (faces[j] > 0 ? FaceLabel(faces[j] - 1, names[faces[j] - 1]) : std::string("a face"));
  }
  return text + (faces.size() > 8 ? ", ..." : "") + " (" + std::to_string(faces.size()) + " faces)";
}

/// The free edges the sewing leaves (where it joined others) bound openings of the model, which
/// the conversion keeps open: a warning describes each closed free boundary (its size, whether it is planar, the
/// faces around it). One as wide as the model is a missing face (absent from the file, or
/// skipped by the translation: see its warning), not a gap that healing should close.
void DescribeOpenings(ShapeRead& r, double diagonal)
{
  TopTools_IndexedMapOfShape faceMap;
  TopTools_IndexedDataMapOfShapeListOfShape edgeFaces;
  TopExp::MapShapes(r.Shape, TopAbs_FACE, faceMap);
  TopExp::MapShapesAndAncestors(r.Shape, TopAbs_EDGE, TopAbs_FACE, edgeFaces);
  const ShapeAnalysis_FreeBounds bounds(r.Shape, Standard_False, Standard_True, Standard_False);
  NamedList closed;
  for (TopExp_Explorer wx(bounds.GetClosedWires(), TopAbs_WIRE); wx.More(); wx.Next())
  {
    int edges = 0;
    for (TopExp_Explorer ex(wx.Current(), TopAbs_EDGE); ex.More(); ex.Next())
    {
      edges += !BRep_Tool::Degenerated(TopoDS::Edge(ex.Current()));
    }
    GProp_GProps length;
    BRepGProp::LinearProperties(wx.Current(), length);
    Bnd_Box box;
    BRepBndLib::Add(wx.Current(), box);
    const double across = std::sqrt(box.SquareExtent());
    // In a plane within 1 % of its size: the boundary of a missing planar face.
    const BRepLib_FindSurface plane(wx.Current(), 0.01 * across, Standard_True);
    closed.Add(std::to_string(edges) + " edges, " + Number(length.Mass()) + " long, " +
      Number(std::round(1000 * across / diagonal) / 10) + " % of the diagonal across, " +
      (plane.Found() ? "in a plane within " + Number(plane.ToleranceReached())
                     : std::string("not planar")) +
      ", around " + FacesAround(wx.Current(), faceMap, edgeFaces, r.FaceNames));
  }
  int open = 0;
  for (TopExp_Explorer wx(bounds.GetOpenWires(), TopAbs_WIRE); wx.More(); wx.Next())
  {
    ++open;
  }
  if (closed.Size() + open > 0)
  {
    r.Warnings.push_back("the model is open after the sewing (its free edges stay free edges "
      "of the result): " + std::to_string(closed.Size()) + " closed free boundar" +
      (closed.Size() == 1 ? "y" : "ies") + " (missing faces, or gaps wider than the tolerance)" +
      (closed.Size() > 0 ? ": " + closed.Text() : std::string()) +
      (open > 0 ? "; " + std::to_string(open) + " open chain(s) of free edges" : std::string()));
  }
}

/// The healing of HealingOptions. Removing slivers must not open the model: where the sewing
/// cannot close the gaps they leave (or is off), the slivers stay. An OCCT failure in it is a
/// warning and keeps the shape as read.
void Heal(ShapeRead& r, const HealingOptions& options, double diagonal)
{
  const double tol = options.Tolerance * diagonal;
  const ShapeRead asRead = r;
  std::string failure;
  int freeBefore = 0, freeAfter = 0;
  bool ok = RunGuarded([&] { freeBefore = CountFreeEdges(r.Shape); }, failure) &&
    HealPass(r, options, tol, freeBefore, true, freeAfter, failure);
  if (ok && r.Healing.RemovedFaces > 0 && freeAfter > freeBefore)
  {
    const int removed = r.Healing.RemovedFaces;
    r = asRead;
    r.Warnings.push_back(std::to_string(removed) + " sliver face(s) kept: " +
      "without them " + std::to_string(freeAfter) + " free edges would be left instead of " +
      std::to_string(freeBefore) + (options.Sew ? " (the sewing cannot close their gaps)" : " (sewing is off)"));
    ok = HealPass(r, options, tol, freeBefore, false, freeAfter, failure);
  }
  if (!ok)
  {
    r = asRead;
    r.Warnings.push_back("healing (sliver faces, sewing at " + Number(tol) +
      ") failed, the shape is kept as read: " + failure);
  }
  else if (options.Sew && r.Healing.SewnEdges > 0 && freeAfter > 0 && // pieces joined: no sheet
    !RunGuarded([&] { DescribeOpenings(r, diagonal); }, failure))
  {
    r.Warnings.push_back("the free boundaries left after the sewing cannot be analysed "
      "(ShapeAnalysis_FreeBounds): " + failure);
  }
}

/// Face names come from the STEP entity each face was transferred from: the entity whose shape
/// result equals the face, else the last whose result IsSame, as
/// XSControl_TransferReader::EntityFromShapeResult(face, 1) finds it. That searches every
/// transferred entity for each face (seconds on a STEP file of a thousand faces): here one pass
/// over the entities collects them per face.
void StepFaceNames(STEPControl_Reader& reader, ShapeRead& r)
{
  TopTools_IndexedMapOfShape faceMap;
  TopExp::MapShapes(r.Shape, TopAbs_FACE, faceMap);
  r.FaceNames.assign(faceMap.Extent(), std::string());
  const Handle(XSControl_TransferReader) tr = reader.WS()->TransferReader();
  const Handle(Transfer_TransientProcess) tp = tr.IsNull() ? nullptr : tr->TransientProcess();
  if (tp.IsNull())
  {
    return;
  }
  // Per face (faceMap compares by IsSame), the entities whose result it is, in their order.
  std::vector<std::vector<std::pair<int, TopAbs_Orientation>>> sources(faceMap.Extent());
  for (int j = 1; j <= tp->NbMapped(); ++j)
  {
    const TopoDS_Shape result = TransferBRep::ShapeResult(tp, tp->Mapped(j));
    const bool face = !result.IsNull() && result.ShapeType() == TopAbs_FACE;
    const int f = face ? faceMap.FindIndex(result) : 0;
    if (f > 0)
    {
      sources[f - 1].emplace_back(j, result.Orientation());
    }
  }
  for (int i = 1; i <= faceMap.Extent(); ++i)
  {
    const auto& s = sources[i - 1];
    if (s.empty())
    {
      continue;
    }
    const TopAbs_Orientation o = faceMap(i).Orientation();
    const auto equal =
      std::find_if(s.begin(), s.end(), [o](const auto& e) { return e.second == o; });
    const int j = equal != s.end() ? equal->first : s.back().first;
    const Handle(StepRepr_RepresentationItem) item =
      Handle(StepRepr_RepresentationItem)::DownCast(tp->Mapped(j));
    if (!item.IsNull() && !item->Name().IsNull())
    {
      r.FaceNames[i - 1] = item->Name()->ToCString();
    }
  }
}

/// "N entities: #12: message; #40: message; ..." for the failed checks, or "".
std::string Failures(const Interface_CheckIterator& checks, const Handle(Interface_InterfaceModel)& model)
{
  int count = 0;
  std::string first;
  for (checks.Start(); checks.More(); checks.Next())
  {
    const Handle(Interface_Check)& check = checks.Value();
    if (check.IsNull() || !check->HasFailed())
    {
      continue;
    }
    if (++count <= 3)
    {
      const int n = checks.Number();
      const Handle(TCollection_HAsciiString) label = n > 0 && !model.IsNull() && n <= model->NbEntities()
        ? model->StringLabel(model->Value(n))
        : Handle(TCollection_HAsciiString)();
      first += std::string(first.empty() ? "" : "; ") + (label.IsNull() ? "the file" : label->ToCString()) +
        ": " + check->CFail(1);
    }
  }
  return count == 0 ? std::string()
                    : std::to_string(count) + (count == 1 ? " entity (" : " entities (") + first +
      (count > 3 ? "; ..." : "") + ")";
}

/// What OCCT's parser and translation failed on (it skips such entities, so the shape may miss
/// faces).
std::string ReadFailures(XSControl_Reader& reader)
{
  const Handle(XSControl_WorkSession) ws = reader.WS();
  const Handle(XSControl_TransferReader) tr = ws->TransferReader();
  std::string text;
  const std::string parsed = Failures(ws->ModelCheckList(Standard_False), ws->Model());
  if (!parsed.empty())
  {
    text = "OpenCASCADE's parser found errors in " + parsed;
  }
  const std::string translated = tr.IsNull() || tr->TransientProcess().IsNull()
    ? std::string()
    : Failures(tr->TransientProcess()->CheckList(Standard_True), ws->Model());
  if (!translated.empty())
  {
    text += (text.empty() ? "" : "; ") + std::string("OpenCASCADE's translation failed on ") + translated +
      " and skipped them";
  }
  return text.empty() ? text : text + ": the model may miss faces";
}

/// The first failure messages OCCT sends to its messenger while it lives (the parser's syntax
/// errors, with their line numbers, go there and nowhere else).
class FailureMessages : public Message_Printer
{
public:
  FailureMessages() { Message::DefaultMessenger()->AddPrinter(this); }
  ~FailureMessages() override = default;
  void Detach() { Message::DefaultMessenger()->RemovePrinter(this); }
  std::string Text() const
  {
    std::string text;
    for (const std::string& line : this->Lines)
    {
      text += (text.empty() ? "" : "; ") + line;
    }
    return text;
  }

protected:
  void send(const TCollection_AsciiString& message, const Message_Gravity gravity) const override
  {
    if (gravity >= Message_Fail && this->Lines.size() < 3)
    {
      std::string line = message.ToCString();
      line.erase(0, line.find_first_not_of(" *"));
      line.erase(line.find_last_not_of(" *\r\n") + 1);
      this->Lines.push_back(line);
    }
  }

private:
  mutable std::vector<std::string> Lines;
};

/// Parsing and translation by OCCT's reader (STEPControl_Reader or IGESControl_Reader).
template <class Reader>
bool Transfer(Reader& reader, Format format, const std::string& fileName, ShapeRead& r, std::string& error)
{
  const std::string prefix = Prefix(format, fileName);
  std::string failure;
  IFSelect_ReturnStatus status = IFSelect_RetVoid;
  const Handle(FailureMessages) messages = new FailureMessages;
  const bool parsed = RunGuarded([&] { status = reader.ReadFile(fileName.c_str()); }, failure);
  messages->Detach();
  if (!parsed)
  {
    error = prefix + "parsing (ReadFile): " + failure;
    return false;
  }
  if (status != IFSelect_RetDone)
  {
    const std::string detail = messages->Text();
    error = prefix + "OpenCASCADE's parser rejected it: " + StatusName(status) + (detail.empty() ? "" : " (" + detail + ")");
    return false;
  }
  if (!RunGuarded(
        [&] {
          reader.TransferRoots();
          r.Shape = reader.OneShape();
        },
        failure))
  {
    error = prefix + "translating its entities into a shape (TransferRoots): " + failure;
    return false;
  }
  std::string warning;
  if (!RunGuarded([&] { warning = ReadFailures(reader); }, failure))
  {
    warning = "the check list of OpenCASCADE's translation cannot be read: " + failure;
  }
  if (!warning.empty())
  {
    r.Warnings.push_back(warning);
  }
  return true;
}

/// A reader of OCCT's that is not freed with `keep`: the reading child ends with _exit, and
/// freeing the file's entities and their transfer records would take a third of its time.
template <class Reader>
std::unique_ptr<Reader, void (*)(Reader*)> NewReader(bool keep)
{
  return { new Reader, keep ? +[](Reader*) {} : +[](Reader* reader) { delete reader; } };
}

/// BRepBndLib::AddOptimal of the shape (exact extents, no tolerances), the same bits: the union
/// of its faces' boxes, computed in parallel (their surfaces' PSO searches were a third of the
/// reading of a 620-face model with fillets), then, as AddOptimal adds them, its edges outside
/// faces and vertices outside edges. On failure, error names the first face (in face order)
/// on which OCCT fails.
bool ShapeBox(const ShapeRead& r, const std::string& prefix, Bnd_Box& box, std::string& error)
{
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(r.Shape, TopAbs_FACE, faces);
  std::vector<Bnd_Box> faceBoxes(faces.Extent());
  std::vector<std::string> failures(faces.Extent());
  ForEachFaceInParallel(faces.Extent(), [&](int f) {
    RunGuarded(
      [&] { BRepBndLib::AddOptimal(faces(f + 1), faceBoxes[f], Standard_False, Standard_False); },
      failures[f]);
  });
  for (int f = 0; f < faces.Extent(); ++f)
  {
    if (!failures[f].empty())
    {
      const std::string name =
        f < static_cast<int>(r.FaceNames.size()) ? r.FaceNames[f] : std::string();
      error = prefix + "the bounding box of " + FaceLabel(f, name) +
        " (BRepBndLib::AddOptimal, evaluating its surface): " + failures[f];
      return false;
    }
    if (!faceBoxes[f].IsVoid())
    {
      double x0, y0, z0, x1, y1, z1;
      faceBoxes[f].Get(x0, y0, z0, x1, y1, z1);
      box.Update(x0, y0, z0, x1, y1, z1);
    }
  }
  TopoDS_Compound rest;
  BRep_Builder builder;
  builder.MakeCompound(rest);
  bool any = false;
  for (TopExp_Explorer e(r.Shape, TopAbs_EDGE, TopAbs_FACE); e.More(); e.Next())
  {
    builder.Add(rest, e.Current());
    any = true;
  }
  for (TopExp_Explorer v(r.Shape, TopAbs_VERTEX, TopAbs_EDGE); v.More(); v.Next())
  {
    builder.Add(rest, v.Current());
    any = true;
  }
  std::string failure;
  const auto addRest = [&] { BRepBndLib::AddOptimal(rest, box, Standard_False, Standard_False); };
  if (any && !RunGuarded(addRest, failure))
  {
    error = prefix + "the bounding box of its edges outside faces (BRepBndLib::AddOptimal): " +
      failure;
    return false;
  }
  return true;
}

/// Translation and the healing that belongs to reading, in this process (inChild: in the
/// reading child, which leaves the reader to its exit).
bool Translate(const std::string& fileName, Format format, const HealingOptions& healing, ShapeRead& r,
  std::string& error, bool inChild)
{
  const std::string prefix = Prefix(format, fileName);
  std::string failure;
  if (format == Format::STEP)
  {
    const auto reader = NewReader<STEPControl_Reader>(inChild);
    if (!Transfer(*reader, format, fileName, r, error))
    {
      return false;
    }
    if (!RunGuarded([&] { StepFaceNames(*reader, r); }, failure))
    {
      error = prefix + "reading the face names: " + failure;
      return false;
    }
  }
  else
  {
    const auto reader = NewReader<IGESControl_Reader>(inChild);
    if (!Transfer(*reader, format, fileName, r, error))
    {
      return false;
    }
    TopTools_IndexedMapOfShape faceMap;
    TopExp::MapShapes(r.Shape, TopAbs_FACE, faceMap);
    r.FaceNames.assign(faceMap.Extent(), std::string());
  }
  if (r.Shape.IsNull() || r.FaceNames.empty())
  {
    error = "no faces in " + fileName + (r.Warnings.empty() ? "" : " (" + r.Warnings[0] + ")");
    return false;
  }
  if (!FixMissingSeams(r, prefix, error))
  {
    return false;
  }
  Bnd_Box box;
  if (!ShapeBox(r, prefix, box, error))
  {
    return false;
  }
  if (box.IsVoid())
  {
    error = prefix + "its shape has an empty bounding box";
    return false;
  }
  box.Get(r.Box[0], r.Box[2], r.Box[4], r.Box[1], r.Box[3], r.Box[5]);
  if (!std::all_of(r.Box, r.Box + 6, [](double v) { return std::isfinite(v) && std::abs(v) < 1e100; }))
  {
    error = prefix + "its shape's bounding box is not finite (coordinates out of range)";
    return false;
  }
  const double diagonal = std::sqrt(std::pow(r.Box[1] - r.Box[0], 2) +
    std::pow(r.Box[3] - r.Box[2], 2) + std::pow(r.Box[5] - r.Box[4], 2));
  if (!RunGuarded([&] {
        r.Healing.DegeneratedEdgesDropped =
          DropFalseDegeneratedEdges(r, 1e-2 * healing.Tolerance * diagonal);
      },
        failure))
  {
    r.Warnings.push_back("dropping the degenerated edges that are not points failed: " + failure);
  }
  if (!RunGuarded(
        [&] { r.Healing.PCurvesReprojected = ReprojectPCurves(r, 1e-2 * healing.Tolerance * diagonal); },
        failure))
  {
    r.Warnings.push_back("reprojecting the pcurves that are off their edges failed: " + failure);
  }
  Heal(r, healing, diagonal);
  return true;
}

// The child's answer on the pipe: 'S' + face names + warnings + healing report (a plain struct:
// same program on both ends) + box + BinTools shape, or 'E' + error.
void PutU32(std::ostream& out, std::uint32_t v)
{
  out.write(reinterpret_cast<const char*>(&v), sizeof v);
}

bool GetU32(std::istream& in, std::uint32_t& v)
{
  return static_cast<bool>(in.read(reinterpret_cast<char*>(&v), sizeof v));
}

void PutStrings(std::ostream& out, const std::vector<std::string>& strings)
{
  PutU32(out, static_cast<std::uint32_t>(strings.size()));
  for (const std::string& s : strings)
  {
    PutU32(out, static_cast<std::uint32_t>(s.size()));
    out.write(s.data(), static_cast<std::streamsize>(s.size()));
  }
}

bool GetStrings(std::istream& in, std::size_t limit, std::vector<std::string>& strings)
{
  std::uint32_t count = 0;
  bool ok = GetU32(in, count) && count <= limit;
  for (std::uint32_t i = 0; ok && i < count; ++i)
  {
    std::uint32_t length = 0;
    ok = GetU32(in, length) && length <= limit;
    std::string s(ok ? length : 0, '\0');
    ok = ok && (length == 0 || in.read(&s[0], length));
    strings.push_back(s);
  }
  return ok;
}

std::string Encode(const ShapeRead& r)
{
  std::ostringstream out(std::ios::binary);
  out.put('S');
  PutStrings(out, r.FaceNames);
  PutStrings(out, r.Warnings);
  out.write(reinterpret_cast<const char*>(&r.Healing), sizeof r.Healing);
  out.write(reinterpret_cast<const char*>(r.Box), sizeof r.Box);
  BinTools::Write(r.Shape, out);
  return out.str();
}

bool Decode(const std::string& payload, const std::string& prefix, ShapeRead& r, std::string& error)
{
  if (!payload.empty() && payload[0] == 'E')
  {
    error = payload.substr(1);
    return false;
  }
  std::istringstream in(payload, std::ios::binary);
  std::uint32_t count = 0;
  bool ok = in.get() == 'S' && GetStrings(in, payload.size(), r.FaceNames);
  count = static_cast<std::uint32_t>(r.FaceNames.size());
  ok = ok && GetStrings(in, payload.size(), r.Warnings) &&
    in.read(reinterpret_cast<char*>(&r.Healing), sizeof r.Healing) &&
    in.read(reinterpret_cast<char*>(r.Box), sizeof r.Box);
  std::string failure;
  if (!ok || !RunGuarded([&] { BinTools::Read(r.Shape, in); }, failure))
  {
    error = prefix + "the shape sent back by the reading process is incomplete " + failure;
    return false;
  }
  TopTools_IndexedMapOfShape faceMap;
  TopExp::MapShapes(r.Shape, TopAbs_FACE, faceMap);
  if (faceMap.Extent() != static_cast<int>(count))
  {
    error = prefix + "the shape sent back by the reading process has " + std::to_string(faceMap.Extent()) +
      " faces instead of " + std::to_string(count);
    return false;
  }
  return true;
}

/// The child: translates, writes its answer to fd and ends without running any of the parent's
/// exit handlers or destructors.
[[noreturn]] void ChildRead(const std::string& fileName, Format format, const HealingOptions& healing,
  const ShapeCheck& check, int fd)
{
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  // This process is ours: OCCT's handlers for every crash signal, even where the parent had its
  // own (OCCT's translation recovers from many crashes inside its own handlers).
  SetOCCTSignals(OSD_SignalMode_Set);
  signal(SIGINT, SIG_DFL); // Ctrl-C ends the child too (a host's handler would only set a flag)
  ShapeRead r;
  std::string error, payload, failure;
  if (!Translate(fileName, format, healing, r, error, true) || (check && !check(r, error)))
  {
    payload = "E" + error;
  }
  else if (!RunGuarded([&] { payload = Encode(r); }, failure))
  {
    payload = "E" + Prefix(format, fileName) + "writing the shape for the reading process's parent: " + failure;
  }
  for (std::size_t done = 0; done < payload.size();)
  {
    const ssize_t n = write(fd, payload.data() + done, payload.size() - done);
    if (n < 0 && errno == EINTR)
    {
      continue;
    }
    if (n <= 0)
    {
      break;
    }
    done += static_cast<std::size_t>(n);
  }
  close(fd);
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  _exit(0);
}

/// Reads fd until end of file; false when the time runs out first.
bool ReceiveUntil(int fd, double seconds, std::string& out)
{
  using Clock = std::chrono::steady_clock;
  const std::chrono::duration<double> limit(std::min(seconds, 1e9)); // no overflow of the clock
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(limit);
  char buffer[1 << 16];
  for (;;)
  {
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    if (left <= 0)
    {
      return false;
    }
    pollfd p{ fd, POLLIN, 0 };
    const int ready = poll(&p, 1, static_cast<int>(std::min(std::ceil(left * 1000), 1e9)));
    if (ready <= 0)
    {
      continue; // EINTR or the time is up (checked above)
    }
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n > 0)
    {
      out.append(buffer, static_cast<std::size_t>(n));
    }
    else if (n == 0 || (errno != EINTR && errno != EAGAIN))
    {
      return true;
    }
  }
}

std::string SignalText(int sig)
{
  const char* what = strsignal(sig);
  return "signal " + std::to_string(sig) + (what ? std::string(", ") + what : std::string());
}

bool ReadInChild(const std::string& fileName, Format format, double timeout, const HealingOptions& healing,
  const ShapeCheck& check, ShapeRead& r, std::string& error)
{
  const std::string prefix = Prefix(format, fileName);
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0)
  {
    error = prefix + "cannot start the reading process (pipe): " + std::strerror(errno);
    return false;
  }
  // What this process has buffered would otherwise be written twice, by the child too.
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0)
  {
    error = prefix + "cannot start the reading process (fork): " + std::strerror(errno);
    close(fds[0]);
    close(fds[1]);
    return false;
  }
  if (pid == 0)
  {
    close(fds[0]);
    ChildRead(fileName, format, healing, check, fds[1]);
  }
  close(fds[1]);
  std::string payload;
  const bool finished = ReceiveUntil(fds[0], timeout, payload);
  close(fds[0]);
  if (!finished)
  {
    kill(pid, SIGKILL);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
  {
  }
  if (!finished)
  {
    std::ostringstream s;
    s << prefix << "OpenCASCADE's translation and healing did not end within the read timeout of "
      << timeout << " s: abandoned (a malformed file, or raise the timeout for a very large model)";
    error = s.str();
    return false;
  }
  if (WIFSIGNALED(status))
  {
    error = prefix + "OpenCASCADE's translation crashed (" + SignalText(WTERMSIG(status)) +
      ") in the reading process: the file is malformed";
    return false;
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || payload.empty())
  {
    error = prefix + "OpenCASCADE ended the reading process without a result (exit status " +
      std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
      ": an exception it found no handler for): the file is malformed";
    return false;
  }
  return Decode(payload, prefix, r, error);
}
} // namespace

void SetOCCTSignals(OSD_SignalMode mode)
{
  const int keep[] = { SIGINT, SIGHUP, SIGQUIT };
  struct sigaction before[3];
  for (int i = 0; i < 3; ++i)
  {
    sigaction(keep[i], nullptr, &before[i]);
  }
  OSD::SetSignal(mode, Standard_False);
  for (int i = 0; i < 3; ++i)
  {
    sigaction(keep[i], &before[i], nullptr);
  }
}

bool ReadCADFile(const std::string& fileName, double timeoutSeconds, const HealingOptions& healing,
  const ShapeCheck& check, ShapeRead& result, std::string& error)
{
  const Format format = FormatOf(fileName);
  if (format == Format::Unknown)
  {
    error = "unknown CAD file extension (want .step, .stp, .iges, .igs): " + fileName;
    return false;
  }
  if (!CheckFileNumbers(fileName, error))
  {
    return false;
  }
  result = ShapeRead();
  return timeoutSeconds > 0 ? ReadInChild(fileName, format, timeoutSeconds, healing, check, result, error)
                            : Translate(fileName, format, healing, result, error, false);
}

} // namespace ctcad
