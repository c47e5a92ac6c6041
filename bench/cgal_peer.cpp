// CGAL as a peer of the sums, in this one translation unit (CGAL is slow to compile):
// convex_hull_3 on the pairwise sums (the paper's comparator), and the exact Minkowski sum of
// Nef polyhedra (minkowski_sum_3).
#include "cgal_peer.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/minkowski_sum_3.h>

namespace minksum::peers {

namespace {
using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;
using Epeck = CGAL::Exact_predicates_exact_constructions_kernel;
}  // namespace

int cgal_quickhull(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  std::vector<Epick::Point_3> sums;
  sums.reserve(a.size() * b.size());
  for (const auto& p : a)
    for (const auto& q : b) sums.emplace_back(p.x() + q.x(), p.y() + q.y(), p.z() + q.z());
  CGAL::Surface_mesh<Epick::Point_3> hull;
  CGAL::convex_hull_3(sums.begin(), sums.end(), hull);
  return int(hull.number_of_faces());
}

int cgal_nef_sum(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  const auto nef = [](const std::vector<Eigen::Vector3d>& pts) {
    std::vector<Epeck::Point_3> p;
    for (const auto& v : pts) p.emplace_back(v.x(), v.y(), v.z());
    CGAL::Polyhedron_3<Epeck> hull;
    CGAL::convex_hull_3(p.begin(), p.end(), hull);
    return CGAL::Nef_polyhedron_3<Epeck>(hull);
  };
  CGAL::Nef_polyhedron_3<Epeck> A = nef(a), B = nef(b);
  const CGAL::Nef_polyhedron_3<Epeck> sum = CGAL::minkowski_sum_3(A, B);
  return int(sum.number_of_vertices());
}

}  // namespace minksum::peers
