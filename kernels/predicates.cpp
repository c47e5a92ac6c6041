#include "predicates.hpp"

#include <gmpxx.h>

#include <cmath>

namespace minksum::detail {

int exact_orient(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  // Every double is a dyadic rational, so mpq_class holds it exactly.
  auto m = [](double x) { return mpq_class(x); };
  const mpq_class det = m(p.x()) * (m(q.y()) * m(r.z()) - m(q.z()) * m(r.y())) -
                        m(p.y()) * (m(q.x()) * m(r.z()) - m(q.z()) * m(r.x())) +
                        m(p.z()) * (m(q.x()) * m(r.y()) - m(q.y()) * m(r.x()));
  return sgn(det);
}

Eigen::Vector3d exact_newell(const std::vector<Eigen::Vector3d>& points,
                             const std::vector<int>& loop) {
  mpq_class n[3];
  for (size_t k = 0; k < loop.size(); ++k) {
    const Eigen::Vector3d& a = points[loop[k]];
    const Eigen::Vector3d& b = points[loop[(k + 1) % loop.size()]];
    for (int d = 0; d < 3; ++d) {
      const int e = (d + 1) % 3, f = (d + 2) % 3;
      n[d] += mpq_class(a[e]) * mpq_class(b[f]) - mpq_class(a[f]) * mpq_class(b[e]);
    }
  }
  // get_d truncates towards zero, which is symmetric under negation as required.
  return Eigen::Vector3d(n[0].get_d(), n[1].get_d(), n[2].get_d());
}

Cross make_cross(const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  Cross c{q, r, q.cross(r), {}};
  c.bound = Eigen::Vector3d(std::abs(q.y() * r.z()) + std::abs(q.z() * r.y()),
                            std::abs(q.z() * r.x()) + std::abs(q.x() * r.z()),
                            std::abs(q.x() * r.y()) + std::abs(q.y() * r.x()));
  return c;
}

int orient(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  return orient(p, make_cross(q, r));
}

}  // namespace minksum::detail
