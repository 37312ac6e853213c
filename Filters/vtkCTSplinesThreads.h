// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @class   vtkCTSplinesThreads
 * @brief   Threads of the CTSplines filters' parallel loops.
 *
 * The filters' loops run on a pool of threads started once and reused (VTK 9.2's STDThread SMP
 * backend starts and joins new threads on every vtkSMPTools::For call it splits, and splits even
 * tiny loops). A loop shorter than a grain size (about a thousand kernel evaluations per thread)
 * runs on the calling thread and wakes no thread. Every element is computed independently, so
 * results do not depend on the number of threads.
 *
 * The number of threads: SetNumberOfThreads(n) with n >= 1; with 0 (the default) it follows
 * VTK: the thread count of vtkSMPTools under its STDThread backend, 1 under the Sequential one.
 * The Python package sets it to the number of cores on import and leaves VTK's own backend
 * alone (unless VTK_SMP_BACKEND_IN_USE is set), so VTK's own small loops start no thread.
 */
#ifndef vtkCTSplinesThreads_h
#define vtkCTSplinesThreads_h

#include "CTSplinesFiltersModule.h" // For export macro
#include "vtkObject.h"

class CTSPLINESFILTERS_EXPORT vtkCTSplinesThreads : public vtkObject
{
public:
  static vtkCTSplinesThreads* New();
  vtkTypeMacro(vtkCTSplinesThreads, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Threads for the filters' loops; 0 follows vtkSMPTools (see the class description).
  static void SetNumberOfThreads(int threads);
  /// The setting (0: follow vtkSMPTools).
  static int GetNumberOfThreadsSetting();
  /// The threads the next loop will use.
  static int GetNumberOfThreads();
  /// Loops that ran split over the pool since the process started (for tests and benchmarks).
  static vtkIdType GetNumberOfParallelLoops();

protected:
  vtkCTSplinesThreads() = default;
  ~vtkCTSplinesThreads() override = default;

private:
  vtkCTSplinesThreads(const vtkCTSplinesThreads&) = delete;
  void operator=(const vtkCTSplinesThreads&) = delete;
};

#endif
