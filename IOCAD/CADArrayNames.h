// SPDX-License-Identifier: GPL-3.0-or-later
// The array names vtkCADFaceSampler writes and vtkWatertightSplineStitcher reads (private
// header): one spelling for both sides.
#ifndef CADArrayNames_h
#define CADArrayNames_h

namespace ctcad
{
namespace names
{
// Point data of every face block.
constexpr const char* UV = "UV";                    // the face's parameters (u, v)
constexpr const char* Du = "dFdu";                  // the surface's own derivatives
constexpr const char* Dv = "dFdv";
constexpr const char* StitchDu = "StitchDFdu";      // the derivatives the stitched spline uses
constexpr const char* StitchDv = "StitchDFdv";
constexpr const char* GlobalNodeId = "GlobalNodeId"; // the model node of every point
// Cell data of every face block (3 local edges per triangle).
constexpr const char* EdgeGradients = "EdgeGradients";
constexpr const char* StitchEdgeGradients = "StitchEdgeGradients";
constexpr const char* TangentInterface = "TangentInterface";
constexpr const char* EdgeCurvePoints = "EdgeCurvePoints";
constexpr const char* BRepEdgeId = "BRepEdgeId";
// Field data of a face block: the construction the face was refined for in place of the
// sampler's (vtkCADFaceSampler::FallbackConstructions).
constexpr const char* FallbackConstruction = "FallbackConstruction";
// Field data of the sampler's output: the spline the faces were refined for.
constexpr const char* RefinedConstruction = "RefinedConstruction";
constexpr const char* RefinedSplitPoint = "RefinedSplitPoint";
constexpr const char* RefinedBoundaryMode = "RefinedBoundaryMode";
} // namespace names
} // namespace ctcad

#endif
