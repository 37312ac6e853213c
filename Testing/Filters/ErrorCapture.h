// SPDX-License-Identifier: GPL-3.0-or-later
// Captures the vtkErrorMacro messages of one algorithm so tests can assert what they say.
#ifndef CTSplines_ErrorCapture_h
#define CTSplines_ErrorCapture_h

#include "vtkAlgorithm.h"
#include "vtkCommand.h"
#include "vtkExecutive.h"
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
  /// Observes an algorithm and its executive.
  static vtkSmartPointer<ErrorCapture> AttachToAlgorithm(vtkAlgorithm* algorithm)
  {
    auto capture = Attach(algorithm);
    algorithm->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, capture);
    return capture;
  }
  int Count = 0;
  std::string Message;
};

/// Runs `algorithm` on `input`; returns the error messages (of the algorithm and its executive)
/// and sets `result` to what the executive's Update returned.
inline std::string RunCapturingErrors(vtkAlgorithm* algorithm, vtkDataObject* input, int& result)
{
  auto errors = ErrorCapture::AttachToAlgorithm(algorithm);
  algorithm->SetInputDataObject(input);
  result = algorithm->GetExecutive()->Update();
  return errors->Message;
}
} // namespace ctsplines_test

#endif
