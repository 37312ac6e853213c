// SPDX-License-Identifier: GPL-3.0-or-later
// ctsplines_write_test_model PATH: writes a small closed solid (a box with a cylindrical
// through-hole: planes, a seamed cylinder, faces with holes) as STEP, so that the Python and
// ParaView tests have a CAD model without committing one; Python cannot write STEP here.
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <STEPControl_Writer.hxx>
#include <gp_Ax2.hxx>

#include <cstdio>

int main(int argc, char* argv[])
{
  if (argc != 2)
  {
    std::fprintf(stderr, "usage: %s PATH.step\n", argv[0]);
    return 2;
  }
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(-1.0, -0.6, 0.0), 2.0, 1.2, 0.8).Shape();
  const TopoDS_Shape drill =
    BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0.2, 0.1, -0.5), gp_Dir(0, 0, 1)), 0.35, 2.0).Shape();
  BRepAlgoAPI_Cut cut(box, drill);
  if (!cut.IsDone())
  {
    std::fprintf(stderr, "boolean cut failed\n");
    return 1;
  }
  STEPControl_Writer writer;
  if (writer.Transfer(cut.Shape(), STEPControl_AsIs) != IFSelect_RetDone ||
    writer.Write(argv[1]) != IFSelect_RetDone)
  {
    std::fprintf(stderr, "cannot write %s\n", argv[1]);
    return 1;
  }
  return 0;
}
