// SPDX-License-Identifier: GPL-3.0-or-later
// Franke's function sampled on a grid, converted into a cubic Clough-Tocher spline and
// tessellated; writes both and prints their sizes, which follow from the grid:
//   input  2 r^2 triangles, (r+1)^2 points
//   spline 3 Bezier triangles per input triangle
//   tessellation level^2 triangles per Bezier triangle.
// Usage: franke_spline [output folder] [grid resolution] [tessellation level]
#include "vtkBezierTriangleTessellator.h"
#include "vtkCloughTocherSplineFilter.h"
#include "vtkSampledSurfaceSource.h"

#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <cstdlib>
#include <iostream>
#include <string>

int main(int argc, char* argv[])
{
  const std::string folder = argc > 1 ? argv[1] : ".";
  const int resolution = argc > 2 ? std::atoi(argv[2]) : 10;
  const int level = argc > 3 ? std::atoi(argv[3]) : 4;

  vtkNew<vtkSampledSurfaceSource> source;
  source->SetSurfaceToFranke();
  source->SetDomainToGrid();
  source->SetResolution(resolution);

  vtkNew<vtkCloughTocherSplineFilter> spline;
  spline->SetInputConnection(source->GetOutputPort());
  spline->SetConstructionToCTi();

  vtkNew<vtkBezierTriangleTessellator> tessellator;
  tessellator->SetInputConnection(spline->GetOutputPort());
  tessellator->SetSubdivisionLevel(level);

  vtkNew<vtkXMLUnstructuredGridWriter> splineWriter;
  splineWriter->SetInputConnection(spline->GetOutputPort());
  splineWriter->SetFileName((folder + "/franke_spline.vtu").c_str());
  vtkNew<vtkXMLPolyDataWriter> tessellationWriter;
  tessellationWriter->SetInputConnection(tessellator->GetOutputPort());
  tessellationWriter->SetFileName((folder + "/franke_tessellation.vtp").c_str());
  if (!splineWriter->Write() || !tessellationWriter->Write())
  {
    std::cerr << "franke_spline: could not compute or write the results in " << folder << "\n";
    return 1;
  }

  vtkPolyData* mesh = source->GetOutput();
  vtkUnstructuredGrid* bezier = spline->GetOutput();
  vtkPolyData* surface = tessellator->GetOutput();
  std::cout << "input triangles " << mesh->GetNumberOfCells() << "\n"
            << "input points " << mesh->GetNumberOfPoints() << "\n"
            << "bezier triangles " << bezier->GetNumberOfCells() << "\n"
            << "control points " << bezier->GetNumberOfPoints() << "\n"
            << "tessellation triangles " << surface->GetNumberOfCells() << "\n"
            << "tessellation points " << surface->GetNumberOfPoints() << "\n";

  const vtkIdType n = 2 * vtkIdType(resolution) * resolution;
  const bool ok = mesh->GetNumberOfCells() == n && bezier->GetNumberOfCells() == 3 * n &&
    surface->GetNumberOfCells() == 3 * n * level * level;
  if (!ok)
  {
    std::cerr << "franke_spline: counts differ from the layout formula\n";
  }
  return ok ? 0 : 1;
}
