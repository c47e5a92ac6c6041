// Prepared shapes are shared read-only across threads: 4 threads run sums, differences and
// proximity queries on the same shapes at once, and every answer equals, bit for bit, the one
// computed on one thread. ci/test also runs this executable under ThreadSanitizer.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <atomic>
#include <random>
#include <thread>

#include "ties.hpp"
#include "support/shapes.hpp"

namespace {

using namespace minksum;
using Eigen::Isometry3d;
using Eigen::Vector3d;

struct Task {
  int a, b;
  Isometry3d pa, pb;
  bool difference;
};

bool identical(const MinkowskiSum& x, const MinkowskiSum& y) {
  if (x.F != y.F || x.V != y.V || x.loop_vertex != y.loop_vertex || x.loop_start != y.loop_start) return false;
  for (int f = 0; f < x.F; ++f)
    if (x.planes[f].normal != y.planes[f].normal || x.planes[f].offset != y.planes[f].offset ||
        x.planes[f].i != y.planes[f].i || x.planes[f].j != y.planes[f].j)
      return false;
  for (int v = 0; v < x.V; ++v)
    if (x.vertices[v].point != y.vertices[v].point) return false;
  return true;
}

TEST(Threads, SharedShapesGiveTheSameAnswersOnFourThreads) {
  std::vector<ConvexShape> shapes(6);
  ASSERT_EQ(shape_from_box(Box{}, shapes[0]), Status::Ok);
  ASSERT_EQ(shape_from_triangle(Triangle{{0, 0, 0}, {1, 0, 0.2}, {0, 1, 0}}, shapes[1]), Status::Ok);
  ASSERT_EQ(shape_from_points(tools::sphere_points(12, 1), shapes[2]), Status::Ok);
  ASSERT_EQ(shape_from_points(tools::sphere_points(60, 2), shapes[3]), Status::Ok);
  ASSERT_EQ(shape_from_points(tools::sphere_points(300, 3), shapes[4]), Status::Ok);
  std::mt19937_64 rng(5);
  ASSERT_EQ(shape_from_points(test::ties::lattice_solid_points(rng, 2, 1), shapes[5]), Status::Ok);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto pose = [&](bool lattice) {
    Isometry3d p = Isometry3d::Identity();
    p.linear() = tools::axis_angle(Vector3d(u(rng), u(rng), u(rng)), 3 * u(rng));
    p.translation() = Vector3d(u(rng), u(rng), u(rng)) * 2;
    // Ties (tests/ties): quarter turns and lattice offsets keep the box's and the lattice
    // shape's coordinates exact (shared normals, parallel edges, exact contact).
    if (lattice) p.linear() = test::ties::quarter_turn(rng), p.translation() = test::ties::lattice_point(rng, 2, 1);
    return p;
  };
  std::vector<Task> tasks;
  for (int k = 0; k < 72; ++k) tasks.push_back({k % 6, (k / 6) % 6, pose(k % 4 == 3), pose(k % 4 == 3), k % 3 == 0});
  // One thread first: the expected answers.
  const auto run = [&](const Task& t, MinkowskiSum& m, Proximity& p) {
    const Status s = t.difference ? minkowski_difference(shapes[t.a], t.pa, shapes[t.b], t.pb, m)
                                  : minkowski_sum(shapes[t.a], t.pa, shapes[t.b], t.pb, m);
    return s == Status::Ok && proximity(shapes[t.a], t.pa, shapes[t.b], t.pb, p) == Status::Ok;
  };
  std::vector<MinkowskiSum> expected(tasks.size());
  std::vector<Proximity> expected_proximity(tasks.size());
  for (size_t k = 0; k < tasks.size(); ++k) ASSERT_TRUE(run(tasks[k], expected[k], expected_proximity[k]));
  std::atomic<int> mismatches{0}, done{0};
  std::vector<std::thread> threads;
  for (int id = 0; id < 4; ++id)
    threads.emplace_back([&, id] {
      MinkowskiSum m;
      Proximity p;
      for (int round = 0; round < 5; ++round)
        for (size_t n = 0; n < tasks.size(); ++n) {
          const size_t k = (n * 7 + size_t(id) * 13 + size_t(round)) % tasks.size();  // each thread its own order
          const bool ok = run(tasks[k], m, p);
          if (!ok || !identical(m, expected[k]) || p.distance != expected_proximity[k].distance ||
              p.penetration_depth != expected_proximity[k].penetration_depth)
            ++mismatches;
          ++done;
        }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(done.load(), 4 * 5 * int(tasks.size()));
  EXPECT_EQ(mismatches.load(), 0);
}

}  // namespace
