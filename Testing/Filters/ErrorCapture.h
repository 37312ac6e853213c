// SPDX-License-Identifier: GPL-3.0-or-later
// Captures the vtkErrorMacro messages of one algorithm so tests can assert what they say.
#ifndef CTSplines_ErrorCapture_h
#define CTSplines_ErrorCapture_h

#include "vtkCommand.h"
#include "vtkObject.h"
#include "vtkSmartPointer.h"

#include <string>

namespace ctsplines_test
{
class ErrorCapture : public vtkCommand
{
public:
  static ErrorCapture* New() { return new ErrorCapture; }
  void Execute(vtkObject*, unsigned long, void* callData) override
  {
    ++this->Count;
    if (callData)
    {
      this->Message += static_cast<const char*>(callData);
    }
  }
  /// Observes errors of `object` (an algorithm, and its executive, where pipeline errors land).
  static vtkSmartPointer<ErrorCapture> Attach(vtkObject* object)
  {
    auto capture = vtkSmartPointer<ErrorCapture>::New();
    object->AddObserver(vtkCommand::ErrorEvent, capture);
    return capture;
  }
  int Count = 0;
  std::string Message;
};
} // namespace ctsplines_test

#endif
