// Triangle pairs queued for the batched exact distance kernel (internal): the exhaustive
// polytope search and the mesh search test many pairs, a few at a time.
#pragma once

#include <minksum/kernels.hpp>

namespace minksum::detail {

/// Up to 16 triangle pairs waiting for their exact distances, on the stack (no allocation),
/// each with the caller's two ids.
struct TrianglePairs {
  TriangleBatch<double, 16> s, t;
  TriangleDistances<double, 16> d;
  int id_s[16], id_t[16];

  /// Queues the pair (corners a, b; ids); true when the queue is full (flush it).
  bool add(const Eigen::Vector3d (&a)[3], const Eigen::Vector3d (&b)[3], int ia = -1, int ib = -1) {
    const int k = s.count++;
    s.set(k, Triangle{a[0], a[1], a[2]}), t.set(k, Triangle{b[0], b[1], b[2]});
    id_s[k] = ia, id_t[k] = ib;
    return s.count == 16;
  }

  /// Every queued pair's exact distance, reported as found(distance, point on s, point on t,
  /// id_s, id_t); then the queue is empty. A few pairs take the scalar triangle_distance,
  /// faster than one SIMD pass; more take the batched kernel.
  template <class Found>
  void flush(Found&& found) {
    if (s.count < 4) {
      for (int k = 0; k < s.count; ++k) {
        Eigen::Vector3d a[3], b[3], p, q;
        for (int i = 0; i < 3; ++i)
          for (int c = 0; c < 3; ++c) a[i][c] = s.v[i][c][k], b[i][c] = t.v[i][c][k];
        const double dist = minksum::triangle_distance(a, b, p, q);
        found(dist, p, q, id_s[k], id_t[k]);
      }
      s.count = 0;
      return;
    }
    t.count = s.count;
    s.pad(), t.pad();
    minksum::triangle_distance(s, t, d);
    for (int k = 0; k < s.count; ++k)
      found(d.distance[k], Eigen::Vector3d(d.point_s[0][k], d.point_s[1][k], d.point_s[2][k]),
            Eigen::Vector3d(d.point_t[0][k], d.point_t[1][k], d.point_t[2][k]), id_s[k], id_t[k]);
    s.count = 0;
  }
};

}  // namespace minksum::detail
