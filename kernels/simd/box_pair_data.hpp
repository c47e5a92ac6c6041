// The single box-pair query's data (internal): the zonotope A (-) B of one box pair, the answer
// and the active set the coherence cache keeps. The query itself is box_pair.hpp, compiled per
// ISA; this header is what the library's other translation units and the tests see.
#pragma once

#include <minksum/kernels.hpp>
#include <minksum/model.hpp>

namespace minksum::detail {

/// M = A (-) B of one box pair: c = c_A - c_B, generators g_k = h_Ak u_Ak (k < 3) and
/// -h_Bk u_Bk (k >= 3), and C = U_A^T U_B.
template <class T>
struct BoxPair {
  T c[3], ca[3];
  T u[6][3];  // unit axes of A then of B
  T h[6];     // half extents of A then of B
  T g[6][3];  // generators
  T C[3][3];  // C[i][j] = u_Ai . u_Bj
  T uc[6];    // u_k . c
};

/// Everything the box-box query computes, as plain numbers.
template <class T>
struct PairAnswer {
  bool intersecting;
  T distance, depth;
  T direction[3], point_a[3], point_b[3];
  bool converged;  // false: the active set ran out of iterations (distance is an upper bound)
  bool warm;       // the answer came from the given active set, proven optimal (KKT)
};

/// An active set of the box-pair query as the coherence cache keeps it: bit 31 set, the free
/// generators in bits 0-5, the signs of the fixed parameters (1: +1) in bits 8-13.
constexpr unsigned kActiveSet = 1u << 31;

/// How far the box-pair query goes: the pair loaded only (the farthest pair reads it), the
/// verdict (the separating axis test alone), the distance or depth and direction (overlapping
/// pairs skip the active-set walk), or the witnesses too.
enum class PairLevel : int { Load, Verdict, Distance, Witnesses };

/// The box-pair query of the active ISA: loads the pair and answers to `level`, starting from
/// the active set `active` (see BoxPairQuery::box_pair; 0: cold).
void box_pair_proximity(const Box& a, const Box& b, PairLevel level, unsigned& active, BoxPair<double>& pair,
                        PairAnswer<double>& out);

}  // namespace minksum::detail
