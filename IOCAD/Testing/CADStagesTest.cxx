// SPDX-License-Identifier: GPL-3.0-or-later
// The stitcher's VTK-free stages (CADFaceSplines, CADStitch, CADMeasure) on OCCT-built shapes
// sampled by vtkCADFaceSampler: facts each stage promises, stage by stage.
#include "BoundarySpanBulge.h"
#include "CADFaceMesher.h"
#include "CADFaceSplines.h"
#include "CADMeasure.h"
#include "CADSampledFace.h"
#include "CADStitch.h"
#include "InterfaceTangentPlanes.h"
#include "SplineDataValidation.h"

#include "vtkCADFaceSampler.h"

#include "CADTestFiles.h"
#include "CADTestShapes.h"

#include "vtkMultiBlockDataSet.h"
#include "vtkNew.h"

#include "CADFileReading.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepTools.hxx>
#include <Standard_Failure.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Geom2d_Line.hxx>
#include <Geom_Circle.hxx>
#include <Geom_SurfaceOfRevolution.hxx>
#include <Geom_TrimmedCurve.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <STEPControl_Writer.hxx>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace
{
/// A shape written to STEP and sampled at `tolerance`, its blocks read as the stages' input.
struct Sampled
{
  vtkNew<vtkCADFaceSampler> Sampler;
  std::vector<ctcad::SampledFace> Faces;
  ctk::SplineOptions Options; // KaG, the stitcher's default

  void Run(const std::string& name, const TopoDS_Shape& shape, double tolerance = 1e-4)
  {
    ASSERT_FALSE(shape.IsNull()) << name;
    const std::string path = ctsplines_test::TempPath("stages_" + name + ".step");
    STEPControl_Writer writer;
    writer.Transfer(shape, STEPControl_AsIs);
    ASSERT_EQ(writer.Write(path.c_str()), IFSelect_RetDone);
    this->Options.Method = ctk::Construction::KaG;
    this->Sampler->SetFileName(path.c_str());
    this->Sampler->SetTolerance(tolerance);
    this->Sampler->SetConstruction(static_cast<int>(this->Options.Method));
    this->Sampler->Update();
    vtkMultiBlockDataSet* blocks = this->Sampler->GetOutput();
    ASSERT_GT(blocks->GetNumberOfBlocks(), 0u) << name;
    this->Faces.resize(blocks->GetNumberOfBlocks());
    for (unsigned int f = 0; f < blocks->GetNumberOfBlocks(); ++f)
    {
      ASSERT_EQ(ctcad::ReadSampledFace(blocks->GetBlock(f), f, this->Options, true, this->Faces[f]), "")
        << name;
    }
  }

  ctcad::FaceSurface Surface()
  {
    vtkCADFaceSampler* s = this->Sampler;
    return [s](int f, double u, double v, double* P, double* Du, double* Dv, std::string& e) {
      return s->EvaluateSurface(f, u, v, P, Du, Dv, e);
    };
  }
};

/// Four threads taking the faces from the last: another order and other threads than both
/// the serial loop and ForEachFaceInParallel.
void ForEachFaceBackwardsOnFourThreads(int n, const std::function<void(int)>& body)
{
  std::vector<std::thread> threads;
  for (int i = 0; i < 4; ++i)
  {
    threads.emplace_back([&, i]() {
      for (int f = n - 1 - i; f >= 0; f -= 4)
      {
        body(f);
      }
    });
  }
  for (std::thread& t : threads)
  {
    t.join();
  }
}

template <typename V, typename A>
bool SameBits(const std::vector<V, A>& a, const std::vector<V, A>& b)
{
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(V)) == 0;
}

std::vector<ctcad::FaceSpline> Build(const Sampled& s, const ctcad::FaceRunner& forEach = nullptr)
{
  std::vector<ctcad::FaceSpline> splines;
  std::string error;
  EXPECT_TRUE(ctcad::BuildFaceSplines(s.Faces, s.Options, splines, error, forEach)) << error;
  return splines;
}
/// Calls body(p, q) with the end vertices of every boundary edge of face's mesh that lies on a
/// tangent interface.
void ForEachTangentEdge(
  const ctcad::SampledFace& face, const std::function<void(ctk::Id p, ctk::Id q)>& body)
{
  for (std::size_t i = 0; i < face.Tangent.size(); ++i)
  {
    const ctk::Id* tri = face.Input.Triangles.data() + 3 * (i / 3);
    if (face.Tangent[i] && face.BRepEdge[i] >= 0)
    {
      body(tri[i % 3], tri[(i + 1) % 3]);
    }
  }
}

/// The splines of s's faces meet within 0.1 degrees at tangent interfaces, without gaps.
void ExpectG1AtTangentInterfaces(const Sampled& s)
{
  const std::vector<ctcad::FaceSpline> splines = Build(s);
  const ctcad::InterfaceMeasures m = ctcad::MeasureInterfaces(s.Faces, splines);
  EXPECT_GT(m.G1[1].Count, 0);
  EXPECT_LE(m.G1[1].Max, 0.1);
  EXPECT_EQ(m.MaxC0Gap, 0.0);
}
} // namespace

// The spline of every face interpolates its samples and follows the shared edge cubics on its
// boundary; the faces built in parallel are the serial ones, bit for bit.
TEST(CADStages, FaceSplinesFollowTheEdgesAndAreTheSameInParallel)
{
  Sampled s;
  s.Run("filleted_box", ctsplines_test::FilletedBox(0.2, true));
  ASSERT_GE(s.Faces.size(), 20u);
  const std::vector<ctcad::FaceSpline> serial = Build(s, ctcad::ForEachFaceSerially);
  const std::vector<ctcad::FaceSpline> parallel = Build(s);
  const std::vector<ctcad::FaceSpline> backwards = Build(s, ForEachFaceBackwardsOnFourThreads);
  ASSERT_EQ(serial.size(), s.Faces.size());
  ctk::Id boundarySpans = 0;
  for (std::size_t f = 0; f < s.Faces.size(); ++f)
  {
    const ctk::CubicSpline& spline = serial[f].Spline;
    for (const auto* other : { &parallel[f].Spline, &backwards[f].Spline })
    {
      EXPECT_TRUE(SameBits(spline.ControlPoints, other->ControlPoints)) << "face " << f;
      EXPECT_TRUE(SameBits(spline.DomainPoints, other->DomainPoints)) << "face " << f;
      EXPECT_TRUE(SameBits(spline.SplitTau, other->SplitTau)) << "face " << f;
    }
    const ctk::SplineInput& in = s.Faces[f].Input;
    for (ctk::Id v = 0; v < in.NumberOfVertices(); ++v)
    {
      ASSERT_EQ(spline.ControlPoints[v], ctk::Vec3(in.F[3 * v], in.F[3 * v + 1], in.F[3 * v + 2]));
    }
    const ctk::MeshTopology& topo = serial[f].Topology;
    for (ctk::Id t = 0; t < in.NumberOfTriangles(); ++t)
    {
      for (int l = 0; l < 3; ++l)
      {
        const double* c = in.BoundaryCurvePoints.data() + 18 * t + 6 * l;
        if (topo.Neighbor(t, l) >= 0 || std::isnan(c[0]))
        {
          continue;
        }
        const ctk::Id a = in.Triangles[3 * t + l];
        const ctk::Id e = topo.TriangleEdges[t][l];
        EXPECT_EQ(
          spline.ControlPoints[spline.Layout.EdgePoint(topo, e, a)], ctk::Vec3(c[0], c[1], c[2]));
        ++boundarySpans;
      }
    }
  }
  EXPECT_GT(boundarySpans, 0);
}

// A face the kernel cannot build is named; with two, the lowest, whatever the loop's order.
TEST(CADStages, FaceSplineFailureNamesTheLowestFace)
{
  Sampled s;
  s.Run("box_failure", BRepPrimAPI_MakeBox(2.0, 1.0, 0.5).Shape());
  ASSERT_EQ(s.Faces.size(), 6u);
  for (const int f : { 4, 2 })
  {
    auto& uv = s.Faces[f].Input.UV;
    const ctk::Id* tri = s.Faces[f].Input.Triangles.data();
    uv[2 * tri[1]] = uv[2 * tri[0]]; // triangle 0 loses its area in the parameter plane
    uv[2 * tri[1] + 1] = uv[2 * tri[0] + 1];
  }
  std::vector<ctcad::FaceSpline> splines;
  for (const ctcad::FaceRunner& loop : { ctcad::FaceRunner(ctcad::ForEachFaceSerially),
         ctcad::FaceRunner(ForEachFaceBackwardsOnFourThreads) })
  {
    std::string error;
    EXPECT_FALSE(ctcad::BuildFaceSplines(s.Faces, s.Options, splines, error, loop));
    EXPECT_EQ(error.rfind("face 2: spline construction failed: ", 0), 0u) << error;
  }
}

// Closed shapes stitch watertight: no free or non-manifold macro-edge, the two sides of every
// interface the same cubic exactly; one face left out opens the surface along its edges.
TEST(CADStages, StitchClosesABoxACylinderAndASphere)
{
  const std::pair<const char*, TopoDS_Shape> shapes[] = {
    { "box", BRepPrimAPI_MakeBox(gp_Pnt(-1, -0.5, 0), 2.0, 1.0, 0.5).Shape() },
    { "cylinder",
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 1.0, 2.0).Shape() },
    { "sphere", BRepPrimAPI_MakeSphere(gp_Pnt(0.1, -0.2, 0.3), 1.0).Shape() } };
  for (const auto& shape : shapes)
  {
    Sampled s;
    s.Run(std::string("stitch_") + shape.first, shape.second);
    const std::vector<ctcad::FaceSpline> splines = Build(s);
    ctcad::StitchedSurface surface;
    ctcad::StitchFaces(s.Faces, splines, surface);
    EXPECT_EQ(surface.FreeEdges, 0) << shape.first;
    EXPECT_EQ(surface.NonManifoldEdges, 0) << shape.first;
    ctk::Id points = 0, macroTriangles = 0;
    for (const ctcad::FaceSpline& fs : splines)
    {
      points += static_cast<ctk::Id>(fs.Spline.ControlPoints.size());
      macroTriangles += fs.Spline.Layout.NumberOfTriangles;
    }
    EXPECT_LT(static_cast<ctk::Id>(surface.Points.size()), points) << "shared points merged";
    EXPECT_EQ(surface.NumberOfMacroTriangles, macroTriangles);
    EXPECT_EQ(static_cast<ctk::Id>(surface.Cells.size()), 30 * macroTriangles);
    const ctcad::InterfaceMeasures m = ctcad::MeasureInterfaces(s.Faces, splines);
    EXPECT_GT(m.G1[0].Count + m.G1[1].Count, 0) << shape.first;
    EXPECT_EQ(m.MaxC0Gap, 0.0) << shape.first;
    if (s.Faces.size() > 1)
    {
      std::vector<ctcad::SampledFace> open(s.Faces.begin() + 1, s.Faces.end());
      std::vector<ctcad::FaceSpline> openSplines(splines.begin() + 1, splines.end());
      ctcad::StitchFaces(open, openSplines, surface);
      EXPECT_GT(surface.FreeEdges, 0) << shape.first << " without its first face";
      EXPECT_EQ(surface.NonManifoldEdges, 0) << shape.first << " without its first face";
    }
  }
}

// The box's faces meet at right angles; the filleted box's tangentially, made G1 by the
// sampler; the stitched faces lie within the tolerance of the CAD surfaces, measured the same
// whatever the loop over the faces.
TEST(CADStages, MeasureAnglesAndDeviation)
{
  Sampled box;
  box.Run("measure_box", BRepPrimAPI_MakeBox(gp_Pnt(-1, -0.5, 0), 2.0, 1.0, 0.5).Shape());
  const std::vector<ctcad::FaceSpline> boxSplines = Build(box);
  const ctcad::InterfaceMeasures right = ctcad::MeasureInterfaces(box.Faces, boxSplines);
  EXPECT_EQ(right.G1[1].Count, 0);
  EXPECT_NEAR(right.G1[0].Max, 90.0, 1e-9);
  EXPECT_NEAR(right.G1[0].Sum / right.G1[0].Count, 90.0, 1e-9);
  for (std::size_t f = 0; f < box.Faces.size(); ++f)
  {
    EXPECT_LT(ctcad::GapBeforeStitching(box.Faces[f], boxSplines[f]), 1e-12) << "planes, lines";
  }

  Sampled s;
  const double tolerance = 1e-4;
  s.Run("measure_filleted_box", ctsplines_test::FilletedBox(0.2, true), tolerance);
  const std::vector<ctcad::FaceSpline> splines = Build(s);
  const ctcad::InterfaceMeasures m = ctcad::MeasureInterfaces(s.Faces, splines);
  EXPECT_GT(m.G1[1].Count, 0) << "the fillets' tangent interfaces";
  EXPECT_LE(m.G1[1].Max, 0.1);
  EXPECT_EQ(m.MaxC0Gap, 0.0);
  std::vector<ctcad::Deviation> perFace, serialPerFace;
  ctcad::Deviation all, serialAll;
  std::string error;
  ASSERT_TRUE(ctcad::MeasureDeviation(s.Surface(), 6, 16, s.Faces, splines, perFace, all, error))
    << error;
  ASSERT_TRUE(ctcad::MeasureDeviation(s.Surface(), 6, 16, s.Faces, splines, serialPerFace,
    serialAll, error, ctcad::ForEachFaceSerially))
    << error;
  EXPECT_GT(all.Count, 0);
  EXPECT_GT(all.MaxDistance, 0.0);
  EXPECT_LE(all.MaxDistance, tolerance * s.Sampler->GetDiagonal());
  EXPECT_EQ(all.MaxDistance, serialAll.MaxDistance);
  EXPECT_EQ(all.SumSquaredDistance, serialAll.SumSquaredDistance);
  EXPECT_EQ(all.MaxAngle, serialAll.MaxAngle);
  for (std::size_t f = 0; f < perFace.size(); ++f)
  {
    EXPECT_LE(perFace[f].MaxDistance, all.MaxDistance);
  }
  // A surface evaluation that throws (as OpenCASCADE's do) inside one face: the face's guard
  // names it and the operation, the lowest such face reported.
  const ctcad::FaceSurface surface = s.Surface();
  for (const bool occt : { true, false })
  {
    const ctcad::FaceSurface throwing = [&](int f, double u, double v, double* P, double* Du,
                                          double* Dv, std::string& e) {
      if (f >= 2)
      {
        if (occt)
        {
          throw Standard_Failure("no normal here");
        }
        throw std::runtime_error("out of range");
      }
      return surface(f, u, v, P, Du, Dv, e);
    };
    EXPECT_FALSE(ctcad::MeasureDeviation(throwing, 6, 16, s.Faces, splines, perFace, all, error));
    EXPECT_NE(error.find(std::string("face 2: the deviation measurement failed: ") +
                (occt ? "Standard_Failure: no normal here" : "std::runtime_error: out of range")),
      std::string::npos)
      << error;
  }
}

// Tangent spans are split until the surface normal turns by at most 11.25 degrees along them,
// on every face that has a normal at both ends, also where the other face has a pole at one end
// (it has no normal there), and there to half of that. Spans from the pole kept the edge
// sampling's length (22.5 degrees here; 26 on KiCad's Altech_AK300 corner patches, a G1 angle
// of 1 degree there). The measured G1 angle stays within 0.1 degrees.
TEST(CADStages, TangentSpansFromAPoleAreSplitByTheTurn)
{
  Sampled s;
  s.Run("pole_on_tangent_edge", ctsplines_test::HemisphereWithPoleOnTangentEdge(1.0));
  auto normal = [](const ctcad::SampledFace& face, ctk::Id v) {
    const std::vector<double>& fu = face.SurfaceFu;
    const std::vector<double>& fv = face.SurfaceFv;
    const ctk::Vec3 n = ctk::Vec3(fu[3 * v], fu[3 * v + 1], fu[3 * v + 2])
                          .cross(ctk::Vec3(fv[3 * v], fv[3 * v + 1], fv[3 * v + 2]));
    return n.norm() > 1e-8 ? ctk::Vec3(n.normalized()) : ctk::Vec3::Zero();
  };
  std::set<ctk::Id> poles; // nodes where a face has no normal
  for (const ctcad::SampledFace& face : s.Faces)
  {
    for (std::size_t v = 0; v < face.GlobalNode.size(); ++v)
    {
      if (normal(face, static_cast<ctk::Id>(v)).squaredNorm() == 0)
      {
        poles.insert(face.GlobalNode[v]);
      }
    }
  }
  ASSERT_FALSE(poles.empty());
  double worst[2] = { 0, 0 }; // away from poles, at a pole
  int spans[2] = { 0, 0 };
  for (const ctcad::SampledFace& face : s.Faces)
  {
    for (std::size_t i = 0; i < face.Tangent.size(); ++i)
    {
      const ctk::Id* tri = face.Input.Triangles.data() + 3 * (i / 3);
      const ctk::Id p = tri[i % 3], q = tri[(i + 1) % 3];
      const ctk::Vec3 a = normal(face, p), b = normal(face, q);
      if (face.Tangent[i] && face.BRepEdge[i] >= 0 && a.squaredNorm() > 0 &&
        b.squaredNorm() > 0)
      {
        const int atPole = poles.count(face.GlobalNode[p]) + poles.count(face.GlobalNode[q]) > 0;
        worst[atPole] =
          std::max(worst[atPole], std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI);
        ++spans[atPole];
      }
    }
  }
  EXPECT_GT(spans[0], 0);
  EXPECT_GT(spans[1], 0);
  EXPECT_LE(worst[0], 11.25 + 1e-9) << "largest turn of a face's normal along a tangent span";
  EXPECT_LE(worst[1], 5.625 + 1e-9) << "the same next to a pole";
  const std::vector<ctcad::FaceSpline> splines = Build(s);
  const ctcad::InterfaceMeasures m = ctcad::MeasureInterfaces(s.Faces, splines);
  EXPECT_LE(m.G1[1].Max, 0.1);
  EXPECT_EQ(m.MaxC0Gap, 0.0);
}

// A tangent span from a pole turns by at most 5.625 degrees, measured from the face's normal
// next to the pole, also where no face has a normal at both of its ends: a sphere's seam from
// its pole. The seam of a cap like a BGA ball turned by 54 degrees in one span (the sampling's
// tolerance needs no more), and G1 was 0.14 degrees off next to the pole on KiCad's BGA-100.
TEST(CADStages, SeamSpansFromAPoleAreSplitByTheTurn)
{
  Sampled s;
  s.Run("spherical_cap", ctsplines_test::SphericalCap(1.0, -0.62), 1e-3);
  const ctcad::FaceSurface surface = s.Surface();
  // The face's unit normal at parameters uv, zero at a pole.
  auto normal = [&](int f, const ctk::Vec2& uv) {
    double P[3], Du[3], Dv[3];
    std::string error;
    EXPECT_TRUE(surface(f, uv.x(), uv.y(), P, Du, Dv, error)) << error;
    const ctk::Vec3 n = ctk::Vec3(Du[0], Du[1], Du[2]).cross(ctk::Vec3(Dv[0], Dv[1], Dv[2]));
    return n.norm() > 1e-8 ? ctk::Vec3(n.normalized()) : ctk::Vec3::Zero();
  };
  double worst = 0;
  int fromPole = 0;
  for (int f = 0; f < static_cast<int>(s.Faces.size()); ++f)
  {
    const ctcad::SampledFace& face = s.Faces[f];
    const auto& uv = face.Input.UV;
    ForEachTangentEdge(face, [&](ctk::Id i, ctk::Id j) {
      const ctk::Vec2 p(uv[2 * i], uv[2 * i + 1]), q(uv[2 * j], uv[2 * j + 1]);
      ctk::Vec3 a = normal(f, p), b = normal(f, q);
      if ((a.squaredNorm() > 0) == (b.squaredNorm() > 0))
      {
        return;
      }
      // Next to the pole along the span.
      (a.squaredNorm() > 0 ? b : a) =
        a.squaredNorm() > 0 ? normal(f, q + 1e-6 * (p - q)) : normal(f, p + 1e-6 * (q - p));
      worst = std::max(worst, std::atan2(a.cross(b).norm(), a.dot(b)) * 180 / M_PI);
      ++fromPole;
    });
  }
  EXPECT_GE(fromPole, 2) << "the seam's span from the pole, on both sides";
  EXPECT_LE(worst, 5.625 + 1e-3) << "largest turn of the normal along a span from the pole";
  ExpectG1AtTangentInterfaces(s);
}

// Where a face curves much faster across a tangent span than along it, the face mesher's
// triangles there are as much longer than wide, and spans are split until turn^2 * max(turn,
// turn across over the span's length) <= 11.25 degrees cubed. A torus section like a bent lead
// wire (KiCad's LairdTech_28C0236: 0.118 degrees off G1 at such a seam): its seam runs along
// the outer equator, turning 7.5 degrees per span as sampled, 90 across the span's length.
TEST(CADStages, TangentSpansAcrossAFastCurvatureAreSplitByTheSkew)
{
  const double R = 2.8, r = 0.254; // the torus's radii: across the seam the normal turns 1 / r
  Sampled s;
  s.Run("bent_wire", ctsplines_test::BentWire(R, r, 30));
  const double maxTurn = M_PI / 16;
  double worst = 0; // turn^2 * max(turn, across) / maxTurn^3
  int spans = 0;
  for (const ctcad::SampledFace& face : s.Faces)
  {
    const std::vector<double>& fu = face.SurfaceFu;
    const std::vector<double>& fv = face.SurfaceFv;
    auto normal = [&](ctk::Id v) {
      return ctk::Vec3(fu[3 * v], fu[3 * v + 1], fu[3 * v + 2])
        .cross(ctk::Vec3(fv[3 * v], fv[3 * v + 1], fv[3 * v + 2]))
        .normalized();
    };
    ForEachTangentEdge(face, [&](ctk::Id p, ctk::Id q) {
      const ctk::Vec3 a = normal(p), b = normal(q);
      const double turn = std::atan2(a.cross(b).norm(), a.dot(b));
      const auto& F = face.Input.F;
      const double length = (ctk::Vec3(F[3 * p], F[3 * p + 1], F[3 * p + 2]) -
        ctk::Vec3(F[3 * q], F[3 * q + 1], F[3 * q + 2]))
                              .norm();
      const double across = length / r;
      worst = std::max(worst, turn * turn * std::max(turn, across) / std::pow(maxTurn, 3));
      ++spans;
    });
  }
  EXPECT_GE(spans, 8) << "the seam's spans, on both sides";
  EXPECT_LE(worst, 1.0 + 1e-3) << "turn^2 * max(turn, across) over 11.25 degrees cubed";
  ExpectG1AtTangentInterfaces(s);
}

// SpansBulgingAcrossFaces splits a span whose cubic bulges into its face by more than a quarter
// of the distance to the nearest other loop node. On a thin strip of an anisotropic plane
// (x = s, y = t / 4) with 1,000 bottom spans and 2,500 top nodes, the bottom spans bulge by 0.5
// to 1.5 times a quarter of the strip's width (the top nodes are nearer than the bottom
// neighbours): exactly the upper half is split, and no top span. The nodes near a span are
// looked up in a grid of the parameter plane, whose reach through the Jacobian this checks.
TEST(CADStages, SpansBulgingAcrossAStripAreThoseAboveAQuarterOfItsWidth)
{
  constexpr int bottom = 1000, top = 2500;
  constexpr double widthST = 0.0016, scaleT = 0.25; // 3D width 4e-4, bottom spans 1e-3 long
  constexpr double threshold = ctcad::MaxBulgeAcrossFace * widthST * scaleT;
  std::vector<ctcad::Point3> nodes;
  ctcad::CADFace face;
  ctcad::FaceLoop& loop = face.Loops.emplace_back();
  auto addNode = [&](double s, double t) {
    loop.Nodes.push_back({ { s, t }, static_cast<ctcad::Id>(nodes.size()) });
    nodes.push_back({ s, scaleT * t, 0 });
  };
  for (int i = 0; i <= bottom; ++i)
  {
    addNode(static_cast<double>(i) / bottom, 0);
  }
  for (int j = top; j >= 0; --j)
  {
    addNode(static_cast<double>(j) / top, widthST);
  }
  for (std::size_t k = 0; k < loop.Nodes.size(); ++k)
  {
    const ctcad::Point3& a = nodes[loop.Nodes[k].GlobalNode];
    const ctcad::Point3& b = nodes[loop.Nodes[(k + 1) % loop.Nodes.size()].GlobalNode];
    ctcad::LoopSegment seg;
    const bool onBottom = k < static_cast<std::size_t>(bottom);
    seg.Edge = onBottom ? 0 : 1;
    seg.Span = onBottom ? static_cast<ctcad::Id>(k) : static_cast<ctcad::Id>(k - bottom);
    // Inner control points at the chord's thirds, raised by 4/3 of the bulge (the cubic's
    // midpoint then lies the bulge above the chord's).
    const double bulge = onBottom ? threshold * (0.5 + (k + 0.5) / bottom) : 0;
    for (int c = 0; c < 3; ++c)
    {
      seg.Near0[c] = (2 * a[c] + b[c]) / 3;
      seg.Near1[c] = (a[c] + 2 * b[c]) / 3;
    }
    seg.Near0[1] += 4.0 / 3 * bulge;
    seg.Near1[1] += 4.0 / 3 * bulge;
    loop.Segments.push_back(seg);
  }
  const ctcad::FaceDerivatives plane = [](int, double s, double t, double P[3], double Ds[3],
                                         double Dt[3]) {
    P[0] = s, P[1] = scaleT * t, P[2] = 0;
    Ds[0] = 1, Ds[1] = 0, Ds[2] = 0;
    Dt[0] = 0, Dt[1] = scaleT, Dt[2] = 0;
  };
  const std::vector<std::pair<ctcad::Id, ctcad::Id>> spans =
    ctcad::SpansBulgingAcrossFaces({ face }, nodes, plane, 0.0);
  std::vector<std::pair<ctcad::Id, ctcad::Id>> expected;
  for (int i = bottom / 2; i < bottom; ++i)
  {
    expected.emplace_back(0, i);
  }
  EXPECT_EQ(spans, expected);
}

namespace
{
/// Two faces on the edge (0,0,0)-(1,0,0) (B-rep edge 0, one span), the plane z = 0 (s, t) and
/// the plane turned by `degrees` about the edge, each closed by a triangle's other two edges.
/// Face f, a triangle of the given nodes (global ids, uv on the pcurves) with one span per B-rep
/// edge of its segments, straight cubics; its loop node at global node 0 is `shift` off its
/// pcurves in t.
ctcad::CADFace TriangleFace(int f, const std::vector<ctcad::Point3>& nodes,
  const ctcad::Id globals[3], const double uv[3][2], const ctcad::Id edges[3], double shift)
{
  ctcad::CADFace face;
  face.Index = f;
  ctcad::FaceLoop loop;
  for (int k = 0; k < 3; ++k)
  {
    loop.Nodes.push_back({ { uv[k][0], uv[k][1] + (globals[k] == 0 ? shift : 0) }, globals[k] });
    const int n = (k + 1) % 3;
    ctcad::LoopSegment seg;
    seg.Edge = edges[k];
    seg.Span = 0;
    const ctcad::Point3& a = nodes[globals[k]];
    const ctcad::Point3& b = nodes[globals[n]];
    for (int i = 0; i < 3; ++i)
    {
      seg.Near0[i] = (2 * a[i] + b[i]) / 3;
      seg.Near1[i] = (a[i] + 2 * b[i]) / 3;
    }
    seg.PCurveChord[0] = uv[n][0] - uv[k][0];
    seg.PCurveChord[1] = uv[n][1] - uv[k][1];
    loop.Segments.push_back(seg);
  }
  face.Loops.push_back(loop);
  return face;
}

/// Face 0's loop node at (0,0,0) is `offset` off its pcurves in t (their ends merged at a
/// vertex, JoinRuns); the node's shared point is `offset3` along y from both faces' surface
/// points at its (u, v) (a vertex where the B-rep's edges end apart). Returns the spans
/// SetInterfaceTangentPlanes reports for splitting.
std::vector<std::pair<ctcad::Id, ctcad::Id>> SplitsNextToAnOffsetNode(
  double degrees, double offset, double offset3 = 0)
{
  const double c = std::cos(degrees * M_PI / 180), s = std::sin(degrees * M_PI / 180);
  const std::vector<ctcad::Point3> nodes{ { 0, offset3, 0 }, { 1, 0, 0 }, { 0.5, 1, 0 },
    { 0.5, -c, -s } };
  std::vector<ctcad::CADFace> faces(2);
  // Per face: its nodes (global, uv on the pcurves) and the B-rep edges of its segments.
  const ctcad::Id globals[2][3] = { { 0, 1, 2 }, { 1, 0, 3 } };
  const double uv[2][3][2] = { { { 0, 0 }, { 1, 0 }, { 0.5, 1 } },
    { { 1, 0 }, { 0, 0 }, { 0.5, -1 } } };
  const ctcad::Id edges[2][3] = { { 0, 1, 2 }, { 0, 3, 4 } };
  for (int f = 0; f < 2; ++f)
  {
    faces[f] = TriangleFace(f, nodes, globals[f], uv[f], edges[f], f == 0 ? offset : 0);
  }
  const ctcad::FaceDerivatives evaluate = [c, s](int f, double u, double v, double P[3],
                                            double Ds[3], double Dt[3]) {
    const double dt[3] = { 0, f == 0 ? 1 : c, f == 0 ? 0 : s };
    for (int i = 0; i < 3; ++i)
    {
      Ds[i] = i == 0 ? 1 : 0;
      Dt[i] = dt[i];
      P[i] = u * Ds[i] + v * Dt[i];
    }
  };
  ctcad::TangentPlaneOptions options;
  options.RestoreG1 = true;
  options.MaxMove = 1e-3;
  return ctcad::SetInterfaceTangentPlanes(faces, nodes, evaluate, options).SpansToSplit;
}
} // namespace

// A loop node off its pcurves (their ends merged at a B-rep vertex) does not get the spans next
// to it split: the offset does not halve with the span, and the halves' chords would run across
// the edge until the boundary micro-triangles fold (KiCad's TQFP-44 and LQFP-128, re-projected
// pcurves: 180 degrees). Neither as a mismatch between the edge cubic and the face's derivative
// along the chord (coplanar faces), nor where the faces meet at 4 degrees (which splits the span
// when the node is on its pcurves).
namespace
{
/// The largest angle (degrees) between a boundary cubic on a tangent interface and its face's
/// surface at the span's midpoint: the shared normal there is made perpendicular to the cubic.
double MaxTangentCubicTilt(Sampled& s)
{
  const ctcad::FaceSurface surface = s.Surface();
  double tilt = 0;
  for (int f = 0; f < static_cast<int>(s.Faces.size()); ++f)
  {
    const ctk::SplineInput& in = s.Faces[f].Input;
    for (std::size_t i = 0; i < s.Faces[f].Tangent.size(); ++i)
    {
      const double* c = in.BoundaryCurvePoints.data() + 6 * i;
      if (!s.Faces[f].Tangent[i] || std::isnan(c[0]))
      {
        continue;
      }
      const ctk::Id* tri = in.Triangles.data() + 3 * (i / 3);
      const ctk::Id a = tri[i % 3], b = tri[(i + 1) % 3];
      auto point = [&](ctk::Id v) { return ctk::Vec3(in.F[3 * v], in.F[3 * v + 1], in.F[3 * v + 2]); };
      const ctk::Vec3 tangent =
        point(b) + ctk::Vec3(c[3], c[4], c[5]) - ctk::Vec3(c[0], c[1], c[2]) - point(a);
      double P[3], Du[3], Dv[3];
      std::string error;
      EXPECT_TRUE(surface(f, 0.5 * (in.UV[2 * a] + in.UV[2 * b]),
        0.5 * (in.UV[2 * a + 1] + in.UV[2 * b + 1]), P, Du, Dv, error))
        << error;
      const ctk::Vec3 normal = ctk::Vec3(Du[0], Du[1], Du[2]).cross(ctk::Vec3(Dv[0], Dv[1], Dv[2]));
      tilt = std::max(tilt, std::asin(std::min(1.0, std::abs(normal.normalized().dot(tangent.normalized())))));
    }
  }
  return tilt * 180 / M_PI;
}
} // namespace

// Where the faces miss each other at a B-rep vertex, its node lies off the mean curve of the
// edges from it, and each edge's cubic carries that offset into its end span. RestoreG1's splits
// there (here of a 3-degree kink, where the faces are not exactly tangent) must not squeeze the
// offset into the piece next to the vertex: its cubic would tilt out of the faces' planes by
// about 1.5 offset / length, and the normal shared at its midpoint with it (linkrods.step: 8
// degrees off the surfaces, 0.4 off G1).
TEST(CADStages, SplitsAtAVertexOffTheEdgeCurvesKeepTheCubicsInThePlanes)
{
  for (const double gap : { 0.0, 1e-4, 2e-4 })
  {
    Sampled s;
    s.Run("loose_side_" + std::to_string(gap), ctsplines_test::KinkedPrismWithLooseSide(3, gap), 1e-4);
    const std::vector<ctcad::FaceSpline> splines = Build(s);
    const ctcad::InterfaceMeasures m = ctcad::MeasureInterfaces(s.Faces, splines);
    const double tilt = MaxTangentCubicTilt(s);
    std::vector<ctcad::Deviation> perFace;
    ctcad::Deviation all;
    std::string error;
    ASSERT_TRUE(ctcad::MeasureDeviation(s.Surface(), 6, 16, s.Faces, splines, perFace, all, error))
      << error;
    std::printf("gap %g: %lld tangent spans, cubics tilted by up to %.3g degrees, normals %.3g "
                "degrees off the surfaces, G1 %.3g\n",
      gap, static_cast<long long>(m.G1[1].Count), tilt, all.MaxAngle, m.G1[1].Max);
    EXPECT_GT(m.G1[1].Count, 0);
    EXPECT_EQ(m.MaxC0Gap, 0.0);
    // 1.5 offset / length = 0.73 degrees at a gap of 2e-4 when the piece at the vertex carries
    // the offset; within the 0.5 degrees of its fade now.
    EXPECT_LE(tilt, gap > 0 ? 0.5 : 1e-6) << gap;
    // Not faded over the whole end span either (half the edge here): boundary nodes off the
    // planes by up to the offset tilt the small triangles next to them (8.6 degrees).
    EXPECT_LE(all.MaxAngle, 4.0) << gap;
    EXPECT_LE(m.G1[1].Max, 0.01) << gap;
  }
}

namespace
{
/// Three triangles at the origin: face 0 (0,0,0), (1,0,0), (0,1,0) in z = 0, normal +z; face 1
/// across its edge 0 on the x axis, turned about it by `degrees` (a tangent span); face 2 across
/// its edge 2 on the y axis, in z = 0 with the normal -z (oriented against face 0). The report
/// of SetInterfaceTangentPlanes (RestoreG1, MaxMove 1e-3).
ctcad::TangentPlaneReport TangentPlanesBesideAnOppositeFace(double degrees)
{
  const double c = std::cos(degrees * M_PI / 180), s = std::sin(degrees * M_PI / 180);
  const std::vector<ctcad::Point3> nodes{ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 },
    { 0.5, -c, -s }, { -1, 0.5, 0 } };
  // Per face: its nodes (global, uv) and the B-rep edges of its segments; face 2's loop runs
  // along the y axis the way face 0's does (the faces are oriented against each other).
  const ctcad::Id globals[3][3] = { { 0, 1, 2 }, { 1, 0, 3 }, { 0, 4, 2 } };
  const double uv[3][3][2] = { { { 0, 0 }, { 1, 0 }, { 0, 1 } },
    { { 1, 0 }, { 0, 0 }, { 0.5, -1 } }, { { 0, 0 }, { -1, -0.5 }, { 0, -1 } } };
  const ctcad::Id edges[3][3] = { { 0, 1, 2 }, { 0, 3, 4 }, { 5, 6, 2 } };
  std::vector<ctcad::CADFace> faces(3);
  for (int f = 0; f < 3; ++f)
  {
    faces[f] = TriangleFace(f, nodes, globals[f], uv[f], edges[f], 0);
  }
  const ctcad::FaceDerivatives evaluate = [c, s](int f, double u, double v, double P[3],
                                            double Ds[3], double Dt[3]) {
    const double dt[3][3] = { { 0, 1, 0 }, { 0, c, s }, { 0, -1, 0 } };
    for (int i = 0; i < 3; ++i)
    {
      Ds[i] = i == 0 ? 1 : 0;
      Dt[i] = dt[f][i];
      P[i] = u * Ds[i] + v * Dt[i];
    }
  };
  ctcad::TangentPlaneOptions options;
  options.RestoreG1 = true;
  options.MaxMove = 1e-3;
  return ctcad::SetInterfaceTangentPlanes(faces, nodes, evaluate, options);
}
} // namespace

// Where a face is oriented against its neighbour (normals opposite: KiCad's Bourns 8100 pins),
// their planes at a shared node are one, and the cubic of the edge between them stays in the
// tangent group's plane: it turns by the group's tilt (half the faces' angle) only. Their line,
// from the group's tilt (or the rounding of its mean normal, 1e-7 on L19), ran anywhere in the
// plane and turned the cubic by up to 90 degrees: the span was halved down to the shortest, and
// the needle triangles next to it left G1 at 0.71 degrees on L19.
TEST(CADStages, OppositeNormalsAtANodeAreOnePlane)
{
  for (const double degrees : { 0.0, 1e-5, 0.1, 2.0 })
  {
    const ctcad::TangentPlaneReport report = TangentPlanesBesideAnOppositeFace(degrees);
    const double turn = std::sin(0.5 * degrees * M_PI / 180) / 3; // |tau| = 1/3
    EXPECT_LE(report.MaxCurveChange, turn + 1e-12) << degrees;
    const bool splitsEdge2 = std::find(report.SpansToSplit.begin(), report.SpansToSplit.end(),
                               std::make_pair(ctcad::Id(2), ctcad::Id(0))) !=
      report.SpansToSplit.end();
    EXPECT_EQ(splitsEdge2, turn > 1e-3) << degrees;
  }
}

TEST(CADStages, NoSplitNextToALoopNodeOffItsPCurves)
{
  auto splitsEdge0 = [](double degrees, double offset) {
    const auto spans = SplitsNextToAnOffsetNode(degrees, offset);
    return std::find(spans.begin(), spans.end(), std::make_pair(ctcad::Id(0), ctcad::Id(0))) !=
      spans.end();
  };
  EXPECT_TRUE(SplitsNextToAnOffsetNode(0, 0).empty());
  EXPECT_TRUE(SplitsNextToAnOffsetNode(0, 0.1).empty());
  EXPECT_TRUE(splitsEdge0(4, 0));
  EXPECT_FALSE(splitsEdge0(4, 0.1));
  // An offset that the halves' chords bear (1 % of the half) does not stop the split.
  EXPECT_TRUE(splitsEdge0(4, 0.005));
}

// The same where the node's shared point is off the faces' surfaces in 3D (a B-rep vertex the
// edges end apart at: KiCad's Bourns 8100 toroids L38.1 and L43.2, where spans split down to
// the offset made boundary triangles whose 3D points and (u, v) disagreed 30-fold, and the
// splines overshot by 2 units).
TEST(CADStages, NoSplitNextToANodeOffItsSurfaces)
{
  auto splitsEdge0 = [](double degrees, double offset3) {
    const auto spans = SplitsNextToAnOffsetNode(degrees, 0, offset3);
    return std::find(spans.begin(), spans.end(), std::make_pair(ctcad::Id(0), ctcad::Id(0))) !=
      spans.end();
  };
  // Coplanar faces: the cubic leaves the node 0.1 / 3 off the faces' derivative along the
  // chord, a mismatch that halving the span would not halve.
  EXPECT_FALSE(splitsEdge0(0, 0.1));
  EXPECT_FALSE(splitsEdge0(4, 0.1));
  EXPECT_TRUE(splitsEdge0(4, 0.005));
}

namespace
{
/// A plane face (z = 0, counter-clockwise) whose bottom side ends in the ear (a, b, c): a at
/// (ax, 0), b at (bx, -sag), c at the origin, then up to (5, 5) and back.
/// No other node lies in the ear's circumcircle, so the triangulation keeps the ear unless the
/// mesher splits it. Meshes the face; `split`: whether b joins a point inside the face.
ctcad::FaceMesh MeshedEar(double ax, double bx, double sag, bool& split)
{
  const double uv[6][2] = { { -1, 0 }, { ax, 0 }, { bx, -sag }, { 0, 0 }, { 5, 5 }, { -1, 5 } };
  std::vector<ctcad::Point3> nodes;
  ctcad::FaceLoop loop;
  for (int k = 0; k < 6; ++k)
  {
    nodes.push_back({ uv[k][0], uv[k][1], 0 });
    loop.Nodes.push_back({ { uv[k][0], uv[k][1] }, k });
  }
  for (int k = 0; k < 6; ++k)
  {
    const int n = (k + 1) % 6;
    ctcad::LoopSegment seg;
    seg.Edge = k;
    seg.Span = 0;
    for (int i = 0; i < 2; ++i)
    {
      seg.Near0[i] = (2 * uv[k][i] + uv[n][i]) / 3;
      seg.Near1[i] = (uv[k][i] + 2 * uv[n][i]) / 3;
      seg.PCurveChord[i] = uv[n][i] - uv[k][i];
    }
    loop.Segments.push_back(seg);
  }
  const ctcad::SurfaceFunction plane = [](double s, double t, double P[3], double Ds[3],
                                         double Dt[3]) {
    const double p[3] = { s, t, 0 }, ds[3] = { 1, 0, 0 }, dt[3] = { 0, 1, 0 };
    std::copy(p, p + 3, P);
    std::copy(ds, ds + 3, Ds);
    std::copy(dt, dt + 3, Dt);
  };
  ctcad::FaceMeshOptions options;
  options.Tolerance = 1e-3;
  ctcad::FaceMesh mesh;
  EXPECT_TRUE(ctcad::MeshFace({ loop }, nodes, plane, options, mesh)) << mesh.Error;
  EXPECT_TRUE(mesh.Converged) << mesh.StopReason;
  const double diag2 = 6 * 6 + 5 * 5;
  split = false;
  for (const std::array<ctcad::Id, 3>& t : mesh.Triangles)
  {
    const auto at = [&](int i) { return ctk::Vec2(mesh.UV[t[i]][0], mesh.UV[t[i]][1]); };
    EXPECT_FALSE(ctk::IsDegenerateArea(ctk::SignedArea2(at(0), at(1), at(2)), diag2))
      << at(0).transpose() << ", " << at(1).transpose() << ", " << at(2).transpose();
    for (int i = 0; i < 3; ++i)
    {
      split = split || (mesh.GlobalNode[t[i]] == 2 && mesh.GlobalNode[t[(i + 1) % 3]] < 0);
    }
  }
  return mesh;
}
} // namespace

// A face whose straight boundary ends in three nodes off their chord by round-off (spans halved
// towards a B-rep vertex on a straight pcurve: KiCad's Bourns 8100 toroids L38.1 and L43.2), with
// no other node in the circumcircle of the ear they make: the triangulation keeps the ear, which
// the kernel finds flat, and the face could not be meshed ("degenerate parameter triangle").
// The ear is split from its middle node, and no triangle of the mesh is flat.
TEST(CADStages, AFlatEarOnAStraightBoundaryIsSplit)
{
  // The ear is 5e-9 high on a chord of 6e-4 (twice its area is half the kernel's zero for this
  // box), its circumcircle's radius 0.88.
  bool split = false;
  MeshedEar(-6e-4, -1.5e-5, 5e-9, split);
  EXPECT_TRUE(split);
}

// An ear whose boundary corner is within 10 degrees of straight is split too (KiCad's
// USB_Micro-B_Molex_47346-0001: an ear of 171 degrees folded, G1 180); one of 160 is kept.
TEST(CADStages, AnEarNearlyStraightIsSplit)
{
  for (const double degrees : { 175.0, 160.0 })
  {
    bool split = false;
    const double sag = 0.05 * std::tan(0.5 * (180 - degrees) * M_PI / 180);
    MeshedEar(-0.1, -0.05, sag, split);
    EXPECT_EQ(split, degrees > 170) << degrees;
  }
}

namespace
{
/// The face OCCT's STEP reader made of a fillet of BatteryHolder_Keystone_2462_2xAA (a quarter
/// circle revolved): the seam from the big circle to the small one, the small circle's pcurve a
/// period off (u from 0 to -2 pi), and the wire closed by two degenerated edges a period long,
/// each at a circle's vertex but running along the other circle's row: u over [-2 pi, 2 pi].
TopoDS_Face FilletGoingTwiceRound()
{
  const double R = 1.1, r = 0.1, pi = M_PI;
  const gp_Ax2 profilePlane(gp_Pnt(r, 0, 0), gp_Dir(0, 1, 0), gp_Dir(1, 0, 0));
  const Handle(Geom_Circle) profile = new Geom_Circle(profilePlane, R - r);
  const Handle(Geom_Surface) S = new Geom_SurfaceOfRevolution(
    new Geom_TrimmedCurve(profile, 0, pi / 2), gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, -1)));
  BRep_Builder B;
  const double tol = 1e-7;
  TopoDS_Vertex big, small;
  B.MakeVertex(big, gp_Pnt(R, 0, 0), tol);
  B.MakeVertex(small, gp_Pnt(r, 0, -(R - r)), tol);
  TopoDS_Face F;
  B.MakeFace(F, S, tol);
  const auto line = [](double u, double v, double du, double dv) {
    return Handle(Geom2d_Curve)(new Geom2d_Line(gp_Pnt2d(u, v), gp_Dir2d(du, dv)));
  };
  const auto edge = [&](const Handle(Geom_Curve)& c, const TopoDS_Vertex& a, const TopoDS_Vertex& b,
                      double t1) {
    TopoDS_Edge E;
    B.MakeEdge(E, c, tol);
    B.Add(E, a.Oriented(TopAbs_FORWARD));
    B.Add(E, b.Oriented(TopAbs_REVERSED));
    B.Range(E, 0, t1);
    return E;
  };
  // Circles about +z; the surface's u turns about -z: u = 2 pi - t.
  const TopoDS_Edge bigCircle = edge(new Geom_Circle(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1),
    gp_Dir(1, 0, 0)), R), big, big, 2 * pi);
  B.UpdateEdge(bigCircle, line(2 * pi, 0, -1, 0), F, tol);
  const TopoDS_Edge smallCircle = edge(new Geom_Circle(gp_Ax2(gp_Pnt(0, 0, -(R - r)),
    gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)), r), small, small, 2 * pi);
  B.UpdateEdge(smallCircle, line(0, pi / 2, -1, 0), F, tol); // a period off
  const TopoDS_Edge seam = edge(profile, big, small, pi / 2);
  B.UpdateEdge(seam, line(2 * pi, 0, 0, 1), line(-2 * pi, 0, 0, 1), F, tol);
  const auto degenerated = [&](const TopoDS_Vertex& v, const Handle(Geom2d_Curve)& pc) {
    TopoDS_Edge E;
    B.MakeEdge(E);
    B.Add(E, v.Oriented(TopAbs_FORWARD));
    B.Add(E, v.Oriented(TopAbs_REVERSED));
    B.Degenerated(E, Standard_True);
    B.UpdateEdge(E, pc, F, tol);
    B.Range(E, 0, 2 * pi);
    return E;
  };
  const TopoDS_Edge top = degenerated(small, line(2 * pi, pi / 2, -1, 0));
  const TopoDS_Edge bottom = degenerated(big, line(-2 * pi, 0, 1, 0));
  TopoDS_Wire W;
  B.MakeWire(W);
  for (const TopoDS_Shape& E : { TopoDS_Shape(top), TopoDS_Shape(smallCircle),
         seam.Reversed(), TopoDS_Shape(bottom), bigCircle.Reversed(), TopoDS_Shape(seam) })
  {
    B.Add(W, E);
  }
  W.Closed(Standard_True);
  B.Add(F, W);
  return F;
}
} // namespace

// The degenerated edges that run along circles are dropped and the small circle moved by a
// period: the face spans one period, keeps its three real edges (the circles, the seam twice)
// and samples within the tolerance; a true degenerated edge (a pole) stays.
TEST(CADStages, DegeneratedEdgesThatAreNoPointAreDropped)
{
  ctcad::ShapeRead r;
  r.Shape = FilletGoingTwiceRound();
  r.FaceNames = { "fillet" };
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  BRepTools::UVBounds(TopoDS::Face(r.Shape), u0, u1, v0, v1);
  ASSERT_NEAR(u1 - u0, 4 * M_PI, 1e-9) << "the face as OCCT read it goes twice round";
  EXPECT_EQ(ctcad::DropFalseDegeneratedEdges(r, 1e-6), 2);
  TopTools_IndexedMapOfShape faces, edges;
  TopExp::MapShapes(r.Shape, TopAbs_FACE, faces);
  ASSERT_EQ(faces.Extent(), 1);
  const TopoDS_Face F = TopoDS::Face(faces(1));
  BRepTools::UVBounds(F, u0, u1, v0, v1);
  EXPECT_NEAR(u1 - u0, 2 * M_PI, 1e-9);
  EXPECT_NEAR(v1 - v0, M_PI / 2, 1e-9);
  TopExp::MapShapes(F, TopAbs_EDGE, edges);
  EXPECT_EQ(edges.Extent(), 3);
  EXPECT_TRUE(BRepCheck_Analyzer(F).IsValid());
  EXPECT_EQ(r.FaceNames, std::vector<std::string>{ "fillet" });
  ASSERT_FALSE(r.Warnings.empty());
  EXPECT_NE(r.Warnings.back().find("2 degenerated edge(s)"), std::string::npos) << r.Warnings.back();
  // The wire closes in (u, v): each edge starts where the one before it ends.
  for (TopExp_Explorer wx(F, TopAbs_WIRE); wx.More(); wx.Next())
  {
    TopoDS_Edge broken;
    const std::vector<TopoDS_Edge> chain = ctcad::WireEdges(TopoDS::Wire(wx.Current()), F, broken);
    ASSERT_EQ(chain.size(), 4u);
    const auto end = [&F](const TopoDS_Edge& E, bool last) {
      double a = 0, b = 0;
      const Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(E, F, a, b);
      return pc->Value((E.Orientation() == TopAbs_REVERSED) != last ? b : a);
    };
    for (std::size_t i = 0; i < chain.size(); ++i)
    {
      EXPECT_LT(end(chain[i], true).Distance(end(chain[(i + 1) % chain.size()], false)), 1e-9) << i;
    }
  }
  // Every pcurve now runs along its edge on the surface (the seam's two included).
  const BRepAdaptor_Surface surface(F, Standard_False);
  for (TopExp_Explorer ex(F, TopAbs_EDGE); ex.More(); ex.Next())
  {
    const TopoDS_Edge& E = TopoDS::Edge(ex.Current());
    ASSERT_FALSE(BRep_Tool::Degenerated(E));
    double a = 0, b = 0;
    const Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(E, F, a, b);
    const BRepAdaptor_Curve curve(E);
    for (int i = 0; i <= 8; ++i)
    {
      const double t = a + (b - a) * i / 8;
      const gp_Pnt2d uv = pc->Value(t);
      EXPECT_LT(surface.Value(uv.X(), uv.Y()).Distance(curve.Value(t)), 1e-9) << i;
    }
  }
  // A sphere's poles are degenerated edges that are points: nothing to drop.
  ctcad::ShapeRead sphere;
  sphere.Shape = BRepPrimAPI_MakeSphere(1.0).Shape();
  sphere.FaceNames = { "" };
  EXPECT_EQ(ctcad::DropFalseDegeneratedEdges(sphere, 1e-6), 0);
  EXPECT_TRUE(sphere.Warnings.empty());
}

namespace
{
/// A curved face over the unit square, z = 0.3 sin(2s) cos(3t), with `perSide` spans a side and
/// its edges' Hermite cubics from the surface, meshed with options (whose Tolerance and
/// Spline.Method the caller sets).
ctcad::FaceMesh MeshWavySquare(int perSide, ctcad::FaceMeshOptions options)
{
  const ctcad::SurfaceFunction wave = [](double s, double t, double P[3], double Ds[3],
                                        double Dt[3]) {
    const double p[3] = { s, t, 0.3 * std::sin(2 * s) * std::cos(3 * t) };
    const double ds[3] = { 1, 0, 0.6 * std::cos(2 * s) * std::cos(3 * t) };
    const double dt[3] = { 0, 1, -0.9 * std::sin(2 * s) * std::sin(3 * t) };
    std::copy(p, p + 3, P);
    std::copy(ds, ds + 3, Ds);
    std::copy(dt, dt + 3, Dt);
  };
  std::vector<std::array<double, 2>> uv; // counter-clockwise round the square
  for (int side = 0; side < 4; ++side)
  {
    for (int k = 0; k < perSide; ++k)
    {
      const double a = double(k) / perSide;
      const std::array<double, 2> at[4] = { { a, 0 }, { 1, a }, { 1 - a, 1 }, { 0, 1 - a } };
      uv.push_back(at[side]);
    }
  }
  const int n = static_cast<int>(uv.size());
  std::vector<ctcad::Point3> nodes(n);
  ctcad::FaceLoop loop;
  for (int k = 0; k < n; ++k)
  {
    ctcad::Point3 ds, dt;
    wave(uv[k][0], uv[k][1], nodes[k].data(), ds.data(), dt.data());
    loop.Nodes.push_back({ { uv[k][0], uv[k][1] }, k });
  }
  for (int k = 0; k < n; ++k)
  {
    const int m = (k + 1) % n;
    ctcad::LoopSegment seg;
    seg.Edge = k / perSide;
    seg.Span = k % perSide;
    const double du = uv[m][0] - uv[k][0], dv = uv[m][1] - uv[k][1];
    seg.PCurveChord[0] = du;
    seg.PCurveChord[1] = dv;
    ctcad::Point3 P, Ds, Dt;
    wave(uv[k][0], uv[k][1], P.data(), Ds.data(), Dt.data());
    for (int i = 0; i < 3; ++i)
    {
      seg.Near0[i] = P[i] + (du * Ds[i] + dv * Dt[i]) / 3;
    }
    wave(uv[m][0], uv[m][1], P.data(), Ds.data(), Dt.data());
    for (int i = 0; i < 3; ++i)
    {
      seg.Near1[i] = P[i] - (du * Ds[i] + dv * Dt[i]) / 3;
    }
    loop.Segments.push_back(seg);
  }
  options.CheckConstruction = true;
  ctcad::FaceMesh mesh;
  EXPECT_TRUE(ctcad::MeshFace({ loop }, nodes, wave, options, mesh)) << mesh.Error;
  return mesh;
}
} // namespace

// A face that its construction leaves over the tolerance when nothing more can go in (here no
// refinement round at all) takes the stitchable construction least over it (FaceMeshOptions::
// FallbackConstructions): measured on the same mesh, with the bits of that construction's own
// check; within the tolerance, the face counts as converged. Without fallbacks, within the
// tolerance, or when the chosen construction is already the best, nothing changes.
TEST(CADStages, AFaceOverTheToleranceTakesTheBestFallbackConstruction)
{
  ctcad::FaceMeshOptions options;
  options.MaxRounds = 0; // the boundary nodes alone, the same mesh whatever the construction
  options.FallbackConstructions = false;
  options.Tolerance = 1;
  std::vector<std::pair<double, int>> errors; // of every stitchable cubic construction
  std::size_t triangles = 0;
  for (int c = 0; c < ctk::NumberOfConstructions; ++c)
  {
    const auto method = static_cast<ctk::Construction>(c);
    if (ctk::CanBeStitched(method) && ctk::Info(method).Degree == 3)
    {
      options.Spline.Method = method;
      const ctcad::FaceMesh mesh = MeshWavySquare(6, options);
      ASSERT_EQ(mesh.FallbackConstruction, -1);
      triangles = triangles ? triangles : mesh.Triangles.size();
      ASSERT_EQ(mesh.Triangles.size(), triangles) << "the same mesh for every construction";
      errors.emplace_back(mesh.MaxEstimatedError, c);
    }
  }
  ASSERT_EQ(errors.size(), 8u);
  // The first least error in the table's order, and the largest.
  const auto best = std::min_element(errors.begin(), errors.end(),
    [](const auto& a, const auto& b) { return a.first < b.first; });
  const auto worst = std::max_element(errors.begin(), errors.end());
  ASSERT_GT(worst->first, 1.5 * best->first) << "the constructions differ on this mesh";
  // Between them, above the best by more than its 0.8 refinement margin (no insert left).
  options.Tolerance = 1.3 * best->first;
  options.Spline.Method = static_cast<ctk::Construction>(worst->second);
  const ctcad::FaceMesh stuck = MeshWavySquare(6, options);
  EXPECT_FALSE(stuck.Converged);
  EXPECT_EQ(stuck.FallbackConstruction, -1);
  options.FallbackConstructions = true;
  const ctcad::FaceMesh fallback = MeshWavySquare(6, options);
  EXPECT_EQ(fallback.FallbackConstruction, best->second);
  EXPECT_EQ(fallback.MaxEstimatedError, best->first);
  EXPECT_EQ(fallback.ChosenError, worst->first);
  EXPECT_EQ(fallback.ChosenStopReason, stuck.StopReason);
  EXPECT_TRUE(fallback.Converged) << fallback.StopReason;
  EXPECT_EQ(fallback.Triangles.size(), triangles);
  // Within the tolerance, short of the margin refinement aims at: no fallback.
  options.Tolerance = 1.1 * worst->first;
  const ctcad::FaceMesh within = MeshWavySquare(6, options);
  EXPECT_FALSE(within.Converged);
  EXPECT_EQ(within.FallbackConstruction, -1);
  // The best one itself over a tolerance below its error: nothing does better.
  options.Tolerance = 0.5 * best->first;
  options.Spline.Method = static_cast<ctk::Construction>(best->second);
  const ctcad::FaceMesh none = MeshWavySquare(6, options);
  EXPECT_FALSE(none.Converged);
  EXPECT_EQ(none.FallbackConstruction, -1);
  EXPECT_EQ(none.MaxEstimatedError, best->first);
}
