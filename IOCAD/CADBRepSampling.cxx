// SPDX-License-Identifier: GPL-3.0-or-later
// OpenCASCADE side of the CAD import: reading, edge-first sampling, face loops. No CGAL here.
#include "CADBRepSampling.h"

#include "InterfaceTangentPlanes.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <Geom2d_Curve.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <ShapeBuild_ReShape.hxx>
#include <ShapeFix_Face.hxx>
#include <STEPControl_Reader.hxx>
#include <StepRepr_RepresentationItem.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>
#include <gp_Pnt.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Vec.hxx>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

namespace ctcad
{
namespace
{
using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a)
{
  return std::chrono::duration<double>(Clock::now() - a).count();
}

Point3 ToPoint(const gp_XYZ& p)
{
  return { p.X(), p.Y(), p.Z() };
}

double Distance(const Point3& a, const Point3& b)
{
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
    (a[2] - b[2]) * (a[2] - b[2]));
}

/// Cubic Bézier (a, b, c, d) at s.
Point3 Bezier3(const Point3& a, const Point3& b, const Point3& c, const Point3& d, double s)
{
  const double r = 1 - s;
  const double w0 = r * r * r, w1 = 3 * r * r * s, w2 = 3 * r * s * s, w3 = s * s * s;
  Point3 p;
  for (int i = 0; i < 3; ++i)
  {
    p[i] = w0 * a[i] + w1 * b[i] + w2 * c[i] + w3 * d[i];
  }
  return p;
}

/// A face on a closed surface bounded by closed wires but without a seam edge (e.g. a
/// cylinder's lateral face between two circles) has pcurves that are open curves in the
/// parameter plane: ShapeFix_Face::FixMissingSeam joins the wires by a seam edge. OCCT's readers
/// do so in their own healing (FixShape, on by default), which can be configured away or fail:
/// this repeats that one fix on the faces that still need it. Returns the number fixed; shape
/// and faceMap are replaced, names follow their faces.
int FixMissingSeams(TopoDS_Shape& shape, TopTools_IndexedMapOfShape& faceMap,
  std::vector<std::string>& names)
{
  const Handle(ShapeBuild_ReShape) context = new ShapeBuild_ReShape;
  int fixed = 0;
  for (int i = 1; i <= faceMap.Extent(); ++i)
  {
    const TopoDS_Face& F = TopoDS::Face(faceMap(i));
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
      continue;
    }
    const Handle(ShapeFix_Face) fix = new ShapeFix_Face(F);
    fix->SetContext(context);
    if (fix->FixMissingSeam())
    {
      if (!context->IsRecorded(F))
      {
        context->Replace(F, fix->Face());
      }
      ++fixed;
    }
  }
  if (fixed == 0)
  {
    return 0;
  }
  shape = context->Apply(shape);
  TopTools_IndexedMapOfShape newMap;
  TopExp::MapShapes(shape, TopAbs_FACE, newMap);
  std::vector<std::string> newNames(newMap.Extent());
  for (int i = 1; i <= faceMap.Extent(); ++i)
  {
    for (TopExp_Explorer fx(context->Value(faceMap(i)), TopAbs_FACE); fx.More(); fx.Next())
    {
      const int j = newMap.FindIndex(fx.Current());
      if (j > 0)
      {
        newNames[j - 1] = names[i - 1];
      }
    }
  }
  faceMap = newMap;
  names = newNames;
  return fixed;
}

std::string Lower(std::string s)
{
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

/// The adaptive Hermite samples of one B-rep edge, in the edge's own parameter direction.
struct EdgeSampling
{
  bool Degenerate = false;
  Id Vertex0 = -1, Vertex1 = -1; // node ids of the first and last vertex
  std::vector<double> T;
  std::vector<Id> Nodes;
  std::vector<Point3> D; // dC/dt
  /// Inner Hermite control points of span k: near sample k, near sample k+1.
  std::vector<std::array<Point3, 2>> Inner;
};

/// A pcurve of an edge on one face (a seam has two on the same face).
struct PCurveUse
{
  int Face;
  Handle(Geom2d_Curve) Curve;
};
} // namespace

struct CADModel::Impl
{
  TopoDS_Shape Shape;
  TopTools_IndexedMapOfShape FaceMap, EdgeMap, VertexMap;
  std::vector<BRepAdaptor_Surface> Surfaces;
  std::vector<std::string> Names;
  std::vector<EdgeSampling> Edges;
};

CADModel::CADModel()
  : Internal(new Impl)
{
}

CADModel::~CADModel() = default;

int CADModel::NumberOfEdges() const
{
  return this->Internal->EdgeMap.Extent();
}

int CADModel::NumberOfVertices() const
{
  return this->Internal->VertexMap.Extent();
}

bool CADModel::Read(const std::string& fileName)
{
  const auto start = Clock::now();
  const std::string name = Lower(fileName);
  auto endsWith = [&](const char* ext) {
    const std::string e(ext);
    return name.size() >= e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0;
  };
  Impl& d = *this->Internal;
  std::vector<std::string> namesByFace;
  if (endsWith(".step") || endsWith(".stp"))
  {
    STEPControl_Reader reader;
    if (reader.ReadFile(fileName.c_str()) != IFSelect_RetDone)
    {
      this->ErrorMessage = "cannot read STEP file " + fileName;
      return false;
    }
    reader.TransferRoots();
    d.Shape = reader.OneShape();
    TopExp::MapShapes(d.Shape, TopAbs_FACE, d.FaceMap);
    // Face names come from the STEP entity each face was transferred from.
    const Handle(XSControl_TransferReader) tr = reader.WS()->TransferReader();
    for (int i = 1; i <= d.FaceMap.Extent(); ++i)
    {
      std::string faceName;
      if (!tr.IsNull())
      {
        const Handle(StepRepr_RepresentationItem) item =
          Handle(StepRepr_RepresentationItem)::DownCast(
            tr->EntityFromShapeResult(d.FaceMap(i), 1));
        if (!item.IsNull() && !item->Name().IsNull())
        {
          faceName = item->Name()->ToCString();
        }
      }
      namesByFace.push_back(faceName);
    }
  }
  else if (endsWith(".iges") || endsWith(".igs"))
  {
    IGESControl_Reader reader;
    if (reader.ReadFile(fileName.c_str()) != IFSelect_RetDone)
    {
      this->ErrorMessage = "cannot read IGES file " + fileName;
      return false;
    }
    reader.TransferRoots();
    d.Shape = reader.OneShape();
    TopExp::MapShapes(d.Shape, TopAbs_FACE, d.FaceMap);
    namesByFace.assign(d.FaceMap.Extent(), std::string());
  }
  else
  {
    this->ErrorMessage = "unknown CAD file extension (want .step, .stp, .iges, .igs): " + fileName;
    return false;
  }
  if (d.Shape.IsNull() || d.FaceMap.Extent() == 0)
  {
    this->ErrorMessage = "no faces in " + fileName;
    return false;
  }
  this->SeamsAdded = FixMissingSeams(d.Shape, d.FaceMap, namesByFace);
  TopExp::MapShapes(d.Shape, TopAbs_EDGE, d.EdgeMap);
  TopExp::MapShapes(d.Shape, TopAbs_VERTEX, d.VertexMap);
  for (int i = 0; i < d.FaceMap.Extent(); ++i)
  {
    const std::string& n = namesByFace[i];
    const bool useful = !n.empty() && n != "NONE" && n != "''";
    d.Names.push_back(useful ? n : "Face " + std::to_string(i));
  }
  Bnd_Box box;
  BRepBndLib::AddOptimal(d.Shape, box, Standard_False, Standard_False);
  box.Get(this->Box[0], this->Box[2], this->Box[4], this->Box[1], this->Box[3], this->Box[5]);
  this->BoxDiagonal = std::sqrt(std::pow(this->Box[1] - this->Box[0], 2) +
    std::pow(this->Box[3] - this->Box[2], 2) + std::pow(this->Box[5] - this->Box[4], 2));
  this->Time.Read = Seconds(start);
  return true;
}

void CADModel::Evaluate(int f, double s, double t, double P[3], double Ds[3], double Dt[3]) const
{
  const bool rev = this->FaceList[f].Reversed;
  gp_Pnt p;
  gp_Vec du, dv;
  this->Internal->Surfaces[f].D1(rev ? -s : s, t, p, du, dv);
  const double sign = rev ? -1.0 : 1.0;
  for (int i = 0; i < 3; ++i)
  {
    P[i] = p.Coord(i + 1);
    Ds[i] = sign * du.Coord(i + 1);
    Dt[i] = dv.Coord(i + 1);
  }
}

void CADModel::Evaluate(int f, double s, double t, double P[3]) const
{
  const gp_Pnt p = this->Internal->Surfaces[f].Value(this->FaceList[f].Reversed ? -s : s, t);
  P[0] = p.X();
  P[1] = p.Y();
  P[2] = p.Z();
}

bool CADModel::Sample(const SamplingOptions& options)
{
  Impl& d = *this->Internal;
  const double tol = options.Tolerance * this->BoxDiagonal;
  const double maxSpan = options.MaxSpanLength * this->BoxDiagonal;
  const int nF = d.FaceMap.Extent(), nE = d.EdgeMap.Extent(), nV = d.VertexMap.Extent();
  this->FaceList.assign(nF, CADFace());
  d.Surfaces.clear();
  for (int f = 0; f < nF; ++f)
  {
    const TopoDS_Face& F = TopoDS::Face(d.FaceMap(f + 1));
    d.Surfaces.emplace_back(F, Standard_False);
    this->FaceList[f].Index = f;
    this->FaceList[f].Name = d.Names[f];
    this->FaceList[f].Reversed = F.Orientation() == TopAbs_REVERSED;
  }
  this->NodePoints.clear();
  for (int v = 1; v <= nV; ++v)
  {
    this->NodePoints.push_back(ToPoint(BRep_Tool::Pnt(TopoDS::Vertex(d.VertexMap(v))).XYZ()));
  }

  // 1. Edges, each once: adaptive cubic Hermite samples of the mean of the adjacent surfaces
  // over their pcurves (the stitched spline's boundary is that cubic over each face's pcurve
  // chord), split as described at spanError below.
  auto start = Clock::now();
  TopTools_IndexedDataMapOfShapeListOfShape edgeFaces;
  TopExp::MapShapesAndAncestors(d.Shape, TopAbs_EDGE, TopAbs_FACE, edgeFaces);
  d.Edges.assign(nE, EdgeSampling());
  this->VertexGap = 0;
  this->EdgeGap = 0;
  this->EdgeSamples = 0;
  // Pass 1: every edge's pcurves (a seam has two on its face), its end vertices, and the
  // vertex positions: the mean of the adjacent surfaces at the pcurve ends. The faces of a real
  // model miss each other and the edge curves by up to ~1e-4 of the diagonal; the mean halves
  // what any one face sees.
  std::vector<std::vector<PCurveUse>> edgeUses(nE);
  std::vector<Point3> vertexSum(nV, Point3{ 0, 0, 0 });
  std::vector<int> vertexCount(nV, 0);
  for (int e = 0; e < nE; ++e)
  {
    EdgeSampling& es = d.Edges[e];
    const TopoDS_Edge E = TopoDS::Edge(d.EdgeMap(e + 1).Oriented(TopAbs_FORWARD));
    TopoDS_Vertex v0, v1;
    TopExp::Vertices(E, v0, v1);
    if (v0.IsNull() || v1.IsNull())
    {
      this->ErrorMessage = "edge " + std::to_string(e) + " has no vertices";
      return false;
    }
    es.Vertex0 = d.VertexMap.FindIndex(v0) - 1;
    es.Vertex1 = d.VertexMap.FindIndex(v1) - 1;
    if (BRep_Tool::Degenerated(E))
    {
      es.Degenerate = true;
      continue;
    }
    std::vector<PCurveUse>& uses = edgeUses[e];
    const int ef = edgeFaces.FindIndex(E);
    if (ef > 0)
    {
      for (const TopoDS_Shape& s : edgeFaces(ef))
      {
        const TopoDS_Face F = TopoDS::Face(s.Oriented(TopAbs_FORWARD));
        const int f = d.FaceMap.FindIndex(s) - 1;
        if (f < 0 || std::any_of(uses.begin(), uses.end(), [&](const PCurveUse& u) { return u.Face == f; }))
        {
          continue;
        }
        double a, b;
        for (const TopoDS_Edge& oriented : { E, TopoDS::Edge(E.Reversed()) })
        {
          Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(oriented, F, a, b);
          if (!pc.IsNull())
          {
            uses.push_back({ f, pc });
          }
          if (!BRep_Tool::IsClosed(E, F))
          {
            break;
          }
        }
      }
    }
    const BRepAdaptor_Curve curve(E);
    for (const PCurveUse& u : uses)
    {
      for (int end = 0; end < 2; ++end)
      {
        const double t = end ? curve.LastParameter() : curve.FirstParameter();
        const gp_Pnt2d q = u.Curve->Value(t);
        const Point3 p = ToPoint(d.Surfaces[u.Face].Value(q.X(), q.Y()).XYZ());
        const Id v = end ? es.Vertex1 : es.Vertex0;
        for (int i = 0; i < 3; ++i)
        {
          vertexSum[v][i] += p[i];
        }
        ++vertexCount[v];
      }
    }
  }
  for (int v = 0; v < nV; ++v)
  {
    if (vertexCount[v] > 0)
    {
      const Point3 mean{ vertexSum[v][0] / vertexCount[v], vertexSum[v][1] / vertexCount[v],
        vertexSum[v][2] / vertexCount[v] };
      this->VertexGap = std::max(this->VertexGap, Distance(mean, this->NodePoints[v]));
      this->NodePoints[v] = mean;
    }
  }

  // Pass 2: adaptive Hermite samples of each edge's mean curve.
  for (int e = 0; e < nE; ++e)
  {
    EdgeSampling& es = d.Edges[e];
    if (es.Degenerate)
    {
      continue;
    }
    const TopoDS_Edge E = TopoDS::Edge(d.EdgeMap(e + 1).Oriented(TopAbs_FORWARD));
    const std::vector<PCurveUse>& uses = edgeUses[e];
    const BRepAdaptor_Curve curve(E);
    const double t0 = curve.FirstParameter(), t1 = curve.LastParameter();
    const Point3 p0 = this->NodePoints[es.Vertex0], p1 = this->NodePoints[es.Vertex1];
    // The edge's point at t: the mean of the adjacent surfaces over their pcurves (the 3D
    // curve when no face has a pcurve), its derivative, and how far the faces are from it.
    auto pointAt = [&](double t, Point3& p, Point3& dp) {
      double spread = 0;
      if (uses.empty())
      {
        gp_Pnt q;
        gp_Vec v;
        curve.D1(t, q, v);
        p = ToPoint(q.XYZ());
        dp = ToPoint(v.XYZ());
        return spread;
      }
      p = dp = Point3{ 0, 0, 0 };
      std::vector<Point3> onFace;
      for (const PCurveUse& u : uses)
      {
        gp_Pnt2d q;
        gp_Vec2d dq;
        u.Curve->D1(t, q, dq);
        gp_Pnt x;
        gp_Vec xu, xv;
        d.Surfaces[u.Face].D1(q.X(), q.Y(), x, xu, xv);
        const gp_Vec dx = dq.X() * xu + dq.Y() * xv;
        onFace.push_back(ToPoint(x.XYZ()));
        for (int i = 0; i < 3; ++i)
        {
          p[i] += x.Coord(i + 1) / uses.size();
          dp[i] += dx.Coord(i + 1) / uses.size();
        }
      }
      for (std::size_t i = 0; i < onFace.size(); ++i)
      {
        for (std::size_t j = 0; j < i; ++j)
        {
          spread = std::max(spread, Distance(onFace[i], onFace[j]));
        }
      }
      return spread;
    };
    struct Sample
    {
      double T;
      Point3 P, D;
    };
    auto makeSample = [&](double t) {
      Sample s{ t, {}, {} };
      this->EdgeGap = std::max(this->EdgeGap, pointAt(t, s.P, s.D));
      return s;
    };
    // Shared vertices: the curve ends are the vertex nodes (means over all faces at the vertex).
    Sample first = makeSample(t0), last = makeSample(t1);
    first.P = p0;
    last.P = p1;
    const int n0 = es.Vertex0 == es.Vertex1 ? 3 : 2;
    std::vector<Sample> samples{ first };
    for (int k = 1; k < n0; ++k)
    {
      samples.push_back(makeSample(t0 + (t1 - t0) * k / n0));
    }
    samples.push_back(last);
    // A span is split while its Hermite cubic is off the mean curve, or while any adjacent
    // surface over the pcurve chord (the stitched spline's boundary lies over that chord) is off
    // the cubic by more than the edge tolerance beyond that surface's own distance from the mean
    // curve. Half the tolerance: the other half is left to the face interiors.
    const double edgeTol = 0.5 * tol;
    auto spanError = [&](const Sample& a, const Sample& b) {
      const double h = b.T - a.T;
      Point3 ca, cb;
      for (int i = 0; i < 3; ++i)
      {
        ca[i] = a.P[i] + h * a.D[i] / 3;
        cb[i] = b.P[i] - h * b.D[i] / 3;
      }
      double err = 0;
      for (const double s : { 0.25, 0.5, 0.75 })
      {
        const Point3 hermite = Bezier3(a.P, ca, cb, b.P, s);
        Point3 c, dc;
        pointAt(a.T + s * h, c, dc);
        err = std::max(err, Distance(hermite, c));
        for (const PCurveUse& u : uses)
        {
          const gp_Pnt2d ua = u.Curve->Value(a.T), ub = u.Curve->Value(b.T);
          const gp_Pnt2d um = u.Curve->Value(a.T + s * h);
          const BRepAdaptor_Surface& S = d.Surfaces[u.Face];
          const Point3 chord = ToPoint(
            S.Value((1 - s) * ua.X() + s * ub.X(), (1 - s) * ua.Y() + s * ub.Y()).XYZ());
          const double gap = Distance(ToPoint(S.Value(um.X(), um.Y()).XYZ()), c);
          err = std::max(err, Distance(chord, hermite) - gap);
        }
      }
      return err;
    };
    const double minSpan = 1e-9 * std::abs(t1 - t0);
    for (bool changed = true; changed && static_cast<int>(samples.size()) < options.MaxSamplesPerEdge;)
    {
      changed = false;
      std::vector<Sample> next{ samples.front() };
      for (std::size_t k = 0; k + 1 < samples.size(); ++k)
      {
        const Sample& a = samples[k];
        const Sample& b = samples[k + 1];
        // Long spans are split too under a length bound: boundary segments are never split by
        // the face mesher, so a face's triangles can meet that bound (and an aspect bound near
        // the boundary) only if the edge samples do.
        const bool tooLong = maxSpan > 0 && Distance(a.P, b.P) > maxSpan;
        if (std::abs(b.T - a.T) > minSpan && (tooLong || spanError(a, b) > edgeTol) &&
          static_cast<int>(samples.size() + next.size()) < 2 * options.MaxSamplesPerEdge)
        {
          next.push_back(makeSample(0.5 * (a.T + b.T)));
          changed = true;
        }
        next.push_back(b);
      }
      samples.swap(next);
    }
    const std::size_t n = samples.size();
    es.T.resize(n);
    es.D.resize(n);
    es.Nodes.resize(n);
    for (std::size_t k = 0; k < n; ++k)
    {
      es.T[k] = samples[k].T;
      es.D[k] = samples[k].D;
      es.Nodes[k] = k == 0 ? es.Vertex0 : k + 1 == n ? es.Vertex1 : this->AddNode(samples[k].P);
    }
    es.Inner.resize(n - 1);
    for (std::size_t k = 0; k + 1 < n; ++k)
    {
      const double h = es.T[k + 1] - es.T[k];
      for (int i = 0; i < 3; ++i)
      {
        es.Inner[k][0][i] = samples[k].P[i] + h * es.D[k][i] / 3;
        es.Inner[k][1][i] = samples[k + 1].P[i] - h * es.D[k + 1][i] / 3;
      }
    }
    this->EdgeSamples += static_cast<Id>(n);
  }
  this->Time.Edges = Seconds(start);

  // 2. Face loops: the edge samples through each face's pcurves, wire by wire, in wire order.
  start = Clock::now();
  for (int f = 0; f < nF; ++f)
  {
    CADFace& face = this->FaceList[f];
    const TopoDS_Face& F = TopoDS::Face(d.FaceMap(f + 1));
    const double sign = face.Reversed ? -1.0 : 1.0;
    auto surfaceAt = [&](const double uv[2]) {
      double P[3];
      this->Evaluate(f, uv[0], uv[1], P);
      return Point3{ P[0], P[1], P[2] };
    };
    // An edge's run of nodes in this face, with the segments between them.
    struct Run
    {
      std::vector<LoopNode> Nodes;
      std::vector<LoopSegment> Segments;
      double Tolerance = 0; // vertex tolerance at the run's start
    };
    for (TopExp_Explorer wx(F, TopAbs_WIRE); wx.More(); wx.Next())
    {
      const TopoDS_Wire& W = TopoDS::Wire(wx.Current());
      std::vector<Run> runs;
      std::vector<TopoDS_Edge> degenerate;
      std::vector<double> spanLengths;
      for (BRepTools_WireExplorer we(W, F); we.More(); we.Next())
      {
        const TopoDS_Edge& E = we.Current();
        const int e = d.EdgeMap.FindIndex(E) - 1;
        const EdgeSampling& es = d.Edges[e];
        double a, b;
        Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(E, F, a, b);
        if (pc.IsNull())
        {
          this->ErrorMessage = "edge " + std::to_string(e) + " has no pcurve on face " + std::to_string(f);
          return false;
        }
        const bool reversed = E.Orientation() == TopAbs_REVERSED;
        Run run;
        run.Tolerance = BRep_Tool::Tolerance(we.CurrentVertex());
        if (es.Degenerate)
        {
          // A pole: one 3D point, a segment in the parameter plane. Its sample count is fixed
          // below from the face's other spans, so that the pole triangles are not slivers.
          for (const double t : { reversed ? b : a, reversed ? a : b })
          {
            const gp_Pnt2d q = pc->Value(t);
            run.Nodes.push_back({ { sign * q.X(), q.Y() }, es.Vertex0 });
          }
          LoopSegment seg;
          seg.Edge = e;
          seg.Degenerate = true;
          seg.Near0 = seg.Near1 = this->NodePoints[es.Vertex0];
          run.Segments.push_back(seg);
          runs.push_back(run);
          continue;
        }
        const std::size_t n = es.T.size();
        for (std::size_t i = 0; i < n; ++i)
        {
          const std::size_t k = reversed ? n - 1 - i : i;
          const gp_Pnt2d q = pc->Value(es.T[k]);
          LoopNode node{ { sign * q.X(), q.Y() }, es.Nodes[k] };
          run.Nodes.push_back(node);
          const double gap = Distance(surfaceAt(node.UV), this->NodePoints[node.GlobalNode]);
          face.MaxGap = std::max(face.MaxGap, gap);
          if (i + 1 < n)
          {
            const std::size_t span = reversed ? k - 1 : k;
            LoopSegment seg;
            seg.Edge = e;
            seg.Span = static_cast<Id>(span);
            seg.Near0 = es.Inner[span][reversed ? 1 : 0];
            seg.Near1 = es.Inner[span][reversed ? 0 : 1];
            run.Segments.push_back(seg);
          }
        }
        for (std::size_t i = 0; i + 1 < n; ++i)
        {
          spanLengths.push_back(std::hypot(run.Nodes[i + 1].UV[0] - run.Nodes[i].UV[0],
            run.Nodes[i + 1].UV[1] - run.Nodes[i].UV[1]));
        }
        runs.push_back(run);
      }
      if (runs.empty())
      {
        continue;
      }
      // Subdivide the pole segments to the median parameter-space span of the other edges.
      double median = 0;
      if (!spanLengths.empty())
      {
        std::nth_element(spanLengths.begin(), spanLengths.begin() + spanLengths.size() / 2, spanLengths.end());
        median = spanLengths[spanLengths.size() / 2];
      }
      for (Run& run : runs)
      {
        if (run.Segments.size() != 1 || !run.Segments[0].Degenerate || median <= 0)
        {
          continue;
        }
        const LoopNode a = run.Nodes[0], b = run.Nodes[1];
        const double len = std::hypot(b.UV[0] - a.UV[0], b.UV[1] - a.UV[1]);
        const int m = std::max(1, std::min(1024, static_cast<int>(std::ceil(len / median))));
        run.Nodes.clear();
        for (int i = 0; i <= m; ++i)
        {
          const double s = static_cast<double>(i) / m;
          run.Nodes.push_back({ { (1 - s) * a.UV[0] + s * b.UV[0], (1 - s) * a.UV[1] + s * b.UV[1] }, a.GlobalNode });
        }
        run.Segments.assign(m, run.Segments[0]);
      }
      // Join the runs: a run's last node and the next run's first are the same B-rep vertex;
      // pcurve ends within the vertex tolerance (in 3D) are merged at their mean, farther ones
      // (a jump across a seam) stay apart, joined by a degenerate segment.
      FaceLoop loop;
      const std::size_t nr = runs.size();
      for (std::size_t r = 0; r < nr; ++r)
      {
        Run& cur = runs[r];
        const Run& nxt = runs[(r + 1) % nr];
        loop.Nodes.insert(loop.Nodes.end(), cur.Nodes.begin(), cur.Nodes.end() - 1);
        loop.Segments.insert(loop.Segments.end(), cur.Segments.begin(), cur.Segments.end());
        const LoopNode& end = cur.Nodes.back();
        const LoopNode& begin = nxt.Nodes.front();
        const double uvGap = std::hypot(end.UV[0] - begin.UV[0], end.UV[1] - begin.UV[1]);
        const double gap3 = Distance(surfaceAt(end.UV), surfaceAt(begin.UV));
        const bool merge = end.GlobalNode == begin.GlobalNode &&
          (uvGap == 0 || gap3 <= std::max(2 * nxt.Tolerance, tol));
        // Same point in 3D, half a period or more apart in the plane: the wire goes round a
        // closed surface, and without a seam edge the face's loops are open (its domain would
        // come out empty).
        const BRepAdaptor_Surface& S = d.Surfaces[f];
        const double du = std::abs(end.UV[0] - begin.UV[0]), dv = std::abs(end.UV[1] - begin.UV[1]);
        const double uRange = S.IsUPeriodic() ? S.UPeriod() : S.LastUParameter() - S.FirstUParameter();
        const double vRange = S.IsVPeriodic() ? S.VPeriod() : S.LastVParameter() - S.FirstVParameter();
        if (merge && uvGap > 0 &&
          ((S.IsUClosed() && du >= 0.5 * uRange) || (S.IsVClosed() && dv >= 0.5 * vRange)))
        {
          this->ErrorMessage = "face " + std::to_string(f) + " (" + face.Name +
            "): a wire closed in 3D is open in the parameter plane (a closed surface without a seam edge)";
          return false;
        }
        if (merge)
        {
          // Node shared with the next run: its first node becomes the mean.
          LoopNode& head = runs[(r + 1) % nr].Nodes.front();
          head.UV[0] = 0.5 * (end.UV[0] + head.UV[0]);
          head.UV[1] = 0.5 * (end.UV[1] + head.UV[1]);
        }
        else
        {
          loop.Nodes.push_back(end);
          LoopSegment seg;
          seg.Degenerate = end.GlobalNode == begin.GlobalNode;
          const Point3& pa = this->NodePoints[end.GlobalNode];
          const Point3& pb = this->NodePoints[begin.GlobalNode];
          for (int i = 0; i < 3; ++i)
          {
            seg.Near0[i] = (2 * pa[i] + pb[i]) / 3;
            seg.Near1[i] = (pa[i] + 2 * pb[i]) / 3;
          }
          loop.Segments.push_back(seg);
        }
      }
      // The first run's head may have been moved by the last join: it is loop node 0.
      loop.Nodes[0] = runs[0].Nodes.front();
      face.Loops.push_back(std::move(loop));
    }
    this->EdgeGap = std::max(this->EdgeGap, face.MaxGap);
  }
  this->Time.Loops = Seconds(start);

  // 3. Smooth interfaces, and their tangent planes in the stitching data (RestoreG1).
  start = Clock::now();
  TangentPlaneOptions planes;
  planes.RestoreG1 = options.RestoreG1;
  planes.G1Threshold = options.G1Threshold;
  const TangentPlaneReport report = SetInterfaceTangentPlanes(this->FaceList, this->NodePoints,
    [this](int f, double s, double t, double* P, double* Ds, double* Dt) { this->Evaluate(f, s, t, P, Ds, Dt); },
    planes);
  this->Changed = { report.MaxCurveChange, report.MaxDerivativeChange, report.SmoothNodes, report.SmoothSpans };
  this->Time.TangentPlanes = Seconds(start);
  return true;
}

} // namespace ctcad
