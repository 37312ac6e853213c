// SPDX-License-Identifier: GPL-3.0-or-later
// The value ranges of the module's output arrays, computed on its threads and stored where VTK
// looks for them first (private header).
//
// vtkDataArray::GetRange and GetFiniteRange cache what they compute in the array's information
// (PER_COMPONENT, PER_FINITE_COMPONENT, L2_NORM_RANGE, L2_NORM_FINITE_RANGE), valid while the
// array is not modified after it. ParaView asks every array of every output for all of them
// (vtkPVArrayInformation), one pass each: 5.6 s for a spline of 1.4e6 triangles and 15 s for its
// tessellation at level 4 in pvpython, longer than the filters took. One pass over the values on
// the module's threads gives them all, in a few tens of milliseconds.
#ifndef CTSplinesArrayRanges_h
#define CTSplinesArrayRanges_h

namespace ctk
{
struct PointRanges;
}
class vtkCompositeDataSet;
class vtkDataArray;
class vtkDataSet;

namespace ctsplines
{
/// Stores the ranges of `array` in its information as vtkDataArray caches them (each component's
/// range and finite range, and the L2 norm's range when it has several components), from one
/// parallel pass. The values are VTK's own, except that a zero extreme is stored as +0 (VTK keeps
/// the first zero it meets, -0 or +0; here the first depends on the thread count). Nothing is
/// stored where VTK would compute
/// something else or the key would outlive the values: an empty or non-contiguous array, one
/// with NaN or inf, extremes beyond VTK's starting values (1e299, or 1e38 for floats), more than
/// 32 components; the L2 norm's when a squared norm reaches 1e299; never the L2 norm's finite
/// range, which vtkDataArray::CopyInformation passes on to the derived arrays of VTK's filters.
/// Nothing is computed when the ranges are cached already. An array shared with the filter's
/// input has its information written, as GetRange would. Returns whether the ranges are cached
/// on return.
bool CacheRanges(vtkDataArray* array);

/// Stores `ranges`, the kernel's scan of every value of `array` as it is now (a double array of
/// ranges.Components components, e.g. the control points a construction wrote), as CacheRanges
/// would store its own scan: under the same conditions, with the same stamp. Returns whether
/// they are stored.
bool StoreRanges(vtkDataArray* array, const ctk::PointRanges& ranges);

/// Stores [lo, hi], the range of every value of `array` as it is now (one component of an
/// integer type, e.g. the ids a filter wrote and knows the extremes of), as CacheRanges would
/// store its own scan. Returns whether it is stored.
bool StoreRange(vtkDataArray* array, double lo, double hi);

/// The range of every component of `array` (range[2 c], range[2 c + 1]: range holds 2 values per
/// component), when CacheRanges stored them and the array has not changed since: its MTime,
/// data pointer and number of values are the ones CacheRanges saw (Modified() after a change of
/// values, as for VTK's own range cache). CacheRanges stores ranges only for arrays without NaN
/// or inf, so these bound every value, and a caller may take them for a check of all values
/// (the probe's reading of a spline filter's output). False, with range untouched, otherwise:
/// ranges VTK computed itself (which skip NaN), a copy's (the stamp is never copied), or none.
bool FiniteRanges(vtkDataArray* array, double* range);

/// CacheRanges of a data set's points and of every data array of its point, cell and field
/// data: called by the filters as the last step of RequestData, on the arrays they wrote and
/// those they passed through. Small arrays too: VTK 9.2 reads the system's processor count for
/// every range it computes, and its STDThread backend starts and joins threads for each, however
/// few the values (a 1,924-face CAD model's face blocks hold 16 one-value field arrays each; its
/// conversion took 179,396 system calls instead of 32,509 under the Sequential backend).
void CacheRanges(vtkDataSet* output);

/// CacheRanges of every data set of a composite output and of its own field data.
void CacheRanges(vtkCompositeDataSet* output);
} // namespace ctsplines

#endif
