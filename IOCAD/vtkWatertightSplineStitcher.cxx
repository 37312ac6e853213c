// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkWatertightSplineStitcher.h"

#include "CADArrayNames.h"
#include "CADFaceMesher.h"
#include "CADStitchedConstruction.h"

#include "vtkCADFaceSampler.h"
#include "vtkCloughTocherSplineFilter.h"
#include "CloughTocherSpline.h"

#include "BezierTriangle.h"
#include "CubicCloughTocher.h"
#include "CubicMacroElement.h"
#include "SplitPoint.h"

#include <Eigen/Geometry> // cross products

#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkExecutive.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMath.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSignedCharArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <chrono>
#include <cmath>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

vtkStandardNewMacro(vtkWatertightSplineStitcher);
vtkCxxSetObjectMacro(vtkWatertightSplineStitcher, SurfaceSource, vtkCADFaceSampler);

namespace
{
using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a)
{
  return std::chrono::duration<double>(Clock::now() - a).count();
}

void AddField(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}

ctk::Vec3 Cubic(const ctk::Vec3& a, const ctk::Vec3& b, const ctk::Vec3& c, const ctk::Vec3& d, double s)
{
  const double r = 1 - s;
  return r * r * r * a + 3 * r * r * s * b + 3 * r * s * s * c + s * s * s * d;
}

/// One side of an interface: the boundary cubic of a face, oriented from the lower node id.
struct Side
{
  std::array<ctk::Vec3, 4> P;
  /// Unit normals of the face's boundary micro-triangle at the G1 sample points, from the lower
  /// node id (zero where the surface is degenerate, at poles).
  std::array<ctk::Vec3, 9> Normal;
};

/// Unit normals of the boundary micro-triangle of macro-triangle t at its local edge l, at the
/// edge points s = (k + 1/2) / 9, k = 0..8, from the edge's end with the lower node id.
std::array<ctk::Vec3, 9> EdgeNormals(const ctk::MacroElementIds& ids, const std::vector<ctk::Vec3>& P,
  int l, bool fromFirst)
{
  // Micro-triangle k = l + 2 spans (U_l, U_{l+1}, Z), counter-clockwise like its macro-triangle,
  // so the normal points out of the solid (the faces' parameter planes are oriented so).
  const std::array<ctk::Id, 10> net = ctk::MicroTriangleNet(ids, (l + 2) % 3);
  ctk::Vec3 Q[10];
  for (int i = 0; i < 10; ++i)
  {
    Q[i] = P[net[i]];
  }
  std::array<ctk::Vec3, 9> normals;
  for (int k = 0; k < 9; ++k)
  {
    // Interior points only: at the edge's ends the surface may be degenerate (poles, apices).
    const double s = fromFirst ? (k + 0.5) / 9 : 1 - (k + 0.5) / 9;
    normals[k] = ctk::PatchNormal(3, Q, nullptr, ctk::Vec3(1 - s, s, 0));
  }
  return normals;
}
// Per face: the cubic spline points (layout order), ids, and what the merge needs.
struct FaceSpline
{
  vtkSmartPointer<vtkUnstructuredGrid> Grid;
  ctk::CubicSpline Spline; // the face's spline read back from Grid (layout order)
  std::vector<ctk::Id> Triangles;
  ctk::MeshTopology Topo;
  vtkIdTypeArray* Gid = nullptr;
  vtkDataArray* UV = nullptr;
  vtkDataArray* Tangent = nullptr;
  vtkDataArray* BRepEdge = nullptr; // the sampler's BRepEdgeId: per local edge, -1 inside
};

/// A boundary macro-edge's identity across faces: its B-rep edge and its end nodes (two B-rep
/// edges, an arc and its chord, can join the same two nodes).
using SpanKey = std::array<vtkIdType, 3>;

/// A macro-edge of the merged grid: the merged ids of its cubic's control points, from its end
/// with the lower (first point, first inner point). Two macro-edges are one only if they share
/// all four: at a pole, the interior macro-edges from two copies of the pole node to one mesh
/// point join the same two nodes but are different curves.
std::array<vtkIdType, 4> MergedEdgeKey(vtkIdType a, vtkIdType ta, vtkIdType tb, vtkIdType b)
{
  return std::make_pair(b, tb) < std::make_pair(a, ta) ? std::array<vtkIdType, 4>{ b, tb, ta, a }
                                                       : std::array<vtkIdType, 4>{ a, ta, tb, b };
}

// Deviation from the CAD surfaces, positions and normals, at every point of the DeviationLevel
// lattice of every micro-triangle (its interior, the macro-edges, shared or not, the inner edges)
// and DeviationSamples pseudo-random points per macro-triangle.
/// The deviation of face f's spline at its lattice points and `samples` pseudo-random points
/// per macro-triangle (a stream of the face's own, so that faces can be measured in parallel).
bool MeasureFace(vtkCADFaceSampler* source, int level, int samples, const FaceSpline& fs, int f,
  ctcad::Deviation& face, std::string& error)
{
  std::uint64_t state = 0x2545F4914F6CDD1DULL ^ (0x9E3779B97F4A7C15ULL * (f + 1));
  auto uniform = [&state]() {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return static_cast<double>(state >> 11) * (1.0 / 9007199254740992.0);
  };
  std::string failure;
  const ctcad::SurfaceFunction surface = [&](double s, double t, double* P, double* Ds,
                                           double* Dt) {
    if (!source->EvaluateSurface(f, s, t, P, Ds, Dt, failure))
    {
      P[0] = std::nan("");
    }
  };
  std::vector<ctk::Vec3> points;
  for (ctk::Id t = 0; t < fs.Spline.Layout.NumberOfTriangles; ++t)
  {
    ctcad::DeviationPoints(fs.Spline.SplitTau[t], level, { false, false, false }, points);
    for (int r = 0; r < samples; ++r)
    {
      double a = uniform(), b = uniform();
      if (a + b > 1)
      {
        a = 1 - a;
        b = 1 - b;
      }
      points.emplace_back(1 - a - b, a, b);
    }
    if (!ctcad::MeasureTriangle(
          fs.Spline, fs.Topo, fs.Triangles.data(), t, points, surface, true, face, error))
    {
      error = "deviation from the CAD surfaces, face " + std::to_string(f) + ": " +
        (failure.empty() ? error : failure);
      return false;
    }
  }
  return true;
}

/// MeasureFace on every face, faces in parallel (each evaluates only its own surface); the
/// maxima go into each face's block and, with the RMS values, into fd.
bool MeasureDeviation(vtkCADFaceSampler* source, int level, int samples,
  const std::vector<FaceSpline>& splines, vtkFieldData* fd, std::string& error)
{
  const int nF = static_cast<int>(splines.size());
  std::vector<ctcad::Deviation> faces(nF);
  std::vector<std::string> errors(nF);
  std::vector<char> ok(nF, 0);
  ctcad::ForEachFaceInParallel(nF, [&](int f) {
    ok[f] = MeasureFace(source, level, samples, splines[f], f, faces[f], errors[f]);
  });
  const double diag = source->GetDiagonal();
  ctcad::Deviation all;
  for (int f = 0; f < nF; ++f)
  {
    if (!ok[f])
    {
      error = errors[f];
      return false;
    }
    AddField(splines[f].Grid->GetFieldData(), "MaxDeviation", faces[f].MaxDistance / diag);
    AddField(splines[f].Grid->GetFieldData(), "MaxNormalDeviation", faces[f].MaxAngle);
    all.Add(faces[f]);
  }
  AddField(fd, "MaxDeviation", all.MaxDistance / diag);
  AddField(
    fd, "RMSDeviation", all.Count ? std::sqrt(all.SumSquaredDistance / all.Count) / diag : 0.0);
  AddField(fd, "MaxNormalDeviation", all.MaxAngle);
  AddField(fd, "RMSNormalDeviation",
    all.AngleCount ? std::sqrt(all.SumSquaredAngle / all.AngleCount) : 0.0);
  return true;
}

} // namespace

vtkWatertightSplineStitcher::vtkWatertightSplineStitcher()
{
  this->SetNumberOfOutputPorts(2);
}

vtkWatertightSplineStitcher::~vtkWatertightSplineStitcher()
{
  this->SetSurfaceSource(nullptr);
}

int vtkWatertightSplineStitcher::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkMultiBlockDataSet");
  return 1;
}

int vtkWatertightSplineStitcher::FillOutputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkDataObject::DATA_TYPE_NAME(), port == 0 ? "vtkMultiBlockDataSet" : "vtkUnstructuredGrid");
  return 1;
}

int vtkWatertightSplineStitcher::RequestDataObject(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  if (!vtkMultiBlockDataSet::GetData(outputVector, 0))
  {
    vtkNew<vtkMultiBlockDataSet> mb;
    outputVector->GetInformationObject(0)->Set(vtkDataObject::DATA_OBJECT(), mb);
  }
  if (!vtkUnstructuredGrid::GetData(outputVector, 1))
  {
    vtkNew<vtkUnstructuredGrid> ug;
    outputVector->GetInformationObject(1)->Set(vtkDataObject::DATA_OBJECT(), ug);
  }
  return 1;
}

int vtkWatertightSplineStitcher::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMultiBlockDataSet* input = vtkMultiBlockDataSet::GetData(inputVector[0], 0);
  vtkMultiBlockDataSet* faces = vtkMultiBlockDataSet::GetData(outputVector, 0);
  vtkUnstructuredGrid* merged = vtkUnstructuredGrid::GetData(outputVector, 1);
  const unsigned int nF = input->GetNumberOfBlocks();
  faces->SetNumberOfBlocks(nF);

  ctk::SplineOptions options;
  options.Method = static_cast<ctk::Construction>(this->Construction);
  options.SplitPoint = static_cast<ctk::SplitPointRule>(this->SplitPoint);
  options.Boundary = static_cast<ctk::BoundaryMode>(this->BoundaryMode);

  // The sampler refines the faces for one spline (without IM steps); another one may exceed its
  // tolerance.
  vtkFieldData* sampled = input->GetFieldData();
  vtkDataArray* refined = sampled->GetArray(ctcad::names::RefinedConstruction);
  if (refined && refined->GetTuple1(0) >= 0)
  {
    auto value = [&](const char* name, int fallback) {
      vtkDataArray* a = sampled->GetArray(name);
      return a ? static_cast<int>(a->GetTuple1(0)) : fallback;
    };
    ctk::SplineOptions theirs;
    theirs.Method = static_cast<ctk::Construction>(refined->GetTuple1(0));
    theirs.SplitPoint = static_cast<ctk::SplitPointRule>(value(ctcad::names::RefinedSplitPoint, this->SplitPoint));
    theirs.Boundary = static_cast<ctk::BoundaryMode>(value(ctcad::names::RefinedBoundaryMode, this->BoundaryMode));
    if (theirs.Method != options.Method || theirs.SplitPoint != options.SplitPoint ||
      ctk::EffectiveBoundaryMode(theirs) != ctk::EffectiveBoundaryMode(options))
    {
      vtkWarningMacro(<< "the faces were refined for another spline (" << ctk::ToString(theirs.Method)
                      << ", split point " << static_cast<int>(theirs.SplitPoint) << ", boundary "
                      << ctk::ToString(ctk::EffectiveBoundaryMode(theirs)) << "; here "
                      << ctk::ToString(options.Method) << ", " << static_cast<int>(options.SplitPoint)
                      << ", " << ctk::ToString(ctk::EffectiveBoundaryMode(options))
                      << "): the deviation may exceed the sampler's tolerance");
    }
    else if (this->Iterations > 0)
    {
      vtkWarningMacro(<< "the faces were refined for the spline without IM steps; with "
                      << this->Iterations << " the deviation may exceed the sampler's tolerance");
    }
  }
  double splineTime = 0, stitchTime = 0;
  double gapBefore = 0;
  std::vector<FaceSpline> splines(nF);
  for (unsigned int f = 0; f < nF; ++f)
  {
    vtkPolyData* block = vtkPolyData::SafeDownCast(input->GetBlock(f));
    FaceSpline& fs = splines[f];
    if (!block)
    {
      vtkErrorMacro(<< "block " << f << " is not a vtkPolyData");
      return 0;
    }
    // vtkCADFaceSampler's arrays (the spline filter checks the sizes of those it reads).
    for (const char* name : { ctcad::names::GlobalNodeId, ctcad::names::UV, ctcad::names::Du, ctcad::names::Dv, ctcad::names::StitchDu,
           ctcad::names::StitchDv })
    {
      if (!block->GetPointData()->GetArray(name))
      {
        vtkErrorMacro(<< "block " << f << " has no point data array '" << name
                      << "' (the input must come from vtkCADFaceSampler)");
        return 0;
      }
    }
    for (const char* name : { ctcad::names::EdgeCurvePoints, ctcad::names::StitchEdgeGradients,
           ctcad::names::BRepEdgeId })
    {
      if (!block->GetCellData()->GetArray(name))
      {
        vtkErrorMacro(<< "block " << f << " has no cell data array '" << name
                      << "' (the input must come from vtkCADFaceSampler)");
        return 0;
      }
    }
    fs.Gid = vtkIdTypeArray::SafeDownCast(block->GetPointData()->GetArray(ctcad::names::GlobalNodeId));
    if (!fs.Gid)
    {
      vtkErrorMacro(<< "block " << f << ": point data array 'GlobalNodeId' is not a vtkIdTypeArray");
      return 0;
    }
    fs.BRepEdge = block->GetCellData()->GetArray(ctcad::names::BRepEdgeId);
    if (fs.BRepEdge->GetNumberOfComponents() != 3 ||
      fs.BRepEdge->GetNumberOfTuples() != block->GetNumberOfCells())
    {
      vtkErrorMacro(<< "block " << f << ": cell data array 'BRepEdgeId' has "
                    << fs.BRepEdge->GetNumberOfTuples() << " tuples of "
                    << fs.BRepEdge->GetNumberOfComponents() << " components, not "
                    << block->GetNumberOfCells() << " of 3");
      return 0;
    }
    vtkDataArray* curve = block->GetCellData()->GetArray(ctcad::names::EdgeCurvePoints);
    vtkDataArray* du = block->GetPointData()->GetArray(ctcad::names::Du);
    vtkDataArray* dv = block->GetPointData()->GetArray(ctcad::names::Dv);
    fs.UV = block->GetPointData()->GetArray(ctcad::names::UV);
    fs.Tangent = block->GetCellData()->GetArray(ctcad::names::TangentInterface);
    auto start = Clock::now();
    vtkNew<vtkCloughTocherSplineFilter> ct;
    ct->SetInputData(block);
    ct->SetConstruction(this->Construction);
    ct->SetSplitPoint(this->SplitPoint);
    ct->SetBoundaryMode(this->BoundaryMode);
    ct->SetIterations(this->Iterations);
    // Stitching: every face follows the shared B-rep edge cubics on its boundary.
    ct->SetBoundaryCurvePointsArrayName(ctcad::names::EdgeCurvePoints);
    ct->SetDuArrayName(ctcad::names::StitchDu);
    ct->SetDvArrayName(ctcad::names::StitchDv);
    ct->SetEdgeGradientsArrayName(ctcad::names::StitchEdgeGradients);
    // The face's own error (e.g. a degenerate parameter triangle) goes into this filter's message.
    std::string faceError;
    vtkNew<vtkCallbackCommand> onError;
    onError->SetClientData(&faceError);
    onError->SetCallback([](vtkObject*, unsigned long, void* clientData, void* message) {
      *static_cast<std::string*>(clientData) += static_cast<const char*>(message);
    });
    ct->AddObserver(vtkCommand::ErrorEvent, onError);
    ct->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, onError);
    ct->Update();
    fs.Grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
    fs.Grid->DeepCopy(ct->GetOutput());
    if (fs.Grid->GetNumberOfCells() == 0)
    {
      vtkErrorMacro(<< "face " << f << ": spline construction failed: " << faceError);
      return 0;
    }
    splineTime += Seconds(start);

    // The filter's output points are in the kernel's layout order.
    start = Clock::now();
    const ctk::Id nV = block->GetNumberOfPoints(), nT = block->GetNumberOfCells();
    fs.Triangles.resize(3 * nT);
    vtkCellArray* polys = block->GetPolys();
    for (ctk::Id t = 0; t < nT; ++t)
    {
      vtkIdType n;
      const vtkIdType* pts;
      polys->GetCellAtId(t, n, pts);
      std::copy_n(pts, 3, fs.Triangles.data() + 3 * t);
    }
    ctk::BuildMeshTopology(nV, nT, fs.Triangles.data(), fs.Topo);
    fs.Spline.Layout = { nV, static_cast<ctk::Id>(fs.Topo.Edges.size()), nT };
    vtkPoints* pts = fs.Grid->GetPoints();
    fs.Spline.ControlPoints.resize(pts->GetNumberOfPoints());
    for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
    {
      pts->GetPoint(i, fs.Spline.ControlPoints[i].data());
    }
    auto uvOf = [&](ctk::Id v) { return ctk::Vec2(fs.UV->GetComponent(v, 0), fs.UV->GetComponent(v, 1)); };
    // The face's UV is the sampler's, per vertex: the vertices' domain points are all that
    // EvaluateSpline reads.
    fs.Spline.DomainPoints.resize(nV);
    for (ctk::Id v = 0; v < nV; ++v)
    {
      fs.Spline.DomainPoints[v] = uvOf(v);
    }
    auto row = [](vtkDataArray* a, ctk::Id v) { return ctk::Vec3(a->GetComponent(v, 0), a->GetComponent(v, 1), a->GetComponent(v, 2)); };
    fs.Spline.SplitTau.resize(nT);
    for (ctk::Id t = 0; t < nT; ++t)
    {
      const ctk::Id* tri = fs.Triangles.data() + 3 * t;
      fs.Spline.SplitTau[t] = ctk::SplitPointBarycentric(options.SplitPoint, uvOf(tri[0]), uvOf(tri[1]),
        uvOf(tri[2]), fs.Spline.ControlPoints[tri[0]], fs.Spline.ControlPoints[tri[1]], fs.Spline.ControlPoints[tri[2]]);
      // How far each face's own boundary cubic (eq. 11 from its vertex derivatives) was from
      // the shared edge cubic it now follows.
      double c[18];
      curve->GetTuple(t, c);
      for (int l = 0; l < 3; ++l)
      {
        if (std::isnan(c[6 * l]) || fs.Topo.Neighbor(t, l) >= 0)
        {
          continue;
        }
        const ctk::Id a = tri[l], b = tri[(l + 1) % 3];
        const ctk::Vec3 va = fs.Spline.ControlPoints[a], vb = fs.Spline.ControlPoints[b];
        const ctk::Vec3 ta = ctk::EdgeControlPoint(va, row(du, a), row(dv, a), uvOf(a), uvOf(b));
        const ctk::Vec3 tb = ctk::EdgeControlPoint(vb, row(du, b), row(dv, b), uvOf(b), uvOf(a));
        const ctk::Vec3 near0(c[6 * l], c[6 * l + 1], c[6 * l + 2]);
        const ctk::Vec3 near1(c[6 * l + 3], c[6 * l + 4], c[6 * l + 5]);
        for (const double s : { 0.25, 0.5, 0.75 })
        {
          gapBefore = std::max(gapBefore, (Cubic(va, ta, tb, vb, s) - Cubic(va, near0, near1, vb, s)).norm());
        }
      }
    }
    stitchTime += Seconds(start);
    faces->SetBlock(f, fs.Grid);
    if (input->HasMetaData(f) && input->GetMetaData(f)->Has(vtkCompositeDataSet::NAME()))
    {
      faces->GetMetaData(f)->Set(vtkCompositeDataSet::NAME(), input->GetMetaData(f)->Get(vtkCompositeDataSet::NAME()));
    }
  }

  // Merge: V points by GlobalNodeId, boundary T points by (B-rep edge, near node, far node),
  // the rest apart.
  Clock::time_point start = Clock::now();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  std::unordered_map<vtkIdType, vtkIdType> nodePoint;
  std::map<SpanKey, vtkIdType> edgePoint;
  std::map<std::array<vtkIdType, 4>, int> macroEdgeUse;
  std::map<SpanKey, Side> firstSide;
  double maxC0Gap = 0;
  // G1 angles over interface macro-edges: [0] feature edges, [1] tangent interfaces (the CAD
  // faces meet tangentially there: the sampler's TangentInterface).
  struct AngleSummary
  {
    double Max = 0, Sum = 0;
    vtkIdType Count = 0;
  } G1[2];
  vtkNew<vtkCellArray> cells;
  vtkNew<vtkIdTypeArray> faceIds, macroIds;
  faceIds->SetName("FaceId");
  macroIds->SetName("MacroTriangleId");
  vtkNew<vtkSignedCharArray> microIds;
  microIds->SetName("MicroTriangleId");
  vtkIdType macroTriangles = 0;
  for (unsigned int f = 0; f < nF; ++f)
  {
    FaceSpline& fs = splines[f];
    const ctk::Id nV = fs.Spline.Layout.NumberOfVertices;
    std::vector<vtkIdType> map(fs.Spline.ControlPoints.size(), -1);
    auto gid = [&](ctk::Id v) { return fs.Gid->GetValue(v); };
    for (ctk::Id v = 0; v < nV; ++v)
    {
      auto it = nodePoint.emplace(gid(v), points->GetNumberOfPoints());
      if (it.second)
      {
        points->InsertNextPoint(fs.Spline.ControlPoints[v].data());
      }
      map[v] = it.first->second;
    }
    const auto& cp = fs.Spline.ControlPoints;
    // A macro-edge whose cubic is one point (a pole segment, a joint across a seam's ends) is
    // no edge of the surface: it neither closes nor opens it.
    auto collapsed = [&](ctk::Id a, ctk::Id ta, ctk::Id tb, ctk::Id b) {
      return cp[ta] == cp[a] && cp[tb] == cp[a] && cp[b] == cp[a];
    };
    for (ctk::Id e = 0; e < static_cast<ctk::Id>(fs.Topo.Edges.size()); ++e)
    {
      if (!fs.Topo.IsBoundaryEdge(e))
      {
        continue;
      }
      const ctk::Id a = fs.Topo.Edges[e][0], b = fs.Topo.Edges[e][1];
      const ctk::Id t = fs.Topo.EdgeTriangles[e][0];
      const int l = fs.Topo.EdgeLocalIndex[e][0];
      const auto brep = static_cast<vtkIdType>(fs.BRepEdge->GetComponent(t, l));
      const SpanKey key{ brep, std::min(gid(a), gid(b)), std::max(gid(a), gid(b)) };
      const ctk::Id ta = fs.Spline.Layout.EdgePoint(fs.Topo, e, a), tb = fs.Spline.Layout.EdgePoint(fs.Topo, e, b);
      for (const auto& nearFar : { std::make_pair(a, b), std::make_pair(b, a) })
      {
        const ctk::Id id = nearFar.first == a ? ta : tb;
        auto it = edgePoint.emplace(
          SpanKey{ brep, gid(nearFar.first), gid(nearFar.second) }, points->GetNumberOfPoints());
        if (it.second)
        {
          points->InsertNextPoint(fs.Spline.ControlPoints[id].data());
        }
        map[id] = it.first->second;
      }
      if (collapsed(a, ta, tb, b))
      {
        continue;
      }
      // The C0 gap and the G1 angle, from this face's own control points against the first
      // side seen.
      const bool forward = gid(a) <= gid(b);
      const ctk::MacroElementIds ids = ctk::GetMacroElementIds(fs.Spline.Layout, fs.Topo, fs.Triangles.data(), t);
      const bool fromFirst = gid(fs.Triangles[3 * t + l]) <= gid(fs.Triangles[3 * t + (l + 1) % 3]);
      const Side side{ { forward ? fs.Spline.ControlPoints[a] : fs.Spline.ControlPoints[b], forward ? fs.Spline.ControlPoints[ta] : fs.Spline.ControlPoints[tb],
                         forward ? fs.Spline.ControlPoints[tb] : fs.Spline.ControlPoints[ta], forward ? fs.Spline.ControlPoints[b] : fs.Spline.ControlPoints[a] },
        EdgeNormals(ids, fs.Spline.ControlPoints, l, fromFirst) };
      auto first = firstSide.emplace(key, side);
      if (!first.second)
      {
        const Side& o = first.first->second;
        for (const double s : { 0.0, 0.25, 0.5, 0.75, 1.0 })
        {
          maxC0Gap = std::max(maxC0Gap,
            (Cubic(o.P[0], o.P[1], o.P[2], o.P[3], s) - Cubic(side.P[0], side.P[1], side.P[2], side.P[3], s)).norm());
        }
        double angle = 0;
        for (int k = 0; k < 9; ++k)
        {
          if (o.Normal[k].squaredNorm() > 0 && side.Normal[k].squaredNorm() > 0)
          {
            angle = std::max(angle,
              std::atan2(o.Normal[k].cross(side.Normal[k]).norm(), o.Normal[k].dot(side.Normal[k])));
          }
        }
        angle *= 180 / vtkMath::Pi();
        const bool tangent = fs.Tangent && fs.Tangent->GetComponent(t, l) > 0;
        G1[tangent].Max = std::max(G1[tangent].Max, angle);
        G1[tangent].Sum += angle;
        ++G1[tangent].Count;
      }
    }
    for (std::size_t i = 0; i < map.size(); ++i)
    {
      if (map[i] < 0)
      {
        map[i] = points->InsertNextPoint(fs.Spline.ControlPoints[i].data());
      }
    }
    // Free and non-manifold edges are counted on the merged grid itself: a macro-edge is used
    // by its face's triangles at it, and by other faces' only where they share its points.
    for (ctk::Id e = 0; e < static_cast<ctk::Id>(fs.Topo.Edges.size()); ++e)
    {
      const ctk::Id a = fs.Topo.Edges[e][0], b = fs.Topo.Edges[e][1];
      const ctk::Id ta = fs.Spline.Layout.EdgePoint(fs.Topo, e, a);
      const ctk::Id tb = fs.Spline.Layout.EdgePoint(fs.Topo, e, b);
      if (!collapsed(a, ta, tb, b))
      {
        const auto key = MergedEdgeKey(map[a], map[ta], map[tb], map[b]);
        macroEdgeUse[key] += fs.Topo.IsBoundaryEdge(e) ? 1 : 2;
      }
    }
    vtkUnstructuredGrid* grid = fs.Grid;
    vtkDataArray* macro = grid->GetCellData()->GetArray("MacroTriangleId");
    vtkDataArray* micro = grid->GetCellData()->GetArray("MicroTriangleId");
    for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c)
    {
      vtkIdType n;
      const vtkIdType* ids;
      grid->GetCellPoints(c, n, ids);
      std::vector<vtkIdType> out(n);
      for (vtkIdType k = 0; k < n; ++k)
      {
        out[k] = map[ids[k]];
      }
      cells->InsertNextCell(n, out.data());
      faceIds->InsertNextValue(f);
      macroIds->InsertNextValue(static_cast<vtkIdType>(macro->GetTuple1(c)));
      microIds->InsertNextValue(static_cast<signed char>(micro->GetTuple1(c)));
    }
    macroTriangles += fs.Spline.Layout.NumberOfTriangles;
  }
  vtkIdType freeEdges = 0, nonManifold = 0;
  for (const auto& use : macroEdgeUse)
  {
    freeEdges += use.second == 1;
    nonManifold += use.second > 2;
  }
  merged->SetPoints(points);
  merged->SetCells(VTK_BEZIER_TRIANGLE, cells);
  merged->GetCellData()->AddArray(faceIds);
  merged->GetCellData()->AddArray(macroIds);
  merged->GetCellData()->AddArray(microIds);
  const double mergeTime = Seconds(start);

  vtkFieldData* fd = merged->GetFieldData();
  AddField(fd, "NumberOfFreeEdges", static_cast<double>(freeEdges));
  AddField(fd, "NumberOfNonManifoldEdges", static_cast<double>(nonManifold));
  AddField(fd, "MaxC0Gap", maxC0Gap);
  AddField(fd, "MaxGapBeforeStitching", gapBefore);
  AddField(fd, "NumberOfMacroTriangles", static_cast<double>(macroTriangles));
  AddField(fd, "MaxG1Angle", std::max(G1[0].Max, G1[1].Max));
  AddField(fd, "NumberOfTangentInterfaceEdges", static_cast<double>(G1[1].Count));
  AddField(fd, "MaxG1AngleTangent", G1[1].Max);
  AddField(fd, "MeanG1AngleTangent", G1[1].Count ? G1[1].Sum / G1[1].Count : 0.0);

  start = Clock::now();
  std::string deviationError;
  if (this->SurfaceSource && this->SurfaceSource->GetDiagonal() > 0 &&
    !MeasureDeviation(this->SurfaceSource, this->DeviationLevel, this->DeviationSamples, splines,
      fd, deviationError))
  {
    vtkErrorMacro(<< deviationError);
    return 0;
  }
  vtkNew<vtkDoubleArray> times;
  times->SetName("StageTimes");
  for (const double v : { splineTime, stitchTime, mergeTime, Seconds(start) })
  {
    times->InsertNextValue(v);
  }
  fd->AddArray(times);
  return 1;
}

void vtkWatertightSplineStitcher::SetConstruction(int construction)
{
  ctcad::SetStitchedConstruction(this, this->Construction, construction);
}

void vtkWatertightSplineStitcher::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Construction: " << vtkCloughTocherSplineFilter::GetConstructionName(this->Construction) << "\n";
  os << indent << "SplitPoint: " << vtkCloughTocherSplineFilter::GetSplitPointName(this->SplitPoint) << "\n";
  os << indent << "BoundaryMode: " << vtkCloughTocherSplineFilter::GetBoundaryModeName(this->BoundaryMode) << "\n";
  os << indent << "Iterations: " << this->Iterations << "\n";
  os << indent << "DeviationLevel: " << this->DeviationLevel << "\n";
  os << indent << "DeviationSamples: " << this->DeviationSamples << "\n";
  os << indent << "SurfaceSource: " << this->SurfaceSource << "\n";
}
