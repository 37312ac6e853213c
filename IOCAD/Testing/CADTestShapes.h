// SPDX-License-Identifier: GPL-3.0-or-later
// Shapes the CAD tests build with OpenCASCADE, shared by the test programs.
#ifndef CTSplines_IOCAD_Testing_CADTestShapes_h
#define CTSplines_IOCAD_Testing_CADTestShapes_h

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_Copy.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS_Wire.hxx>
#include <gp_Pln.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <GC_MakeArcOfCircle.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <gp_Circ.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_SphericalSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_OffsetSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <BRep_Tool.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Vertex.hxx>
#include <TopoDS.hxx>
#include <gp_Ax2.hxx>
#include <gp_Ax3.hxx>
#include <Geom2dAPI_Interpolate.hxx>
#include <Geom_BSplineCurve.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <TColStd_HArray1OfReal.hxx>
#include <TColgp_HArray1OfPnt2d.hxx>

#include <cmath>

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

/// BoxWithHole whose hole has, on its cylinder, one circle's pcurve off the circle: u(t) =
/// t + sin(t) / 2 (still flagged SameParameter), as OCCT's STEP reader left the pcurves of KiCad's
/// NXP_MPL115A1 on surfaces of revolution: the surface over it is off the edge by up to a third
/// of the hole's radius. OCCT's STEP reader recomputes such a pcurve; its IGES reader keeps it
/// (and raises the edge's tolerance over the gap).
inline TopoDS_Shape BoxWithSkewedPCurve()
{
  const TopoDS_Shape shape = BoxWithHole();
  for (TopExp_Explorer fx(shape, TopAbs_FACE); fx.More(); fx.Next())
  {
    const TopoDS_Face& F = TopoDS::Face(fx.Current());
    if (BRepAdaptor_Surface(F).GetType() != GeomAbs_Cylinder)
    {
      continue;
    }
    for (TopExp_Explorer ex(F, TopAbs_EDGE); ex.More(); ex.Next())
    {
      const TopoDS_Edge& E = TopoDS::Edge(ex.Current());
      double a = 0, b = 0;
      const Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(E, F, a, b);
      if (BRep_Tool::IsClosed(E, F) || pc.IsNull())
      {
        continue;
      }
      const int n = 32;
      const Handle(TColgp_HArray1OfPnt2d) points = new TColgp_HArray1OfPnt2d(1, n + 1);
      const Handle(TColStd_HArray1OfReal) params = new TColStd_HArray1OfReal(1, n + 1);
      for (int i = 0; i <= n; ++i)
      {
        const double t = a + (b - a) * i / n;
        const gp_Pnt2d p = pc->Value(t);
        points->SetValue(i + 1, gp_Pnt2d(p.X() + 0.5 * std::sin(p.X()), p.Y()));
        params->SetValue(i + 1, t);
      }
      Geom2dAPI_Interpolate skewed(points, params, Standard_False, 1e-9);
      skewed.Perform();
      BRep_Builder().UpdateEdge(E, Handle(Geom2d_Curve)(skewed.Curve().get()), F, BRep_Tool::Tolerance(E));
      return shape;
    }
  }
  return TopoDS_Shape();
}

/// A plane wedge between two cubic B-spline edges from the first pole (a vertex shared by
/// both), one with `poles`, the other with their mirror image in y, and the segment joining
/// their ends. With `sides`, a shell: also the face beyond each B-spline edge, up to the
/// segment from the first pole to the edge's end with y doubled (every face sharing its
/// B-spline edge with the wedge, the first pole with both others).
inline TopoDS_Shape MirroredBSplineWedge(const TColgp_Array1OfPnt& poles,
  const TColStd_Array1OfReal& knots, const TColStd_Array1OfInteger& mults, bool sides = false)
{
  const TopoDS_Vertex start = BRepBuilderAPI_MakeVertex(poles(poles.Lower()));
  TopoDS_Vertex ends[2], outer[2];
  TopoDS_Edge edges[2];
  for (int side = 0; side < 2; ++side)
  {
    TColgp_Array1OfPnt mirrored(poles);
    for (int k = mirrored.Lower(); side == 1 && k <= mirrored.Upper(); ++k)
    {
      mirrored(k).SetY(-mirrored(k).Y());
    }
    const gp_Pnt end = mirrored(mirrored.Upper());
    ends[side] = BRepBuilderAPI_MakeVertex(end);
    outer[side] = BRepBuilderAPI_MakeVertex(gp_Pnt(end.X(), 2 * end.Y(), end.Z()));
    edges[side] =
      BRepBuilderAPI_MakeEdge(new Geom_BSplineCurve(mirrored, knots, mults, 3), start, ends[side]);
  }
  BRepBuilderAPI_MakeWire wire;
  wire.Add(edges[0]);
  wire.Add(BRepBuilderAPI_MakeEdge(ends[0], ends[1]).Edge());
  wire.Add(TopoDS::Edge(edges[1].Reversed()));
  const TopoDS_Face wedge = BRepBuilderAPI_MakeFace(wire.Wire(), Standard_True).Face();
  if (!sides)
  {
    return wedge;
  }
  TopoDS_Shell shell;
  BRep_Builder builder;
  builder.MakeShell(shell);
  builder.Add(shell, wedge);
  const TopoDS_Edge rays[2] = { BRepBuilderAPI_MakeEdge(start, outer[0]).Edge(),
    BRepBuilderAPI_MakeEdge(start, outer[1]).Edge() };
  // Each side runs the other way round along its B-spline edge than the wedge does.
  BRepBuilderAPI_MakeWire upper, lower;
  upper.Add(rays[0]);
  upper.Add(BRepBuilderAPI_MakeEdge(outer[0], ends[0]).Edge());
  upper.Add(TopoDS::Edge(edges[0].Reversed()));
  lower.Add(edges[1]);
  lower.Add(BRepBuilderAPI_MakeEdge(ends[1], outer[1]).Edge());
  lower.Add(TopoDS::Edge(rays[1].Reversed()));
  builder.Add(shell, BRepBuilderAPI_MakeFace(upper.Wire(), Standard_True).Face());
  builder.Add(shell, BRepBuilderAPI_MakeFace(lower.Wire(), Standard_True).Face());
  return shell;
}

/// A prism (height 0.3) over a wedge between two cubic B-spline edges from the origin to
/// (1, +-0.2) and the segment joining those: both edges have the poles (0, 0), (0, 0), (0, 0),
/// (1e-6, 0) on their first knot span, so for half their parameter range they stall at the origin
/// and run together (as the windings of KiCad's Bourns 8100 toroids do), then part.
inline TopoDS_Shape StallingEdgesPrism()
{
  TColStd_Array1OfReal knots(1, 3);
  TColStd_Array1OfInteger mults(1, 3);
  for (int k = 1; k <= 3; ++k)
  {
    knots(k) = 0.5 * (k - 1);
    mults(k) = k == 2 ? 1 : 4;
  }
  TColgp_Array1OfPnt poles(1, 5);
  poles(1) = poles(2) = poles(3) = gp::Origin();
  poles(4) = gp_Pnt(1e-6, 0, 0);
  poles(5) = gp_Pnt(1, 0.2, 0);
  return BRepPrimAPI_MakePrism(MirroredBSplineWedge(poles, knots, mults), gp_Vec(0, 0, 0.3)).Shape();
}

/// A plane wedge between two cubic B-spline edges from the origin to (1, +-0.2) and the segment
/// joining those: both edges first run 0.037 past the origin (to x = -0.037, their loops
/// crossing each other) and come back to it (three poles at the origin), as the windings of
/// KiCad's Bourns 8100 toroids do, then part. (Not a prism: its side faces, extrusions of the
/// curves, would hold the loops themselves.) With `passing`, they come back at speed (poles
/// (-0.01, -0.002), (0, 0), (0.01, 0.002) around the knot 0.6), not stalling at the origin: no
/// sample of theirs need lie within the tolerance of it there, as on KiCad's L19.3mm toroid,
/// whose winding edge 321 passes vertex 206 between two samples 0.011 and 0.012 from it; and
/// the faces beyond the edges (up to (1, +-0.4)) make a shell of three.
inline TopoDS_Shape DoublingBackEdgesWedge(bool passing = false)
{
  TColStd_Array1OfReal knots(1, 6);
  TColStd_Array1OfInteger mults(1, 6);
  for (int k = 1; k <= 6; ++k)
  {
    knots(k) = 0.2 * (k - 1);
    mults(k) = k == 1 || k == 6 ? 4 : 1;
  }
  TColgp_Array1OfPnt poles(1, 8);
  poles(1) = poles(4) = poles(5) = poles(6) = gp::Origin();
  poles(2) = gp_Pnt(-0.04, 0.01, 0);
  poles(3) = gp_Pnt(-0.04, -0.01, 0);
  poles(7) = gp_Pnt(0.5, 0.1, 0);
  poles(8) = gp_Pnt(1, 0.2, 0);
  if (passing)
  {
    poles(4) = gp_Pnt(-0.01, -0.002, 0);
    poles(6) = gp_Pnt(0.01, 0.002, 0);
  }
  return MirroredBSplineWedge(poles, knots, mults, passing);
}

/// The quarter of the pinched hemisphere (radius 10, 18 deg hole at the pole about +z): one
/// spherical face, longitude 0..90 deg from +x, latitude 0..72 deg (u, v in radians).
inline TopoDS_Shape HemisphereQuarter(double radius = 10.0)
{
  Handle(Geom_SphericalSurface) sphere =
    new Geom_SphericalSurface(gp_Ax3(gp::Origin(), gp::DZ(), gp::DX()), radius);
  BRepBuilderAPI_MakeFace face(sphere, 0.0, M_PI / 2, 0.0, 72.0 * M_PI / 180.0, 1e-7);
  return face.IsDone() ? face.Shape() : TopoDS_Shape();
}

/// The octant of the pinched cylinder (radius 300, axis y, x = r sin(theta), z = r cos(theta),
/// theta 0..90 deg, y 0..300) as two cylindrical faces split at theta = 45 deg, sewn so that they
/// share that edge, where they meet tangentially. The faces have their own parameters: the first
/// (theta < 45 deg) u = theta, v = y; the second lies on a cylinder with axis -y and angle origin
/// on +x, u = 90 deg - theta, v = -y (the transition between them is a flip of both).
inline TopoDS_Shape CylinderOctantTwoFaces(double radius = 300.0, double halfLength = 300.0)
{
  Handle(Geom_CylindricalSurface) first =
    new Geom_CylindricalSurface(gp_Ax3(gp::Origin(), gp::DY(), gp::DZ()), radius);
  Handle(Geom_CylindricalSurface) second =
    new Geom_CylindricalSurface(gp_Ax3(gp::Origin(), -gp::DY(), gp::DX()), radius);
  BRepBuilderAPI_MakeFace a(first, 0.0, M_PI / 4, 0.0, halfLength, 1e-7);
  BRepBuilderAPI_MakeFace b(second, 0.0, M_PI / 4, -halfLength, 0.0, 1e-7);
  if (!a.IsDone() || !b.IsDone())
  {
    return TopoDS_Shape();
  }
  BRepBuilderAPI_Sewing sewing(1e-6);
  sewing.Add(a.Face());
  sewing.Add(b.Face());
  sewing.Perform();
  return sewing.SewedShape();
}
/// The faces of a 2 x 1 x 0.5 box as loose faces, as in a STEP file of unconnected faces: each
/// face is a copy with edges and vertices of its own, moved out along its normal by `gap`, so
/// that neighbouring faces miss each other by up to ~1.4 gap and nothing connects them until
/// they are sewn. `missing` >= 0 leaves that face out (5: the top, z = 0.5): an open box.
inline TopoDS_Shape LooseBoxFaces(double gap = 1e-5, int missing = -1)
{
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 2.0, 1.0, 0.5).Shape();
  BRep_Builder builder;
  TopoDS_Compound faces;
  builder.MakeCompound(faces);
  int index = 0;
  for (TopExp_Explorer fx(box, TopAbs_FACE); fx.More(); fx.Next())
  {
    if (index++ == missing)
    {
      continue;
    }
    const TopoDS_Face face = TopoDS::Face(BRepBuilderAPI_Copy(fx.Current()).Shape());
    gp_Pnt centre;
    gp_Vec du, dv;
    double u0, u1, v0, v1;
    BRepTools::UVBounds(face, u0, u1, v0, v1);
    BRepAdaptor_Surface(face).D1(0.5 * (u0 + u1), 0.5 * (v0 + v1), centre, du, dv);
    gp_Vec normal = du.Crossed(dv).Normalized();
    if (face.Orientation() == TopAbs_REVERSED)
    {
      normal.Reverse();
    }
    gp_Trsf move;
    move.SetTranslation(gap * normal);
    builder.Add(faces, BRepBuilderAPI_Transform(face, move, Standard_True).Shape());
  }
  return faces;
}

/// A prism (height 0.5) over an L-shaped outline whose step is `step` high: the step's side is
/// a sliver face `step` x 0.5, with two edges `step` long (a ledge left by a CAD operation).
inline TopoDS_Shape SteppedPrism(double step)
{
  BRepBuilderAPI_MakePolygon outline;
  for (const gp_Pnt& p : { gp_Pnt(0, 0, 0), gp_Pnt(1, 0, 0), gp_Pnt(1, 1, 0), gp_Pnt(0.5, 1, 0),
         gp_Pnt(0.5, 1 - step, 0), gp_Pnt(0, 1 - step, 0) })
  {
    outline.Add(p);
  }
  outline.Close();
  const TopoDS_Face base = BRepBuilderAPI_MakeFace(outline.Wire(), Standard_True).Face();
  return BRepPrimAPI_MakePrism(base, gp_Vec(0, 0, 0.5)).Shape();
}
/// A box with a zero-area face beside it, as exporters leave them: a planar face bounded by
/// three collinear edges (on the line from (0, 0, 2) to (1, 0, 2)).
inline TopoDS_Shape BoxWithZeroAreaFace()
{
  BRep_Builder builder;
  TopoDS_Compound shapes;
  builder.MakeCompound(shapes);
  builder.Add(shapes, BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 1.0, 1.0, 1.0).Shape());
  const TopoDS_Vertex a = BRepBuilderAPI_MakeVertex(gp_Pnt(0, 0, 2));
  const TopoDS_Vertex b = BRepBuilderAPI_MakeVertex(gp_Pnt(0.4, 0, 2));
  const TopoDS_Vertex c = BRepBuilderAPI_MakeVertex(gp_Pnt(1, 0, 2));
  TopoDS_Wire wire;
  builder.MakeWire(wire);
  builder.Add(wire, BRepBuilderAPI_MakeEdge(a, b).Edge());
  builder.Add(wire, BRepBuilderAPI_MakeEdge(b, c).Edge());
  builder.Add(wire, BRepBuilderAPI_MakeEdge(c, a).Edge());
  builder.Add(shapes, BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0, 0, 2), gp::DZ()), wire, Standard_True).Face());
  return shapes;
}

/// A box (-1..1, -0.6..0.6, 0..0.8) with edges rounded by OCCT's fillets
/// (BRepFilletAPI_MakeFillet), which meet the box's faces tangentially: all 12 edges
/// (cylinders along the edges, spheres at the corners), or only the two top edges at the
/// corner (1, 0.6, 0.8). Those two fillets meet each other in a mitre: tangent at the top,
/// where both touch the top face, at 90 degrees where they reach the box's sides.
inline TopoDS_Shape FilletedBox(double radius, bool allEdges)
{
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(-1.0, -0.6, 0.0), 2.0, 1.2, 0.8).Shape();
  BRepFilletAPI_MakeFillet fillet(box);
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(box, TopAbs_EDGE, edges);
  for (int i = 1; i <= edges.Extent(); ++i)
  {
    const TopoDS_Edge& edge = TopoDS::Edge(edges(i));
    TopoDS_Vertex a, b;
    TopExp::Vertices(edge, a, b);
    const gp_Pnt p = BRep_Tool::Pnt(a), q = BRep_Tool::Pnt(b);
    const gp_Pnt corner(1.0, 0.6, 0.8);
    const bool top = p.Z() > 0.7 && q.Z() > 0.7;
    if (allEdges || (top && (p.Distance(corner) < 1e-9 || q.Distance(corner) < 1e-9)))
    {
      fillet.Add(radius, edge);
    }
  }
  fillet.Build();
  return fillet.IsDone() ? fillet.Shape() : TopoDS_Shape();
}
/// A prism 0.5 high over the outline (0, 0), (1, 0), (2, tan(kink) ), (2, 1), (0, 1), taken
/// apart into its faces, the side face from (1, 0) moved out along its normal by `gap`: its two
/// front faces meet at the vertical edge at x = 1 at `kink` degrees (a tangent interface within
/// RestoreG1's threshold, not exactly tangent), and the nodes at that edge's ends (the mean of
/// the faces there) lie off the edge's mean curve (a model whose faces miss each other).
inline TopoDS_Shape KinkedPrismWithLooseSide(double kink, double gap)
{
  BRepBuilderAPI_MakePolygon outline;
  const double rise = std::tan(kink * M_PI / 180);
  for (const gp_Pnt& p : { gp_Pnt(0, 0, 0), gp_Pnt(1, 0, 0), gp_Pnt(2, rise, 0), gp_Pnt(2, 1, 0),
         gp_Pnt(0, 1, 0) })
  {
    outline.Add(p);
  }
  outline.Close();
  const TopoDS_Face base = BRepBuilderAPI_MakeFace(outline.Wire(), Standard_True).Face();
  const TopoDS_Shape prism = BRepPrimAPI_MakePrism(base, gp_Vec(0, 0, 0.5)).Shape();
  BRep_Builder builder;
  TopoDS_Compound faces;
  builder.MakeCompound(faces);
  const gp_Vec normal(rise, -1, 0); // outward from the side face from (1, 0) to (2, rise)
  for (TopExp_Explorer fx(prism, TopAbs_FACE); fx.More(); fx.Next())
  {
    const TopoDS_Face face = TopoDS::Face(BRepBuilderAPI_Copy(fx.Current()).Shape());
    double u0, u1, v0, v1;
    BRepTools::UVBounds(face, u0, u1, v0, v1);
    const gp_Pnt centre = BRepAdaptor_Surface(face).Value(0.5 * (u0 + u1), 0.5 * (v0 + v1));
    const bool loose = centre.X() > 1.1 && centre.Y() < 0.5 * rise + 1e-6 && std::abs(centre.Z() - 0.25) < 1e-6;
    gp_Trsf move;
    move.SetTranslation(loose ? gap * normal.Normalized() : gp_Vec(0, 0, 0));
    builder.Add(faces, BRepBuilderAPI_Transform(face, move, Standard_True).Shape());
  }
  return faces;
}

/// A square face on the offset (by 0.1) of a planar biquadratic B-spline patch whose middle
/// third collapses to one point: there the offset surface has no normal, and OpenCASCADE throws
/// (Geom_UndefinedValue) when it evaluates it, e.g. for the bounding box when the file is read.
inline TopoDS_Shape OffsetSurfaceWithoutNormal()
{
  TColgp_Array2OfPnt poles(1, 5, 1, 5);
  for (int i = 1; i <= 5; ++i)
  {
    for (int j = 1; j <= 5; ++j)
    {
      const bool middle = i > 1 && i < 5 && j > 1 && j < 5;
      poles(i, j) = middle ? gp_Pnt(2, 2, 0) : gp_Pnt(i - 1, j - 1, 0);
    }
  }
  TColStd_Array1OfReal knots(1, 4);
  TColStd_Array1OfInteger mults(1, 4);
  const double k[4] = { 0, 1.0 / 3, 2.0 / 3, 1 };
  const int m[4] = { 3, 1, 1, 3 };
  for (int i = 0; i < 4; ++i)
  {
    knots(i + 1) = k[i];
    mults(i + 1) = m[i];
  }
  Handle(Geom_BSplineSurface) patch =
    new Geom_BSplineSurface(poles, knots, knots, mults, mults, 2, 2);
  BRepBuilderAPI_MakeFace face(new Geom_OffsetSurface(patch, 0.1, Standard_True), 0, 1, 0, 1, 1e-7);
  return face.IsDone() ? face.Shape() : TopoDS_Shape();
}

/// A prism (`height` high) over a thin ring sector: radii `radius` and `radius + width` about the
/// z axis, from 0 to `degrees`. Its top and bottom are strips far narrower than long, whose
/// inner arc bulges across them between samples that are far enough apart for the tolerance.
inline TopoDS_Shape ThinRingSector(double radius, double width, double degrees, double height)
{
  const double a = degrees * M_PI / 180;
  const gp_Circ inner(gp_Ax2(gp_Pnt(0, 0, 0), gp::DZ()), radius);
  const gp_Circ outer(gp_Ax2(gp_Pnt(0, 0, 0), gp::DZ()), radius + width);
  const gp_Pnt p0(radius, 0, 0), p1(radius * std::cos(a), radius * std::sin(a), 0);
  const gp_Pnt q0(radius + width, 0, 0);
  const gp_Pnt q1((radius + width) * std::cos(a), (radius + width) * std::sin(a), 0);
  BRepBuilderAPI_MakeWire wire;
  auto arc = [](const gp_Circ& c, const gp_Pnt& from, const gp_Pnt& to) {
    return BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(c, from, to, Standard_True).Value()).Edge();
  };
  wire.Add(arc(inner, p0, p1));
  wire.Add(BRepBuilderAPI_MakeEdge(p1, q1).Edge());
  wire.Add(arc(outer, q0, q1));
  wire.Add(BRepBuilderAPI_MakeEdge(q0, p0).Edge());
  const TopoDS_Face base = BRepBuilderAPI_MakeFace(wire.Wire(), Standard_True).Face();
  return BRepPrimAPI_MakePrism(base, gp_Vec(0, 0, height)).Shape();
}
/// A box (2 r x 2 r x height) fused with the cylinder of radius r inscribed in it: its top and
/// bottom are split into the disk and four corner pieces, which end in cusps where the circle
/// touches the box's sides (the arc tangent to the side's line), and which meet the disk
/// tangentially (coplanar) along the arcs.
inline TopoDS_Shape BoxWithInscribedDisk(double r, double height)
{
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(-r, -r, 0), 2 * r, 2 * r, height).Shape();
  const TopoDS_Shape disk =
    BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp::DZ()), r, height).Shape();
  return BRepAlgoAPI_Fuse(box, disk).Shape();
}

/// A pad as KiCad's RC1602A display has 32 of: a block (2 r wide, 2 r deep) whose semicircular
/// bite of radius r meets its sides x = +-r tangentially (two cusps on each of its top and
/// bottom faces), fused with a half ring (radii r / 2 to r) that fills the bite coplanarly: the
/// ring's arc is a tangent interface from cusp to cusp.
inline TopoDS_Shape PadWithRingInBite(double r, double height)
{
  const TopoDS_Shape block = BRepPrimAPI_MakeBox(gp_Pnt(-r, 0, 0), 2 * r, 2 * r, height).Shape();
  const TopoDS_Shape bite =
    BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, -height), gp::DZ()), r, 3 * height).Shape();
  const TopoDS_Shape disk =
    BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp::DZ()), r, height).Shape();
  const TopoDS_Shape hole =
    BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, -height), gp::DZ()), r / 2, 3 * height).Shape();
  const TopoDS_Shape lower = BRepPrimAPI_MakeBox(gp_Pnt(-2 * r, -2 * r, -height), 4 * r, 2 * r,
    3 * height).Shape(); // y < 0: the ring is the half y > 0
  const TopoDS_Shape ring = BRepAlgoAPI_Cut(BRepAlgoAPI_Cut(disk, hole).Shape(), lower).Shape();
  return BRepAlgoAPI_Fuse(BRepAlgoAPI_Cut(block, bite).Shape(), ring).Shape();
}

/// A plate (2 r x 2 r x height) with a hole of radius r / 2 through it that touches the side
/// x = -r: the top and bottom faces' inner loop touches their outer one at (-r, 0), where the
/// face's boundary curves (the circle and the side's line) are tangent: two cusps at one node.
inline TopoDS_Shape PlateWithTouchingHole(double r, double height)
{
  const TopoDS_Shape plate = BRepPrimAPI_MakeBox(gp_Pnt(-r, -r, 0), 2 * r, 2 * r, height).Shape();
  const TopoDS_Shape hole =
    BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(-r / 2, 0, -height), gp::DZ()), r / 2, 3 * height)
      .Shape();
  return BRepAlgoAPI_Cut(plate, hole).Shape();
}

/// A hemisphere (radius r, z >= 0) on its disk, the spherical part in two faces of different
/// parametrisations that meet tangentially along the half circle y = 0: for y >= 0 a sphere
/// about z, whose pole (0, 0, r) lies inside that edge (the face has no normal there and a
/// degenerated edge, like the corner patches of KiCad's Altech_AK300 terminal blocks); for
/// y <= 0 a sphere about x, regular there (its poles are the edge's ends). Sewn into one shell.
inline TopoDS_Shape HemisphereWithPoleOnTangentEdge(double r)
{
  Handle(Geom_SphericalSurface) aboutZ =
    new Geom_SphericalSurface(gp_Ax3(gp::Origin(), gp::DZ(), gp::DX()), r);
  Handle(Geom_SphericalSurface) aboutX =
    new Geom_SphericalSurface(gp_Ax3(gp::Origin(), gp::DX(), gp::DY()), r);
  BRepBuilderAPI_MakeFace north(aboutZ, 0, M_PI, 0, M_PI / 2, 1e-7);
  BRepBuilderAPI_MakeFace south(aboutX, M_PI / 2, M_PI, -M_PI / 2, M_PI / 2, 1e-7);
  const TopoDS_Edge rim = BRepBuilderAPI_MakeEdge(gp_Circ(gp_Ax2(gp::Origin(), gp::DZ()), r));
  BRepBuilderAPI_MakeFace disk(gp_Pln(gp::Origin(), gp::DZ()), BRepBuilderAPI_MakeWire(rim).Wire());
  if (!north.IsDone() || !south.IsDone() || !disk.IsDone())
  {
    return TopoDS_Shape();
  }
  BRepBuilderAPI_Sewing sewing(1e-6);
  sewing.Add(north.Face());
  sewing.Add(south.Face());
  sewing.Add(disk.Face());
  sewing.Perform();
  return sewing.SewedShape();
}

/// A sphere of radius r below the latitude `top` (radians, above -pi/2): a cap with a flat top,
/// like a BGA ball. The sphere's seam runs from its south pole to the top's circle.
inline TopoDS_Shape SphericalCap(double r, double top)
{
  return BRepPrimAPI_MakeSphere(gp_Ax2(gp::Origin(), gp::DZ()), r, -M_PI / 2, top).Shape();
}

/// A section of `degrees` of a torus of radii R and r about the z axis, capped by two disks: a
/// bent wire. Its seam runs along the outer equator.
inline TopoDS_Shape BentWire(double R, double r, double degrees)
{
  return BRepPrimAPI_MakeTorus(R, r, degrees * M_PI / 180).Shape();
}

/// A cylinder (radius 1, height 1, axis z) with its top rim rounded (a torus of tube radius
/// `rim`, tangent to the side and the top along circles), cut off by the plane through `point`
/// with normal `normal`. The cut crosses the tangent circles: at those vertices the tangent
/// interfaces (the normal turning along them) meet the cut's edges, whose pcurves on the
/// cylinder and the torus curve (ellipse-like), so that their cubics leave the vertices off the
/// faces' derivatives along the chords.
inline TopoDS_Shape CutRoundedCylinder(double rim, const gp_Pnt& point, const gp_Dir& normal)
{
  const TopoDS_Shape cylinder =
    BRepPrimAPI_MakeCylinder(gp_Ax2(gp::Origin(), gp::DZ()), 1.0, 1.0).Shape();
  BRepFilletAPI_MakeFillet fillet(cylinder);
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(cylinder, TopAbs_EDGE, edges);
  for (int i = 1; i <= edges.Extent(); ++i)
  {
    TopoDS_Vertex a, b;
    TopExp::Vertices(TopoDS::Edge(edges(i)), a, b);
    if (BRep_Tool::Pnt(a).Z() > 0.99 && BRep_Tool::Pnt(b).Z() > 0.99 &&
      !BRep_Tool::Degenerated(TopoDS::Edge(edges(i))))
    {
      fillet.Add(rim, TopoDS::Edge(edges(i)));
    }
  }
  fillet.Build();
  if (!fillet.IsDone())
  {
    return TopoDS_Shape();
  }
  // The half-space beyond the plane: a box with one face on it.
  const gp_Ax2 frame(point, normal);
  const gp_Pnt corner =
    point.Translated(-2.5 * gp_Vec(frame.XDirection()) - 2.5 * gp_Vec(frame.YDirection()));
  const TopoDS_Shape beyond =
    BRepPrimAPI_MakeBox(gp_Ax2(corner, normal, frame.XDirection()), 5, 5, 5).Shape();
  return BRepAlgoAPI_Cut(fillet.Shape(), beyond).Shape();
}

/// A tube about the x axis like the body of KiCad's axial inductors (Fastron VHBCC): bore 0.3,
/// outer cylinder 3.15 from x = -16 to about -0.24, and at x = 0 a flat ring out to radius 0.6
/// whose rim the end face, the revolution of an arc of radius 327 (the face's F_t is 327, its
/// F_s the distance to the axis: 0.6 to 3.15), leaves at `degrees` to the ring: a tangent
/// interface within the default G1 threshold but not an exact one.
inline TopoDS_Shape TubeWithDomedEnd(double degrees)
{
  const double a = degrees * M_PI / 180, radius = 327, sweep = 0.0078;
  // In the (x, y) plane, y the distance to the axis: the arc leaves A along (-sin a, cos a).
  const gp_Pnt A(0, 0.6, 0);
  const gp_Pnt C(-radius * std::cos(a), 0.6 - radius * std::sin(a), 0);
  const double start = std::atan2(A.Y() - C.Y(), A.X() - C.X());
  const gp_Pnt B(C.X() + radius * std::cos(start + sweep), C.Y() + radius * std::sin(start + sweep), 0);
  const gp_Pnt outer(-16, B.Y(), 0), innerEnd(-16, 0.3, 0), inner(0, 0.3, 0);
  BRepBuilderAPI_MakeWire wire;
  wire.Add(BRepBuilderAPI_MakeEdge(inner, A).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(A, gp_Vec(-std::sin(a), std::cos(a), 0), B).Value()).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(B, outer).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(outer, innerEnd).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(innerEnd, inner).Edge());
  const TopoDS_Face profile = BRepBuilderAPI_MakeFace(wire.Wire(), Standard_True).Face();
  return BRepPrimAPI_MakeRevol(profile, gp_Ax1(gp::Origin(), gp::DX()), 2 * M_PI).Shape();
}
/// The unit square in z = 0 whose side along x = 0 ends at the origin in a cubic B-spline edge
/// from (0, 0.5) with the poles (0, 1e-3) and (1e-5, -1e-5): the edge crawls to the origin
/// (speed 1.5 at its start, 4e-5 at its end) and comes to it turning back, its derivative there
/// pointing against its approach, as the windings of KiCad's Bourns 8100 toroids come to their
/// vertices.
inline TopoDS_Shape HookedEdgeSquare()
{
  const gp_Pnt start(0, 0.5, 0), corners[3] = { gp_Pnt(1, 0, 0), gp_Pnt(1, 1, 0), gp_Pnt(0, 1, 0) };
  TColgp_Array1OfPnt poles(1, 4);
  poles(1) = start;
  poles(2) = gp_Pnt(0, 1e-3, 0);
  poles(3) = gp_Pnt(1e-5, -1e-5, 0);
  poles(4) = gp::Origin();
  TColStd_Array1OfReal knots(1, 2);
  TColStd_Array1OfInteger mults(1, 2);
  knots(1) = 0;
  knots(2) = 1;
  mults(1) = mults(2) = 4;
  const TopoDS_Vertex origin = BRepBuilderAPI_MakeVertex(gp::Origin());
  const TopoDS_Vertex top = BRepBuilderAPI_MakeVertex(start);
  BRepBuilderAPI_MakeWire wire;
  wire.Add(BRepBuilderAPI_MakeEdge(new Geom_BSplineCurve(poles, knots, mults, 3), top, origin).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(origin, BRepBuilderAPI_MakeVertex(corners[0])).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(corners[0], corners[1]).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(corners[1], corners[2]).Edge());
  wire.Add(BRepBuilderAPI_MakeEdge(corners[2], start).Edge());
  return BRepBuilderAPI_MakeFace(wire.Wire(), Standard_True).Face();
}
} // namespace ctsplines_test

#endif
