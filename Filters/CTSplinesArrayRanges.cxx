// SPDX-License-Identifier: GPL-3.0-or-later
#include "CTSplinesArrayRanges.h"

#include "CTSplinesSMP.h" // for ParallelFor
#include "LocalityOrder.h" // for PrefetchAhead

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

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

#if defined(__SSE2__)
// The extremes of a pair of tuples (lane l of register k holds value 2 k + l of the pair:
// components (x, y) (z, x) (y, z) for three, (x, y) twice for two) and of their squared norms,
// which add the same squares in the same order as ScanTuples. A NaN shows in its tuple's squared
// norm (squares are never -inf, so inf + -inf cannot make one).
template <int NC>
struct PairRanges
{
  __m128d Lo[3], Hi[3], NormLo, NormHi, NaN;

  PairRanges()
  {
    const __m128d inf = _mm_set1_pd(std::numeric_limits<double>::infinity());
    const __m128d minusInf = _mm_set1_pd(-std::numeric_limits<double>::infinity());
    for (int k = 0; k < 3; ++k)
    {
      this->Lo[k] = inf;
      this->Hi[k] = minusInf;
    }
    this->NormLo = inf;
    this->NormHi = minusInf;
    this->NaN = _mm_setzero_pd();
  }
  void Add(const double* p)
  {
    __m128d a[3];
    for (int k = 0; k < NC; ++k)
    {
      a[k] = _mm_loadu_pd(p + 2 * k);
      this->Lo[k] = _mm_min_pd(this->Lo[k], a[k]);
      this->Hi[k] = _mm_max_pd(this->Hi[k], a[k]);
    }
    __m128d s;
    if (NC == 3)
    {
      const __m128d q0 = _mm_mul_pd(a[0], a[0]), q1 = _mm_mul_pd(a[1], a[1]),
                    q2 = _mm_mul_pd(a[2], a[2]);
      s = _mm_add_pd(_mm_add_pd(_mm_shuffle_pd(q0, q1, 2), _mm_shuffle_pd(q0, q2, 1)),
        _mm_shuffle_pd(q1, q2, 2));
    }
    else
    {
      const __m128d q0 = _mm_mul_pd(a[0], a[0]), q1 = _mm_mul_pd(a[1], a[1]);
      s = _mm_add_pd(_mm_unpacklo_pd(q0, q1), _mm_unpackhi_pd(q0, q1));
    }
    this->NormLo = _mm_min_pd(this->NormLo, s);
    this->NormHi = _mm_max_pd(this->NormHi, s);
    this->NaN = _mm_or_pd(this->NaN, _mm_cmpunord_pd(s, s)); // a NaN component, and only then
  }
  void MergeInto(Ranges& r) const
  {
    double l[6], h[6], n[4];
    for (int k = 0; k < NC; ++k)
    {
      _mm_storeu_pd(l + 2 * k, this->Lo[k]);
      _mm_storeu_pd(h + 2 * k, this->Hi[k]);
    }
    _mm_storeu_pd(n, this->NormLo);
    _mm_storeu_pd(n + 2, this->NormHi);
    for (int j = 0; j < 2 * NC; ++j)
    {
      r.Lo[j % NC] = std::min(r.Lo[j % NC], l[j]);
      r.Hi[j % NC] = std::max(r.Hi[j % NC], h[j]);
    }
    r.SquaredNormLo = std::min({ r.SquaredNormLo, n[0], n[1] });
    r.SquaredNormHi = std::max({ r.SquaredNormHi, n[2], n[3] });
    r.NaN = r.NaN || _mm_movemask_pd(this->NaN) != 0;
  }
};

// ScanTuples for doubles: two pairs of tuples at a time, into two sets of extremes, the data
// asked for StreamPrefetchBytes ahead. Speeds on one thread, data from memory:
// - the scalar loop: 7.5 GB/s;
// - one set of pairs, no prefetch: 7.7 GB/s (a sixth of the spline filter at 1e6 triangles,
//   whose 570 MB of points and (u, v) it reads);
// - this loop: 12.7 GB/s;
// - the same in ForStreamChunks' chunks: 9-10.6 GB/s (its merges and bursts of prefetches).
template <int NC>
void ScanDoublePairs(const double* v, vtkIdType b, vtkIdType e, Ranges& r)
{
  static_assert(NC == 2 || NC == 3, "two or three components");
  PairRanges<NC> even, odd;
  vtkIdType i = b;
  for (; i + 4 <= e; i += 4)
  {
    const double* p = v + NC * i;
    // One prefetch per 4 tuples (96 bytes of three components, 64 of two): the lines it skips
    // come with their neighbours (the adjacent-line prefetcher).
    ctk::PrefetchAhead(p, ctk::StreamPrefetchBytes);
    even.Add(p);
    odd.Add(p + 2 * NC);
  }
  if (i + 2 <= e)
  {
    even.Add(v + NC * i);
    i += 2;
  }
  even.MergeInto(r);
  odd.MergeInto(r);
  ScanTuples<NC>(v, NC, i, e, true, r); // an odd last tuple
}
#endif

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
#if defined(__SSE2__)
  if constexpr (std::is_same<T, double>::value)
  {
    if (norms && (nc == 2 || nc == 3))
    {
      nc == 2 ? ScanDoublePairs<2>(values, b, e, part) : ScanDoublePairs<3>(values, b, e, part);
      return;
    }
  }
#endif
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
void StoreRanges(vtkDataArray* array, const Ranges& r, bool norms)
{
  const int nc = array->GetNumberOfComponents();
  vtkInformation* info = array->GetInformation();
  for (vtkInformationInformationVectorKey* key :
    { vtkDataArray::PER_COMPONENT(), vtkDataArray::PER_FINITE_COMPONENT() })
  {
    vtkNew<vtkInformationVector> perComponent;
    perComponent->SetNumberOfInformationObjects(nc);
    for (int c = 0; c < nc; ++c)
    {
      const double range[2] = { r.Lo[c], r.Hi[c] };
      perComponent->GetInformationObject(c)->Set(vtkDataArray::COMPONENT_RANGE(), range, 2);
    }
    info->Set(key, perComponent);
  }
  if (norms)
  {
    const double range[2] = { std::sqrt(r.SquaredNormLo), std::sqrt(r.SquaredNormHi) };
    info->Set(vtkDataArray::L2_NORM_RANGE(), range, 2);
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
  // Which zero min and max keep depends on the order they see them in, so on the chunks.
  for (int c = 0; c < nc; ++c)
  {
    r.Lo[c] = r.Lo[c] == 0.0 ? 0.0 : r.Lo[c];
    r.Hi[c] = r.Hi[c] == 0.0 ? 0.0 : r.Hi[c];
  }
  StoreRanges(array, r, norms && NormsLikeVTK(r));
  vtkNew<vtkDoubleArray> stamp;
  stamp->SetNumberOfValues(3);
  if (CurrentStamp(array, stamp->GetPointer(0)))
  {
    array->GetInformation()->Set(FiniteStamp(), stamp);
  }
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
}
} // namespace ctsplines
