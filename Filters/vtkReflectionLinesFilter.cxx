// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkReflectionLinesFilter.h"

#include "CTSplinesArrayRanges.h"
#include "CTSplinesBezierCells.h"
#include "CTSplinesInput.h"
#include "SplineDataValidation.h"

#include <Eigen/Geometry> // for cross

#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

vtkStandardNewMacro(vtkReflectionLinesFilter);

vtkReflectionLinesFilter::vtkReflectionLinesFilter() = default;
vtkReflectionLinesFilter::~vtkReflectionLinesFilter() = default;

int vtkReflectionLinesFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorMacro(<< "missing input or output data object");
    return 0;
  }
  const vtkIdType nPoints = input->GetNumberOfPoints();
  if (nPoints == 0)
  {
    vtkErrorMacro(<< "empty input: no points to compute reflection lines at");
    return 0;
  }
  vtkPointData* pd = input->GetPointData();
  vtkDataArray* normalArray = pd->GetNormals();
  if (!normalArray)
  {
    normalArray = ctsplines::FindArray(pd, this->NormalsArrayName);
  }
  if (!normalArray)
  {
    vtkErrorMacro(<< "the input has no point normals (no active normals and no point data array '"
                  << this->NormalsArrayName << "')");
    return 0;
  }
  std::vector<double> normals, coords;
  const std::string what = std::string("point data array '") +
    (normalArray->GetName() ? normalArray->GetName() : "") + "' (normals)";
  std::string error = ctsplines::CopyArray(normalArray, what, 3, nPoints, "point", normals);
  if (error.empty())
  {
    error = ctsplines::CopyPoints(input->GetPoints(), coords);
  }
  using V = Eigen::Vector3d;
  const V eye(this->EyePosition), origin(this->LightPlaneOrigin);
  const V planeNormal = V(this->LightPlaneNormal).normalized();
  const V lineDirection = V(this->LightLineDirection);
  // Offsets are measured across the lines, in the plane.
  const V across = planeNormal.cross(lineDirection);
  const V light = V(this->LightDirection).normalized();
  const std::pair<const char*, const double*> vectors[] = { { "EyePosition", this->EyePosition },
    { "LightPlaneOrigin", this->LightPlaneOrigin }, { "LightPlaneNormal", this->LightPlaneNormal },
    { "LightLineDirection", this->LightLineDirection }, { "LightDirection", this->LightDirection } };
  for (const auto& [name, value] : vectors)
  {
    if (error.empty() && !ctk::IsUsablePoint(V(value)))
    {
      error = std::string(name) + " is (" + std::to_string(value[0]) + ", " +
        std::to_string(value[1]) + ", " + std::to_string(value[2]) +
        "): its components must be finite and below 1e100 in magnitude";
    }
  }
  if (error.empty() && !(V(this->LightPlaneNormal).norm() > 0))
  {
    error = "LightPlaneNormal is zero";
  }
  if (error.empty() && !(across.norm() > 1e-12 * lineDirection.norm()))
  {
    error = "LightLineDirection is zero or parallel to LightPlaneNormal: the light lines must "
            "lie in the light plane";
  }
  if (error.empty() && !(V(this->LightDirection).norm() > 0))
  {
    error = "LightDirection is zero";
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  const V m = across.normalized();

  auto makeArray = [nPoints](const char* name) {
    vtkSmartPointer<vtkDoubleArray> a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(name);
    a->SetNumberOfTuples(nPoints);
    return a;
  };
  auto parameter = makeArray("ReflectionLineParameter");
  auto stripes = makeArray("ReflectionLines");
  auto isophotes = makeArray("Isophotes");
  auto isoAngle = makeArray("IsophoteAngle");
  double* par = parameter->GetPointer(0);
  double* str = stripes->GetPointer(0);
  double* iso = isophotes->GetPointer(0);
  double* ang = isoAngle->GetPointer(0);
  const double spacing = this->Spacing, isoSpacing = this->IsophoteSpacing;
  const double nan = std::numeric_limits<double>::quiet_NaN();

  auto compute = [&](vtkIdType begin, vtkIdType end) {
    for (vtkIdType i = begin; i < end; ++i)
    {
      const V x(&coords[3 * i]);
      V n(&normals[3 * i]);
      const double length = n.norm();
      if (!(length > 0))
      {
        par[i] = str[i] = iso[i] = ang[i] = nan;
        continue;
      }
      n /= length;
      const V d = (x - eye).normalized();
      const V r = d - 2 * d.dot(n) * n;
      const double rn = r.dot(planeNormal);
      const double lambda = (origin - x).dot(planeNormal) / rn;
      // Only rays that travel to the plane see a light line.
      if (std::abs(rn) > 1e-14 && lambda >= 0)
      {
        const V hit = x + lambda * r;
        par[i] = (hit - origin).dot(m);
        str[i] = std::cos(2 * M_PI * par[i] / spacing);
      }
      else
      {
        par[i] = str[i] = nan;
      }
      ang[i] = std::acos(std::max(-1.0, std::min(1.0, n.dot(light)))) * 180.0 / M_PI;
      iso[i] = std::cos(2 * M_PI * ang[i] / isoSpacing);
    }
  };
  // Blocks in sequence, each in parallel: progress and abort stay on the calling thread.
  if (!ctsplines::ForInBlocks(this, nPoints, 10, 0.0, 1.0, compute))
  {
    output->Initialize();
    return 1;
  }

  output->ShallowCopy(input);
  vtkPointData* outPD = output->GetPointData();
  outPD->AddArray(parameter);
  outPD->AddArray(isoAngle);
  outPD->AddArray(isophotes);
  outPD->AddArray(stripes);
  outPD->SetActiveScalars("ReflectionLines");
  ctsplines::CacheRanges(output); // for ParaView's data information and colour maps
  return 1;
}

void vtkReflectionLinesFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  auto vec = [&os, indent](const char* name, const double* v) {
    os << indent << name << ": (" << v[0] << ", " << v[1] << ", " << v[2] << ")\n";
  };
  vec("EyePosition", this->EyePosition);
  vec("LightLineDirection", this->LightLineDirection);
  vec("LightPlaneOrigin", this->LightPlaneOrigin);
  vec("LightPlaneNormal", this->LightPlaneNormal);
  os << indent << "Spacing: " << this->Spacing << "\n";
  vec("LightDirection", this->LightDirection);
  os << indent << "IsophoteSpacing: " << this->IsophoteSpacing << "\n";
  os << indent << "NormalsArrayName: " << this->NormalsArrayName << "\n";
}
