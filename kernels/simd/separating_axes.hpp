// The 15 axes of the separating axis test for two boxes, written once for the single-pair query
// (box_pair.hpp, one scalar value) and the lane kernels (box_proximity.hpp, one register).
#pragma once

#include <type_traits>

namespace minksum::detail {

/// Below this |u_Ai x u_Bj|^2 the single-pair query (BoxPairSat) measures an edge axis's
/// separation again in the world frame, from the accurate cross product and the axes as given.
/// visit forms it from C = U_A^T U_B, whose entries carry an ulp and whose identities assume
/// exactly orthonormal axes: d / |L| errs by about eps (|c| + sum h) / |L|. At |L| = 4e-11 a
/// nearly parallel edge pair undercut the smallest overlap by 2.9e-4 of 471 (a fuzz_query
/// finding). Under 1e-4 rad that error passes 1e-12 of the coordinates; such pairs are rare.
/// (The batched proximity's fast path only picks its facet by visit and proves the facet's own
/// accurate overlap, else takes all 15. The fused bound, box_box_separation, does not measure
/// again: at |L| = 1e-8 it can pass the distance by 3e-8 of the coordinates, an open issue.)
template <class T>
constexpr T kNearParallel2 = std::is_same_v<T, float> ? T(1e-4) : T(1e-8);

/// The separating axes of two boxes in A's frame (Gottschalk, Lin & Manocha, "OBBTree",
/// SIGGRAPH 1996). S is the value's operations (Simd<T, X>: abs, fma); Arch tells the copies of
/// the ISA translation units apart (see BoxPairQuery), also when S is scalar.
template <class S, class Arch>
struct SeparatingAxes {
  using V = typename S::B;

  /// Calls face(p, d) for p = 0..5, A's axes u_Ai (p = i) then B's u_Bj (p = 3 + j), and
  /// edge(p, d, len2) for p = 6 + 3i + j, the cross L = u_Ai x u_Bj. d = |L . c| - r is the
  /// separation of the unnormalised axis, len2 = |L|^2 (faces: 1); the separation is
  /// d / sqrt(len2), negative when the boxes overlap along it. Inputs in A's frame:
  /// C = U_A^T U_B, cA = U_A^T c and cB = U_B^T c for c = c_A - c_B, and the half extents.
  /// In A's frame u_Ai = e_i and u_Bj = column j of C, so L = e_i x C_j: L . c =
  /// cA_i1 C_i2j - cA_i2 C_i1j, |L|^2 = C_i1j^2 + C_i2j^2, and the support radius comes from
  /// |C|: |L . u_A(i+1)| = |C_i2j|, |L . u_A(i+2)| = |C_i1j|, |L . u_B(j+1)| = |C_ij2|,
  /// |L . u_B(j+2)| = |C_ij1| (any orthonormal frames; the signs drop out).
  template <class Face, class Edge>
  [[gnu::always_inline]] static void visit(const V (&C)[3][3], const V* cA, const V* cB, const V* ha, const V* hb,
                                           Face&& face, Edge&& edge) {
    V absC[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) absC[i][j] = S::abs(C[i][j]);
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i)
      face(i, S::abs(cA[i]) - (ha[i] + S::fma(hb[0], absC[i][0], S::fma(hb[1], absC[i][1], hb[2] * absC[i][2]))));
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j)
      face(3 + j, S::abs(cB[j]) - (hb[j] + S::fma(ha[0], absC[0][j], S::fma(ha[1], absC[1][j], ha[2] * absC[2][j]))));
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) {
        const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
        const V len2 = S::fma(C[i1][j], C[i1][j], C[i2][j] * C[i2][j]);
        const V r =
            S::fma(ha[i1], absC[i2][j], S::fma(ha[i2], absC[i1][j], S::fma(hb[j1], absC[i][j2], hb[j2] * absC[i][j1])));
        edge(6 + 3 * i + j, S::abs(cA[i1] * C[i2][j] - cA[i2] * C[i1][j]) - r, len2);
      }
    }
  }
};

}  // namespace minksum::detail
