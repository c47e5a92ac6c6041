// minksum: fixed-size structure-of-arrays kernels (box-box, box-triangle, support push,
// triangle distance) with runtime ISA dispatch. Opt-in: the umbrella header minksum.hpp does
// not include it (a user of the shape API never sees the batch types).
// No SIMD types appear here: the kernels live in kernels/, one translation unit per ISA.
#pragma once

#include <minksum/model.hpp>
#include <minksum/sum.hpp>

#include <cstdint>
#include <type_traits>
#include <vector>

namespace minksum {

/// Instruction sets the kernels are compiled for (all of them on x86-64).
enum class Isa { Scalar = 0, Sse4_2 = 1, Avx2 = 2, Avx512 = 3 };

/// "scalar", "sse4_2", "avx2" or "avx512".
const char* to_string(Isa isa);

/// The ISA the kernels use: the best one this CPU supports, chosen once at start-up, unless
/// the environment variable MINKSUM_ISA=scalar|sse4_2|avx2|avx512 forces one.
Isa active_isa();

/// True if this CPU can run the kernels compiled for `isa`.
bool isa_supported(Isa isa);

/// Switches the kernels to `isa` (tests and benchmarks); false if the CPU lacks it. Not
/// thread-safe with concurrent kernel calls: call it before using the kernels.
bool force_isa(Isa isa);

/// Lanes per batch are a multiple of this (the widest SIMD register holds 16 floats).
constexpr int kLaneMultiple = 16;

/// Row length of the structure-of-arrays buffers: large power-of-two capacities get one extra
/// register of padding per row, so that the rows a kernel touches together do not all map to
/// the same L1 cache set.
template <int N>
constexpr int kRow = N >= 256 ? N + kLaneMultiple : N;

/// Integer type of support codes and masks: as wide as the kernel's float type.
template <class T>
using CodeOf = std::conditional_t<std::is_same_v<T, float>, std::int32_t, std::int64_t>;

/// |e_A x e_B| below this (edges as unit vectors) marks an edge-cross axis invalid: nearly
/// parallel edges give no reliable direction. Dropping that plane keeps the planes a superset
/// of the sum's facets' half-spaces, i.e. the H-representation stays conservative.
template <class T>
constexpr T kParallelThreshold = std::is_same_v<T, float> ? T(3e-4) : T(1e-8);

/// Edges of two boxes closer to parallel than this (|u_A x u_B|) span a sliver facet of A (-) B
/// that the box-box proximity kernel skips; that moves the distance by at most this fraction of
/// the longer edge's half length.
template <class T>
constexpr T kSliverThreshold = std::is_same_v<T, float> ? T(1e-5) : T(1e-11);

/// N boxes, structure of arrays, 64-byte aligned; caller-owned, fixed capacity N.
template <class T, int N>
struct alignas(64) BoxBatch {
  static_assert(N % kLaneMultiple == 0, "capacity must be a multiple of 16");
  alignas(64) T c[3][kRow<N>];     ///< centre, component d of lane k at c[d][k]
  alignas(64) T u[3][3][kRow<N>];  ///< axis a (column a of the rotation), component d at u[a][d][k]
  alignas(64) T h[3][kRow<N>];     ///< half extents
  int count = 0;                   ///< lanes in use; the rest are padded with valid boxes
  /// Stores box b in lane k (0 <= k < N).
  void set(int k, const Box& b) {
    for (int d = 0; d < 3; ++d) {
      c[d][k] = T(b.center[d]);
      h[d][k] = T(b.half_extents[d]);
      for (int a = 0; a < 3; ++a) u[a][d][k] = T(b.rotation(d, a));
    }
  }
  /// Fills lanes [count, N) with the unit box, so whole SIMD registers hold valid input.
  void pad() {
    for (int k = count; k < N; ++k) set(k, Box{});
  }
  /// Holds box b alone: lane 0, count 1, the other lanes padded.
  void set_one(const Box& b) {
    set(0, b);
    count = 1;
    pad();
  }
};

/// N triangles in structure of arrays: vertex i, component d of lane k at v[i][d][k].
template <class T, int N>
struct alignas(64) TriangleBatch {
  static_assert(N % kLaneMultiple == 0, "capacity must be a multiple of 16");
  alignas(64) T v[3][3][kRow<N>];  ///< vertices
  int count = 0;                   ///< lanes in use
  /// Stores triangle t in lane k.
  void set(int k, const Triangle& t) {
    const Eigen::Vector3d* p[3] = {&t.a, &t.b, &t.c};
    for (int i = 0; i < 3; ++i)
      for (int d = 0; d < 3; ++d) v[i][d][k] = T((*p[i])[d]);
  }
  /// Fills lanes [count, N) with a valid unit triangle.
  void pad() {
    for (int k = count; k < N; ++k) set(k, Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  }
};

/// The 30 planes of each box-box sum A (+) B or difference A (-) B, from 15 axes: 3 of A,
/// 3 of B, then the 9 crosses u_A[i] x u_B[j] (axis 6 + 3 i + j). Plane p < 15 is
/// n_p . x <= offset[p]; plane p + 15 is -n_p . x <= offset[p + 15] (central symmetry).
/// code[p] = corner of A | corner of B << 3 for plane p (corner bit a set: +u_a side); plane
/// p + 15 has both 3-bit corner codes complemented. For the difference, B's corner is the one
/// whose negation is the support. Bit p of valid is clear for an invalid (parallel) axis,
/// whose normal and offsets are written as 0.
template <class T, int N>
struct alignas(64) BoxBoxPlanes {
  alignas(64) T n[15][3][kRow<N>];          ///< axis p, component d of lane k at n[p][d][k]
  alignas(64) T offset[30][kRow<N>];        ///< plane offsets
  alignas(64) CodeOf<T> code[15][kRow<N>];  ///< support corner codes of the + plane of each axis
  alignas(64) CodeOf<T> valid[kRow<N>];     ///< bit p: axis p is valid
};

/// The up to 26 planes of each box-triangle sum: 13 axes (3 box axes, the triangle normal,
/// then the 9 crosses u[i] x e_j with e_j = v[(j+1)%3] - v[j], axis 4 + 3 i + j), plane p
/// and p + 13 on opposite sides. code[p] = box corner | triangle vertex << 3 per plane
/// (ties between triangle vertices go to the lowest index). valid bit p: axis p is valid;
/// bit 30: the triangle is degenerate (the whole lane is invalid): its edges within
/// kParallelThreshold of parallel, or twice its area under the square root of T's smallest
/// normal number (1.1e-19 in float), whose direction T cannot hold. An edge-cross axis whose
/// cross product is that short is invalid too (conservative, as for parallel edges).
template <class T, int N>
struct alignas(64) BoxTrianglePlanes {
  alignas(64) T n[13][3][kRow<N>];          ///< axis p, component d of lane k
  alignas(64) T offset[26][kRow<N>];        ///< plane offsets
  alignas(64) CodeOf<T> code[26][kRow<N>];  ///< per plane: box corner | triangle vertex << 3
  alignas(64) CodeOf<T> valid[kRow<N>];     ///< bit p: axis p valid; bit 30: degenerate triangle
};

namespace detail {
/// Component arrays of a box batch (row stride kRow<N>), as the ISA kernels read them.
template <class T>
struct BoxLanes {
  const T* c;  ///< c[d * N + k]
  const T* u;  ///< u[(a * 3 + d) * N + k]
  const T* h;  ///< h[d * N + k]
};
/// Output arrays of a plane kernel (row stride kRow<N>).
template <class T>
struct PlaneLanes {
  T* n;              ///< n[(p * 3 + d) * N + k]
  T* offset;         ///< offset[p * N + k]
  CodeOf<T>* code;   ///< code[p * N + k]
  CodeOf<T>* valid;  ///< valid[k]
};
/// Extra output arrays of the box-box sum kernel (row stride kRow<N>); all null for planes only.
template <class T>
struct SumLanes {
  CodeOf<T>* loop = nullptr;     ///< loop[p * N + k]
  T* corner_a = nullptr;         ///< corner_a[(i * 3 + d) * N + k]
  T* corner_b = nullptr;         ///< corner_b[(j * 3 + d) * N + k]
  CodeOf<T>* general = nullptr;  ///< general[k]
};
/// Output arrays of the box-box proximity kernel (row stride kRow<N>).
template <class T>
struct ProximityLanes {
  T* distance;   ///< distance[k]
  T* depth;      ///< depth[k]
  T* direction;  ///< direction[d * N + k]
  T* point_a;    ///< point_a[d * N + k]
  T* point_b;    ///< point_b[d * N + k]
};
template <class T, int N>
BoxLanes<T> lanes(const BoxBatch<T, N>& b) {
  return {&b.c[0][0], &b.u[0][0][0], &b.h[0][0]};
}
template <class T, int N, class P>
PlaneLanes<T> lanes(P& p) {
  return {&p.n[0][0][0], &p.offset[0][0], &p.code[0][0], &p.valid[0]};
}
// Type-erased entry points behind the templates below (stride: the row length); they
// dispatch on the active ISA.
void box_box(BoxLanes<float> a, BoxLanes<float> b, int count, int stride, bool difference, PlaneLanes<float> out,
             SumLanes<float> sum = {});
void box_box(BoxLanes<double> a, BoxLanes<double> b, int count, int stride, bool difference, PlaneLanes<double> out,
             SumLanes<double> sum = {});
void box_triangle(BoxLanes<float> box, const float* tri, int count, int stride, bool difference, PlaneLanes<float> out);
void box_triangle(BoxLanes<double> box, const double* tri, int count, int stride, bool difference,
                  PlaneLanes<double> out);
void box_box_proximity(BoxLanes<float> a, BoxLanes<float> b, int count, int stride, ProximityLanes<float> out);
void box_box_proximity(BoxLanes<double> a, BoxLanes<double> b, int count, int stride, ProximityLanes<double> out);
void box_box_separation(BoxLanes<float> a, BoxLanes<float> b, int count, int stride, float* bound, std::int32_t* hit);
void box_box_separation(BoxLanes<double> a, BoxLanes<double> b, int count, int stride, double* bound,
                        std::int64_t* hit);
void box_triangle_overlap(BoxLanes<float> box, const float* tri, int count, int stride, std::int32_t* hit);
void box_triangle_overlap(BoxLanes<double> box, const double* tri, int count, int stride, std::int64_t* hit);
void triangle_distance(const float* s, const float* t, int count, int stride, float* distance, float* point_s,
                       float* point_t);
void triangle_distance(const double* s, const double* t, int count, int stride, double* distance, double* point_s,
                       double* point_t);
/// Packs a box pair for the single-pair kernels: c_A, c_B, the axes of A then of B (each
/// column-major), h_A, h_B.
void pack_box_pair(const Box& a, const Box& b, double (&in)[30]);
}  // namespace detail

/// The 30 planes of A[k] (+) B[k] (or A[k] (-) B[k]) for every lane k < a.count; a and b
/// must have the same count and be padded (pad()). No allocation, no exception, no lock.
template <class T, int N>
void box_box_planes(const BoxBatch<T, N>& a, const BoxBatch<T, N>& b, bool difference, BoxBoxPlanes<T, N>& out) {
  detail::box_box(detail::lanes(a), detail::lanes(b), a.count, kRow<N>, difference, detail::lanes<T, N>(out));
}

/// The whole polytope A (+) B of each of N box pairs, index-tracked: the 30 facet planes with
/// their support corners (as box_box_planes), each facet's vertex loop, and the boxes' corners.
/// A vertex is a support pair (i, j), coded i | j << 3 with corner codes as in box_corner; its
/// point is corner_a[i] + corner_b[j]. In general position (general = 1: every |u_Ai x u_Bj|
/// and every |u_Ai . u_Bj| above tau = kParallelThreshold, so no two edges are parallel and no
/// three coplanar) the sum is a zonotope with 30 parallelogram facets, 60 edges and 32 vertices: facet p is the
/// plane p of `planes` with the loop of four vertex codes loop[p] = v0 | v1 << 6 | v2 << 12 |
/// v3 << 18, counter-clockwise seen from outside. Lanes with general = 0 have merged facets:
/// take them through minkowski_sum (their loops are not meaningful).
template <class T, int N>
struct alignas(64) BoxBoxSum {
  BoxBoxPlanes<T, N> planes;                ///< the 30 facet planes
  alignas(64) CodeOf<T> loop[30][kRow<N>];  ///< facet p's vertex loop, four 6-bit codes
  alignas(64) T corner_a[8][3][kRow<N>];    ///< corner i of A, component d of lane k
  alignas(64) T corner_b[8][3][kRow<N>];    ///< corner j of B
  alignas(64) CodeOf<T> general[kRow<N>];   ///< 1 if the lane is in general position
};

/// A[k] (+) B[k] for every lane k < a.count (pad() both), as a whole polytope (see
/// BoxBoxSum). No allocation, no exception, no lock.
template <class T, int N>
void box_box_sum(const BoxBatch<T, N>& a, const BoxBatch<T, N>& b, BoxBoxSum<T, N>& out) {
  detail::box_box(detail::lanes(a), detail::lanes(b), a.count, kRow<N>, false, detail::lanes<T, N>(out.planes),
                  {&out.loop[0][0], &out.corner_a[0][0][0], &out.corner_b[0][0][0], out.general});
}

/// The planes of box[k] (+) tri[k] (or box[k] (-) tri[k]) for every lane k < box.count.
template <class T, int N>
void box_triangle_planes(const BoxBatch<T, N>& box, const TriangleBatch<T, N>& tri, bool difference,
                         BoxTrianglePlanes<T, N>& out) {
  detail::box_triangle(detail::lanes(box), &tri.v[0][0][0], box.count, kRow<N>, difference, detail::lanes<T, N>(out));
}

/// Proximity of N box pairs, one per lane (see box_box_proximity).
template <class T, int N>
struct alignas(64) BoxBoxProximity {
  alignas(64) T distance[kRow<N>];      ///< exact distance; 0 when the boxes intersect
  alignas(64) T depth[kRow<N>];         ///< penetration depth; 0 when separated
  alignas(64) T direction[3][kRow<N>];  ///< unit: moving B by depth * direction separates them
  alignas(64) T point_a[3][kRow<N>];    ///< closest point on A, or A's deepest point
  alignas(64) T point_b[3][kRow<N>];    ///< closest point on B, or B's deepest point
};

/// Exact distance with closest points, or penetration depth and direction, of every pair
/// a[k], b[k] (k < a.count; pad() the batches), on the zonotope A (-) B: the facet the
/// separating axis test picks, proven optimal per lane, else all 15 facets. No allocation.
template <class T, int N>
void box_box_proximity(const BoxBatch<T, N>& a, const BoxBatch<T, N>& b, BoxBoxProximity<T, N>& out) {
  detail::box_box_proximity(detail::lanes(a), detail::lanes(b), a.count, kRow<N>,
                            {out.distance, out.depth, &out.direction[0][0], &out.point_a[0][0], &out.point_b[0][0]});
}

/// The separating axis test of N box pairs, fused (no planes written).
template <class T, int N>
struct alignas(64) BoxBoxSeparation {
  alignas(64) T bound[kRow<N>];        ///< lower bound of the distance (0 when they intersect)
  alignas(64) CodeOf<T> hit[kRow<N>];  ///< 1 if the boxes intersect (the origin is in A (-) B)
};

/// Collision and a distance lower bound of every pair (the largest separation over the 15
/// axes), for traversal: the cheapest box-box query. No allocation.
template <class T, int N>
void box_box_separation(const BoxBatch<T, N>& a, const BoxBatch<T, N>& b, BoxBoxSeparation<T, N>& out) {
  detail::box_box_separation(detail::lanes(a), detail::lanes(b), a.count, kRow<N>, out.bound, out.hit);
}

/// Box-triangle overlap flags of N pairs.
template <class T, int N>
struct alignas(64) BoxTriangleOverlap {
  alignas(64) CodeOf<T> hit[kRow<N>];  ///< 1 if the box and the triangle intersect
};

/// Box-triangle overlap of every pair by the separating axis test on the 13 axes, fused.
/// No allocation.
template <class T, int N>
void box_triangle_overlap(const BoxBatch<T, N>& box, const TriangleBatch<T, N>& tri, BoxTriangleOverlap<T, N>& out) {
  detail::box_triangle_overlap(detail::lanes(box), &tri.v[0][0][0], box.count, kRow<N>, out.hit);
}

/// Exact distance between two triangles given by their corners, with the closest points;
/// 0 when they intersect (degenerate triangles allowed). The distance kernel of mesh_distance;
/// triangle_distance(TriangleBatch...) below is its batched form.
double triangle_distance(const Eigen::Vector3d (&s)[3], const Eigen::Vector3d (&t)[3], Eigen::Vector3d& ps,
                         Eigen::Vector3d& pt);

/// Exact distances of N triangle pairs, one per lane.
template <class T, int N>
struct alignas(64) TriangleDistances {
  alignas(64) T distance[kRow<N>];    ///< exact distance; 0 when the triangles meet
  alignas(64) T point_s[3][kRow<N>];  ///< closest point on s (component d of lane k at [d][k])
  alignas(64) T point_t[3][kRow<N>];  ///< closest point on t
};

/// Exact distance and closest points of every pair s[k], t[k] (k < s.count; pad() both), the
/// batched form of the scalar triangle_distance (minksum/mesh.hpp): edge pairs, vertex-face
/// and edge-face crossings, relative to a corner (so large coordinates keep their precision).
/// A pair spanning beyond 1e+-60 (float: 1e+-6) of its corner takes the scalar path; NaN or
/// Inf coordinates give NaN. No allocation.
template <class T, int N>
void triangle_distance(const TriangleBatch<T, N>& s, const TriangleBatch<T, N>& t, TriangleDistances<T, N>& out) {
  detail::triangle_distance(&s.v[0][0][0], &t.v[0][0][0], s.count, kRow<N>, out.distance, &out.point_s[0][0],
                            &out.point_t[0][0]);
}

/// One plane of a kernel result, for callers with one pair.
struct KernelPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< unit normal (zero when invalid)
  double offset = 0;                                 ///< n . x <= offset
  int i = -1, j = -1;  ///< support pair: box corner code, and B's corner or triangle vertex
  bool valid = false;  ///< false for an axis of parallel edges (or a degenerate triangle)
};

/// The planes of one box pair in double (the single-pair API): axis q < 15 (numbered as in
/// BoxBoxPlanes) in lane q.
struct alignas(64) BoxBoxPair {
  alignas(64) double n[3][16];         ///< axis q: (n[0][q], n[1][q], n[2][q]); zero if invalid
  alignas(64) double offset[2][16];    ///< offset[0][q]: plane +n_q; offset[1][q]: plane -n_q
  alignas(64) std::int64_t code[16];   ///< corner codes of plane +n_q (plane -n_q: 63 - code)
  alignas(64) std::int64_t valid[16];  ///< 1 if axis q is valid
  /// Plane p < 30: p < 15 is +n_p, p >= 15 is -n_(p-15).
  KernelPlane plane(int p) const;
};

/// The planes of one box-box pair, through the active ISA's box-box kernel with the pair's 15
/// axes in its lanes. No allocation.
void box_box_planes(const Box& a, const Box& b, bool difference, BoxBoxPair& out);

/// The 26 planes of one box-triangle pair in double, through the same kernels.
void box_triangle_planes(const Box& box, const Triangle& tri, bool difference, KernelPlane (&out)[26]);

/// Support push: for each of k directions (dx, dy, dz), the maximum of d . v over the n
/// vertices (x, y, z) and the index of the first vertex that attains it. n >= 1.
void support_push(const float* x, const float* y, const float* z, int n, const float* dx, const float* dy,
                  const float* dz, int k, float* max_out, int* arg_out);
/// The same in double.
void support_push(const double* x, const double* y, const double* z, int n, const double* dx, const double* dy,
                  const double* dz, int k, double* max_out, int* arg_out);

// The topology tables of one batch lane (sum.hpp has the general one and `instantiate`).

/// The table of one box-box lane: boxes are taken relative to their centres, so that tA and tB
/// are the copies' centres; invalid axes are left out.
template <class T, int N>
TopologyTable topology_table(const BoxBoxPlanes<T, N>& planes, int lane, const Box& a, const Box& b, bool difference);

/// The table of one box-triangle lane (box relative to its centre, triangle as given).
template <class T, int N>
TopologyTable topology_table(const BoxTrianglePlanes<T, N>& planes, int lane, const Box& box, const Triangle& tri,
                             bool difference);

}  // namespace minksum
