// Topology tables: the paper's Section 4 index tracking, from a general sum or a kernel lane.
#include <minksum/kernels.hpp>
#include <minksum/sum.hpp>

namespace minksum {

namespace {

void add_facet(TopologyTable& t, const Eigen::Vector3d& n, const Eigen::Vector3d& a, const Eigen::Vector3d& b, int i,
               int j) {
  t.nx.push_back(n.x()), t.ny.push_back(n.y()), t.nz.push_back(n.z());
  t.pa.push_back(n.dot(a)), t.pb.push_back(t.sign_b * n.dot(b));
  t.i.push_back(i), t.j.push_back(j);
}

// Normal of axis `axis` in lane `lane` of a planes struct, on side s (+1 or -1).
template <class Planes>
Eigen::Vector3d lane_normal(const Planes& planes, int axis, int lane, double s) {
  return s * Eigen::Vector3d(planes.n[axis][0][lane], planes.n[axis][1][lane], planes.n[axis][2][lane]);
}

// Corner `code` of a box relative to its centre (the tables take the centre as translation).
Eigen::Vector3d corner(const Box& b, int code) { return box_corner(b, code) - b.center; }

}  // namespace

TopologyTable topology_table(const MinkowskiSum& m, const ConvexPolytope& a, const ConvexPolytope& b, bool difference) {
  TopologyTable t;
  t.sign_b = difference ? -1 : 1;
  for (const auto& p : m.planes) add_facet(t, p.normal, a.vertices[p.i], b.vertices[p.j], p.i, p.j);
  return t;
}

template <class T, int N>
TopologyTable topology_table(const BoxBoxPlanes<T, N>& planes, int lane, const Box& a, const Box& b, bool difference) {
  TopologyTable t;
  t.sign_b = difference ? -1 : 1;
  for (int p = 0; p < 30; ++p) {
    const int axis = p % 15;
    if (!(planes.valid[lane] >> axis & 1)) continue;
    const Eigen::Vector3d n = lane_normal(planes, axis, lane, p < 15 ? 1 : -1);
    const int code = int(p < 15 ? planes.code[axis][lane] : 63 - planes.code[axis][lane]);
    add_facet(t, n, corner(a, code & 7), corner(b, code >> 3), code & 7, code >> 3);
  }
  return t;
}

template <class T, int N>
TopologyTable topology_table(const BoxTrianglePlanes<T, N>& planes, int lane, const Box& box, const Triangle& tri,
                             bool difference) {
  TopologyTable t;
  t.sign_b = difference ? -1 : 1;
  if (planes.valid[lane] >> 30 & 1) return t;
  const Eigen::Vector3d* v[3] = {&tri.a, &tri.b, &tri.c};
  for (int p = 0; p < 26; ++p) {
    const int axis = p % 13;
    if (!(planes.valid[lane] >> axis & 1)) continue;
    const Eigen::Vector3d n = lane_normal(planes, axis, lane, p < 13 ? 1 : -1);
    const int code = int(planes.code[p][lane]);
    add_facet(t, n, corner(box, code & 7), *v[code >> 3], code & 7, code >> 3);
  }
  return t;
}

void instantiate(const TopologyTable& t, double sA, const Eigen::Vector3d& tA, double sB, const Eigen::Vector3d& tB,
                 double* offsets) {
  const Eigen::Vector3d c = tA + t.sign_b * tB;
  const size_t n = t.nx.size();
  const double *nx = t.nx.data(), *ny = t.ny.data(), *nz = t.nz.data();
  const double *pa = t.pa.data(), *pb = t.pb.data();
  for (size_t k = 0; k < n; ++k)  // five multiply-adds per facet; the compiler vectorises it
    offsets[k] = sA * pa[k] + sB * pb[k] + nx[k] * c.x() + ny[k] * c.y() + nz[k] * c.z();
}

// The batch capacities the library instantiates its table factories for.
#define MINKSUM_TABLES(T, N)                                                                           \
  template TopologyTable topology_table(const BoxBoxPlanes<T, N>&, int, const Box&, const Box&, bool); \
  template TopologyTable topology_table(const BoxTrianglePlanes<T, N>&, int, const Box&, const Triangle&, bool);
MINKSUM_TABLES(float, 16)
MINKSUM_TABLES(double, 16)
MINKSUM_TABLES(float, 64)
MINKSUM_TABLES(double, 64)
MINKSUM_TABLES(float, 1024)
MINKSUM_TABLES(double, 1024)
#undef MINKSUM_TABLES

}  // namespace minksum
