// SPDX-License-Identifier: GPL-3.0-or-later
// ctsplines_write_test_model [--shape NAME] PATH: writes a shape of CADTestShapes.h as STEP, so
// that the Python and ParaView tests have CAD models without committing any; Python cannot write
// STEP here. NAME: box_with_hole (default: a small closed solid with planes, a seamed cylinder
// and faces with holes), hemisphere_quarter, cylinder_octant_two_faces (the shell benchmarks),
// loose_box_faces (a box's faces unconnected, for the sewing), offset_without_normal (a face on
// which OpenCASCADE throws, for the CLI's error).
#include "CADTestShapes.h"

#include <STEPControl_Writer.hxx>

#include <cstdio>
#include <cstring>
#include <string>

namespace
{
TopoDS_Shape ShapeNamed(const std::string& name)
{
  if (name == "box_with_hole")
  {
    return ctsplines_test::BoxWithHole();
  }
  if (name == "hemisphere_quarter")
  {
    return ctsplines_test::HemisphereQuarter();
  }
  if (name == "cylinder_octant_two_faces")
  {
    return ctsplines_test::CylinderOctantTwoFaces();
  }
  if (name == "loose_box_faces")
  {
    return ctsplines_test::LooseBoxFaces();
  }
  if (name == "offset_without_normal")
  {
    return ctsplines_test::OffsetSurfaceWithoutNormal();
  }
  return TopoDS_Shape();
}
} // namespace

int main(int argc, char* argv[])
{
  std::string name = "box_with_hole";
  const char* path = nullptr;
  if (argc == 2)
  {
    path = argv[1];
  }
  else if (argc == 4 && std::strcmp(argv[1], "--shape") == 0)
  {
    name = argv[2];
    path = argv[3];
  }
  else
  {
    std::fprintf(stderr,
      "usage: %s [--shape box_with_hole|hemisphere_quarter|cylinder_octant_two_faces|"
      "loose_box_faces|offset_without_normal] PATH.step\n",
      argv[0]);
    return 2;
  }
  const TopoDS_Shape shape = ShapeNamed(name);
  if (shape.IsNull())
  {
    std::fprintf(stderr, "unknown shape or OpenCASCADE failed to build it: %s\n", name.c_str());
    return 2;
  }
  STEPControl_Writer writer;
  if (writer.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone ||
    writer.Write(path) != IFSelect_RetDone)
  {
    std::fprintf(stderr, "cannot write %s\n", path);
    return 1;
  }
  return 0;
}
