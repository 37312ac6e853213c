// SPDX-License-Identifier: GPL-3.0-or-later
// The table of constructions: one row per construction of the two papers (the comparative study
// "Watertight conversion of trimmed CAD surfaces to Clough-Tocher splines" and Fang and Mann's
// "A Quartic Clough-Tocher Interpolant"), with what each reads, what it guarantees and where it
// can be used. The kernel, the VTK filters, the CAD classes, the Python package and the ParaView
// XML read their lists and limits from here; docs/constructions.md is the reader's version.
#ifndef CTSplines_Kernel_Constructions_h
#define CTSplines_Kernel_Constructions_h

#include <array>
#include <string>

namespace ctk
{
/// Values are stable: they are the VTK filters' ConstructionType values and the ParaView
/// enumerations.
enum class Construction
{
  CTo = 0,
  CTi = 1,
  Fa = 2,
  FO = 3,
  Ka = 4,
  MGo = 5,
  MGi = 6,
  KaG = 7,
  Kashyap = 8,
  Quartic = 9
};
constexpr int NumberOfConstructions = 10;

/// How Step 2 fixes the cubic macro-patch's central point Q across a macro-edge from both
/// sides' data (study sections 3.4-3.5): comparing the neighbour's second row with T's
/// macro-patch extended there gives two residuals.
enum class MacroEdgeRule
{
  None,            // the construction does not use the neighbour's 3D data this way
  ZeroResidualSum, // eq. (22), FO: the sum of the two residuals vanishes
  LeastSquares     // eq. (23), Ka: the sum of their squares is least
};

/// Where a construction reads mid-edge gradients (SplineData::EdgeGradients).
enum class EdgeGradientUse
{
  None,          // only through a gradient boundary mode, if the construction takes one
  BoundaryEdges, // on boundary edges: a gradient boundary mode is the default
  AllEdges       // on every edge
};

struct ConstructionInfo
{
  Construction Method;
  const char* Name;
  const char* Paper;   // paper, section and equations
  const char* Summary; // one line for the user
  int Degree;          // of the output Bézier triangles
  /// Highest degree of polynomial data reproduced exactly, and where (with the default
  /// Midpoint boundary mode and no IM steps; for the fairing schemes, after their rounds).
  int Precision;
  const char* PrecisionWhere;
  bool AffineInvariant; // under affine reparameterisation, with Bary or Inc3 split points
  /// Local constructions read one triangle's data (and its edges' gradients) only; the others
  /// read the neighbours' data and take a BoundaryMode on boundary edges.
  bool Local;
  EdgeGradientUse EdgeGradients;
  MacroEdgeRule EdgeRule;
  /// Step 2 takes its central points at an interior macro-edge from both sides' 3D data.
  bool EdgeBased;
  /// The construction this one starts from (itself, or FO for the fairing schemes).
  Construction StartsFrom;
  /// Iterations: IM steps (study section 3.7), or fairing rounds of the fairing schemes.
  bool IterationsAreFairingRounds;
  /// Takes prescribed boundary curves (SplineData::BoundaryCurvePoints); the CAD stitcher
  /// needs them, so these are the constructions a CAD model can be converted with.
  bool TakesBoundaryCurves;
  bool HasBezierExtraction;
};

/// All rows, in Construction order.
const std::array<ConstructionInfo, NumberOfConstructions>& ConstructionTable();
const ConstructionInfo& Info(Construction c);
/// Whether value is a Construction (0 .. NumberOfConstructions - 1).
bool IsConstruction(int value);
const char* ToString(Construction c);
/// Finds a construction by its name (as ToString gives it); false when there is none.
bool FindConstruction(const std::string& name, Construction& c);

/// Whether the CAD conversion can stitch faces built with c (it prescribes their boundary
/// curves).
inline bool CanBeStitched(Construction c)
{
  return Info(c).TakesBoundaryCurves;
}

/// Rings of neighbouring triangles a piece needs around its own triangles for its spline to be
/// the serial one: none for a local construction without iterations; otherwise the neighbours'
/// split points and data (two rings) plus one ring per iteration.
int RequiredGhostRings(Construction c, int iterations);

} // namespace ctk

#endif
