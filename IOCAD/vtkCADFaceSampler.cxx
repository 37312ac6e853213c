// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkCADFaceSampler.h"

#include "CTSplinesArrayRanges.h"

#include "CADArrayNames.h"
#include "CADStitchedConstruction.h"

#include "CADBRepSampling.h"
#include "CADFaceMesher.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSignedCharArray.h"
#include "vtkStringArray.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

class vtkCADFaceSamplerInternals
{
public:
  std::unique_ptr<ctcad::CADModel> Model;   // of the last update that succeeded
  std::unique_ptr<ctcad::CADModel> Current; // during RequestData
  std::vector<ctcad::FaceMesh> Meshes;
  ctcad::FaceMeshOptions MeshOptions;
  std::string EvaluationError;
};

vtkStandardNewMacro(vtkCADFaceSampler);

namespace
{
vtkSmartPointer<vtkDoubleArray> NewArray(const char* name, int components, vtkIdType tuples)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(tuples);
  return a;
}

void AddField(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}

void AddIntField(vtkFieldData* fd, const char* name, vtkIdType value)
{
  vtkNew<vtkIdTypeArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}
} // namespace

vtkCADFaceSampler::vtkCADFaceSampler()
  : Internals(new vtkCADFaceSamplerInternals)
{
  this->SetNumberOfInputPorts(0);
}

vtkCADFaceSampler::~vtkCADFaceSampler() = default;

bool vtkCADFaceSampler::EvaluateSurface(int face, double s, double t, double p[3])
{
  double ds[3], dt[3];
  return this->EvaluateSurface(face, s, t, p, ds, dt);
}

bool vtkCADFaceSampler::EvaluateSurface(
  int face, double s, double t, double p[3], double ds[3], double dt[3])
{
  return this->EvaluateSurface(face, s, t, p, ds, dt, this->Internals->EvaluationError);
}

bool vtkCADFaceSampler::EvaluateSurface(
  int face, double s, double t, double p[3], double ds[3], double dt[3], std::string& error) const
{
  const ctcad::CADModel* model = this->Internals->Model.get();
  if (!model || face < 0 || face >= static_cast<int>(model->Faces().size()))
  {
    error = "no face " + std::to_string(face) + " in the sampled model";
    return false;
  }
  std::string failure;
  if (!ctcad::RunGuarded([&] { model->Evaluate(face, s, t, p, ds, dt); }, failure))
  {
    error = "face " + std::to_string(face) + " (" + model->Faces()[face].Name +
      "): OpenCASCADE's evaluation at (" + std::to_string(s) + ", " + std::to_string(t) +
      ") failed: " + failure;
    return false;
  }
  return true;
}

const char* vtkCADFaceSampler::GetEvaluationError()
{
  return this->Internals->EvaluationError.c_str();
}

double vtkCADFaceSampler::GetDiagonal()
{
  return this->Internals->Model ? this->Internals->Model->Diagonal() : 0.0;
}

int vtkCADFaceSampler::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkMultiBlockDataSet* output = vtkMultiBlockDataSet::GetData(outputVector, 0);
  if (this->FileName.empty())
  {
    vtkErrorMacro(<< "no FileName");
    return 0;
  }
  if (!this->ReadModel())
  {
    return 0;
  }
  const auto start = std::chrono::steady_clock::now();
  if (!this->MeshFaces())
  {
    return 0;
  }
  const double faceTime =
    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const int nF = static_cast<int>(this->Internals->Current->Faces().size());
  output->SetNumberOfBlocks(nF);
  for (int f = 0; f < nF; ++f)
  {
    if (!this->MakeFaceBlock(f, output))
    {
      return 0;
    }
  }
  this->AddModelFields(output, faceTime);
  this->Internals->Model = std::move(this->Internals->Current);
  this->Internals->Meshes.clear();
  if (this->CacheArrayRanges)
  {
    ctsplines::CacheRanges(output); // for ParaView's data information and colour maps
  }
  return 1;
}

bool vtkCADFaceSampler::ReadModel()
{
  auto& model = this->Internals->Current;
  model = std::make_unique<ctcad::CADModel>();
  ctcad::HealingOptions healing;
  healing.Sew = this->Sew;
  healing.Tolerance = this->Tolerance;
  const bool read = model->Read(this->FileName, this->ReadTimeout, healing);
  for (const std::string& w : model->Warnings())
  {
    vtkWarningMacro(<< this->FileName << ": " << w);
  }
  if (!read)
  {
    vtkErrorMacro(<< model->Error());
    return false;
  }
  ctcad::SamplingOptions sampling;
  sampling.Tolerance = this->Tolerance;
  sampling.AngularTolerance = this->AngularTolerance;
  sampling.MaxSpanLength = this->MaxEdgeLength;
  sampling.RestoreG1 = this->RestoreG1;
  sampling.G1Threshold = this->G1Threshold;
  const std::size_t readWarnings = model->Warnings().size();
  const bool sampled = model->Sample(sampling);
  for (std::size_t k = readWarnings; k < model->Warnings().size(); ++k)
  {
    vtkWarningMacro(<< this->FileName << ": " << model->Warnings()[k]);
  }
  if (!sampled)
  {
    vtkErrorMacro(<< this->FileName << ": " << model->Error());
    return false;
  }
  if (this->RestoreG1 && model->Changes().MaxCurveChange > 0.5 * this->Tolerance * model->Diagonal())
  {
    vtkWarningMacro(<< "RestoreG1 moved edge-cubic points by " << model->Changes().MaxCurveChange
                    << " (" << model->Changes().MaxCurveChange / model->Diagonal()
                    << " of the diagonal): interfaces within G1Threshold = " << this->G1Threshold
                    << " degrees are far from tangent; the deviation may exceed the tolerance");
  }
  return true;
}

bool vtkCADFaceSampler::MeshFaces()
{
  // Faces are independent once their loops exist: mesh them concurrently (each face evaluates
  // only its own surface adaptor, so no OCCT object is shared between threads).
  ctcad::CADModel* model = this->Internals->Current.get();
  const std::vector<ctcad::CADFace>& faces = model->Faces();
  const int nF = static_cast<int>(faces.size());
  std::vector<ctcad::FaceMesh>& meshes = this->Internals->Meshes;
  meshes.assign(nF, ctcad::FaceMesh());
  std::vector<char> ok(nF, 0);
  ctcad::FaceMeshOptions& meshOptions = this->Internals->MeshOptions;
  meshOptions.Tolerance = this->Tolerance * model->Diagonal();
  meshOptions.AngularTolerance = this->AngularTolerance;
  meshOptions.AspectRatio = this->AspectRatio;
  meshOptions.MaxEdgeLength = this->MaxEdgeLength * model->Diagonal();
  meshOptions.MaxRounds = this->MaxRounds;
  meshOptions.MaxTriangles = static_cast<long>(this->MaxTrianglesPerFace);
  meshOptions.CheckConstruction = this->RefineStitchedSpline;
  meshOptions.FallbackConstructions = this->FallbackConstructions;
  meshOptions.Spline.Method = static_cast<ctk::Construction>(this->Construction);
  meshOptions.Spline.SplitPoint = static_cast<ctk::SplitPointRule>(this->SplitPoint);
  meshOptions.Spline.Boundary = static_cast<ctk::BoundaryMode>(this->BoundaryMode);
  ctcad::ForEachFaceInParallel(nF, [&](int f) {
    const ctcad::SurfaceFunction surface = [&, f](double s, double t, double* P, double* Ds,
                                             double* Dt) { model->Evaluate(f, s, t, P, Ds, Dt); };
    // A face whose surface lies farther from the shared boundary than the tolerance (the
    // model's faces miss each other by more) cannot get within it next to the boundary:
    // refined to twice that distance instead (and said below), not without end.
    ctcad::FaceMeshOptions options = meshOptions;
    options.Tolerance = std::max(meshOptions.Tolerance, 2 * faces[f].MaxGap);
    // Nothing may escape a thread: OCCT's exceptions (and signals) and CGAL's end here.
    std::string failure;
    if (!ctcad::RunGuarded(
          [&] { ok[f] = ctcad::MeshFace(faces[f].Loops, model->Nodes(), surface, options, meshes[f]); },
          failure))
    {
      ok[f] = 0;
      meshes[f].Error = "evaluating its surface or triangulating failed: " + failure;
    }
  });
  for (int f = 0; f < nF; ++f)
  {
    if (!ok[f])
    {
      vtkErrorMacro(<< this->FileName << ": meshing face " << f << " (" << faces[f].Name
                    << "): " << meshes[f].Error);
      return false;
    }
  }
  return true;
}

/// Warnings on face f's mesh: the model's own gap, a fallback construction, or refinement
/// stopped short of the tolerances.
void vtkCADFaceSampler::WarnAboutFaceMesh(int f)
{
  const ctcad::CADModel* model = this->Internals->Current.get();
  const std::vector<ctcad::CADFace>& faces = model->Faces();
  const ctcad::FaceMesh& mesh = this->Internals->Meshes[f];
  if (2 * faces[f].MaxGap > this->Internals->MeshOptions.Tolerance)
  {
    vtkWarningMacro(<< "face " << f << " (" << faces[f].Name << "): its surface lies up to "
                    << faces[f].MaxGap / model->Diagonal()
                    << " of the diagonal from the boundary it shares with its neighbours (the model's"
                    << " own gap), more than half the tolerance: refined to "
                    << 2 * faces[f].MaxGap / model->Diagonal() << " instead");
  }
  if (mesh.FallbackConstruction >= 0)
  {
    std::ostringstream now; // what the fallback reached
    if (mesh.Converged)
    {
      now << "within the tolerance";
    }
    else
    {
      now << "estimated error " << mesh.MaxEstimatedError / model->Diagonal() << " of the diagonal";
    }
    vtkWarningMacro(<< "face " << f << " (" << faces[f].Name << "): "
                    << ctk::ToString(static_cast<ctk::Construction>(this->Construction))
                    << " stopped at estimated error " << mesh.ChosenError / model->Diagonal()
                    << " of the diagonal (" << mesh.ChosenStopReason << "); built with "
                    << ctk::ToString(static_cast<ctk::Construction>(mesh.FallbackConstruction))
                    << " instead: " << now.str());
  }
  else if (!mesh.Converged)
  {
    vtkWarningMacro(<< "face " << f << " (" << faces[f].Name << ") stopped refining at estimated error "
                    << mesh.MaxEstimatedError / model->Diagonal() << " of the diagonal"
                    << (this->AngularTolerance > 0
                           ? ", normal angle " + std::to_string(mesh.MaxEstimatedAngle) + " degrees"
                           : std::string())
                    << " after " << mesh.Rounds + mesh.CheckRounds << " rounds: "
                    << mesh.StopReason);
  }
}

bool vtkCADFaceSampler::MakeFaceBlock(int f, vtkMultiBlockDataSet* output)
{
  ctcad::CADModel* model = this->Internals->Current.get();
  const std::vector<ctcad::CADFace>& faces = model->Faces();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const ctcad::FaceMesh& mesh = this->Internals->Meshes[f];
  this->WarnAboutFaceMesh(f);
  const vtkIdType nP = static_cast<vtkIdType>(mesh.UV.size());
  const vtkIdType nT = static_cast<vtkIdType>(mesh.Triangles.size());
  vtkNew<vtkPolyData> pd;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(nP);
  auto uv = NewArray(ctcad::names::UV, 2, nP);
  auto du = NewArray(ctcad::names::Du, 3, nP);
  auto dv = NewArray(ctcad::names::Dv, 3, nP);
  auto stitchDu = NewArray(ctcad::names::StitchDu, 3, nP);
  auto stitchDv = NewArray(ctcad::names::StitchDv, 3, nP);
  vtkNew<vtkIdTypeArray> gid;
  gid->SetName(ctcad::names::GlobalNodeId);
  gid->SetNumberOfTuples(nP);
  for (vtkIdType p = 0; p < nP; ++p)
  {
    points->SetPoint(p, mesh.F[p].data());
    uv->SetTuple(p, mesh.UV[p].data());
    du->SetTuple(p, mesh.SurfaceFs[p].data());
    dv->SetTuple(p, mesh.SurfaceFt[p].data());
    stitchDu->SetTuple(p, mesh.Fs[p].data());
    stitchDv->SetTuple(p, mesh.Ft[p].data());
    // Interior points become model nodes of their own (one face each).
    gid->SetValue(p, mesh.GlobalNode[p] >= 0 ? mesh.GlobalNode[p] : model->AddNode(mesh.F[p]));
  }
  vtkNew<vtkCellArray> polys;
  auto edgeGradients = NewArray(ctcad::names::EdgeGradients, 18, nT);
  auto stitchGradients = NewArray(ctcad::names::StitchEdgeGradients, 18, nT);
  vtkNew<vtkSignedCharArray> tangent;
  tangent->SetName(ctcad::names::TangentInterface);
  tangent->SetNumberOfComponents(3);
  tangent->SetNumberOfTuples(nT);
  auto curvePoints = NewArray(ctcad::names::EdgeCurvePoints, 18, nT);
  vtkNew<vtkIdTypeArray> edgeIds;
  edgeIds->SetName(ctcad::names::BRepEdgeId);
  edgeIds->SetNumberOfComponents(3);
  edgeIds->SetNumberOfTuples(nT);
  // The exact mid-edge gradients: the only calls into OpenCASCADE here.
  std::string failure;
  const bool evaluated = ctcad::RunGuarded(
    [&] {
      for (vtkIdType t = 0; t < nT; ++t)
      {
        const std::array<ctcad::Id, 3>& tri = mesh.Triangles[t];
        const vtkIdType ids[3] = { tri[0], tri[1], tri[2] };
        polys->InsertNextCell(3, ids);
        double g[18], sg[18], c[18];
        for (int l = 0; l < 3; ++l)
        {
          const auto& a = mesh.UV[tri[l]];
          const auto& b = mesh.UV[tri[(l + 1) % 3]];
          double P[3];
          model->Evaluate(f, 0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), P, g + 6 * l, g + 6 * l + 3);
          const ctcad::LoopSegment* seg = mesh.Segments[t][l];
          edgeIds->SetTypedComponent(t, l, seg ? (seg->Edge >= 0 ? seg->Edge : -2) : -1);
          tangent->SetTypedComponent(t, l, seg ? (seg->Tangent ? 1 : 0) : -1);
          std::copy_n(g + 6 * l, 6, sg + 6 * l);
          if (seg)
          {
            ctcad::StitchEdgeGradient(*seg, sg + 6 * l);
          }
          for (int i = 0; i < 3; ++i)
          {
            const bool flip = mesh.SegmentFlipped[t][l];
            c[6 * l + i] = seg ? (flip ? seg->Near1 : seg->Near0)[i] : nan;
            c[6 * l + 3 + i] = seg ? (flip ? seg->Near0 : seg->Near1)[i] : nan;
          }
        }
        edgeGradients->SetTuple(t, g);
        stitchGradients->SetTuple(t, sg);
        curvePoints->SetTuple(t, c);
      }
    },
    failure);
  if (!evaluated)
  {
    vtkErrorMacro(<< "face " << f << " (" << faces[f].Name
                  << "): evaluating the surface derivatives at the triangle edges failed: " << failure);
    return false;
  }
  pd->SetPoints(points);
  pd->SetPolys(polys);
  pd->GetPointData()->AddArray(uv);
  pd->GetPointData()->AddArray(du);
  pd->GetPointData()->AddArray(dv);
  pd->GetPointData()->AddArray(stitchDu);
  pd->GetPointData()->AddArray(stitchDv);
  pd->GetPointData()->AddArray(gid);
  pd->GetCellData()->AddArray(edgeGradients);
  pd->GetCellData()->AddArray(stitchGradients);
  pd->GetCellData()->AddArray(tangent);
  pd->GetCellData()->AddArray(curvePoints);
  pd->GetCellData()->AddArray(edgeIds);
  vtkFieldData* fd = pd->GetFieldData();
  AddIntField(fd, "FaceId", faces[f].Index);
  vtkNew<vtkStringArray> name;
  name->SetName("FaceName");
  name->InsertNextValue(faces[f].Name);
  fd->AddArray(name);
  AddIntField(fd, "Reversed", faces[f].Reversed ? 1 : 0);
  AddField(fd, "MaxGap", faces[f].MaxGap);
  AddIntField(fd, "Converged", mesh.Converged ? 1 : 0);
  AddField(fd, "MaxEstimatedError", mesh.MaxEstimatedError);
  AddField(fd, "MaxEstimatedAngle", mesh.MaxEstimatedAngle);
  AddIntField(fd, "RefinementRounds", mesh.Rounds + mesh.CheckRounds);
  if (mesh.FallbackConstruction >= 0)
  {
    AddIntField(fd, ctcad::names::FallbackConstruction, mesh.FallbackConstruction);
  }
  output->SetBlock(f, pd);
  output->GetMetaData(static_cast<unsigned int>(f))->Set(vtkCompositeDataSet::NAME(), faces[f].Name.c_str());
  return true;
}

void vtkCADFaceSampler::AddModelFields(vtkMultiBlockDataSet* output, double faceTime)
{
  const ctcad::CADModel* model = this->Internals->Current.get();
  vtkFieldData* fd = output->GetFieldData();
  AddField(fd, "Diagonal", model->Diagonal());
  AddField(fd, "AbsoluteTolerance", this->Tolerance * model->Diagonal());
  AddIntField(fd, "NumberOfGlobalNodes", static_cast<vtkIdType>(model->Nodes().size()));
  AddIntField(fd, "NumberOfBRepEdges", model->NumberOfEdges());
  AddIntField(fd, "NumberOfBRepVertices", model->NumberOfVertices());
  AddField(fd, "MaxVertexGap", model->MaxVertexGap());
  AddField(fd, "MaxEdgeGap", model->MaxEdgeGap());
  AddIntField(fd, "NumberOfSeamsAdded", model->NumberOfSeamsAdded());
  AddIntField(fd, "NumberOfPCurvesReprojected", model->NumberOfPCurvesReprojected());
  AddIntField(fd, "NumberOfDegeneratedEdgesDropped", model->NumberOfDegeneratedEdgesDropped());
  const ctcad::HealingReport& healed = model->Healing();
  AddIntField(fd, "NumberOfSewnEdges", healed.SewnEdges);
  AddIntField(fd, "NumberOfRemovedFaces", healed.RemovedFaces);
  AddIntField(fd, "NumberOfCollapsedEdges", healed.CollapsedEdges);
  AddField(fd, "SewingTolerance", healed.SewingTolerance);
  AddField(fd, "SewingTime", healed.SewingSeconds);
  const ctcad::BoundaryChanges& changes = model->Changes();
  AddField(fd, "MaxBoundaryCurveChange", changes.MaxCurveChange);
  AddField(fd, "MaxBoundaryDerivativeChange", changes.MaxDerivativeChange);
  AddIntField(fd, "RestoreG1", this->RestoreG1 ? 1 : 0);
  AddIntField(fd, "NumberOfG1Nodes", changes.SmoothNodes);
  AddIntField(fd, "NumberOfG1Spans", changes.SmoothSpans);
  // What the faces were refined for (vtkWatertightSplineStitcher compares with its own).
  AddIntField(fd, ctcad::names::RefinedConstruction, this->RefineStitchedSpline ? this->Construction : -1);
  AddIntField(fd, ctcad::names::RefinedSplitPoint, this->SplitPoint);
  AddIntField(fd, ctcad::names::RefinedBoundaryMode, this->BoundaryMode);
  vtkNew<vtkDoubleArray> times;
  times->SetName("StageTimes");
  const ctcad::StageTimes& st = model->Times();
  for (const double v : { st.Read, st.Edges, st.Loops, st.TangentPlanes, faceTime })
  {
    times->InsertNextValue(v);
  }
  fd->AddArray(times);
}

void vtkCADFaceSampler::SetConstruction(int construction)
{
  ctcad::SetStitchedConstruction(this, this->Construction, construction);
}

void vtkCADFaceSampler::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
  os << indent << "ReadTimeout: " << this->ReadTimeout << "\n";
  os << indent << "Sew: " << this->Sew << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "AngularTolerance: " << this->AngularTolerance << "\n";
  os << indent << "AspectRatio: " << this->AspectRatio << "\n";
  os << indent << "MaxEdgeLength: " << this->MaxEdgeLength << "\n";
  os << indent << "MaxRounds: " << this->MaxRounds << "\n";
  os << indent << "MaxTrianglesPerFace: " << this->MaxTrianglesPerFace << "\n";
  os << indent << "RefineStitchedSpline: " << this->RefineStitchedSpline << "\n";
  os << indent << "FallbackConstructions: " << this->FallbackConstructions << "\n";
  os << indent << "Construction: " << this->Construction << "\n";
  os << indent << "SplitPoint: " << this->SplitPoint << "\n";
  os << indent << "BoundaryMode: " << this->BoundaryMode << "\n";
  os << indent << "RestoreG1: " << this->RestoreG1 << "\n";
  os << indent << "G1Threshold: " << this->G1Threshold << "\n";
  os << indent << "CacheArrayRanges: " << this->CacheArrayRanges << "\n";
}
