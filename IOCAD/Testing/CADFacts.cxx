// SPDX-License-Identifier: GPL-3.0-or-later
// ctsplines_cad_facts [--tangent-threshold DEG] MODEL...: what OpenCASCADE itself says about
// each STEP/IGES model, as one JSON line per model, for the corpus benchmark
// (Testing/Benchmarks/cad_corpus.py): faces, shells, closed shells, free edges (used by one face;
// seams and degenerated edges excluded), non-manifold edges (more than two faces), degenerated
// edges, tangent edges (two faces whose oriented normals at the edge's midpoint are within the
// threshold, default 10 degrees), whether the model is closed (faces and no free edge), and
// OCCT's plain read time (ReadFile + TransferRoots + OneShape, nothing else: the yardstick of
// the conversion's time). Independent of the conversion on purpose: no healing, no sampling.
// Exit code 0 when every model was characterised, 1 otherwise (its line says "error").
#include "CADBRepSampling.h" // ctcad::RunGuarded

#include <BRepAdaptor_Surface.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_Curve.hxx>
#include <IGESControl_Reader.hxx>
#include <STEPControl_Reader.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Vec.hxx>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace
{
struct Facts
{
  int Faces = 0, Shells = 0, ClosedShells = 0, Edges = 0;
  int FreeEdges = 0, NonManifoldEdges = 0, DegeneratedEdges = 0, SeamEdges = 0;
  int TangentEdges = 0, UndefinedNormalEdges = 0;
  double ReadTime = 0;
};

std::string Lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string Extension(const std::string& path)
{
  const std::size_t dot = path.find_last_of('.');
  return dot == std::string::npos ? std::string() : Lower(path.substr(dot + 1));
}

/// OCCT's plain read: the time the conversion's own read is compared with.
bool ReadPlain(const std::string& path, TopoDS_Shape& shape, double& seconds, std::string& error)
{
  const std::string ext = Extension(path);
  STEPControl_Reader step;
  IGESControl_Reader iges;
  XSControl_Reader* reader = nullptr;
  if (ext == "step" || ext == "stp")
  {
    reader = &step;
  }
  else if (ext == "iges" || ext == "igs")
  {
    reader = &iges;
  }
  else
  {
    error = "unknown CAD file extension ." + ext;
    return false;
  }
  const auto start = std::chrono::steady_clock::now();
  if (reader->ReadFile(path.c_str()) != IFSelect_RetDone)
  {
    error = "OpenCASCADE cannot read the file";
    return false;
  }
  reader->TransferRoots();
  shape = reader->OneShape();
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return true;
}

/// The distinct faces of an edge's ancestor list (MapShapesAndAncestors lists a seam's face
/// twice).
std::vector<TopoDS_Face> DistinctFaces(const TopTools_ListOfShape& ancestors)
{
  std::vector<TopoDS_Face> faces;
  for (TopTools_ListOfShape::Iterator it(ancestors); it.More(); it.Next())
  {
    const TopoDS_Face& f = TopoDS::Face(it.Value());
    if (std::none_of(faces.begin(), faces.end(), [&](const TopoDS_Face& g) { return g.IsSame(f); }))
    {
      faces.push_back(f);
    }
  }
  return faces;
}

/// The outward (orientation-aware) unit normal of `face` at the midpoint of `edge`'s pcurve;
/// false where the pcurve is missing or the normal is undefined (a pole).
bool NormalAtMidpoint(const TopoDS_Edge& edge, const TopoDS_Face& face, gp_Vec& normal)
{
  double first = 0, last = 0;
  const Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, face, first, last);
  if (pcurve.IsNull())
  {
    return false;
  }
  const gp_Pnt2d uv = pcurve->Value(0.5 * (first + last));
  BRepAdaptor_Surface surface(face, Standard_False);
  gp_Pnt p;
  gp_Vec du, dv;
  surface.D1(uv.X(), uv.Y(), p, du, dv);
  normal = du.Crossed(dv);
  const double length = normal.Magnitude();
  if (!(length > 1e-14 * std::max(1.0, du.Magnitude() * dv.Magnitude())))
  {
    return false;
  }
  normal /= length;
  if (face.Orientation() == TopAbs_REVERSED)
  {
    normal.Reverse();
  }
  return true;
}

void CountEdges(const TopoDS_Shape& shape, double cosThreshold, Facts& facts)
{
  TopTools_IndexedDataMapOfShapeListOfShape edgeFaces;
  TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, edgeFaces);
  facts.Edges = edgeFaces.Extent();
  for (int i = 1; i <= edgeFaces.Extent(); ++i)
  {
    const TopoDS_Edge& edge = TopoDS::Edge(edgeFaces.FindKey(i));
    if (BRep_Tool::Degenerated(edge))
    {
      ++facts.DegeneratedEdges;
      continue;
    }
    const std::vector<TopoDS_Face> faces = DistinctFaces(edgeFaces.FindFromIndex(i));
    const bool seam = std::any_of(faces.begin(), faces.end(),
      [&](const TopoDS_Face& f) { return BRep_Tool::IsClosed(edge, f); });
    facts.SeamEdges += seam ? 1 : 0;
    if (faces.size() == 1 && !seam)
    {
      ++facts.FreeEdges;
    }
    else if (faces.size() > 2)
    {
      ++facts.NonManifoldEdges;
    }
    else if (faces.size() == 2)
    {
      gp_Vec n0, n1;
      if (!NormalAtMidpoint(edge, faces[0], n0) || !NormalAtMidpoint(edge, faces[1], n1))
      {
        ++facts.UndefinedNormalEdges;
      }
      else if (n0.Dot(n1) >= cosThreshold)
      {
        ++facts.TangentEdges;
      }
    }
  }
}

void Characterise(const TopoDS_Shape& shape, double cosThreshold, Facts& facts)
{
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  facts.Faces = faces.Extent();
  TopTools_IndexedMapOfShape shells;
  TopExp::MapShapes(shape, TopAbs_SHELL, shells);
  facts.Shells = shells.Extent();
  for (int i = 1; i <= shells.Extent(); ++i)
  {
    facts.ClosedShells += BRep_Tool::IsClosed(shells(i)) ? 1 : 0;
  }
  CountEdges(shape, cosThreshold, facts);
}

std::string JsonString(const std::string& text)
{
  std::string out = "\"";
  for (const unsigned char c : text)
  {
    if (c == '"' || c == '\\')
    {
      out += '\\';
      out += static_cast<char>(c);
    }
    else if (c < 0x20)
    {
      char buffer[8];
      std::snprintf(buffer, sizeof(buffer), "\\u%04x", c);
      out += buffer;
    }
    else
    {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

void PrintFacts(const std::string& path, const Facts& f, bool ok, const std::string& error)
{
  std::string line = "{\"model\": " + JsonString(path);
  if (ok)
  {
    char buffer[512];
    std::snprintf(buffer, sizeof(buffer),
      ", \"faces\": %d, \"shells\": %d, \"closed_shells\": %d, \"edges\": %d, "
      "\"free_edges\": %d, \"non_manifold_edges\": %d, \"degenerated_edges\": %d, "
      "\"seam_edges\": %d, \"tangent_edges\": %d, \"undefined_normal_edges\": %d, "
      "\"closed\": %s, \"read_time\": %.6f",
      f.Faces, f.Shells, f.ClosedShells, f.Edges, f.FreeEdges, f.NonManifoldEdges,
      f.DegeneratedEdges, f.SeamEdges, f.TangentEdges, f.UndefinedNormalEdges,
      f.Faces > 0 && f.FreeEdges == 0 ? "true" : "false", f.ReadTime);
    line += buffer;
  }
  else
  {
    line += ", \"error\": " + JsonString(error);
  }
  std::printf("%s}\n", line.c_str());
  std::fflush(stdout);
}
} // namespace

int main(int argc, char* argv[])
{
  double threshold = 10;
  std::vector<std::string> models;
  for (int i = 1; i < argc; ++i)
  {
    if (std::strcmp(argv[i], "--tangent-threshold") == 0 && i + 1 < argc)
    {
      threshold = std::atof(argv[++i]);
    }
    else
    {
      models.emplace_back(argv[i]);
    }
  }
  if (models.empty())
  {
    std::fprintf(stderr, "usage: %s [--tangent-threshold DEGREES] MODEL.step|.iges...\n", argv[0]);
    return 2;
  }
  const double cosThreshold = std::cos(threshold * 3.14159265358979323846 / 180.0);
  int status = 0;
  for (const std::string& path : models)
  {
    Facts facts;
    std::string error, failure;
    bool ok = false;
    // Every Standard_Failure (and a signal inside OCCT) ends here, named, for this model only.
    const bool guarded = ctcad::RunGuarded(
      [&] {
        TopoDS_Shape shape;
        ok = ReadPlain(path, shape, facts.ReadTime, error);
        if (ok && shape.IsNull())
        {
          ok = false;
          error = "no shape in the file";
        }
        if (ok)
        {
          Characterise(shape, cosThreshold, facts);
        }
      },
      failure);
    if (!guarded)
    {
      ok = false;
      error = "OpenCASCADE failed: " + failure;
    }
    PrintFacts(path, facts, ok, error);
    status = ok ? status : 1;
  }
  return status;
}
