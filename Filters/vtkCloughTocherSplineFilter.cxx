// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkCloughTocherSplineFilter.h"

#include "CTSplinesArrayRanges.h"
#include "CTSplinesBezierCells.h"
#include "CTSplinesInput.h"
#include "CTSplinesRecycledArrays.h"
#include "CTSplinesSMP.h"
#include "CTSplinesSplineGrid.h"
#include "BezierExtraction.h"
#include "CloughTocherSpline.h"
#include "DerivativeEstimation.h"
#include "LargeArrays.h"
#include "MessageIds.h"
#include "SplineInput.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataSetAttributes.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkSignedCharArray.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"
#include "vtkVersionMacros.h" // for VTK_MAJOR_VERSION

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring> // for memchr
#include <limits>
#include <memory>
#include <mutex>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>

vtkStandardNewMacro(vtkCloughTocherSplineFilter);

struct vtkCloughTocherSplineFilter::RecycledOutput : ctsplines::RecycledArrays
{
};

vtkCloughTocherSplineFilter::vtkCloughTocherSplineFilter()
  : Recycled(new RecycledOutput)
{
}
vtkCloughTocherSplineFilter::~vtkCloughTocherSplineFilter() = default;

vtkTypeUInt64 vtkCloughTocherSplineFilter::GetReusedOutputBytes() const
{
  return this->Recycled->GetReusedBytes();
}

void vtkCloughTocherSplineFilter::SetReuseOutputArrays(bool reuse)
{
  if (this->Recycled->SetReuse(this->ReuseOutputArrays, reuse))
  {
    this->Modified();
  }
}

// The filter's values are the kernel's (the ParaView XML and Python read them through these).
static_assert(vtkCloughTocherSplineFilter::CTo == static_cast<int>(ctk::Construction::CTo) &&
    vtkCloughTocherSplineFilter::KaG == static_cast<int>(ctk::Construction::KaG) &&
    vtkCloughTocherSplineFilter::Kashyap == static_cast<int>(ctk::Construction::Kashyap) &&
    vtkCloughTocherSplineFilter::Quartic == static_cast<int>(ctk::Construction::Quartic) &&
    vtkCloughTocherSplineFilter::Quartic + 1 == ctk::NumberOfConstructions,
  "vtkCloughTocherSplineFilter::ConstructionType and ctk::Construction differ");
static_assert(vtkCloughTocherSplineFilter::NoEstimation == static_cast<int>(ctk::DerivativeEstimation::None) &&
    vtkCloughTocherSplineFilter::LocalQuadratic ==
      static_cast<int>(ctk::DerivativeEstimation::LocalQuadratic) &&
    vtkCloughTocherSplineFilter::MinimumEnergy ==
      static_cast<int>(ctk::DerivativeEstimation::MinimumEnergy),
  "vtkCloughTocherSplineFilter::DerivativeEstimationType and ctk::DerivativeEstimation differ");

namespace
{
const ctk::ConstructionInfo* Row(int c)
{
  return ctk::IsConstruction(c) ? &ctk::Info(static_cast<ctk::Construction>(c)) : nullptr;
}

// Frees v's storage (clear() keeps it): the filter drops what later stages no longer read
// before it allocates more (peak memory).
template <typename Vector>
void Release(Vector& v)
{
  Vector().swap(v);
}
} // namespace

void vtkCloughTocherSplineFilter::SetRetainedMemoryLimit(vtkTypeUInt64 bytes)
{
  ctk::SetLargeBlockCacheLimit(static_cast<std::size_t>(bytes));
}

vtkTypeUInt64 vtkCloughTocherSplineFilter::GetRetainedMemoryLimit()
{
  return ctk::LargeBlockCacheLimit();
}

vtkTypeUInt64 vtkCloughTocherSplineFilter::GetRetainedMemory()
{
  return ctk::LargeBlockCacheBytes();
}

void vtkCloughTocherSplineFilter::ReleaseRetainedMemory()
{
  ctk::ReleaseLargeBlockCache();
}

int vtkCloughTocherSplineFilter::GetNumberOfConstructions()
{
  return ctk::NumberOfConstructions;
}

const char* vtkCloughTocherSplineFilter::GetConstructionName(int c)
{
  return Row(c) ? Row(c)->Name : "Unknown";
}

int vtkCloughTocherSplineFilter::GetConstructionValue(const char* name)
{
  ctk::Construction c;
  return name && ctk::FindConstruction(name, c) ? static_cast<int>(c) : -1;
}

const char* vtkCloughTocherSplineFilter::GetConstructionSummary(int c)
{
  return Row(c) ? Row(c)->Summary : "";
}

int vtkCloughTocherSplineFilter::GetConstructionDegree(int c)
{
  return Row(c) ? Row(c)->Degree : 0;
}

bool vtkCloughTocherSplineFilter::GetConstructionTakesBoundaryCurves(int c)
{
  return Row(c) && Row(c)->TakesBoundaryCurves;
}

bool vtkCloughTocherSplineFilter::GetConstructionCanBeStitched(int c)
{
  return Row(c) && ctk::CanBeStitched(Row(c)->Method);
}

bool vtkCloughTocherSplineFilter::GetConstructionHasBezierExtraction(int c)
{
  return Row(c) && Row(c)->HasBezierExtraction;
}


const char* vtkCloughTocherSplineFilter::GetSplitPointName(int s)
{
  return ctk::ToString(static_cast<ctk::SplitPointRule>(s));
}

const char* vtkCloughTocherSplineFilter::GetBoundaryModeName(int m)
{
  return ctk::ToString(static_cast<ctk::BoundaryMode>(m));
}

const char* vtkCloughTocherSplineFilter::GetDerivativeEstimationName(int method)
{
  return method >= NoEstimation && method <= MinimumEnergy
    ? ctk::ToString(static_cast<ctk::DerivativeEstimation>(method))
    : "Unknown";
}

int vtkCloughTocherSplineFilter::GetRequiredGhostLevels() const
{
  return ctk::RequiredGhostRings(static_cast<ctk::Construction>(this->Construction), this->Iterations) +
    (this->DerivativeEstimation != NoEstimation ? ctk::MaxEstimationRings : 0);
}

int vtkCloughTocherSplineFilter::RequestUpdateExtent(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  using SDDP = vtkStreamingDemandDrivenPipeline;
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  inInfo->Set(SDDP::UPDATE_PIECE_NUMBER(), outInfo->Get(SDDP::UPDATE_PIECE_NUMBER()));
  inInfo->Set(SDDP::UPDATE_NUMBER_OF_PIECES(), outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES()));
  inInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(),
    outInfo->Get(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS()) + this->GetRequiredGhostLevels());
  return 1;
}

int vtkCloughTocherSplineFilter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  info->Append(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkUnstructuredGrid");
  return 1;
}

namespace
{
// Cell and field data of the Bézier extraction (see ComputeBezierExtraction).
void AddBezierExtraction(vtkUnstructuredGrid* output,
  const ctk::SplineData& data, const ctk::MeshTopology& topology,
  const ctk::BezierExtraction& extraction, const std::vector<ctk::Id>* keptTriangles)
{
  constexpr int M = ctk::BezierExtraction::MaxElementDofs;
  const vtkIdType nCells = output->GetNumberOfCells();
  vtkNew<vtkIdTypeArray> dofIds;
  dofIds->SetName("GlobalDofIds");
  dofIds->SetNumberOfComponents(M);
  dofIds->SetNumberOfTuples(nCells);
  vtkNew<vtkDoubleArray> operators;
  operators->SetName("BezierExtraction");
  operators->SetNumberOfComponents(10 * M);
  operators->SetNumberOfTuples(nCells);
  // Kernel rows are in canonical order; the cell's points are in VTK order. Output cell 3 i + k
  // is micro-triangle k of the i-th written kernel triangle (FillSplineGrid), the kernel's cell
  // 3 t + k (ghosts are not written).
  static constexpr std::array<int, 10> vtkOrder = ctk::VtkBezierTriangleOrderOf<3>();
  ctsplines::ParallelFor(0, nCells, ctsplines::GrainForEvaluations, [&](vtkIdType b, vtkIdType e) {
    for (vtkIdType c = b; c < e; ++c)
    {
      const vtkIdType k = 3 * (keptTriangles ? (*keptTriangles)[c / 3] : c / 3) + c % 3;
      std::copy_n(&extraction.CellDofs[k * M], M, dofIds->GetPointer(c * M));
      const double* op = &extraction.CellOperators[k * 10 * M];
      double* out = operators->GetPointer(c * 10 * M);
      for (int row = 0; row < 10; ++row)
      {
        std::copy_n(op + vtkOrder[row] * M, M, out + row * M);
      }
    }
  });
  output->GetCellData()->AddArray(dofIds);
  output->GetCellData()->AddArray(operators);

  vtkNew<vtkIdTypeArray> count;
  count->SetName("NumberOfDofs");
  count->InsertNextValue(extraction.NumberOfDofs);
  output->GetFieldData()->AddArray(count);
  vtkNew<vtkIdTypeArray> edgeDofs;
  edgeDofs->SetName("EdgeDofIds");
  edgeDofs->SetNumberOfComponents(3);
  edgeDofs->SetNumberOfTuples(static_cast<vtkIdType>(topology.Edges.size()));
  for (size_t e = 0; e < topology.Edges.size(); ++e)
  {
    const vtkIdType t[3] = { topology.Edges[e][0], topology.Edges[e][1], extraction.EdgeDofs[e] };
    edgeDofs->SetTypedTuple(static_cast<vtkIdType>(e), t);
  }
  output->GetFieldData()->AddArray(edgeDofs);
  const std::vector<ctk::Vec3> dofs = ctk::DegreesOfFreedom(data, topology, extraction);
  vtkNew<vtkDoubleArray> dofValues;
  dofValues->SetName("DegreesOfFreedom");
  dofValues->SetNumberOfComponents(3);
  dofValues->SetNumberOfTuples(static_cast<vtkIdType>(dofs.size()));
  for (size_t j = 0; j < dofs.size(); ++j)
  {
    dofValues->SetTuple(static_cast<vtkIdType>(j), dofs[j].data());
  }
  output->GetFieldData()->AddArray(dofValues);
}

void AddFieldString(vtkFieldData* fd, const char* name, const char* value)
{
  vtkNew<vtkStringArray> a;
  a->SetName(name);
  a->InsertNextValue(value);
  fd->AddArray(a);
}
} // namespace

namespace
{
// The names of the constructions for which which(value) holds, comma separated.
std::string ConstructionNames(bool (*which)(int))
{
  std::string names;
  for (int c = 0; c < ctk::NumberOfConstructions; ++c)
  {
    if (which(c))
    {
      names += (names.empty() ? "" : ", ") + std::string(ctk::ToString(static_cast<ctk::Construction>(c)));
    }
  }
  return names;
}

// Whether the derivatives are estimated: asked for, and dFdu or dFdv missing.
bool EstimatesDerivatives(vtkPointData* pd, vtkCloughTocherSplineFilter* self)
{
  return self->GetDerivativeEstimation() != vtkCloughTocherSplineFilter::NoEstimation &&
    (!ctsplines::FindArray(pd, self->GetDuArrayName()) || !ctsplines::FindArray(pd, self->GetDvArrayName()));
}

// 1. Validate the input and map its mesh and arrays to the kernel's owning input (the
// derivatives stay empty when they are to be estimated).
std::string ReadSplineInput(vtkPointSet* input, vtkCloughTocherSplineFilter* self,
  const ctk::SplineOptions& options, ctk::SplineInput& in)
{
  const vtkIdType nPoints = input->GetNumberOfPoints(), nCells = input->GetNumberOfCells();
  if (nPoints == 0 || nCells == 0)
  {
    return "empty input: " + std::to_string(nPoints) + " points and " + std::to_string(nCells) +
      " cells; need a triangle mesh";
  }
  vtkPolyData* polyInput = vtkPolyData::SafeDownCast(input);
  std::string error = polyInput
    ? ctsplines::ExtractTriangles(polyInput, in.Triangles)
    : ctsplines::ExtractTriangles(vtkUnstructuredGrid::SafeDownCast(input), in.Triangles);
  if (error.empty())
  {
    error = ctsplines::CopyPoints(input->GetPoints(), in.F);
  }
  vtkPointData* pd = input->GetPointData();
  const std::string uvName = self->GetUVArrayName();
  if (error.empty())
  {
    vtkDataArray* uv = ctsplines::FindArray(pd, uvName);
    std::string what = "point data array '" + uvName + "' (parameter coordinates)";
    if (!uv && pd->GetTCoords())
    {
      uv = pd->GetTCoords();
      what = std::string("active texture coordinates '") +
        (uv->GetName() ? uv->GetName() : "") + "' (parameter coordinates)";
    }
    error = uv ? ctsplines::CopyArray(uv, what, 2, nPoints, "point", in.UV)
               : "no parameter coordinates: point data array '" + uvName +
        "' is missing and there are no active texture coordinates";
  }
  const std::string du = self->GetDuArrayName(), dv = self->GetDvArrayName();
  const bool estimate = EstimatesDerivatives(pd, self);
  auto readDerivative = [&](const std::string& name, const char* what,
                          ctk::OverwriteVector<double>& values) {
    if (!error.empty() || estimate)
    {
      return;
    }
    vtkDataArray* a = ctsplines::FindArray(pd, name);
    error = ctsplines::CopyArray(
      a, "point data array '" + name + "' (derivative " + what + ")", 3, nPoints, "point", values);
    if (!a)
    {
      error += " (DerivativeEstimation LocalQuadratic or MinimumEnergy estimates the derivatives)";
    }
  };
  readDerivative(du, "d/du", in.Fu);
  readDerivative(dv, "d/dv", in.Fv);
  const ctk::ConstructionInfo& info = ctk::Info(options.Method);
  const std::string egName = self->GetEdgeGradientsArrayName();
  if (error.empty() && ctk::UsesEdgeGradients(options))
  {
    const std::string what = "cell data array '" + egName + "' (mid-edge gradients, needed by " +
      info.Name + " with boundary mode " +
      vtkCloughTocherSplineFilter::GetBoundaryModeName(self->GetBoundaryMode()) + ")";
    // Read in place: the construction reads them through a row map (SplineInput::Renumber) and
    // checks the values it reads (all for MGo and MGi, the boundary edges' for the others).
    error = ctsplines::ShareOrCopyArray(ctsplines::FindArray(input->GetCellData(), egName), what,
      18, nCells, "cell", in.EdgeGradients, in.SharedEdgeGradients);
    in.SharedEdgeGradients = in.EdgeGradients.empty() ? in.SharedEdgeGradients : nullptr;
  }
  const std::string curves = self->GetBoundaryCurvePointsArrayName();
  if (error.empty() && !curves.empty())
  {
    const std::string what = "cell data array '" + curves + "' (boundary curve points)";
    if (!info.TakesBoundaryCurves)
    {
      error = what + " is given, but " + info.Name + " does not take prescribed boundary curves (" +
        ConstructionNames(&vtkCloughTocherSplineFilter::GetConstructionTakesBoundaryCurves) +
        " do)";
    }
    else if (self->GetComputeBezierExtraction())
    {
      error = what + " is given: the Bezier extraction is of the unconstrained spline space";
    }
    else
    {
      error = ctsplines::CopyArray(ctsplines::FindArray(input->GetCellData(), curves), what, 18,
        nCells, "cell", in.BoundaryCurvePoints, 6);
    }
  }
  // CopyArray checked every value it copied (estimated derivatives are not copied).
  in.ValuesChecked = error.empty() && !estimate;
  return error;
}

// Distributed runs: the global cell ids and ghost flags, read per input cell.
std::string ReadPieceArrays(vtkPointSet* input, std::vector<vtkIdType>& globalIds,
  vtkDataArray*& globalIdArray, vtkUnsignedCharArray*& ghosts)
{
  const vtkIdType nCells = input->GetNumberOfCells();
  globalIdArray = input->GetCellData()->GetGlobalIds();
  std::string error;
  if (globalIdArray)
  {
    error = ctsplines::CopyIdArray(globalIdArray,
      std::string("cell data global ids '") + (globalIdArray->GetName() ? globalIdArray->GetName() : "") + "'",
      nCells, "cell", -1, globalIds);
  }
  ghosts = input->GetCellGhostArray();
  if (error.empty() && ghosts)
  {
    error = ctsplines::CheckTuples(ghosts, "cell ghost array 'vtkGhostType'", nCells, "cell");
  }
  return error;
}

// The kernel's control and domain points become the output's arrays without a copy (half the
// construction's memory, and no second first touch of it). VTK releases an array's storage
// through a plain function pointer, so the vectors are kept here, by their data pointer, until
// VTK releases it. The registry is never destroyed: arrays may outlive static destruction.
class AdoptedVectors
{
public:
  /// A double array of `components` per element that owns v's storage (v is left empty).
  template <typename Vec>
  static vtkSmartPointer<vtkDoubleArray> Adopt(ctk::OverwriteVector<Vec>&& v, int components)
  {
    static_assert(sizeof(Vec) == sizeof(double) * Vec::SizeAtCompileTime, "packed vectors");
    auto array = vtkSmartPointer<vtkDoubleArray>::New();
    array->SetNumberOfComponents(components);
    if (v.empty())
    {
      return array;
    }
    auto kept = std::make_shared<ctk::OverwriteVector<Vec>>(std::move(v));
    double* data = kept->data()->data();
    {
      std::lock_guard<std::mutex> lock(Registry().Mutex);
      Registry().Kept[data] = Entry{ kept, Vec::SizeAtCompileTime };
    }
    array->SetArray(data, static_cast<vtkIdType>(components * kept->size()), 0,
      vtkAbstractArray::VTK_DATA_ARRAY_USER_DEFINED);
    array->SetArrayFreeFunction(&AdoptedVectors::Release);
    return array;
  }

  /// Moves into v the vector of a double array of Vec that Adopt made and that only recycled
  /// references (ctsplines::RecycledArrays), for the kernel to write again; v is left as it is
  /// when there is none. The array, released with it, no longer owns the storage.
  template <typename Vec>
  static void Reclaim(ctsplines::RecycledArrays& recycled, ctk::OverwriteVector<Vec>& v)
  {
    constexpr int components = Vec::SizeAtCompileTime;
    auto adopted = [](vtkDataArray* a) {
      if (!vtkDoubleArray::SafeDownCast(a) || a->GetNumberOfComponents() != components ||
        a->GetNumberOfTuples() == 0)
      {
        return false;
      }
      std::lock_guard<std::mutex> lock(Registry().Mutex);
      auto it = Registry().Kept.find(a->GetVoidPointer(0));
      return it != Registry().Kept.end() && it->second.Components == components;
    };
    vtkSmartPointer<vtkDataArray> array = recycled.Take(adopted);
    if (!array)
    {
      return;
    }
    {
      std::lock_guard<std::mutex> lock(Registry().Mutex);
      auto it = Registry().Kept.find(array->GetVoidPointer(0));
      if (it == Registry().Kept.end())
      {
        return;
      }
      v = std::move(*std::static_pointer_cast<ctk::OverwriteVector<Vec>>(it->second.Vector));
      Registry().Kept.erase(it);
    }
    // Release() finds nothing now: the array lets go of the storage without freeing it.
    vtkDoubleArray::SafeDownCast(array)->SetArray(nullptr, 0, 1);
  }

private:
  struct Entry
  {
    std::shared_ptr<void> Vector; // a ctk::OverwriteVector<Vec>
    int Components;               // Vec's size: the vector's type
  };
  struct Store
  {
    std::mutex Mutex;
    std::unordered_map<void*, Entry> Kept;
  };
  static Store& Registry()
  {
    static Store* store = new Store;
    return *store;
  }
  static void Release(void* data)
  {
    std::shared_ptr<void> last; // freed outside the lock
    std::lock_guard<std::mutex> lock(Registry().Mutex);
    auto it = Registry().Kept.find(data);
    if (it != Registry().Kept.end())
    {
      last = std::move(it->second.Vector);
      Registry().Kept.erase(it);
    }
  }
};

} // namespace

namespace
{
// The number of points marked in `used`. A function of its own: summed into a variable that the
// renumbering's lambda captures, the count went through memory at every point (12 ms of a 0.19 s
// piece of 5e5 triangles).
vtkIdType CountUsed(const std::vector<std::atomic<unsigned char>>& used)
{
  vtkIdType count = 0;
  for (const std::atomic<unsigned char>& u : used)
  {
    count += u.load(std::memory_order_relaxed);
  }
  return count;
}

// The ranges of the control and domain points marked in `used`, from the kernel's ranges of
// each block of points (CubicSpline::BlockRanges): a block whose points are all used gives its
// own; only the others, which hold points that only ghost cells use (a thin band along a
// piece's border, a few per cent of the blocks in the locality order), are scanned again, their
// used points only. Scanning every kept point again cost about 3 % of a piece's spline.
// Ranges of no components (nothing stored) when the blocks do not cover the points.
std::array<ctk::PointRanges, 2> UsedPointRanges(
  const ctk::CubicSpline& cubic, const std::vector<std::atomic<unsigned char>>& used)
{
  const std::vector<ctk::PointBlockRanges>& blocks = cubic.BlockRanges;
  const vtkIdType n = static_cast<vtkIdType>(used.size());
  vtkIdType covered = 0;
  for (const ctk::PointBlockRanges& b : blocks)
  {
    covered += b.First >= 0 && b.Count >= 0 && b.First + b.Count <= n ? b.Count : n + 1;
  }
  if (blocks.empty() || covered != n || static_cast<vtkIdType>(cubic.ControlPoints.size()) != n ||
    static_cast<vtkIdType>(cubic.DomainPoints.size()) != n)
  {
    return {};
  }
  const double* points = cubic.ControlPoints.data()->data();
  const double* domain = cubic.DomainPoints.data()->data();
  // The marks' bytes, read after the threads that set them have joined: memchr finds a block's
  // first unused point 16 or 32 marks at a time (one atomic load a mark took 1.5 % of the piece).
  static_assert(sizeof(std::atomic<unsigned char>) == 1, "one byte per mark");
  const unsigned char* marks = reinterpret_cast<const unsigned char*>(used.data());
  const auto isUsed = [marks](vtkIdType p) { return marks[p] != 0; };
  std::array<ctk::PointRanges, 2> result{ ctk::PointRanges(3), ctk::PointRanges(2) };
  std::mutex merge;
  const auto scan = [&](vtkIdType b0, vtkIdType b1) {
    std::array<ctk::PointRanges, 2> whole{ ctk::PointRanges(3), ctk::PointRanges(2) };
    ctk::PointRangeScan pointScan(3), domainScan(2); // the used points of the other blocks
    for (vtkIdType k = b0; k < b1; ++k)
    {
      const ctk::PointBlockRanges& b = blocks[k];
      const vtkIdType end = b.First + b.Count;
      if (!std::memchr(marks + b.First, 0, static_cast<size_t>(b.Count)))
      {
        whole[0].Merge(b.Points);
        whole[1].Merge(b.Domain);
        continue;
      }
      for (vtkIdType p = b.First; p < end;) // each run of used points
      {
        while (p < end && !isUsed(p))
        {
          ++p;
        }
        vtkIdType q = p;
        while (q < end && isUsed(q))
        {
          ++q;
        }
        pointScan.Add(points + 3 * p, q - p);
        domainScan.Add(domain + 2 * p, q - p);
        p = q;
      }
    }
    whole[0].Merge(pointScan.Result());
    whole[1].Merge(domainScan.Result());
    std::lock_guard<std::mutex> lock(merge);
    result[0].Merge(whole[0]);
    result[1].Merge(whole[1]);
  };
  ctsplines::ParallelFor(
    0, static_cast<vtkIdType>(blocks.size()), ctsplines::GrainForEvaluations, scan);
  return result;
}

// The first connectivity entry that can name a point at or past `point`. The points are numbered
// vertices, edges, then pointsPerTriangle of each macro-triangle (the kernel's layouts), which
// only the triangle's own cells name; the written triangles are in increasing order (0 when they
// are not, or when `point` is a vertex's or an edge's).
vtkIdType FirstEntryNaming(vtkIdType point, vtkIdType nPoints, vtkIdType nTriangles,
  int pointsPerTriangle, const std::vector<ctk::Id>& written, vtkIdType entriesPerTriangle)
{
  const vtkIdType firstTrianglePoint = nPoints - pointsPerTriangle * nTriangles;
  if (point < firstTrianglePoint || !std::is_sorted(written.begin(), written.end()))
  {
    return 0;
  }
  const ctk::Id t = (point - firstTrianglePoint) / pointsPerTriangle;
  const auto from = std::lower_bound(written.begin(), written.end(), t);
  return entriesPerTriangle * static_cast<vtkIdType>(from - written.begin());
}

// Keeps the `kept` points marked in `used` and renumbers the nConn connectivity entries that can
// name the others (FirstEntryNaming). Ghost triangles' micro-cells are never written, so the
// unused points are the few that only ghosts have (a thin band along the piece's border): each
// used point past the kept count fills the first free hole below it, and only the entries naming
// those points change, which only the last triangles' cells can. (Shifting every point down
// instead moved all of them, 272 MB at 1e6 triangles, and rewrote every entry: a piece's spline
// cost 30 % more than its share of the whole's; checking every entry cost 4.4 % of a piece.)
template <typename CellId>
void KeepUsedPoints(CellId* conn, vtkIdType nConn, vtkIdType kept,
  const std::vector<std::atomic<unsigned char>>& used, ctk::OverwriteVector<ctk::Vec3>& points,
  ctk::OverwriteVector<ctk::Vec2>& uv)
{
  const vtkIdType n = static_cast<vtkIdType>(points.size());
  std::vector<vtkIdType> moved(static_cast<size_t>(n - kept), -1); // new id of point kept + j
  vtkIdType hole = 0;
  for (vtkIdType p = kept; p < n; ++p)
  {
    if (used[p])
    {
      while (used[hole])
      {
        ++hole;
      }
      points[hole] = points[p];
      uv[hole] = uv[p];
      moved[p - kept] = hole++;
    }
  }
  points.resize(kept);
  uv.resize(kept);
  ctsplines::ParallelFor(0, nConn, ctsplines::GrainForCopies, [&](vtkIdType b, vtkIdType e) {
    const CellId first = static_cast<CellId>(kept); // a local: conn's entries could alias it
    const vtkIdType* to = moved.data();
    for (vtkIdType a = b; a < e; ++a)
    {
      if (conn[a] >= first)
      {
        conn[a] = static_cast<CellId>(to[conn[a] - first]);
      }
    }
  });
}
} // namespace

namespace
{
// The connectivity of cells 3 i + k of the i-th written triangle (keptTriangles[i], or i), in
// the storage's id type; marks the points they use in `used` when it is not empty. The degree
// is a template argument: the cells' sizes are then constants, and the copies unrolled.
template <int Degree, typename CellId>
void WriteSplineConnectivity(const ctk::CloughTocherSpline& spline,
  const ctk::MeshTopology& topology, const ctk::SplineInput& in,
  const std::vector<ctk::Id>* keptTriangles, vtkIdType nT, CellId* offsets,
  CellId* connectivity, std::vector<std::atomic<unsigned char>>& used)
{
  constexpr int n = ctk::BezierPointCount(Degree);
  // A constant: each entry of a cell is then copied from its net's entry, without a look-up.
  static constexpr std::array<int, n> o = ctk::VtkBezierTriangleOrderOf<Degree>();
  ctsplines::ParallelFor(0, nT, ctsplines::GrainForEvaluations, [&](vtkIdType b, vtkIdType e) {
    // Locals: the entries written could alias the captured pointers, which the loops would
    // otherwise load again for every entry.
    CellId* const conn = connectivity;
    CellId* const offs = offsets;
    std::atomic<unsigned char>* mark = used.empty() ? nullptr : used.data();
    const ctk::Id* triangles = in.Triangles.data();
    for (vtkIdType i = b; i < e; ++i)
    {
      const vtkIdType t = keptTriangles ? (*keptTriangles)[i] : i;
      const auto nets = spline.MicroNets<Degree>(topology, triangles, t);
      for (int k = 0; k < 3; ++k)
      {
        const vtkIdType c = 3 * i + k;
        CellId* cell = conn + n * c;
        for (int a = 0; a < n; ++a)
        {
          cell[a] = static_cast<CellId>(nets[k][o[a]]);
        }
        for (int a = 0; mark && a < n; ++a)
        {
          mark[nets[k][a]].store(1, std::memory_order_relaxed);
        }
        offs[c] = static_cast<CellId>(n * c);
      }
    }
  });
  offsets[3 * nT] = static_cast<CellId>(n * 3 * nT);
}

// The cell data of the same cells: type, MacroTriangleId (the caller's triangle id) and
// MicroTriangleId. Returns the extremes of the MacroTriangleIds written (for their stored range:
// a scan of its own cost 1 % of CTi at 1e6 triangles).
std::array<vtkIdType, 2> WriteSplineCellData(const std::vector<ctk::Id>* keptTriangles,
  const std::vector<ctk::Id>* inputTriangles, vtkIdType nT, unsigned char* types,
  vtkIdType* macroIds, signed char* microIds)
{
  std::array<vtkIdType, 2> extremes{ VTK_ID_MAX, VTK_ID_MIN };
  std::mutex merge;
  ctsplines::ParallelFor(0, nT, ctsplines::GrainForCopies, [&](vtkIdType b, vtkIdType e) {
    vtkIdType lo = VTK_ID_MAX, hi = VTK_ID_MIN;
    for (vtkIdType i = b; i < e; ++i)
    {
      const vtkIdType t = keptTriangles ? (*keptTriangles)[i] : i;
      const vtkIdType macro = inputTriangles ? (*inputTriangles)[t] : t;
      lo = std::min(lo, macro);
      hi = std::max(hi, macro);
      for (int k = 0; k < 3; ++k)
      {
        types[3 * i + k] = VTK_BEZIER_TRIANGLE;
        macroIds[3 * i + k] = macro;
        microIds[3 * i + k] = static_cast<signed char>(k);
      }
    }
    std::lock_guard<std::mutex> lock(merge);
    extremes = { std::min(extremes[0], lo), std::max(extremes[1], hi) };
  });
  return extremes;
}

} // namespace

namespace ctsplines
{
// 3. The output: shared control points with their domain points, three Bézier cells per
// triangle with MacroTriangleId and MicroTriangleId. Consumes the spline's points.
void FillSplineGrid(ctk::CloughTocherSpline& spline, const ctk::MeshTopology& topology,
  const ctk::SplineInput& in, const char* uvName, vtkUnstructuredGrid* output,
  const std::vector<ctk::Id>* keptTriangles, const std::vector<ctk::Id>* inputTriangles,
  const std::function<void()>& connectivityWritten)
{
  ctk::CubicSpline& cubic = spline.Cubic;
  ctk::QuarticSpline& quartic = spline.Quartic;
  Release(spline.Degree == 4 ? quartic.SplitTau : cubic.SplitTau);
  ctk::OverwriteVector<ctk::Vec3>& controlPoints =
    spline.Degree == 4 ? quartic.ControlPoints : cubic.ControlPoints;
  ctk::OverwriteVector<ctk::Vec2>& domainPoints =
    spline.Degree == 4 ? quartic.DomainPoints : cubic.DomainPoints;

  const vtkIdType perCell = ctk::BezierPointCount(spline.Degree);
  const vtkIdType nT =
    keptTriangles ? static_cast<vtkIdType>(keptTriangles->size()) : in.NumberOfTriangles();
  const vtkIdType nCells = 3 * nT;
  vtkSmartPointer<vtkCellArray> cells = ctsplines::NewCellArray(
    nCells, perCell * nCells, static_cast<vtkIdType>(controlPoints.size()));
  // With ghosts, the points the written cells use (threads may mark a point together).
  std::vector<std::atomic<unsigned char>> used(keptTriangles ? controlPoints.size() : 0);
  std::array<ctk::PointRanges, 2> keptRanges; // of the points kept: with ghosts, from the blocks
  const auto write = [&](auto* offsets, auto* connectivity) {
    if (spline.Degree == 4)
    {
      WriteSplineConnectivity<4>(spline, topology, in, keptTriangles, nT, offsets, connectivity, used);
    }
    else
    {
      WriteSplineConnectivity<3>(spline, topology, in, keptTriangles, nT, offsets, connectivity, used);
    }
    if (keptTriangles)
    {
      if (spline.Degree == 3)
      {
        keptRanges = UsedPointRanges(cubic, used);
      }
      const vtkIdType kept = CountUsed(used);
      const vtkIdType first = spline.Degree == 4
        ? FirstEntryNaming(kept, controlPoints.size(), quartic.Layout.NumberOfTriangles,
            quartic.Layout.PointsPerTriangle, *keptTriangles, 3 * perCell)
        : FirstEntryNaming(kept, controlPoints.size(), cubic.Layout.NumberOfTriangles,
            cubic.Layout.PointsPerTriangle, *keptTriangles, 3 * perCell);
      KeepUsedPoints(connectivity + first, perCell * nCells - first, kept, used, controlPoints,
        domainPoints);
    }
  };
  if (cells->IsStorage64Bit())
  {
    write(cells->GetOffsetsArray64()->GetPointer(0), cells->GetConnectivityArray64()->GetPointer(0));
  }
  else
  {
    write(cells->GetOffsetsArray32()->GetPointer(0), cells->GetConnectivityArray32()->GetPointer(0));
  }
  Release(used);
  if (connectivityWritten)
  {
    connectivityWritten(); // in and topology are not read from here on
  }
  vtkNew<vtkUnsignedCharArray> types;
  ctsplines::AllocateTuples(types, nCells);
  vtkNew<vtkIdTypeArray> macroIds;
  macroIds->SetName("MacroTriangleId");
  ctsplines::AllocateTuples(macroIds, nCells);
  vtkNew<vtkSignedCharArray> microIds;
  microIds->SetName("MicroTriangleId");
  ctsplines::AllocateTuples(microIds, nCells);
  const std::array<vtkIdType, 2> macroRange = WriteSplineCellData(keptTriangles, inputTriangles,
    nT, types->GetPointer(0), macroIds->GetPointer(0), microIds->GetPointer(0));
  vtkSmartPointer<vtkDoubleArray> coords = AdoptedVectors::Adopt(std::move(controlPoints), 3);
  vtkSmartPointer<vtkDoubleArray> uvOut = AdoptedVectors::Adopt(std::move(domainPoints), 2);
  uvOut->SetName(uvName);

  vtkNew<vtkPoints> points;
  points->SetData(coords);
  output->SetPoints(points);
  // No faces: the two-argument overload scans every cell type for polyhedra, serially (1.5-4 ms
  // at 1e6 cells, 1-2 % of CTi on two threads). VTK 9.4 renamed the overload without the scan.
#if VTK_MAJOR_VERSION > 9 || (VTK_MAJOR_VERSION == 9 && VTK_MINOR_VERSION >= 4)
  output->SetPolyhedralCells(types, cells, nullptr, nullptr);
#else
  output->SetCells(types, cells, nullptr, nullptr);
#endif
  output->GetPointData()->AddArray(uvOut);
  output->GetCellData()->AddArray(macroIds);
  output->GetCellData()->AddArray(microIds);
  // The ids as written, no scan of their own (nothing is stored for no cells).
  ctsplines::StoreRange(macroIds, double(macroRange[0]), double(macroRange[1]));
  ctsplines::StoreRange(microIds, 0.0, 2.0);
  if (spline.Degree == 3) // the points as written and scanned by the kernel
  {
    // After SetData, which names the points' array (and so modifies it).
    ctsplines::StoreRanges(coords, keptTriangles ? keptRanges[0] : cubic.ControlPointRanges);
    ctsplines::StoreRanges(uvOut, keptTriangles ? keptRanges[1] : cubic.DomainPointRanges);
  }
}
} // namespace ctsplines

namespace
{
// A kernel message (status: BuildStatus or TopologyStatus) naming the input's cells and points.
// The kernel numbers its triangles and vertices: kernel triangle t is input cell
// cells[order.Triangles[t]] (repeated ghosts dropped, then renumbered; either map empty: the
// identity) and kernel vertex v is input point order.Vertices[v] (points are never dropped).
template <typename Status>
std::string InInputIds(const Status& status, const std::vector<ctk::Id>& cells,
  const ctk::LocalityRenumbering& order)
{
  auto map = [](const auto& m, ctk::Id id) { // cells or order.Triangles; order.Vertices
    return id >= 0 && static_cast<size_t>(id) < m.size() ? m[id] : id;
  };
  return ctk::RenameIds(status.Message, status.Ids, [&](ctk::IdKind kind, ctk::Id id) {
    return kind == ctk::IdKind::Vertex ? map(order.Vertices, id)
                                       : map(cells, map(order.Triangles, id));
  });
}

// 2. The topology, the estimated derivatives (estimation: NoEstimation or the method; in the
// input's numbering, so that their bits do not depend on the order) and the kernel's spline,
// built in the locality order when renumber is set and the mesh large enough (in is then left
// renumbered by order). An error message naming input cells and points (cells: the input cell
// of each triangle of in, see InInputIds), or empty.
std::string BuildSpline(ctk::SplineInput& in, const std::vector<ctk::Id>& cells,
  const ctk::SplineOptions& options, int estimation, bool renumber,
  ctk::LocalityRenumbering& order, ctk::MeshTopology& topology, ctk::CloughTocherSpline& spline,
  std::string& warning)
{
  order = ctk::LocalityRenumbering();
  auto buildTopology = [&]() -> std::string {
    // Each edge's triangles in the input's order, as the constructions read them: same bits.
    const ctk::TopologyStatus topo = ctk::BuildMeshTopology(in.NumberOfVertices(),
      in.NumberOfTriangles(), in.Triangles.data(), topology, ctsplines::SMPCopyFor,
      order.Triangles.empty() ? nullptr : order.Triangles.data());
    return topo.Ok ? std::string() : "invalid mesh: " + InInputIds(topo, cells, order);
  };
  std::string error;
  if (estimation != vtkCloughTocherSplineFilter::NoEstimation)
  {
    if (!(error = buildTopology()).empty())
    {
      return error;
    }
    in.Fu.assign(in.F.size(), 0.0);
    in.Fv.assign(in.F.size(), 0.0);
    const ctk::BuildStatus est = ctk::EstimateDerivatives(in.View(), topology,
      static_cast<ctk::DerivativeEstimation>(estimation), in.Fu.data(), in.Fv.data(),
      ctsplines::SMPFor);
    if (!est.Ok)
    {
      return InInputIds(est, cells, order);
    }
  }
  if (renumber)
  {
    order = in.RenumberToLocalityOrder(ctsplines::SMPCopyFor);
  }
  if ((estimation == vtkCloughTocherSplineFilter::NoEstimation || !order.IsIdentity()) &&
    !(error = buildTopology()).empty())
  {
    return error;
  }
  const ctk::BuildStatus built =
    ctk::BuildCloughTocher(in.View(), topology, options, spline, ctsplines::SMPFor);
  const std::string message = InInputIds(built, cells, order);
  warning = built.Ok ? message : std::string();
  return built.Ok ? std::string() : message;
}

// Distributed runs: the n kernel triangles that are not ghosts (duplicates of another piece's),
// in the kernel's numbering (input cell order[t] for kernel triangle t; empty: the same), or
// nothing to drop.
std::vector<ctk::Id> OwnedTriangles(vtkUnsignedCharArray* ghosts, ctk::Id n,
  const std::vector<ctk::Id>& order, bool& anyGhost)
{
  std::vector<ctk::Id> owned;
  anyGhost = false;
  if (!ghosts)
  {
    return owned;
  }
  const unsigned char* flag = ghosts->GetPointer(0);
  owned.reserve(n);
  for (ctk::Id t = 0; t < n; ++t)
  {
    if (!(flag[order.empty() ? t : order[t]] & vtkDataSetAttributes::DUPLICATECELL))
    {
      owned.push_back(t);
    }
  }
  anyGhost = static_cast<ctk::Id>(owned.size()) < n;
  return owned;
}

// Distributed runs: the input cells kept as the kernel's triangles (empty: all of them). A ghost
// triangle with the same three points as an owned or earlier ghost triangle is that triangle
// received twice (ParaView 5.11's D3 sends a few ghost cells twice; each of its edges would
// have three triangles): it is dropped with its rows of the per-triangle arrays.
std::vector<ctk::Id> DropRepeatedGhosts(vtkUnsignedCharArray* ghosts, ctk::SplineInput& in)
{
  std::vector<ctk::Id> kept;
  if (!ghosts)
  {
    return kept;
  }
  const ctk::Id nT = in.NumberOfTriangles(), nV = in.NumberOfVertices();
  const unsigned char* flag = ghosts->GetPointer(0);
  auto isGhost = [&](ctk::Id t) { return (flag[t] & vtkDataSetAttributes::DUPLICATECELL) != 0; };
  // A triangle with a point out of range is neither read nor dropped: the topology names it.
  auto inRange = [&](ctk::Id t) {
    const ctk::Id* p = &in.Triangles[3 * t];
    return std::all_of(p, p + 3, [nV](ctk::Id v) { return v >= 0 && v < nV; });
  };
  // Only a triangle whose points all belong to ghost triangles can equal a ghost: the set holds
  // the thin band along the piece's border, not the piece.
  std::vector<char> ghostPoint(static_cast<size_t>(nV), 0);
  for (ctk::Id t = 0; t < nT; ++t)
  {
    for (int a = 0; a < 3 && isGhost(t) && inRange(t); ++a)
    {
      ghostPoint[in.Triangles[3 * t + a]] = 1;
    }
  }
  using Key = std::array<ctk::Id, 3>;
  struct KeyHash
  {
    size_t operator()(const Key& k) const
    {
      return std::hash<ctk::Id>()(k[0]) ^ (std::hash<ctk::Id>()(k[1]) * 0x9e3779b97f4a7c15ULL) ^
        (std::hash<ctk::Id>()(k[2]) * 0xc2b2ae3d27d4eb4fULL);
    }
  };
  std::unordered_set<Key, KeyHash> seen;
  std::vector<char> drop(static_cast<size_t>(nT), 0);
  bool anyDropped = false;
  for (const bool ghostPass : { false, true }) // owned triangles first: they are kept
  {
    for (ctk::Id t = 0; t < nT; ++t)
    {
      const ctk::Id* p = &in.Triangles[3 * t];
      if (isGhost(t) != ghostPass || !inRange(t) ||
        !(ghostPoint[p[0]] && ghostPoint[p[1]] && ghostPoint[p[2]]))
      {
        continue;
      }
      Key key{ p[0], p[1], p[2] };
      std::sort(key.begin(), key.end());
      drop[t] = !seen.insert(key).second && ghostPass;
      anyDropped = anyDropped || drop[t];
    }
  }
  if (!anyDropped)
  {
    return kept;
  }
  for (ctk::Id t = 0; t < nT; ++t)
  {
    if (!drop[t])
    {
      kept.push_back(t);
    }
  }
  auto keepRows = [&](auto& v, size_t width) {
    ctk::PermuteRows(v, width, kept, false);
    v.resize(v.empty() ? 0 : width * kept.size());
  };
  if (in.HasEdgeGradients())
  {
    keepRows(in.EdgeGradientRowMap(), 1); // its rows are the input cells'
  }
  keepRows(in.Triangles, 3);
  keepRows(in.BoundaryCurvePoints, 18);
  keepRows(in.SplitTau, 1);
  return kept;
}

// The input cell of each kernel triangle t: cells[order[t]] (either empty: the identity), or
// empty when that is t. Consumes the renumbering, which the output no longer needs.
std::vector<ctk::Id> InputCells(const std::vector<ctk::Id>& cells, ctk::LocalityRenumbering& order)
{
  std::vector<ctk::Id> triangles = std::move(order.Triangles);
  order = ctk::LocalityRenumbering();
  if (cells.empty() || triangles.empty())
  {
    if (cells.empty())
    {
      return triangles; // moved: a conditional expression would copy it (32 MB at 4e6 triangles)
    }
    return cells;
  }
  for (ctk::Id& t : triangles)
  {
    t = cells[t];
  }
  return triangles;
}

// Frees what only the construction reads before the output's cells are allocated (peak memory:
// the input's values and, for cubic splines, whose micro-nets read TriangleEdges alone, the
// topology's per-edge arrays). The cells still need the triangles.
void ReleaseBuildOnlyData(int degree, ctk::SplineInput& in, ctk::MeshTopology& topology)
{
  Release(in.UV);
  Release(in.F);
  Release(in.Fu);
  Release(in.Fv);
  Release(in.EdgeGradients);
  Release(in.BoundaryCurvePoints);
  Release(in.SplitTau);
  Release(in.EdgeGradientRows);
  in.SharedEdgeGradients = nullptr;
  if (degree == 3)
  {
    Release(topology.Edges);
    Release(topology.EdgeTriangles);
    Release(topology.EdgeLocalIndex);
  }
}

// Distributed runs: the global id of every cell's macro-triangle.
void AddMacroGlobalIds(vtkUnstructuredGrid* output, const std::vector<vtkIdType>& globalIds)
{
  const vtkIdType nCells = output->GetNumberOfCells();
  vtkIdTypeArray* macroIds =
    vtkIdTypeArray::SafeDownCast(output->GetCellData()->GetArray("MacroTriangleId"));
  vtkNew<vtkIdTypeArray> macroGlobal;
  macroGlobal->SetName("MacroTriangleGlobalId");
  macroGlobal->SetNumberOfTuples(nCells);
  for (vtkIdType c = 0; c < nCells; ++c)
  {
    macroGlobal->SetValue(c, globalIds[macroIds->GetValue(c)]);
  }
  output->GetCellData()->AddArray(macroGlobal);
}
} // namespace

int vtkCloughTocherSplineFilter::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPointSet* input = vtkPointSet::GetData(inputVector[0]);
  vtkUnstructuredGrid* output = vtkUnstructuredGrid::GetData(outputVector);
  if (!input || !output)
  {
    vtkErrorMacro(<< "missing input or output data object");
    return 0;
  }
  ctk::SplineOptions options;
  options.Method = static_cast<ctk::Construction>(this->Construction);
  options.SplitPoint = static_cast<ctk::SplitPointRule>(this->SplitPoint);
  options.Boundary = static_cast<ctk::BoundaryMode>(this->BoundaryMode);
  options.Iterations = this->Iterations;
  options.ScanRanges = true; // stored in the output's arrays (FillSplineGrid)
  // With ghost cells, the ranges of the points kept come from those of the blocks.
  options.ScanBlockRanges =
    input->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()) != nullptr;
  const ctk::ConstructionInfo& info = ctk::Info(options.Method);

  // The previous output's control and domain points, when the input has its sizes, for the
  // kernel to write again (ReuseOutputArrays). Only those: the old cells would stay resident
  // through the build, which the new ones are not (peak memory); and only for the cubic
  // constructions, whose builder writes them first (the quartic one builds a cubic spline first).
  ctk::CloughTocherSpline spline;
  ctsplines::RecycledArraysScope recycling(*this->Recycled, this->ReuseOutputArrays,
    { input->GetNumberOfPoints(), input->GetNumberOfCells(), info.Degree,
      input->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()) ? 1 : 0,
      this->ComputeBezierExtraction ? 1 : 0 });
  if (ctsplines::RecycledArrays* recycled = recycling.Get())
  {
    if (info.Degree == 3)
    {
      AdoptedVectors::Reclaim(*recycled, spline.Cubic.ControlPoints);
      AdoptedVectors::Reclaim(*recycled, spline.Cubic.DomainPoints);
    }
    recycled->ReleaseUnused();
  }

  // 1. Validate and map.
  ctk::SplineInput in;
  std::vector<vtkIdType> globalIds;
  vtkDataArray* globalIdArray = nullptr;
  vtkUnsignedCharArray* ghosts = nullptr;
  std::string error = ReadSplineInput(input, this, options, in);
  if (error.empty())
  {
    error = ReadPieceArrays(input, globalIds, globalIdArray, ghosts);
  }
  const std::vector<ctk::Id> cells = error.empty() ? DropRepeatedGhosts(ghosts, in)
                                                   : std::vector<ctk::Id>();
  if (error.empty() && this->ComputeBezierExtraction && !info.HasBezierExtraction)
  {
    error = std::string("Bézier extraction is available for ") +
      ConstructionNames(&GetConstructionHasBezierExtraction) + " only, not for " + info.Name;
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  // 2. Topology, derivatives and the kernel (which validates the values: finite, no zero-area or
  // folded triangle), in the locality order unless the input's is asked for.
  const bool estimated = EstimatesDerivatives(input->GetPointData(), this);
  const int estimation = estimated ? this->DerivativeEstimation : NoEstimation;
  ctk::LocalityRenumbering order;
  ctk::MeshTopology topology;
  std::string warning;
  const bool renumber = this->OutputOrder == LocalityOrder && !this->ComputeBezierExtraction;
  error = BuildSpline(in, cells, options, estimation, renumber, order, topology, spline, warning);
  if (!error.empty() && !order.IsIdentity())
  {
    // The kernel reports the lowest failing triangle of its numbering: built again in the
    // input's, the message is the one the input's order gives.
    in.Renumber(order, true, ctsplines::SMPCopyFor);
    error = BuildSpline(in, cells, options, estimation, false, order, topology, spline, warning);
  }
  if (!error.empty())
  {
    vtkErrorMacro(<< error);
    return 0;
  }
  if (!warning.empty())
  {
    vtkWarningMacro(<< warning); // e.g. the quartic fairing stopped early
  }
  this->UpdateProgress(0.6);
  if (this->GetAbortExecute())
  {
    return 1;
  }
  if (!this->ComputeBezierExtraction)
  {
    ReleaseBuildOnlyData(spline.Degree, in, topology);
  }

  // 3. Fill the output.
  bool anyGhost = false;
  const std::vector<ctk::Id> inputCells = InputCells(cells, order);
  const std::vector<ctk::Id> owned =
    OwnedTriangles(ghosts, in.NumberOfTriangles(), inputCells, anyGhost);
  // Without the Bézier extraction nothing reads the triangles and the topology once the cells'
  // connectivity is written: freed before the cell data is allocated (peak memory).
  const auto releaseMesh = [&]() {
    Release(in.Triangles);
    topology = ctk::MeshTopology();
  };
  ctsplines::FillSplineGrid(spline, topology, in,
    this->UVArrayName.empty() ? "UV" : this->UVArrayName.c_str(), output,
    anyGhost ? &owned : nullptr, inputCells.empty() ? nullptr : &inputCells,
    this->ComputeBezierExtraction ? std::function<void()>() : releaseMesh);
  vtkFieldData* fd = output->GetFieldData();
  AddFieldString(fd, "Construction", GetConstructionName(this->Construction));
  AddFieldString(fd, "SplitPoint", GetSplitPointName(this->SplitPoint));
  AddFieldString(fd, "BoundaryMode", GetBoundaryModeName(this->BoundaryMode));
  AddFieldString(fd, "DerivativeEstimation",
    GetDerivativeEstimationName(estimated ? this->DerivativeEstimation : NoEstimation));
  vtkNew<vtkIntArray> iterations;
  iterations->SetName("Iterations");
  iterations->InsertNextValue(this->Iterations);
  fd->AddArray(iterations);
  if (this->ComputeBezierExtraction)
  {
    const ctk::SplineData data = in.View();
    ctk::BezierExtraction extraction;
    const ctk::BuildStatus ex =
      ctk::BuildBezierExtraction(data, topology, options, extraction, ctsplines::SMPFor);
    if (!ex.Ok)
    {
      vtkErrorMacro(<< InInputIds(ex, cells, order));
      return 0;
    }
    AddBezierExtraction(output, data, topology, extraction, anyGhost ? &owned : nullptr);
  }
  if (globalIdArray)
  {
    AddMacroGlobalIds(output, globalIds);
  }
  ctsplines::CacheRanges(output); // for ParaView's data information and colour maps
  recycling.End(
    output, ctsplines::RecycledArrays::MayKeepOutput(this, this->ReuseOutputArrays));
  this->UpdateProgress(1.0);
  return 1;
}

void vtkCloughTocherSplineFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Construction: " << GetConstructionName(this->Construction) << "\n";
  os << indent << "SplitPoint: " << GetSplitPointName(this->SplitPoint) << "\n";
  os << indent << "BoundaryMode: " << GetBoundaryModeName(this->BoundaryMode) << "\n";
  os << indent << "Iterations: " << this->Iterations << "\n";
  os << indent << "ComputeBezierExtraction: " << this->ComputeBezierExtraction << "\n";
  os << indent << "DerivativeEstimation: " << GetDerivativeEstimationName(this->DerivativeEstimation)
     << "\n";
  os << indent << "OutputOrder: " << (this->OutputOrder == InputOrder ? "Input" : "Locality") << "\n";
  os << indent << "UVArrayName: " << this->UVArrayName << "\n";
  os << indent << "DuArrayName: " << this->DuArrayName << "\n";
  os << indent << "DvArrayName: " << this->DvArrayName << "\n";
  os << indent << "EdgeGradientsArrayName: " << this->EdgeGradientsArrayName << "\n";
  os << indent << "BoundaryCurvePointsArrayName: " << this->BoundaryCurvePointsArrayName << "\n";
  os << indent << "ReuseOutputArrays: " << this->ReuseOutputArrays << "\n";
  os << indent << "RetainedMemory (process-wide): " << GetRetainedMemory() << " of "
     << GetRetainedMemoryLimit() << " bytes\n";
  os << indent << "ReusedOutputBytes: " << this->GetReusedOutputBytes() << "\n";
}
