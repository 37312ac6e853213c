// SPDX-License-Identifier: GPL-3.0-or-later
// VTK helpers shared by the filters and CAD targets: errors kept off the terminal, an algorithm
// run with its first error traced, finite-output checks.
#ifndef CTSplines_FuzzVTK_h
#define CTSplines_FuzzVTK_h

#include "FuzzInput.h"

#include "vtkAlgorithm.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkExecutive.h"
#include "vtkNew.h"
#include "vtkOutputWindow.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <cmath>
#include <cstring>
#include <string>

namespace ctsplines_fuzz
{
/// Errors are expected answers: they go to the observers of Run, never to the terminal.
class SilentOutputWindow : public vtkOutputWindow
{
public:
  static SilentOutputWindow* New() { return new SilentOutputWindow; }
  void DisplayText(const char*) override {}
};

inline void SilenceVTK()
{
  static const bool silenced = [] {
    vtkNew<SilentOutputWindow> silent;
    vtkOutputWindow::SetInstance(silent);
    return true;
  }();
  (void)silenced;
}

/// Keeps the first error message of an algorithm (its own, before the executive's).
class FirstError : public vtkCommand
{
public:
  static FirstError* New() { return new FirstError; }
  void Execute(vtkObject*, unsigned long, void* callData) override
  {
    if (this->Message.empty() && callData)
    {
      this->Message = static_cast<const char*>(callData);
    }
  }
  std::string Message;
};

/// Runs the algorithm; returns its output (port 0) when it succeeded.
inline vtkDataObject* Run(vtkAlgorithm* algorithm)
{
  vtkNew<FirstError> error;
  algorithm->AddObserver(vtkCommand::ErrorEvent, error);
  algorithm->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, error);
  const int ok = algorithm->GetExecutive()->Update();
  Trace(algorithm->GetClassName(), ok != 0, error->Message.substr(0, 300));
  return ok ? algorithm->GetOutputDataObject(0) : nullptr;
}

/// Every point of a point set, or of every point set in a composite data set, is finite.
inline void RequireFinitePoints(vtkDataObject* output, const char* what)
{
  if (auto* composite = vtkCompositeDataSet::SafeDownCast(output))
  {
    vtkSmartPointer<vtkCompositeDataIterator> it;
    it.TakeReference(composite->NewIterator());
    for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem())
    {
      RequireFinitePoints(it->GetCurrentDataObject(), what);
    }
    return;
  }
  auto* set = vtkPointSet::SafeDownCast(output);
  for (vtkIdType p = 0; set && set->GetPoints() && p < set->GetNumberOfPoints(); ++p)
  {
    double x[3];
    set->GetPoint(p, x);
    if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    {
      Finding(what, p);
      return;
    }
  }
}

/// Runs the algorithm and, when it succeeded and `check` is set, requires finite output points.
inline vtkDataObject* RunChecked(vtkAlgorithm* algorithm, bool check, const char* what)
{
  vtkDataObject* output = Run(algorithm);
  if (output && check)
  {
    RequireFinitePoints(output, what);
  }
  return output;
}

/// Whether two arrays hold the same values, bit for bit (NaN payloads and the sign of zero too),
/// with the same name, type and shape; two null arrays are the same.
inline bool SameBits(vtkDataArray* a, vtkDataArray* b)
{
  if (!a || !b)
  {
    return a == b;
  }
  const char* na = a->GetName() ? a->GetName() : "";
  const char* nb = b->GetName() ? b->GetName() : "";
  if (std::strcmp(na, nb) != 0 || a->GetDataType() != b->GetDataType() ||
    a->GetNumberOfComponents() != b->GetNumberOfComponents() ||
    a->GetNumberOfTuples() != b->GetNumberOfTuples())
  {
    return false;
  }
  if (a->HasStandardMemoryLayout() && b->HasStandardMemoryLayout())
  {
    const std::size_t bytes = static_cast<std::size_t>(a->GetNumberOfValues()) *
      static_cast<std::size_t>(a->GetDataTypeSize());
    return bytes == 0 || std::memcmp(a->GetVoidPointer(0), b->GetVoidPointer(0), bytes) == 0;
  }
  for (vtkIdType v = 0; v < a->GetNumberOfValues(); ++v)
  {
    const double x = a->GetComponent(v / a->GetNumberOfComponents(), v % a->GetNumberOfComponents());
    const double y = b->GetComponent(v / b->GetNumberOfComponents(), v % b->GetNumberOfComponents());
    if (std::memcmp(&x, &y, sizeof(double)) != 0)
    {
      return false;
    }
  }
  return true;
}

/// SameBits for every data array of two field data, in order.
inline bool SameArrays(vtkFieldData* a, vtkFieldData* b)
{
  if (a->GetNumberOfArrays() != b->GetNumberOfArrays())
  {
    return false;
  }
  for (int i = 0; i < a->GetNumberOfArrays(); ++i)
  {
    if (!SameBits(a->GetArray(i), b->GetArray(i)))
    {
      return false;
    }
  }
  return true;
}

/// SameBits for the arrays of a cell array (offsets, then connectivity); null cell arrays are
/// the same.
inline bool SameCells(vtkCellArray* a, vtkCellArray* b)
{
  if (!a || !b)
  {
    return (a ? a->GetNumberOfCells() : 0) == (b ? b->GetNumberOfCells() : 0);
  }
  return a->GetNumberOfCells() == b->GetNumberOfCells() &&
    SameBits(a->GetOffsetsArray(), b->GetOffsetsArray()) &&
    SameBits(a->GetConnectivityArray(), b->GetConnectivityArray());
}

/// Whether two point sets (unstructured grids or polydata) have the same points, cells, point
/// data and cell data, bit for bit. Other data objects are not compared (true).
inline bool SameOutput(vtkDataObject* a, vtkDataObject* b)
{
  auto* pa = vtkPointSet::SafeDownCast(a);
  auto* pb = vtkPointSet::SafeDownCast(b);
  if (!pa || !pb)
  {
    return true;
  }
  if (std::strcmp(pa->GetClassName(), pb->GetClassName()) != 0 ||
    !SameBits(pa->GetPoints() ? pa->GetPoints()->GetData() : nullptr,
      pb->GetPoints() ? pb->GetPoints()->GetData() : nullptr) ||
    !SameArrays(pa->GetPointData(), pb->GetPointData()) ||
    !SameArrays(pa->GetCellData(), pb->GetCellData()))
  {
    return false;
  }
  if (auto* ua = vtkUnstructuredGrid::SafeDownCast(a))
  {
    auto* ub = vtkUnstructuredGrid::SafeDownCast(b);
    return SameCells(ua->GetCells(), ub->GetCells()) &&
      SameBits(ua->GetCellTypesArray(), ub->GetCellTypesArray());
  }
  if (auto* qa = vtkPolyData::SafeDownCast(a))
  {
    auto* qb = vtkPolyData::SafeDownCast(b);
    return SameCells(qa->GetVerts(), qb->GetVerts()) && SameCells(qa->GetLines(), qb->GetLines()) &&
      SameCells(qa->GetPolys(), qb->GetPolys()) && SameCells(qa->GetStrips(), qb->GetStrips());
  }
  return true;
}

/// A deep copy of a point set with every point moved by (0, 0, 1): the same sizes, other
/// values. Other data objects: a deep copy.
inline vtkSmartPointer<vtkDataObject> Moved(vtkDataObject* data)
{
  vtkSmartPointer<vtkDataObject> copy;
  copy.TakeReference(data->NewInstance());
  copy->DeepCopy(data);
  auto* set = vtkPointSet::SafeDownCast(copy);
  for (vtkIdType p = 0; set && set->GetPoints() && p < set->GetNumberOfPoints(); ++p)
  {
    double x[3];
    set->GetPoints()->GetPoint(p, x);
    set->GetPoints()->SetPoint(p, x[0], x[1], x[2] + 1.0);
  }
  return copy;
}

/// The check of ReuseOutputArrays: `reused` runs on other inputs of the same sizes (other()
/// sets them), then on the real ones (real()), writing into the first output's arrays; `fresh`,
/// a new algorithm with the same settings and the real inputs, must give the same answer: both
/// fail, or both succeed with the same output, bit for bit (a value the second run forgot to
/// write would still be the other inputs'). Returns fresh's output, or null when it failed.
template <typename Other, typename Real>
vtkDataObject* RunRecycled(
  vtkAlgorithm* reused, vtkAlgorithm* fresh, Other&& other, Real&& real, const char* what)
{
  other();
  Run(reused);
  real();
  vtkDataObject* second = Run(reused);
  vtkDataObject* output = Run(fresh);
  if (!second != !output || (output && !SameOutput(second, output)))
  {
    Finding(what, 0);
  }
  return output;
}
} // namespace ctsplines_fuzz

#endif
