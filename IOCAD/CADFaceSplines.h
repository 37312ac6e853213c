// SPDX-License-Identifier: GPL-3.0-or-later
// The spline stage of the CAD conversion (no VTK): every sampled face becomes a cubic
// Clough-Tocher spline whose boundary macro-edges follow the shared B-rep edge cubics, built by
// the kernel directly, faces in parallel.
#ifndef CADFaceSplines_h
#define CADFaceSplines_h

#include "CloughTocherSpline.h"
#include "SplineInput.h"

#include <functional>
#include <string>
#include <vector>

namespace ctcad
{
/// One sampled face (vtkCADFaceSampler's block) as the stages read it.
struct SampledFace
{
  /// The construction's input: triangles, UV, points, the stitch derivatives (Fu, Fv), the
  /// stitch mid-edge gradients and the B-rep edge cubics' inner points (BoundaryCurvePoints).
  ctk::SplineInput Input;
  /// The surface's own derivatives, #V by 3 each: what the face's boundary cubics would be
  /// without stitching (MaxGapBeforeStitching).
  std::vector<double> SurfaceFu, SurfaceFv;
  std::vector<ctk::Id> GlobalNode; // #V model node ids: equal ids are one point of the model
  std::vector<ctk::Id> BRepEdge;   // #T by 3: the B-rep edge of each local edge, -1 inside
  /// Empty or #T by 3: nonzero where the local edge is an interface at which the CAD faces
  /// meet tangentially.
  std::vector<signed char> Tangent;
  /// The construction the sampler refined this face for in place of the model's (its
  /// FallbackConstructions), or -1.
  int FallbackConstruction = -1;
};

/// The options face is built with: options, with its FallbackConstruction if it has one.
ctk::SplineOptions FaceOptions(const SampledFace& face, const ctk::SplineOptions& options);

/// A face's spline with the mesh topology it was built on.
struct FaceSpline
{
  ctk::MeshTopology Topology;
  ctk::CubicSpline Spline;
};

/// Runs body(f) for f in [0, n), in any order and on any threads.
using FaceRunner = std::function<void(int n, const std::function<void(int)>& body)>;
/// FaceRunner on the calling thread, in order.
void ForEachFaceSerially(int n, const std::function<void(int)>& body);
/// Runs body(f, error) on faces [0, n) through forEach (ForEachFaceInParallel when empty).
/// Returns false with the error of the lowest face whose body returned false.
bool RunOnFaces(int n, const std::function<bool(int f, std::string& error)>& body,
  std::string& error, const FaceRunner& forEach);

/// Builds face's spline of a stitchable (cubic, boundary-curve taking) construction; serially
/// inside the face. The arrays' sizes must agree (the stitcher checks them when it reads the
/// sampler's blocks); the kernel checks the values. On failure returns false with the kernel's
/// message.
bool BuildFaceSpline(const SampledFace& face, const ctk::SplineOptions& options,
  FaceSpline& spline, std::string& error);

/// BuildFaceSpline on every face with its FaceOptions, forEach running the faces (ForEachFaceInParallel by default):
/// the splines are the same bit for bit whatever forEach. On failure returns false with the
/// error of the lowest failed face, named ("face 3: spline construction failed: ...").
bool BuildFaceSplines(const std::vector<SampledFace>& faces, const ctk::SplineOptions& options,
  std::vector<FaceSpline>& splines, std::string& error, const FaceRunner& forEach = nullptr);

} // namespace ctcad

#endif
