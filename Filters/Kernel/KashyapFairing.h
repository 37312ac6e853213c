// SPDX-License-Identifier: GPL-3.0-or-later
// Kashyap's cubic scheme (quartic paper section 3): start from a cubic-precision interpolant,
// alternate exterior fairing (eq. 1-3, the Fa/IM minimisation across macro-edges, see
// MicroEdgeC2Minimisation.h) and interior fairing (eq. 4-6), and finish with C1 smoothing.
#ifndef CTSplines_Kernel_KashyapFairing_h
#define CTSplines_Kernel_KashyapFairing_h

#include "CubicMacroElement.h"

namespace ctk
{
/// Interior fairing, eq. (4)-(6) for any split point: the three central points C_k move least so
/// that the micro-patches are C2 across the inner edges, i.e. pieces of one cubic macro-patch
/// with C_k = tau_i T_ij + tau_j T_ji + tau_k Q (i, j the vertices of T_k). Q is the least-squares
/// fit; with the barycentre this is eq. (6) (Q = E').
void KashyapInteriorFairing(const MacroElementIds& ids, const Vec3& tau, Vec3* points);

/// C1 smoothing across a macro-edge: restores the C1 condition between the central points C and
/// Cbar of the micro-triangles at the edge (Cbar = M's blossom at Mbar's vertices) moving both
/// least. PM is M's cubic net (its centre is replaced by C).
void RestoreMacroEdgeC1(const Vec3* PM, const Vec2* AM, const Vec2* AMbar, Vec3& C, Vec3& Cbar);

} // namespace ctk

#endif
