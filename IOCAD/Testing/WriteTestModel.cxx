// SPDX-License-Identifier: GPL-3.0-or-later
// ctsplines_write_test_model PATH: writes a small closed solid (a box with a cylindrical
// through-hole: planes, a seamed cylinder, faces with holes) as STEP, so that the Python and
// ParaView tests have a CAD model without committing one; Python cannot write STEP here.
#include "CADTestShapes.h"

#include <STEPControl_Writer.hxx>

#include <cstdio>

int main(int argc, char* argv[])
{
  if (argc != 2)
  {
    std::fprintf(stderr, "usage: %s PATH.step\n", argv[0]);
    return 2;
  }
  const TopoDS_Shape shape = ctsplines_test::BoxWithHole();
  STEPControl_Writer writer;
  if (shape.IsNull() || writer.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone ||
    writer.Write(argv[1]) != IFSelect_RetDone)
  {
    std::fprintf(stderr, "cannot write %s\n", argv[1]);
    return 1;
  }
  return 0;
}
