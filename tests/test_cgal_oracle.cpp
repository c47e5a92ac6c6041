// The exact oracle: CGAL's exact kernel (Epeck) builds the hull of the pairwise sums and merges
// exactly coplanar triangles (peers::exact_counts, in bench/cgal_peer.cpp); its V, E, F must
// equal the fast path's. CGAL's exact polytope distance checks the queries.
#include <CGAL/Gmpzf.h>
#include <CGAL/Homogeneous.h>
#include <CGAL/Polytope_distance_d.h>
#include <CGAL/Polytope_distance_d_traits_3.h>
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <random>

#include "cgal_peer.hpp"
#include "checks.hpp"
#include "tools/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;

using tools::exact_rotated;
using tools::scaled;

void expect_matches_oracle(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b,
                           int expected_F = -1) {
  ConvexPolytope A, B;
  ASSERT_EQ(polytope_from_points(a, A), Status::Ok);
  ASSERT_EQ(polytope_from_points(b, B), Status::Ok);
  for (double s : {1.0, -1.0}) {
    MinkowskiSum m;
    ASSERT_EQ(s > 0 ? minkowski_sum(A, B, m) : minkowski_difference(A, B, m), Status::Ok);
    const peers::ExactCounts exact = peers::exact_counts(a, b, s);
    EXPECT_EQ(m.F, exact.F) << "sign " << s;
    EXPECT_EQ(m.E, exact.E) << "sign " << s;
    EXPECT_EQ(m.V, exact.V) << "sign " << s;
    EXPECT_FALSE(m.corrected);
    if (expected_F >= 0) EXPECT_EQ(exact.F, expected_F) << "the oracle itself, sign " << s;
  }
}

TEST(ExactOracle, Table1PairsWithExactCoordinates) {
  for (const auto& pair : tools::exact_table1_pairs()) {
    SCOPED_TRACE(pair.name);
    expect_matches_oracle(pair.a, pair.b, pair.name == "cube_rotcube" ? 30 : -1);
  }
}

std::vector<Vector3d> box(const Vector3d& h, const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  std::vector<Vector3d> p;
  for (const auto& q : tools::cube_points()) p.push_back(R * q.cwiseProduct(h));
  return p;
}

TEST(ExactOracle, AlignedBoxes) { expect_matches_oracle(box({1, 2, 3}), box({0.5, 0.25, 4}), 6); }

TEST(ExactOracle, FortyFiveDegreesAboutZ) {
  expect_matches_oracle(box({1, 1, 1}), box({1, 1, 1}, tools::axis_angle({0, 0, 1}, M_PI / 4)), 10);
}

TEST(ExactOracle, TriangleCoplanarWithABoxFace) {
  expect_matches_oracle(box({1, 1, 1}), {{-0.5, -0.5, 1}, {0.75, -0.25, 1}, {0.125, 0.5, 1}}, 9);
}

TEST(ExactOracle, TrianglePlusTriangle) {
  expect_matches_oracle({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                        {{0.25, 0.125, -0.5}, {0.375, 0.25, 0.75}, {-0.5, 0.75, 0.125}});
}

TEST(ExactOracle, IdenticalAndMirroredPolytopes) {
  const auto d = exact_rotated(scaled(tools::exact_dodecahedron_points(), 30));
  expect_matches_oracle(d, d, 12);
  std::vector<Vector3d> mirrored;
  for (const auto& p : d) mirrored.push_back(Vector3d(-p.x(), p.y(), p.z()));
  expect_matches_oracle(d, mirrored);
}

TEST(ExactOracle, ThinBox) { expect_matches_oracle(box({1, 1, 1e-7}), exact_rotated(scaled(tools::cube_points(), 30))); }

// CGAL's exact polytope distance (an LP-type solver over the input points, exact Gmpzf
// arithmetic) as the oracle of minksum's distances: its squared distance is an exact ratio.
double cgal_distance(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b) {
  using HK = CGAL::Homogeneous<double>;
  using Traits = CGAL::Polytope_distance_d_traits_3<HK, CGAL::Gmpzf, double>;
  std::vector<HK::Point_3> p, q;
  for (const auto& v : a) p.emplace_back(v.x(), v.y(), v.z());
  for (const auto& v : b) q.emplace_back(v.x(), v.y(), v.z());
  CGAL::Polytope_distance_d<Traits> pd(p.begin(), p.end(), q.begin(), q.end());
  return std::sqrt(CGAL::to_double(pd.squared_distance_numerator()) /
                   CGAL::to_double(pd.squared_distance_denominator()));
}

TEST(ExactOracle, DistancesAgreeWithCgalPolytopeDistance) {
  std::mt19937_64 rng(81);
  std::uniform_int_distribution<int> count(4, 20);
  std::uniform_real_distribution<double> u(-1, 1);
  int separated = 0;
  for (int k = 0; k < 3000; ++k) {
    std::vector<Vector3d> pts[2];
    for (auto& pt : pts) {
      const Vector3d c = 2 * Vector3d(u(rng), u(rng), u(rng));
      if (k % 3 == 0) {  // boxes
        const Box b = tools::random_box(rng, 0);
        for (const auto& q : tools::cube_points()) pt.push_back(c + b.rotation * q.cwiseProduct(b.half_extents));
      } else if (k % 3 == 1) {  // triangles
        for (int v = 0; v < 3; ++v) pt.push_back(c + Vector3d(u(rng), u(rng), u(rng)));
      } else {  // random polytopes
        for (const auto& q : tools::sphere_points(count(rng), unsigned(rng()))) pt.push_back(c + q);
      }
    }
    ConvexPolytope A, B;
    ASSERT_EQ(polytope_from_points(pts[0], A), Status::Ok);
    ASSERT_EQ(polytope_from_points(pts[1], B), Status::Ok);
    Proximity p;
    ASSERT_EQ(proximity(A, B, p), Status::Ok);
    const double exact = cgal_distance(pts[0], pts[1]);
    EXPECT_NEAR(p.distance, exact, 1e-9 * (1 + exact)) << "pair " << k;
    separated += exact > 0;
  }
  EXPECT_GT(separated, 1000);  // and the rest overlap: both outcomes are exercised
  EXPECT_LT(separated, 2900);
}

// The stability suite (issue 7): named hard cases (../shared/GUIDE.md section 3), each in
// several variants, through every path (fast, reference, hull; sum and difference). Every result
// must be a valid polytope holding every pairwise sum, with a support function within 1e-12 of
// h_A + h_B; where the input is exactly representable and the structure well defined, V, E and
// F must equal CGAL's exact hull of the pairwise sums; bad input must get a status.
struct HardCase {
  std::string name;
  std::vector<Vector3d> a, b;
  bool exact = false;         // compare the structure with CGAL's exact counts
  double tol = 1e-12;         // containment tolerance, relative to the sum's size
  Status error = Status::Ok;  // the status polytope_from_points must return, if not Ok
  Status sum_status = Status::Ok;  // the status every path must return
};

std::ostream& operator<<(std::ostream& os, const HardCase& c) { return os << c.name; }

std::vector<Vector3d> offset(std::vector<Vector3d> pts, const Vector3d& by) {
  for (auto& p : pts) p += by;
  return pts;
}

std::vector<HardCase> hard_cases() {
  const Vector3d generic = Vector3d(0.3, -0.5, 0.81).normalized();
  const auto cube = scaled(tools::cube_points(), 30 * 7), ico = scaled(tools::exact_icosahedron_points(), 30);
  const auto dod = scaled(tools::exact_dodecahedron_points(), 30);
  const auto R = tools::table1_rotation();
  std::vector<HardCase> c;
  for (const auto& pair : tools::exact_table1_pairs()) c.push_back({"table1_exact_" + pair.name, pair.a, pair.b, true});
  c.push_back({"aligned_boxes_123_plus_half", box({1, 2, 3}), box({0.5, 0.25, 4}), true});
  c.push_back({"aligned_boxes_equal", box({1, 1, 1}), box({1, 1, 1}), true});
  c.push_back({"aligned_boxes_one_thin", box({1, 1, 1e-7}), box({2, 3, 4}), true});
  for (int e = 3; e <= 15; ++e)
    c.push_back({"tiny_rotation_1e-" + std::to_string(e), box({1, 1, 1}),
                 box({1, 1, 1}, tools::axis_angle(generic, std::pow(10.0, -e))), false, 1e-8});
  c.push_back({"rot45_about_z", box({1, 1, 1}), box({1, 1, 1}, tools::axis_angle({0, 0, 1}, M_PI / 4)), true});
  c.push_back({"rot45_about_x", box({1, 2, 3}), box({1, 1, 1}, tools::axis_angle({1, 0, 0}, M_PI / 4)), false});
  c.push_back({"rot45_about_generic_axis", box({1, 1, 1}), box({1, 1, 1}, tools::axis_angle(generic, M_PI / 4)), false});
  for (double tilt : {1e-6, 1e-9, 1e-12})  // the paper's Fig. 6: edges almost parallel
    c.push_back({"paper_fig6_tilt_" + std::to_string(int(-std::log10(tilt))), box({2, 2, 2}),
                 box({1, 1, 1}, tools::axis_angle(generic, tilt) * tools::axis_angle({0, 0, 1}, M_PI / 2)), false, 1e-8});
  const Vector3d far(1e6, -1e6, 1e6);
  c.push_back({"offset_1e6_box_box", offset(box({1, 2, 3}), far), offset(box({1, 1, 1}, R), far)});
  c.push_back({"offset_1e6_icosa_dodeca", offset(tools::icosahedron_points(), far), offset(tools::rotated(tools::dodecahedron_points(), R), far)});
  c.push_back({"offset_1e6_box_triangle", offset(box({1, 1, 1}, R), far), offset({{0.1, 0.2, 0.3}, {1.1, -0.4, 0.5}, {0.3, 0.9, -0.7}}, far)});
  c.push_back({"scale_1e-6_icosa_tiny_box", tools::icosahedron_points(), box({1e-6, 1e-6, 1e-6}, R)});
  c.push_back({"scale_1e-6_cube_tiny_icosa", box({1, 1, 1}, R), scaled(tools::icosahedron_points(), 1e-6)});
  c.push_back({"scale_1e-6_tiny_triangle_box", {{0, 0, 0}, {1e-6, 0, 0}, {0, 1e-6, 0}}, box({1, 2, 3}, R)});
  for (int axis = 0; axis < 3; ++axis) {
    Vector3d h(30, 30, 30);
    h[axis] = 30e-7;
    c.push_back({"thin_box_1e-7_axis_" + std::to_string(axis), box(h), exact_rotated(scaled(tools::cube_points(), 30)), true});
  }
  // A triangle in the plane of a box face (dyadic coordinates: exact).
  c.push_back({"triangle_on_box_face_top", box({1, 1, 1}), {{-0.5, -0.5, 1}, {0.75, -0.25, 1}, {0.125, 0.5, 1}}, true});
  c.push_back({"triangle_on_box_face_side", box({1, 1, 1}), {{-1, -0.5, -0.5}, {-1, 0.75, -0.25}, {-1, 0.125, 0.5}}, true});
  c.push_back({"triangle_on_box_face_larger", box({1, 1, 1}), {{-4, -4, -1}, {4, -4, -1}, {0, 4, -1}}, true});
  c.push_back({"triangle_triangle_generic", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0.25, 0.125, -0.5}, {0.375, 0.25, 0.75}, {-0.5, 0.75, 0.125}}, true});
  // Two flat operands in parallel planes: the sum is flat, which is not a solid.
  c.push_back({"triangle_triangle_parallel_planes", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0.5, 0.5, 1}, {-0.5, 0.25, 1}, {0.25, -0.75, 1}},
               false, 0, Status::Ok, Status::DegenerateResult});
  c.push_back({"triangle_triangle_coplanar", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{2, 0, 0}, {3, 1, 0}, {2, 2, 0}},
               false, 0, Status::Ok, Status::DegenerateResult});
  c.push_back({"triangle_triangle_shared_edge_direction", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, 1}, {2, 0, 1}, {0.5, 0.5, 3}}, true});
  c.push_back({"identical_cube", exact_rotated(cube), exact_rotated(cube), true});
  c.push_back({"identical_icosahedron", exact_rotated(ico), exact_rotated(ico), true});
  c.push_back({"identical_pyritohedron", exact_rotated(dod), exact_rotated(dod), true});
  for (const auto* shape : {&cube, &ico, &dod}) {
    std::vector<Vector3d> mirrored;
    const auto turned = exact_rotated(*shape);
    for (const auto& p : turned) mirrored.push_back(Vector3d(-p.x(), p.y(), p.z()));
    c.push_back({std::string("mirrored_") + (shape == &cube ? "cube" : shape == &ico ? "icosahedron" : "pyritohedron"), turned, mirrored, true});
  }
  for (double eps : {0.0, 1e-15, 1e-9}) {
    auto a = tools::icosahedron_points();
    const auto copy = a;
    for (const auto& p : copy) a.push_back(p * (1 + eps));
    c.push_back({eps == 0 ? "duplicated_vertices" : "near_duplicated_vertices_" + std::string(eps == 1e-15 ? "1e-15" : "1e-9"),
                 a, tools::rotated(tools::cube_points(), R), false, eps == 1e-9 ? 1e-8 : 1e-12});
  }
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}) {
    auto pts = tools::cube_points();
    pts[5][1] = bad;
    c.push_back({std::string("non_finite_") + (std::isnan(bad) ? "nan" : bad > 0 ? "inf" : "minus_inf"), tools::cube_points(), pts, false, 0, Status::NonFinite});
  }
  auto huge = tools::cube_points();
  huge[2][0] = 1e200;
  c.push_back({"coordinate_beyond_1e100", tools::cube_points(), huge, false, 0, Status::OutOfRange});
  return c;
}

class Stability : public testing::TestWithParam<HardCase> {};

TEST_P(Stability, EveryPathIsValidAndExactWhereDefined) {
  const HardCase& c = GetParam();
  ConvexPolytope A, B;
  const Status sa = polytope_from_points(c.a, A), sb = polytope_from_points(c.b, B);
  if (c.error != Status::Ok) {
    EXPECT_EQ(sa == Status::Ok ? sb : sa, c.error);
    return;
  }
  ASSERT_EQ(sa, Status::Ok);
  ASSERT_EQ(sb, Status::Ok);
  for (double s : {1.0, -1.0}) {
    const peers::ExactCounts exact = c.exact ? peers::exact_counts(c.a, c.b, s) : peers::ExactCounts{};
    for (Method method : {Method::Fast, Method::Reference, Method::Hull}) {
      SCOPED_TRACE(std::string(s > 0 ? "sum " : "difference ") + (method == Method::Fast ? "fast" : method == Method::Reference ? "reference" : "hull"));
      MinkowskiSum m;
      const Status st = s > 0 ? minkowski_sum(A, B, m, method) : minkowski_difference(A, B, m, method);
      ASSERT_EQ(st, c.sum_status) << to_string(st);
      if (st != Status::Ok) continue;
      EXPECT_TRUE(test::valid_sum(c.a, c.b, s, A, B, m, c.tol, 1e-12, 300));
      if (c.exact) {
        EXPECT_EQ(m.F, exact.F);
        EXPECT_EQ(m.E, exact.E);
        EXPECT_EQ(m.V, exact.V);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(HardCases, Stability, testing::ValuesIn(hard_cases()),
                         [](const testing::TestParamInfo<HardCase>& info) {
                           std::string name = info.param.name;  // "1e-9" -> "1em9": gtest names are [A-Za-z0-9_]
                           for (char& ch : name) ch = ch == '-' ? 'm' : ch;
                           return name;
                         });

}  // namespace
}  // namespace minksum
