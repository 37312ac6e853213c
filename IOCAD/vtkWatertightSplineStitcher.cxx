// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkWatertightSplineStitcher.h"

#include "CADBRepSampling.h"
#include "CADFaceMesher.h"
#include "CADFaceSplines.h"
#include "CADMeasure.h"
#include "CADSampledFace.h"
#include "CADStitch.h"
#include "CADArrayNames.h"
#include "CADStitchedConstruction.h"
#include "CTSplinesArrayRanges.h"
#include "CTSplinesSplineGrid.h"

#include "vtkCADFaceSampler.h"
#include "vtkCloughTocherSplineFilter.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkSignedCharArray.h"
#include "vtkStringArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
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

void AddFieldString(vtkFieldData* fd, const char* name, const char* value)
{
  vtkNew<vtkStringArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}

/// Whether the sampler refined the faces for this spline's construction, split point and
/// boundary mode (or says nothing of it); if not, their fallback constructions were chosen
/// against another one. Another spline, or IM steps, may exceed the sampler's tolerance: a
/// warning on self says so.
bool FacesRefinedForThisSpline(
  vtkObject* self, vtkFieldData* sampled, const ctk::SplineOptions& options)
{
  vtkDataArray* refined = sampled->GetArray(ctcad::names::RefinedConstruction);
  if (!refined || refined->GetTuple1(0) < 0)
  {
    return true;
  }
  auto value = [&](const char* name, int fallback) {
    vtkDataArray* a = sampled->GetArray(name);
    return a ? static_cast<int>(a->GetTuple1(0)) : fallback;
  };
  ctk::SplineOptions theirs;
  theirs.Method = static_cast<ctk::Construction>(refined->GetTuple1(0));
  theirs.SplitPoint = static_cast<ctk::SplitPointRule>(
    value(ctcad::names::RefinedSplitPoint, static_cast<int>(options.SplitPoint)));
  theirs.Boundary = static_cast<ctk::BoundaryMode>(
    value(ctcad::names::RefinedBoundaryMode, static_cast<int>(options.Boundary)));
  if (theirs.Method != options.Method || theirs.SplitPoint != options.SplitPoint ||
    ctk::EffectiveBoundaryMode(theirs) != ctk::EffectiveBoundaryMode(options))
  {
    vtkWarningWithObjectMacro(self, << "the faces were refined for another spline ("
      << ctk::ToString(theirs.Method) << ", split point " << static_cast<int>(theirs.SplitPoint)
      << ", boundary " << ctk::ToString(ctk::EffectiveBoundaryMode(theirs)) << "; here "
      << ctk::ToString(options.Method) << ", " << static_cast<int>(options.SplitPoint) << ", "
      << ctk::ToString(ctk::EffectiveBoundaryMode(options))
      << "): the deviation may exceed the sampler's tolerance");
    return false;
  }
  if (options.Iterations > 0)
  {
    vtkWarningWithObjectMacro(self,
      << "the faces were refined for the spline without IM steps; with " << options.Iterations
      << " the deviation may exceed the sampler's tolerance");
  }
  return true;
}

/// A new array of `components` per tuple holding a copy of the n values.
template <typename Array, typename T>
vtkSmartPointer<Array> NewArray(const char* name, int components, const T* values, std::size_t n)
{
  static_assert(sizeof(typename Array::ValueType) == sizeof(T), "same layout");
  auto a = vtkSmartPointer<Array>::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  a->SetNumberOfTuples(static_cast<vtkIdType>(n / components));
  std::copy_n(reinterpret_cast<const typename Array::ValueType*>(values), n, a->GetPointer(0));
  return a;
}
template <typename Array, typename T>
vtkSmartPointer<Array> NewArray(const char* name, const std::vector<T>& values)
{
  return NewArray<Array>(name, 1, values.data(), values.size());
}

/// The merged grid of the stitched surface, with its cell data.
void FillMergedGrid(const ctcad::StitchedSurface& surface, vtkUnstructuredGrid* merged)
{
  static_assert(sizeof(ctk::Vec3) == 3 * sizeof(double), "packed points");
  const double* xyz = surface.Points.empty() ? nullptr : surface.Points[0].data();
  vtkNew<vtkPoints> points;
  points->SetData(NewArray<vtkDoubleArray>(nullptr, 3, xyz, 3 * surface.Points.size()));
  const vtkIdType nCells = static_cast<vtkIdType>(surface.FaceIds.size());
  std::vector<ctk::Id> offsets(nCells + 1);
  for (vtkIdType c = 0; c <= nCells; ++c)
  {
    offsets[c] = 10 * c;
  }
  vtkNew<vtkCellArray> cells;
  cells->SetData(NewArray<vtkIdTypeArray>(nullptr, offsets),
    NewArray<vtkIdTypeArray>(nullptr, surface.Cells));
  merged->SetPoints(points);
  merged->SetCells(VTK_BEZIER_TRIANGLE, cells);
  merged->GetCellData()->AddArray(NewArray<vtkIdTypeArray>("FaceId", surface.FaceIds));
  merged->GetCellData()->AddArray(
    NewArray<vtkIdTypeArray>("MacroTriangleId", surface.MacroTriangles));
  merged->GetCellData()->AddArray(
    NewArray<vtkSignedCharArray>("MicroTriangleId", surface.MicroTriangles));
}

/// The Bézier triangle of face f's macro-triangle t, micro-triangle k in the merged grid (-1:
/// none).
vtkIdType CellOf(const ctcad::StitchedSurface& surface, int f, ctk::Id t, int k)
{
  for (std::size_t c = 0; c < surface.FaceIds.size(); ++c)
  {
    if (surface.FaceIds[c] == f && surface.MacroTriangles[c] == t &&
      surface.MicroTriangles[c] == k)
    {
      return static_cast<vtkIdType>(c);
    }
  }
  return -1;
}

/// Cell data `Deviation` (relative to the diagonal) and `NormalDeviation` (degrees): the largest
/// of each cell's macro-triangle (cell data MacroTriangleId) in its face (cell data FaceId, or
/// `face` when not -1); field data `MaxDeviationCell`, `MaxNormalDeviationCell`: the first cell
/// where each is largest.
void AddDeviationArrays(vtkDataSet* grid, int face,
  const std::vector<std::vector<ctcad::Deviation>>& perTriangle, double diagonal)
{
  vtkCellData* cd = grid->GetCellData();
  vtkDataArray* faceIds = face < 0 ? cd->GetArray("FaceId") : nullptr;
  vtkDataArray* macro = cd->GetArray("MacroTriangleId");
  const vtkIdType n = grid->GetNumberOfCells();
  if (!macro || (face < 0 && !faceIds))
  {
    return;
  }
  vtkNew<vtkDoubleArray> distance, angle;
  distance->SetName("Deviation");
  angle->SetName("NormalDeviation");
  distance->SetNumberOfTuples(n);
  angle->SetNumberOfTuples(n);
  vtkIdType worstDistance = 0, worstAngle = 0;
  for (vtkIdType c = 0; c < n; ++c)
  {
    const auto f = static_cast<std::size_t>(face < 0 ? faceIds->GetTuple1(c) : face);
    const ctcad::Deviation& d = perTriangle[f][static_cast<std::size_t>(macro->GetTuple1(c))];
    distance->SetValue(c, d.MaxDistance / diagonal);
    angle->SetValue(c, d.MaxAngle);
    worstDistance = distance->GetValue(c) > distance->GetValue(worstDistance) ? c : worstDistance;
    worstAngle = d.MaxAngle > angle->GetValue(worstAngle) ? c : worstAngle;
  }
  cd->AddArray(distance);
  cd->AddArray(angle);
  if (n > 0)
  {
    AddField(grid->GetFieldData(), "MaxDeviationCell", static_cast<double>(worstDistance));
    AddField(grid->GetFieldData(), "MaxNormalDeviationCell", static_cast<double>(worstAngle));
  }
}

/// With a SurfaceSource, the deviation of every face (perFace) and macro-triangle (perTriangle)
/// and of all (into fd).
bool MeasureDeviation(vtkWatertightSplineStitcher* self,
  const std::vector<ctcad::SampledFace>& sampled,
  const std::vector<ctcad::FaceSpline>& splines, std::vector<ctcad::Deviation>& perFace,
  std::vector<std::vector<ctcad::Deviation>>& perTriangle, vtkFieldData* fd)
{
  vtkCADFaceSampler* source = self->GetSurfaceSource();
  if (!source || source->GetDiagonal() <= 0)
  {
    return true;
  }
  const ctcad::FaceSurface surface = [source](int f, double s, double t, double* P,
                                       double* Ds, double* Dt, std::string& failure) {
    return source->EvaluateSurface(f, s, t, P, Ds, Dt, failure);
  };
  ctcad::Deviation all;
  std::string error;
  if (!ctcad::MeasureDeviation(surface, self->GetDeviationLevel(), self->GetDeviationSamples(),
        sampled, splines, perFace, all, error, nullptr, &perTriangle))
  {
    vtkErrorWithObjectMacro(self, << error);
    return false;
  }
  const double diag = source->GetDiagonal();
  AddField(fd, "MaxDeviation", all.MaxDistance / diag);
  AddField(
    fd, "RMSDeviation", all.Count ? std::sqrt(all.SumSquaredDistance / all.Count) / diag : 0.0);
  AddField(fd, "MaxNormalDeviation", all.MaxAngle);
  AddField(fd, "RMSNormalDeviation",
    all.AngleCount ? std::sqrt(all.SumSquaredAngle / all.AngleCount) : 0.0);
  AddField(fd, "NumberOfCuspNodes", static_cast<double>(all.CuspNodes));
  return true;
}

/// Output port 0: every face's spline (moved out of splines) with its deviation.
void FillFaceBlocks(vtkWatertightSplineStitcher* self, vtkMultiBlockDataSet* input,
  const std::vector<ctcad::SampledFace>& sampled, std::vector<ctcad::FaceSpline>& splines,
  const std::vector<ctcad::Deviation>& deviations,
  const std::vector<std::vector<ctcad::Deviation>>& perTriangle, vtkMultiBlockDataSet* faces)
{
  const unsigned int nF = static_cast<unsigned int>(splines.size());
  faces->SetNumberOfBlocks(nF);
  for (unsigned int f = 0; f < nF; ++f)
  {
    // The spline's points move into the block: the stages are done with them.
    ctk::CloughTocherSpline spline;
    spline.Cubic = std::move(splines[f].Spline);
    vtkNew<vtkUnstructuredGrid> grid;
    ctsplines::FillSplineGrid(
      spline, splines[f].Topology, sampled[f].Input, ctcad::names::UV, grid);
    vtkFieldData* fd = grid->GetFieldData();
    fd->PassData(input->GetBlock(f)->GetFieldData()); // the sampler's face data first
    if (sampled[f].FallbackConstruction < 0)
    {
      fd->RemoveArray(ctcad::names::FallbackConstruction); // not taken
    }
    using Filter = vtkCloughTocherSplineFilter;
    const int fallback = sampled[f].FallbackConstruction;
    AddFieldString(fd, "Construction",
      Filter::GetConstructionName(fallback >= 0 ? fallback : self->GetConstruction()));
    AddFieldString(fd, "SplitPoint", Filter::GetSplitPointName(self->GetSplitPoint()));
    AddFieldString(fd, "BoundaryMode", Filter::GetBoundaryModeName(self->GetBoundaryMode()));
    AddFieldString(fd, "DerivativeEstimation",
      Filter::GetDerivativeEstimationName(Filter::NoEstimation));
    vtkNew<vtkIntArray> iterations;
    iterations->SetName("Iterations");
    iterations->InsertNextValue(self->GetIterations());
    fd->AddArray(iterations);
    if (!deviations.empty())
    {
      const double diag = self->GetSurfaceSource()->GetDiagonal();
      AddField(fd, "MaxDeviation", deviations[f].MaxDistance / diag);
      AddField(fd, "MaxNormalDeviation", deviations[f].MaxAngle);
      AddDeviationArrays(grid, static_cast<int>(f), perTriangle, diag);
    }
    faces->SetBlock(f, grid);
    if (input->HasMetaData(f) && input->GetMetaData(f)->Has(vtkCompositeDataSet::NAME()))
    {
      faces->GetMetaData(f)->Set(
        vtkCompositeDataSet::NAME(), input->GetMetaData(f)->Get(vtkCompositeDataSet::NAME()));
    }
  }
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
  const int nF = static_cast<int>(input->GetNumberOfBlocks());
  ctk::SplineOptions options;
  options.Method = static_cast<ctk::Construction>(this->Construction);
  options.SplitPoint = static_cast<ctk::SplitPointRule>(this->SplitPoint);
  options.Boundary = static_cast<ctk::BoundaryMode>(this->BoundaryMode);
  options.Iterations = this->Iterations;
  const bool fallbacks = FacesRefinedForThisSpline(this, input->GetFieldData(), options);

  // Validate and map.
  std::vector<ctcad::SampledFace> sampled(nF);
  for (int f = 0; f < nF; ++f)
  {
    const std::string error =
      ctcad::ReadSampledFace(input->GetBlock(f), f, options, fallbacks, sampled[f]);
    if (!error.empty())
    {
      vtkErrorMacro(<< error);
      return 0;
    }
  }
  // The stages: splines (faces in parallel), stitch, measure.
  auto start = Clock::now();
  std::vector<ctcad::FaceSpline> splines;
  std::string error;
  if (!ctcad::BuildFaceSplines(sampled, options, splines, error))
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  const double splineTime = Seconds(start);
  start = Clock::now();
  double gapBefore = 0;
  for (int f = 0; f < nF; ++f)
  {
    gapBefore = std::max(gapBefore, ctcad::GapBeforeStitching(sampled[f], splines[f]));
  }
  const double stitchTime = Seconds(start);
  start = Clock::now();
  ctcad::StitchedSurface surface;
  ctcad::StitchFaces(sampled, splines, surface);
  const ctcad::InterfaceMeasures interfaces = ctcad::MeasureInterfaces(sampled, splines);
  FillMergedGrid(surface, merged);
  const double mergeTime = Seconds(start);

  vtkFieldData* fd = merged->GetFieldData();
  AddField(fd, "NumberOfFreeEdges", static_cast<double>(surface.FreeEdges));
  AddField(fd, "NumberOfNonManifoldEdges", static_cast<double>(surface.NonManifoldEdges));
  AddField(
    fd, "NumberOfExtraNonManifoldEdges", static_cast<double>(surface.ExtraNonManifoldEdges));
  AddField(fd, "MaxC0Gap", interfaces.MaxC0Gap);
  AddField(fd, "MaxGapBeforeStitching", gapBefore);
  AddField(fd, "NumberOfMacroTriangles", static_cast<double>(surface.NumberOfMacroTriangles));
  AddField(fd, "NumberOfFallbackFaces",
    static_cast<double>(std::count_if(sampled.begin(), sampled.end(),
      [](const ctcad::SampledFace& face) { return face.FallbackConstruction >= 0; })));
  const ctcad::AngleSummary& tangent = interfaces.G1[1];
  AddField(fd, "MaxG1Angle", std::max(interfaces.G1[0].Max, tangent.Max));
  AddField(fd, "NumberOfTangentInterfaceEdges", static_cast<double>(tangent.Count));
  AddField(fd, "MaxG1AngleTangent", tangent.Max);
  AddField(fd, "MeanG1AngleTangent", tangent.Count ? tangent.Sum / tangent.Count : 0.0);
  const vtkIdType worstTangent =
    CellOf(surface, tangent.Face, tangent.Triangle, tangent.MicroTriangle);
  if (worstTangent >= 0)
  {
    AddField(fd, "MaxG1AngleTangentCell", static_cast<double>(worstTangent));
  }

  start = Clock::now();
  std::vector<ctcad::Deviation> deviations;
  std::vector<std::vector<ctcad::Deviation>> perTriangle;
  if (!MeasureDeviation(this, sampled, splines, deviations, perTriangle, fd))
  {
    return 0;
  }
  if (!deviations.empty())
  {
    AddDeviationArrays(merged, -1, perTriangle, this->GetSurfaceSource()->GetDiagonal());
  }
  const double deviationTime = Seconds(start);
  start = Clock::now();
  FillFaceBlocks(this, input, sampled, splines, deviations, perTriangle, faces);
  vtkNew<vtkDoubleArray> times;
  times->SetName("StageTimes");
  // The per-face blocks are the spline stage's output.
  for (const double v : { splineTime + Seconds(start), stitchTime, mergeTime, deviationTime })
  {
    times->InsertNextValue(v);
  }
  fd->AddArray(times);
  ctsplines::CacheRanges(faces); // for ParaView's data information and colour maps
  ctsplines::CacheRanges(merged);
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
