// SPDX-License-Identifier: GPL-3.0-or-later
#include "Constructions.h"

#include <algorithm>

namespace ctk
{
namespace
{
using C = Construction;
using G = EdgeGradientUse;
using R = MacroEdgeRule;

// Precision and invariance: the study's section 4 table (spec section 4), tested in
// Testing/Kernel/CubicConstructionsTest.cxx.
constexpr std::array<ConstructionInfo, NumberOfConstructions> Table = { {
  { C::CTo, "CTo", "study section 3.1, eq. (15)-(16)",
    "original Clough-Tocher: cross derivative perpendicular to the edge, local", 3, 2,
    "everywhere", false, true, G::None, R::None, false, C::CTo, false, true, true },
  { C::CTi, "CTi", "study section 3.2, eq. (15), (17)",
    "cross derivative along Z Zbar, invariant", 3, 2, "everywhere", true, false, G::None, R::None,
    false, C::CTi, false, true, true },
  { C::Fa, "Fa", "study section 3.3, eq. (18)-(21)",
    "Farin: least C2 jump across macro-edges", 3, 2, "everywhere", true, false, G::None, R::None,
    true, C::Fa, false, true, true },
  { C::FO, "FO", "study section 3.4, eq. (22)", "Foley-Opitz as modified by Mann", 3, 3,
    "interior triangles", true, false, G::None, R::ZeroResidualSum, true, C::FO, false, true,
    true },
  { C::Ka, "Ka", "study section 3.5, eq. (23)",
    "Kashyap/Mann macro-level C2 minimisation", 3, 3, "interior triangles", true, false, G::None,
    R::LeastSquares, true, C::Ka, false, true, true },
  { C::MGo, "MGo", "study section 3.6, eq. (24)-(25), v_eps perpendicular",
    "mid-edge gradients on every edge, local", 3, 3, "everywhere, with mid-edge gradients", false,
    true, G::AllEdges, R::None, false, C::MGo, false, true, true },
  { C::MGi, "MGi", "study section 3.6, eq. (24)-(25), v_eps along Z Zbar",
    "mid-edge gradients on every edge, invariant", 3, 3, "everywhere, with mid-edge gradients",
    true, false, G::AllEdges, R::None, false, C::MGi, false, true, true },
  { C::KaG, "KaG", "study sections 3.5 and 3.8, eq. (23), (25)",
    "Ka with mid-edge gradients on boundary edges (the study's recommendation)", 3, 3,
    "everywhere, with boundary mid-edge gradients", true, false, G::BoundaryEdges,
    R::LeastSquares, true, C::KaG, false, true, true },
  { C::Kashyap, "Kashyap", "quartic paper section 3",
    "Kashyap's cubic fairing scheme, from FO, Iterations rounds", 3, 2, "everywhere", true, false,
    G::None, R::ZeroResidualSum, true, C::FO, true, false, true },
  { C::Quartic, "Quartic", "quartic paper section 4, eq. (7)-(15)",
    "Fang-Mann quartic scheme, from FO degree-raised, Iterations rounds", 4, 2, "everywhere", true,
    false, G::None, R::None, false, C::FO, true, false, false },
} };

constexpr bool RowsInOrder()
{
  for (int i = 0; i < NumberOfConstructions; ++i)
  {
    if (static_cast<int>(Table[i].Method) != i)
    {
      return false;
    }
  }
  return true;
}
} // namespace

const std::array<ConstructionInfo, NumberOfConstructions>& ConstructionTable()
{
  return Table;
}

bool IsConstruction(int value)
{
  return value >= 0 && value < NumberOfConstructions;
}

const ConstructionInfo& Info(Construction c)
{
  static_assert(RowsInOrder(), "construction table rows out of Construction order");
  return Table[std::clamp(static_cast<int>(c), 0, NumberOfConstructions - 1)];
}

const char* ToString(Construction c)
{
  return IsConstruction(static_cast<int>(c)) ? Info(c).Name : "Unknown";
}

bool FindConstruction(const std::string& name, Construction& c)
{
  for (const ConstructionInfo& row : Table)
  {
    if (name == row.Name)
    {
      c = row.Method;
      return true;
    }
  }
  return false;
}

int RequiredGhostRings(Construction c, int iterations)
{
  const int its = std::max(iterations, 0);
  return Info(c).Local && its == 0 ? 0 : 2 + its;
}

} // namespace ctk
