// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkApproximationErrorFilter.h"

#include "CTSplinesArrayRanges.h"
#include "CTSplinesInput.h"
#include "CTSplinesSMP.h"
#include "PointToMeshDistance.h"
#include "vtkBezierTriangleTessellator.h"
#include "vtkSplineParameterProbe.h"

#include "vtkAlgorithmOutput.h"
#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkApproximationErrorFilter);

namespace
{
// Collects the error messages of an internal filter so they can be reported by this one.
void CollectError(vtkObject*, unsigned long, void* clientData, void* callData)
{
  auto* message = static_cast<std::string*>(clientData);
  if (callData)
  {
    if (!message->empty())
    {
      *message += "; ";
    }
    *message += static_cast<const char*>(callData);
  }
}

// Runs an internal filter; returns its error messages (empty on success).
std::string RunInternal(vtkAlgorithm* algorithm)
{
  std::string message;
  vtkNew<vtkCallbackCommand> callback;
  callback->SetCallback(CollectError);
  callback->SetClientData(&message);
  algorithm->AddObserver(vtkCommand::ErrorEvent, callback);
  algorithm->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, callback);
  algorithm->Update();
  algorithm->RemoveObserver(callback);
  algorithm->GetExecutive()->RemoveObserver(callback);
  if (message.empty() && algorithm->GetErrorCode() != 0)
  {
    message = "failed";
  }
  return message;
}

// Max and sum of squares of the values whose mask entry is nonzero (mask may be null).
struct Statistics
{
  double Max = 0.0;
  double SumSquares = 0.0;
  vtkIdType Count = 0;
};

Statistics Summarise(const std::vector<double>& values, const std::vector<char>* mask)
{
  Statistics s;
  for (size_t i = 0; i < values.size(); ++i)
  {
    if (mask && !(*mask)[i])
    {
      continue;
    }
    s.Max = std::max(s.Max, values[i]);
    s.SumSquares += values[i] * values[i];
    ++s.Count;
  }
  return s;
}

void AddValue(vtkFieldData* fd, const char* name, double value)
{
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfTuples(1);
  a->SetValue(0, value);
  fd->AddArray(a);
}

double Diagonal(vtkPoints* points)
{
  double b[6];
  points->GetBounds(b);
  return std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
    (b[5] - b[4]) * (b[5] - b[4]));
}

// Writes the summary into the output's field data.
void WriteFieldData(vtkPolyData* output, double hSplineToRef, double hRefToSpline, double rms,
  double diagonal, vtkIdType referenceSamples)
{
  vtkFieldData* fd = output->GetFieldData();
  const double maxError = std::max(hSplineToRef, hRefToSpline);
  // A reference without extent has no relative scale.
  const double scale =
    diagonal > 0.0 ? 1.0 / diagonal : std::numeric_limits<double>::quiet_NaN();
  AddValue(fd, "MaxError", maxError);
  AddValue(fd, "RMSError", rms);
  AddValue(fd, "HausdorffSplineToReference", hSplineToRef);
  AddValue(fd, "HausdorffReferenceToSpline", hRefToSpline);
  AddValue(fd, "BoundingBoxDiagonal", diagonal);
  AddValue(fd, "RelativeMaxError", maxError * scale);
  AddValue(fd, "RelativeRMSError", rms * scale);
  AddValue(fd, "RelativeHausdorffSplineToReference", hSplineToRef * scale);
  AddValue(fd, "RelativeHausdorffReferenceToSpline", hRefToSpline * scale);
  AddValue(fd, "NumberOfReferenceSamples", static_cast<double>(referenceSamples));
}
} // namespace

vtkApproximationErrorFilter::vtkApproximationErrorFilter()
{
  this->SetNumberOfInputPorts(2);
}

vtkApproximationErrorFilter::~vtkApproximationErrorFilter() = default;

const char* vtkApproximationErrorFilter::GetModeName(int mode)
{
  switch (mode)
  {
    case Parametric:
      return "Parametric";
    case MeshDistance:
      return "MeshDistance";
    default:
      return "Unknown";
  }
}

void vtkApproximationErrorFilter::SetReferenceConnection(vtkAlgorithmOutput* algOutput)
{
  this->SetInputConnection(1, algOutput);
}

void vtkApproximationErrorFilter::SetReferenceData(vtkDataObject* reference)
{
  this->SetInputData(1, reference);
}

vtkDataObject* vtkApproximationErrorFilter::GetReference()
{
  if (this->GetNumberOfInputConnections(1) < 1)
  {
    return nullptr;
  }
  return this->GetExecutive()->GetInputData(1, 0);
}

int vtkApproximationErrorFilter::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
    return 1;
  }
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  // Optional for the pipeline so that a missing reference gets a clear message from RequestData.
  info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  return 1;
}

int vtkApproximationErrorFilter::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector*)
{
  // Distances need the whole spline and the whole reference.
  for (int port = 0; port < 2; ++port)
  {
    if (vtkInformation* info = inputVector[port]->GetInformationObject(0))
    {
      info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER(), 0);
      info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES(), 1);
      info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
      if (info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
      {
        info->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
          info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()), 6);
      }
    }
  }
  return 1;
}

int vtkApproximationErrorFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* spline = vtkDataSet::GetData(inputVector[0]);
  vtkInformation* referenceInfo = inputVector[1]->GetInformationObject(0);
  vtkPolyData* reference = referenceInfo ? vtkPolyData::GetData(referenceInfo) : nullptr;
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (!spline || !output)
  {
    vtkErrorMacro(<< "missing spline input or output data object");
    return 0;
  }
  if (!reference)
  {
    vtkErrorMacro(<< "no reference surface: set a vtkPolyData with SetReferenceConnection() or "
                     "SetReferenceData()");
    return 0;
  }
  if (spline->GetNumberOfCells() == 0)
  {
    vtkErrorMacro(<< "the spline input has no cells (expected VTK_BEZIER_TRIANGLE cells)");
    return 0;
  }
  if (reference->GetNumberOfPoints() == 0 || !reference->GetPoints())
  {
    vtkErrorMacro(<< "the reference has no points");
    return 0;
  }
  std::vector<double> referencePoints;
  const std::string pointError = ctsplines::CopyPoints(reference->GetPoints(), referencePoints);
  if (!pointError.empty())
  {
    vtkErrorMacro(<< "reference: " << pointError);
    return 0;
  }
  // Internal pipelines get shallow copies so that they never touch this pipeline's data.
  vtkSmartPointer<vtkDataSet> splineCopy;
  splineCopy.TakeReference(spline->NewInstance());
  splineCopy->ShallowCopy(spline);
  const int ok = this->Mode == Parametric
    ? this->ComputeParametric(splineCopy, reference, referencePoints, output)
    : this->ComputeMeshDistance(splineCopy, reference, referencePoints, output);
  if (ok)
  {
    ctsplines::CacheRanges(output); // for ParaView's data information and colour maps
  }
  return ok;
}

int vtkApproximationErrorFilter::ComputeParametric(vtkDataSet* spline, vtkPolyData* reference,
  const std::vector<double>& referencePoints, vtkPolyData* output)
{
  vtkDataArray* uvArray = ctsplines::FindArray(reference->GetPointData(), this->ReferenceUVArrayName);
  if (!uvArray)
  {
    uvArray = reference->GetPointData()->GetTCoords();
  }
  if (!uvArray)
  {
    vtkErrorMacro(<< "Parametric mode: the reference has no point data array '"
                  << this->ReferenceUVArrayName << "' and no texture coordinates (its (u, v))");
    return 0;
  }
  std::vector<double> uv;
  std::string error = ctsplines::CopyArray(uvArray,
    std::string("the reference's point data array '") + (uvArray->GetName() ? uvArray->GetName() : "") + "'",
    2, reference->GetNumberOfPoints(), "point", uv);
  if (!error.empty())
  {
    vtkErrorMacro(<< "Parametric mode: " << error);
    return 0;
  }

  // Query points (u, v, 0) with the reference's cells, so the output keeps its structure.
  const vtkIdType n = reference->GetNumberOfPoints();
  vtkNew<vtkPoints> queryPoints;
  queryPoints->SetDataTypeToDouble();
  queryPoints->SetNumberOfPoints(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    queryPoints->SetPoint(i, uv[2 * i], uv[2 * i + 1], 0.0);
  }
  vtkNew<vtkPolyData> query;
  query->SetPoints(queryPoints);
  query->SetVerts(reference->GetVerts());
  query->SetLines(reference->GetLines());
  query->SetPolys(reference->GetPolys());
  query->SetStrips(reference->GetStrips());

  vtkNew<vtkSplineParameterProbe> probe;
  probe->SetInputData(query);
  probe->SetSourceData(spline);
  probe->SetUVArrayName(this->UVArrayName.c_str());
  error = RunInternal(probe);
  if (!error.empty())
  {
    vtkErrorMacro(<< "evaluating the spline at the reference's parameters failed: " << error);
    return 0;
  }
  this->UpdateProgress(0.5);
  vtkPolyData* evaluated = vtkPolyData::SafeDownCast(probe->GetOutput());
  vtkDataArray* maskArray = evaluated ? evaluated->GetPointData()->GetArray("vtkValidPointMask") : nullptr;
  if (!evaluated || !maskArray || evaluated->GetNumberOfPoints() != n)
  {
    vtkErrorMacro(<< "evaluating the spline at the reference's parameters gave no valid output");
    return 0;
  }

  std::vector<double> errors(static_cast<size_t>(n), 0.0);
  std::vector<char> mask(static_cast<size_t>(n), 0);
  vtkPoints* splinePoints = evaluated->GetPoints();
  ctsplines::ParallelFor(0, n, ctsplines::GrainForEvaluations, [&](vtkIdType begin, vtkIdType end) {
    if (this->GetAbortExecute())
    {
      return;
    }
    for (vtkIdType i = begin; i < end; ++i)
    {
      if (maskArray->GetComponent(i, 0) == 0.0)
      {
        continue;
      }
      double p[3];
      splinePoints->GetPoint(i, p);
      const double* r = &referencePoints[3 * i];
      errors[i] = std::sqrt((p[0] - r[0]) * (p[0] - r[0]) + (p[1] - r[1]) * (p[1] - r[1]) +
        (p[2] - r[2]) * (p[2] - r[2]));
      mask[i] = 1;
    }
  });
  if (this->GetAbortExecute())
  {
    return 1;
  }
  const Statistics stats = Summarise(errors, &mask);
  if (stats.Count == 0)
  {
    vtkErrorMacro(<< "Parametric mode: none of the reference's " << n
                  << " points has a (u, v) inside the spline's parameter domain");
    return 0;
  }

  output->ShallowCopy(evaluated);
  vtkNew<vtkDoubleArray> errorArray;
  errorArray->SetName("Error");
  errorArray->SetNumberOfTuples(n);
  std::copy(errors.begin(), errors.end(), errorArray->GetPointer(0));
  output->GetPointData()->AddArray(errorArray);
  output->GetPointData()->SetActiveScalars("Error");
  // The reference's parameters, so the output can be compared with the reference point by point.
  vtkNew<vtkDoubleArray> uvOut;
  uvOut->SetName("UV");
  uvOut->SetNumberOfComponents(2);
  uvOut->SetNumberOfTuples(n);
  std::copy(uv.begin(), uv.end(), uvOut->GetPointer(0));
  output->GetPointData()->AddArray(uvOut);

  const double rms = std::sqrt(stats.SumSquares / static_cast<double>(stats.Count));
  WriteFieldData(output, stats.Max, stats.Max, rms, Diagonal(reference->GetPoints()), stats.Count);
  this->UpdateProgress(1.0);
  return 1;
}

namespace
{
// The sample points of a reference mesh: its triangles' vertices (each once), then the points
// (i, j, k)/level of every triangle that are not its corners.
struct ReferenceSampling
{
  const std::vector<double>& Points;
  const std::vector<ctk::Id>& Triangles;
  std::vector<vtkIdType> UsedVertices;
  std::vector<std::array<int, 3>> Pattern;
  int Level;

  ReferenceSampling(const std::vector<double>& points, const std::vector<ctk::Id>& triangles,
    ctk::Id nPoints, int level)
    : Points(points)
    , Triangles(triangles)
    , Level(level)
  {
    std::vector<char> used(static_cast<size_t>(nPoints), 0);
    for (const ctk::Id v : triangles)
    {
      used[static_cast<size_t>(v)] = 1;
    }
    for (ctk::Id v = 0; v < nPoints; ++v)
    {
      if (used[static_cast<size_t>(v)])
      {
        this->UsedVertices.push_back(v);
      }
    }
    for (int i = 0; i <= level; ++i)
    {
      for (int j = 0; i + j <= level; ++j)
      {
        const int k = level - i - j;
        if (i != level && j != level && k != level)
        {
          this->Pattern.push_back({ i, j, k });
        }
      }
    }
  }
  vtkIdType Count() const
  {
    return static_cast<vtkIdType>(this->UsedVertices.size() +
      this->Pattern.size() * (this->Triangles.size() / 3));
  }
  ctk::Vec3 Point(vtkIdType s) const
  {
    const vtkIdType nVertices = static_cast<vtkIdType>(this->UsedVertices.size());
    if (s < nVertices)
    {
      return ctk::Vec3(this->Points.data() + 3 * this->UsedVertices[s]);
    }
    const vtkIdType per = static_cast<vtkIdType>(this->Pattern.size());
    const vtkIdType t = (s - nVertices) / per;
    const std::array<int, 3>& b = this->Pattern[static_cast<size_t>((s - nVertices) % per)];
    ctk::Vec3 p = ctk::Vec3::Zero();
    for (int a = 0; a < 3; ++a)
    {
      p += (static_cast<double>(b[a]) / this->Level) *
        ctk::Vec3(this->Points.data() + 3 * this->Triangles[3 * t + a]);
    }
    return p;
  }
};
} // namespace

int vtkApproximationErrorFilter::ComputeMeshDistance(vtkDataSet* spline, vtkPolyData* reference,
  const std::vector<double>& referencePoints, vtkPolyData* output)
{
  std::vector<ctk::Id> referenceTriangles;
  std::string error = ctsplines::ExtractTriangles(reference, referenceTriangles);
  if (error.empty() && referenceTriangles.empty())
  {
    error = "it has no triangles";
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< "MeshDistance mode needs a triangle mesh as reference: " << error);
    return 0;
  }
  const ctk::Id nReferencePoints = reference->GetNumberOfPoints();
  const ctk::Id nReferenceTriangles = static_cast<ctk::Id>(referenceTriangles.size() / 3);
  ctk::PointToMeshDistance toReference;
  error = toReference.Build(
    nReferencePoints, referencePoints.data(), nReferenceTriangles, referenceTriangles.data());
  if (!error.empty())
  {
    vtkErrorMacro(<< "reference mesh: " << error);
    return 0;
  }
  this->UpdateProgress(0.1);

  vtkNew<vtkBezierTriangleTessellator> tessellator;
  tessellator->SetInputData(spline);
  tessellator->SetSubdivisionLevel(this->SubdivisionLevel);
  tessellator->SetUVArrayName(this->UVArrayName.c_str());
  error = RunInternal(tessellator);
  if (!error.empty())
  {
    vtkErrorMacro(<< "tessellating the spline failed: " << error);
    return 0;
  }
  vtkPolyData* tessellation = tessellator->GetOutput();
  std::vector<double> splinePoints;
  std::vector<ctk::Id> splineTriangles;
  error = ctsplines::CopyPoints(tessellation->GetPoints(), splinePoints);
  if (error.empty())
  {
    error = ctsplines::ExtractTriangles(tessellation, splineTriangles);
  }
  ctk::PointToMeshDistance toSpline;
  if (error.empty())
  {
    error = toSpline.Build(tessellation->GetNumberOfPoints(), splinePoints.data(),
      static_cast<ctk::Id>(splineTriangles.size() / 3), splineTriangles.data());
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< "the spline's tessellation: " << error);
    return 0;
  }
  this->UpdateProgress(0.4);

  // Spline -> reference: every tessellation point.
  const vtkIdType nSpline = tessellation->GetNumberOfPoints();
  std::vector<double> errors(static_cast<size_t>(nSpline), 0.0);
  ctsplines::ParallelFor(
    0, nSpline, ctsplines::GrainForEvaluations, [&](vtkIdType begin, vtkIdType end) {
    if (this->GetAbortExecute())
    {
      return;
    }
    for (vtkIdType i = begin; i < end; ++i)
    {
      errors[i] = toReference.Query(ctk::Vec3(splinePoints[3 * i], splinePoints[3 * i + 1],
                                      splinePoints[3 * i + 2]))
                    .Distance;
    }
  });
  if (this->GetAbortExecute())
  {
    return 1;
  }
  this->UpdateProgress(0.7);

  // Reference -> spline: the vertices of the reference triangles (each once), then the points
  // (i, j, k)/n of every triangle that are not its corners.
  const ReferenceSampling sampling(
    referencePoints, referenceTriangles, nReferencePoints, this->ReferenceSampleLevel);
  const vtkIdType nSamples = sampling.Count();
  std::vector<double> referenceErrors(static_cast<size_t>(nSamples), 0.0);
  ctsplines::ParallelFor(
    0, nSamples, ctsplines::GrainForEvaluations, [&](vtkIdType begin, vtkIdType end) {
    if (this->GetAbortExecute())
    {
      return;
    }
    for (vtkIdType s = begin; s < end; ++s)
    {
      const ctk::Vec3 p = sampling.Point(s);
      referenceErrors[s] = toSpline.Query(p).Distance;
    }
  });
  if (this->GetAbortExecute())
  {
    return 1;
  }

  const Statistics splineStats = Summarise(errors, nullptr);
  const Statistics referenceStats = Summarise(referenceErrors, nullptr);
  output->ShallowCopy(tessellation);
  vtkNew<vtkDoubleArray> errorArray;
  errorArray->SetName("Error");
  errorArray->SetNumberOfTuples(nSpline);
  std::copy(errors.begin(), errors.end(), errorArray->GetPointer(0));
  output->GetPointData()->AddArray(errorArray);
  output->GetPointData()->SetActiveScalars("Error");
  const double rms =
    nSpline > 0 ? std::sqrt(splineStats.SumSquares / static_cast<double>(nSpline)) : 0.0;
  WriteFieldData(output, splineStats.Max, referenceStats.Max, rms,
    Diagonal(reference->GetPoints()), nSamples);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkApproximationErrorFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mode: " << GetModeName(this->Mode) << "\n";
  os << indent << "SubdivisionLevel: " << this->SubdivisionLevel << "\n";
  os << indent << "ReferenceSampleLevel: " << this->ReferenceSampleLevel << "\n";
  os << indent << "UVArrayName: " << this->UVArrayName << "\n";
  os << indent << "ReferenceUVArrayName: " << this->ReferenceUVArrayName << "\n";
}
