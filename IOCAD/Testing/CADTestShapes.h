// SPDX-License-Identifier: GPL-3.0-or-later
// Shapes the CAD tests build with OpenCASCADE, shared by the test programs.
#ifndef CTSplines_IOCAD_Testing_CADTestShapes_h
#define CTSplines_IOCAD_Testing_CADTestShapes_h

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <gp_Ax2.hxx>

namespace ctsplines_test
{
/// A box with a cylindrical through-hole: planes, a seamed cylinder, faces with holes.
inline TopoDS_Shape BoxWithHole()
{
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(-1.0, -0.6, 0.0), 2.0, 1.2, 0.8).Shape();
  const TopoDS_Shape drill =
    BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0.2, 0.1, -0.5), gp_Dir(0, 0, 1)), 0.35, 2.0).Shape();
  return BRepAlgoAPI_Cut(box, drill).Shape();
}
} // namespace ctsplines_test

#endif
