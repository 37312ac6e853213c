// SPDX-License-Identifier: GPL-3.0-or-later
#include "CADFaceSplines.h"

#include "CADFaceMesher.h" // ForEachFaceInParallel

namespace ctcad
{
void ForEachFaceSerially(int n, const std::function<void(int)>& body)
{
  for (int f = 0; f < n; ++f)
  {
    body(f);
  }
}

ctk::SplineOptions FaceOptions(const SampledFace& face, const ctk::SplineOptions& options)
{
  ctk::SplineOptions own = options;
  if (face.FallbackConstruction >= 0)
  {
    own.Method = static_cast<ctk::Construction>(face.FallbackConstruction);
  }
  return own;
}

bool RunOnFaces(int n, const std::function<bool(int f, std::string& error)>& body,
  std::string& error, const FaceRunner& forEach)
{
  std::vector<std::string> errors(n);
  std::vector<char> ok(n, 0);
  auto run = [&](int f) { ok[f] = body(f, errors[f]); };
  if (forEach)
  {
    forEach(n, run);
  }
  else
  {
    ForEachFaceInParallel(n, run);
  }
  for (int f = 0; f < n; ++f)
  {
    if (!ok[f])
    {
      error = errors[f];
      return false;
    }
  }
  return true;
}

bool BuildFaceSpline(const SampledFace& face, const ctk::SplineOptions& options,
  FaceSpline& spline, std::string& error)
{
  const ctk::SplineInput& in = face.Input;
  const ctk::TopologyStatus topo = ctk::BuildMeshTopology(
    in.NumberOfVertices(), in.NumberOfTriangles(), in.Triangles.data(), spline.Topology);
  if (!topo.Ok)
  {
    error = "invalid mesh: " + topo.Message;
    return false;
  }
  if (!ctk::CanBeStitched(options.Method) || ctk::Info(options.Method).Degree != 3)
  {
    error = std::string("construction ") + ctk::ToString(options.Method) + " cannot be stitched";
    return false;
  }
  // The kernel validates the values (finite, no zero-area or folded triangle). Serial inside
  // the face: the faces are the parallel loop.
  const ctk::BuildStatus status =
    ctk::BuildCubicCloughTocher(in.View(), spline.Topology, options, spline.Spline);
  if (!status.Ok)
  {
    error = status.Message;
  }
  return status.Ok;
}

bool BuildFaceSplines(const std::vector<SampledFace>& faces, const ctk::SplineOptions& options,
  std::vector<FaceSpline>& splines, std::string& error, const FaceRunner& forEach)
{
  splines.assign(faces.size(), FaceSpline());
  return RunOnFaces(
    static_cast<int>(faces.size()),
    [&](int f, std::string& message) {
      if (BuildFaceSpline(faces[f], FaceOptions(faces[f], options), splines[f], message))
      {
        return true;
      }
      message = "face " + std::to_string(f) + ": spline construction failed: " + message;
      return false;
    },
    error, forEach);
}

} // namespace ctcad
