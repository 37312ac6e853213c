// SPDX-License-Identifier: GPL-3.0-or-later
#include "CTSplinesArrayRanges.h"

#include "CTSplinesSMP.h" // for ParallelFor
#include "PointRanges.h"

#include "vtkCellData.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationInformationVectorKey.h"
#include "vtkInformationObjectBaseKey.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPoints.h"
#include "vtkSmartPointer.h"
#include "vtkType.h"
#include "vtkTypeTraits.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <type_traits>

namespace
{
// The stamp of an array whose values CacheRanges found all finite when it stored their ranges
// (FiniteRanges): the array's MTime, data pointer and number of values then, as doubles (exact
// below 2^53), in a vtkDoubleArray of 3 values. VTK's own range keys cannot tell finiteness: its
// ranges skip NaN. A key of its own kind, which vtkInformation::Copy never copies (nor, so,
// CopyInformation and DeepCopy): a stamp copied with the information to another array could
// match that array's MTime once values without the stamp's guarantee are copied into it. An
// object key, which VTK's XML and legacy writers leave out: as a double vector key it went into
// every file written from an output, and readers without this module warned about it.
class FiniteStampKey : public vtkInformationObjectBaseKey
{
public:
  FiniteStampKey()
    : vtkInformationObjectBaseKey("FINITE_STAMP", "ctsplines::CacheRanges", "vtkDoubleArray")
  {
  }
  void ShallowCopy(vtkInformation*, vtkInformation*) override {}
  void DeepCopy(vtkInformation*, vtkInformation*) override {}
};

vtkInformationObjectBaseKey* FiniteStamp()
{
  static FiniteStampKey* const key = new FiniteStampKey; // as VTK's keys: never deleted
  return key;
}

// The stamp of `array` as it is now; false when a part is not exact in a double.
bool CurrentStamp(vtkDataArray* array, double stamp[3])
{
  constexpr std::uint64_t exact = std::uint64_t(1) << 53;
  const std::uint64_t parts[3] = { static_cast<std::uint64_t>(array->GetMTime()),
    static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(array->GetVoidPointer(0))),
    static_cast<std::uint64_t>(array->GetNumberOfValues()) };
  for (int k = 0; k < 3; ++k)
  {
    if (parts[k] >= exact)
    {
      return false;
    }
    stamp[k] = static_cast<double>(parts[k]);
  }
  return true;
}

// Arrays with more components are left to VTK (the module writes at most 18: mid-edge gradients).
constexpr int MaxComponents = 32;

// Ranges of a part of an array: each component's, the squared L2 norm's, and whether a NaN was
// seen (comparisons skip it; inf shows in the extremes).
struct Ranges
{
  double Lo[MaxComponents], Hi[MaxComponents];
  double SquaredNormLo = std::numeric_limits<double>::infinity();
  double SquaredNormHi = -std::numeric_limits<double>::infinity();
  bool NaN = false;

  Ranges()
  {
    std::fill_n(this->Lo, MaxComponents, std::numeric_limits<double>::infinity());
    std::fill_n(this->Hi, MaxComponents, -std::numeric_limits<double>::infinity());
  }
  void Merge(const Ranges& o, int nc)
  {
    for (int c = 0; c < nc; ++c)
    {
      this->Lo[c] = std::min(this->Lo[c], o.Lo[c]);
      this->Hi[c] = std::max(this->Hi[c], o.Hi[c]);
    }
    this->SquaredNormLo = std::min(this->SquaredNormLo, o.SquaredNormLo);
    this->SquaredNormHi = std::max(this->SquaredNormHi, o.SquaredNormHi);
    this->NaN = this->NaN || o.NaN;
  }
};

// Tuples [b, e) of v (nc components, a constant when NC > 0). The squared norm is summed over
// the components in order, in double, as VTK sums it (this file is built without contracting
// a * b + c into fused multiply-adds, which would change its bits).
template <int NC, typename T>
void ScanTuples(const T* v, int nc, vtkIdType b, vtkIdType e, bool norms, Ranges& r)
{
  const int n = NC > 0 ? NC : nc;
  double lo[MaxComponents], hi[MaxComponents];
  std::copy_n(r.Lo, n, lo);
  std::copy_n(r.Hi, n, hi);
  double nlo = r.SquaredNormLo, nhi = r.SquaredNormHi;
  bool nan = false;
  for (vtkIdType i = b; i < e; ++i)
  {
    double s = 0.0;
    for (int c = 0; c < n; ++c)
    {
      const double x = static_cast<double>(v[i * n + c]);
      lo[c] = std::min(lo[c], x); // a NaN x is skipped: it comes second
      hi[c] = std::max(hi[c], x);
      nan |= x != x;
      s += x * x;
    }
    if (norms)
    {
      nlo = s < nlo ? s : nlo;
      nhi = s > nhi ? s : nhi;
    }
  }
  std::copy_n(lo, n, r.Lo);
  std::copy_n(hi, n, r.Hi);
  r.SquaredNormLo = nlo;
  r.SquaredNormHi = nhi;
  r.NaN = r.NaN || nan;
}

// A kernel scan's ranges (2 or 3 components) as the ranges of a part.
Ranges FromPointRanges(const ctk::PointRanges& p)
{
  Ranges r;
  std::copy_n(p.Lo, p.Components, r.Lo);
  std::copy_n(p.Hi, p.Components, r.Hi);
  r.SquaredNormLo = p.SquaredNormLo;
  r.SquaredNormHi = p.SquaredNormHi;
  r.NaN = p.NaN;
  return r;
}

// Values [b, e) of a one-component array, compared in their own type (converting every value to
// double cost 4 ns a value).
template <typename T>
void ScanValues(const T* v, vtkIdType b, vtkIdType e, Ranges& r)
{
  if constexpr (std::is_floating_point<T>::value)
  {
    ScanTuples<1>(v, 1, b, e, false, r);
  }
  else
  {
    T lo = v[b], hi = v[b];
    for (vtkIdType i = b; i < e; ++i)
    {
      lo = v[i] < lo ? v[i] : lo;
      hi = v[i] > hi ? v[i] : hi;
    }
    r.Lo[0] = std::min(r.Lo[0], static_cast<double>(lo));
    r.Hi[0] = std::max(r.Hi[0], static_cast<double>(hi));
  }
}

// Tuples [b, e) of v, by the fastest loop for its type and component count.
template <typename T>
void ScanPart(const T* values, int nc, vtkIdType b, vtkIdType e, bool norms, Ranges& part)
{
  if constexpr (std::is_same<T, double>::value)
  {
    if (norms && (nc == 2 || nc == 3)) // points and (u, v): the kernel's scan (AVX2)
    {
      part.Merge(FromPointRanges(ctk::ScanPointRanges(values + nc * b, nc, e - b)), nc);
      return;
    }
  }
  switch (nc)
  {
    case 1:
      ScanValues(values, b, e, part);
      break;
    case 2:
      ScanTuples<2>(values, nc, b, e, norms, part);
      break;
    case 3:
      ScanTuples<3>(values, nc, b, e, norms, part);
      break;
    default:
      ScanTuples<0>(values, nc, b, e, norms, part);
  }
}

// The ranges of a whole array; min and max are exact, so chunks merge in any order.
template <typename T>
Ranges ScanArray(const T* values, vtkIdType tuples, int nc, bool norms)
{
  Ranges all;
  std::mutex merge;
  ctsplines::ParallelFor(0, tuples, ctsplines::GrainForCopies, [&](vtkIdType b, vtkIdType e) {
    Ranges part;
    ScanPart(values, nc, b, e, norms, part);
    std::lock_guard<std::mutex> lock(merge);
    all.Merge(part, nc);
  });
  return all;
}

// Whether the ranges are VTK's, or nothing is stored. VTK starts from +-vtkTypeTraits<T>::Max()
// (1e299 for doubles, 1e38 for floats), which hides extremes beyond it, and the squared norms'
// from +-1e299. Inf (its finite range skips it) is beyond too. NaN, which VTK skips in both, is
// left to it as well: a component of NaN alone would need VTK's starting values.
template <typename T>
bool ComponentsLikeVTK(const Ranges& r, int nc)
{
  if constexpr (std::is_floating_point<T>::value)
  {
    const double limit = vtkTypeTraits<T>::Max();
    for (int c = 0; c < nc; ++c)
    {
      if (!(std::abs(r.Lo[c]) < limit && std::abs(r.Hi[c]) < limit)) // inf too
      {
        return false;
      }
    }
  }
  return !r.NaN;
}
bool NormsLikeVTK(const Ranges& r)
{
  return r.SquaredNormHi < vtkTypeTraits<double>::Max();
}

// Whether the information holds ranges of every kind CacheRanges stores, newer than the array.
bool RangesCached(vtkDataArray* array, bool norms)
{
  vtkInformation* info = array->GetInformation();
  if (array->GetMTime() > info->GetMTime())
  {
    return false;
  }
  for (vtkInformationInformationVectorKey* key :
    { vtkDataArray::PER_COMPONENT(), vtkDataArray::PER_FINITE_COMPONENT() })
  {
    vtkInformationVector* perComponent = info->Get(key);
    if (!perComponent ||
      perComponent->GetNumberOfInformationObjects() < array->GetNumberOfComponents())
    {
      return false;
    }
    for (int c = 0; c < array->GetNumberOfComponents(); ++c)
    {
      if (!perComponent->GetInformationObject(c)->Has(vtkDataArray::COMPONENT_RANGE()))
      {
        return false;
      }
    }
  }
  return !norms || info->Has(vtkDataArray::L2_NORM_RANGE());
}

// The finite L2 range is not stored: vtkDataArray::CopyInformation keeps that key (and drops the
// others), so arrays that VTK's filters derive from this one (thresholds, extractions) would
// report it for their own, fewer values. VTK computes it when asked.
void StoreRangeKeys(vtkDataArray* array, const Ranges& r, bool norms)
{
  const int nc = array->GetNumberOfComponents();
  vtkInformation* info = array->GetInformation();
  for (vtkInformationInformationVectorKey* key :
    { vtkDataArray::PER_COMPONENT(), vtkDataArray::PER_FINITE_COMPONENT() })
  {
    // A new vector each time (another array's information may share the old one), released by
    // FastDelete: a Delete of a vector still held looks for reference cycles, and those
    // garbage-collection passes took a tenth of converting a 2,000-face CAD model.
    vtkInformationVector* perComponent = vtkInformationVector::New();
    perComponent->SetNumberOfInformationObjects(nc);
    for (int c = 0; c < nc; ++c)
    {
      const double range[2] = { r.Lo[c], r.Hi[c] };
      perComponent->GetInformationObject(c)->Set(vtkDataArray::COMPONENT_RANGE(), range, 2);
    }
    info->Set(key, perComponent);
    perComponent->FastDelete(); // info holds it
  }
  if (norms)
  {
    const double range[2] = { std::sqrt(r.SquaredNormLo), std::sqrt(r.SquaredNormHi) };
    info->Set(vtkDataArray::L2_NORM_RANGE(), range, 2);
  }
}

// Stores the ranges of a whole array that passed ComponentsLikeVTK, and its stamp.
void StoreScanned(vtkDataArray* array, Ranges r, bool norms)
{
  // Which zero min and max keep depends on the order they see them in, so on the chunks.
  for (int c = 0; c < array->GetNumberOfComponents(); ++c)
  {
    r.Lo[c] = r.Lo[c] == 0.0 ? 0.0 : r.Lo[c];
    r.Hi[c] = r.Hi[c] == 0.0 ? 0.0 : r.Hi[c];
  }
  StoreRangeKeys(array, r, norms && NormsLikeVTK(r));
  vtkNew<vtkDoubleArray> stamp;
  stamp->SetNumberOfValues(3);
  if (CurrentStamp(array, stamp->GetPointer(0)))
  {
    array->GetInformation()->Set(FiniteStamp(), stamp);
  }
}

void CacheRangesOf(vtkFieldData* data)
{
  for (int i = 0; data && i < data->GetNumberOfArrays(); ++i)
  {
    if (vtkDataArray* array = data->GetArray(i))
    {
      ctsplines::CacheRanges(array);
    }
  }
}
} // namespace

namespace ctsplines
{
bool CacheRanges(vtkDataArray* array)
{
  const vtkIdType tuples = array ? array->GetNumberOfTuples() : 0;
  const int nc = array ? array->GetNumberOfComponents() : 0;
  if (tuples <= 0 || nc < 1 || nc > MaxComponents || !array->HasStandardMemoryLayout())
  {
    return false;
  }
  const bool norms = nc > 1;
  if (RangesCached(array, norms))
  {
    return true;
  }
  Ranges r;
  bool components = false;
  switch (array->GetDataType())
  {
    vtkTemplateMacro(
      r = ScanArray(static_cast<const VTK_TT*>(array->GetVoidPointer(0)), tuples, nc, norms);
      components = ComponentsLikeVTK<VTK_TT>(r, nc));
    default:
      return false;
  }
  if (!components)
  {
    return false;
  }
  StoreScanned(array, r, norms);
  return true;
}

bool StoreRanges(vtkDataArray* array, const ctk::PointRanges& ranges)
{
  if (!array || array->GetDataType() != VTK_DOUBLE || array->GetNumberOfTuples() <= 0 ||
    array->GetNumberOfComponents() != ranges.Components || !array->HasStandardMemoryLayout())
  {
    return false;
  }
  const Ranges r = FromPointRanges(ranges);
  if (!ComponentsLikeVTK<double>(r, ranges.Components))
  {
    return false;
  }
  StoreScanned(array, r, true);
  return true;
}

bool StoreRange(vtkDataArray* array, double lo, double hi)
{
  if (!array || array->GetNumberOfTuples() <= 0 || array->GetNumberOfComponents() != 1 ||
    array->GetDataType() == VTK_FLOAT || array->GetDataType() == VTK_DOUBLE ||
    array->GetDataType() == VTK_BIT ||
    !array->HasStandardMemoryLayout() || !(lo <= hi))
  {
    return false;
  }
  Ranges r;
  r.Lo[0] = lo;
  r.Hi[0] = hi;
  StoreScanned(array, r, false);
  return true;
}

bool FiniteRanges(vtkDataArray* array, double* range)
{
  vtkInformation* info = array && array->HasInformation() ? array->GetInformation() : nullptr;
  vtkDoubleArray* stored = info ? vtkDoubleArray::SafeDownCast(info->Get(FiniteStamp())) : nullptr;
  double stamp[3];
  if (!stored || stored->GetNumberOfValues() != 3 || array->GetNumberOfTuples() <= 0 ||
    !array->HasStandardMemoryLayout() || !CurrentStamp(array, stamp) ||
    !std::equal(stamp, stamp + 3, stored->GetPointer(0)) || !RangesCached(array, false))
  {
    return false;
  }
  vtkInformationVector* perComponent = info->Get(vtkDataArray::PER_COMPONENT());
  for (int c = 0; c < array->GetNumberOfComponents(); ++c)
  {
    perComponent->GetInformationObject(c)->Get(vtkDataArray::COMPONENT_RANGE(), range + 2 * c);
  }
  return true;
}

void CacheRanges(vtkDataSet* output)
{
  if (!output)
  {
    return;
  }
  if (vtkPointSet* pointSet = vtkPointSet::SafeDownCast(output))
  {
    if (vtkPoints* points = pointSet->GetPoints())
    {
      CacheRanges(points->GetData());
    }
  }
  CacheRangesOf(output->GetPointData());
  CacheRangesOf(output->GetCellData());
  CacheRangesOf(output->GetFieldData());
}

void CacheRanges(vtkCompositeDataSet* output)
{
  if (!output)
  {
    return;
  }
  vtkSmartPointer<vtkCompositeDataIterator> it;
  it.TakeReference(output->NewIterator());
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
  {
    CacheRanges(vtkDataSet::SafeDownCast(it->GetCurrentDataObject()));
  }
  CacheRangesOf(output->GetFieldData());
}
} // namespace ctsplines
