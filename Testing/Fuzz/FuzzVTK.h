// SPDX-License-Identifier: GPL-3.0-or-later
// VTK helpers shared by the filters and CAD targets: errors kept off the terminal, an algorithm
// run with its first error traced, finite-output checks.
#ifndef CTSplines_FuzzVTK_h
#define CTSplines_FuzzVTK_h

#include "FuzzInput.h"

#include "vtkAlgorithm.h"
#include "vtkCommand.h"
#include "vtkCompositeDataIterator.h"
#include "vtkCompositeDataSet.h"
#include "vtkDataObject.h"
#include "vtkExecutive.h"
#include "vtkNew.h"
#include "vtkOutputWindow.h"
#include "vtkPointSet.h"
#include "vtkSmartPointer.h"

#include <cmath>
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
} // namespace ctsplines_fuzz

#endif
