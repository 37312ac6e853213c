// SPDX-License-Identifier: GPL-3.0-or-later
#include "CTSplinesRecycledArrays.h"

#include "vtkAOSDataArrayTemplate.h"
#include "vtkAlgorithm.h"
#include "vtkDataArray.h" // for vtkArrayDownCast
#include "vtkBuffer.h"
#include "vtkCellData.h"
#include "vtkDemandDrivenPipeline.h"
#include "vtkInformation.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"
#include "vtkUnstructuredGrid.h"

#include <algorithm>
#include <limits>
#include <typeinfo>

namespace ctsplines
{
namespace
{
std::size_t Bytes(vtkDataArray* a)
{
  return static_cast<std::size_t>(a->GetNumberOfValues()) * a->GetDataTypeSize();
}

// The storage of an AOS array: vtkAOSDataArrayTemplate::ShallowCopy shares this reference-counted
// buffer between array objects. A derived class may name the protected member.
template <typename T>
struct StorageOf : vtkAOSDataArrayTemplate<T>
{
  static int References(vtkAOSDataArrayTemplate<T>* a)
  {
    vtkBuffer<T>* vtkAOSDataArrayTemplate<T>::*buffer = &StorageOf::Buffer;
    return (a->*buffer)->GetReferenceCount();
  }
};

// Only this object references the array and its storage: the old output and everything that
// held it, or a view of its values, are gone. Other layouts are never written again.
bool Exclusive(vtkDataArray* a)
{
  if (a->GetReferenceCount() != 1)
  {
    return false;
  }
  switch (a->GetDataType())
  {
    vtkTemplateMacro(if (auto* aos = vtkArrayDownCast<vtkAOSDataArrayTemplate<VTK_TT>>(a)) {
      return StorageOf<VTK_TT>::References(aos) == 1;
    });
  }
  return false;
}
} // namespace

void RecycledArrays::Begin(bool enabled, const std::vector<vtkIdType>& shape)
{
  this->Reused = 0;
  if (!enabled || shape != this->Shape)
  {
    this->Clear();
  }
  this->Shape = shape;
  this->ReleaseIf([](vtkDataArray* a) { return !Exclusive(a); });
}

vtkSmartPointer<vtkDataArray> RecycledArrays::Take(
  const std::function<bool(vtkDataArray*)>& accept)
{
  for (auto it = this->Kept.begin(); it != this->Kept.end(); ++it)
  {
    if (Exclusive(*it) && accept(*it))
    {
      vtkSmartPointer<vtkDataArray> array = std::move(*it);
      this->Kept.erase(it);
      this->Reused += Bytes(array);
      return array;
    }
  }
  return nullptr;
}

vtkSmartPointer<vtkDataArray> RecycledArrays::NewLike(
  vtkDataArray* prototype, int components, vtkIdType tuples)
{
  const std::type_info& type = typeid(*prototype);
  vtkSmartPointer<vtkDataArray> array = this->Take([&](vtkDataArray* a) {
    // Component names cannot be cleared; the module's arrays have none.
    return typeid(*a) == type && a->GetNumberOfComponents() == components &&
      a->GetNumberOfTuples() == tuples && a->HasStandardMemoryLayout() &&
      !a->HasAComponentName();
  });
  if (array)
  {
    // As a new array: no name, no cached ranges or other keys, no lookup, and a new MTime for
    // the caches keyed by it (a renderer's buffers).
    array->SetName(nullptr);
    array->SetLookupTable(nullptr);
    if (array->HasInformation())
    {
      array->GetInformation()->Clear();
    }
    array->DataChanged();
    array->Modified();
    return array;
  }
  return NewOutputArrayLike(nullptr, prototype, components, tuples);
}

vtkSmartPointer<vtkDataArray> NewOutputArrayLike(
  RecycledArrays* recycled, vtkDataArray* prototype, int components, vtkIdType tuples)
{
  if (recycled)
  {
    return recycled->NewLike(prototype, components, tuples);
  }
  auto array = vtkSmartPointer<vtkDataArray>::Take(prototype->NewInstance());
  array->SetNumberOfComponents(components);
  AllocateTuples(array, tuples);
  return array;
}

bool RecycledArrays::MayKeepOutput(vtkAlgorithm* algorithm, bool reuse)
{
  auto* executive = vtkDemandDrivenPipeline::SafeDownCast(algorithm->GetExecutive());
  return reuse && !vtkDataObject::GetGlobalReleaseDataFlag() &&
    !(executive && executive->GetReleaseDataFlag(0));
}

void RecycledArrays::ReleaseIf(const std::function<bool(vtkDataArray*)>& release)
{
  this->Kept.erase(std::remove_if(this->Kept.begin(), this->Kept.end(),
                     [&](const vtkSmartPointer<vtkDataArray>& a) { return release(a); }),
    this->Kept.end());
}

void RecycledArrays::ReleaseUnused()
{
  this->Kept.clear();
}

bool RecycledArrays::SetReuse(bool& property, bool reuse)
{
  if (reuse == property)
  {
    return false;
  }
  property = reuse;
  if (!reuse)
  {
    this->Clear();
  }
  return true;
}

void RecycledArrays::Clear()
{
  this->Kept.clear();
  this->Shape.clear();
  this->Reused = 0;
}

void RecycledArrays::End(vtkDataSet* output, bool enabled)
{
  std::vector<vtkDataArray*> arrays;
  if (enabled && output)
  {
    auto addCells = [&](vtkCellArray* cells) {
      if (cells)
      {
        arrays.push_back(cells->GetOffsetsArray());
        arrays.push_back(cells->GetConnectivityArray());
      }
    };
    if (vtkPointSet* ps = vtkPointSet::SafeDownCast(output))
    {
      arrays.push_back(ps->GetPoints() ? ps->GetPoints()->GetData() : nullptr);
    }
    for (vtkDataSetAttributes* attributes :
      { static_cast<vtkDataSetAttributes*>(output->GetPointData()),
        static_cast<vtkDataSetAttributes*>(output->GetCellData()) })
    {
      for (int i = 0; i < attributes->GetNumberOfArrays(); ++i)
      {
        arrays.push_back(attributes->GetArray(i));
      }
    }
    if (vtkUnstructuredGrid* grid = vtkUnstructuredGrid::SafeDownCast(output))
    {
      addCells(grid->GetCells());
      arrays.push_back(grid->GetCellTypesArray());
    }
    else if (vtkPolyData* poly = vtkPolyData::SafeDownCast(output))
    {
      for (vtkCellArray* cells : { poly->GetVerts(), poly->GetLines(), poly->GetPolys(),
             poly->GetStrips() })
      {
        addCells(cells);
      }
    }
  }
  this->End(arrays, enabled && output);
}

std::atomic<std::size_t>& RecycledArrays::MinimumBytesValue()
{
  static std::atomic<std::size_t> bytes{ std::size_t(1) << 20 };
  return bytes;
}

void RecycledArrays::End(const std::vector<vtkDataArray*>& arrays, bool enabled)
{
  this->Kept.clear();
  if (!enabled)
  {
    this->Shape.clear();
    return;
  }
  for (vtkDataArray* a : arrays)
  {
    if (a && Bytes(a) >= MinimumBytes() &&
      std::find(this->Kept.begin(), this->Kept.end(), a) == this->Kept.end())
    {
      this->Kept.emplace_back(a);
    }
  }
}

vtkSmartPointer<vtkCellArray> NewCellArray(
  vtkIdType nCells, vtkIdType connectivitySize, vtkIdType maxId, RecycledArrays* recycled)
{
  const vtkIdType limit = std::numeric_limits<vtkTypeInt32>::max();
  const bool narrow = connectivitySize <= limit && maxId <= limit;
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  if (narrow)
  {
    cells->SetData(NewOutputArray<vtkCellArray::ArrayType32>(recycled, 1, nCells + 1),
      NewOutputArray<vtkCellArray::ArrayType32>(recycled, 1, connectivitySize));
  }
  else
  {
    cells->SetData(NewOutputArray<vtkCellArray::ArrayType64>(recycled, 1, nCells + 1),
      NewOutputArray<vtkCellArray::ArrayType64>(recycled, 1, connectivitySize));
  }
  return cells;
}
} // namespace ctsplines
