// Prepared shapes are shared read-only across threads: 4 threads run sums, differences and
// proximity queries on the same shapes at once, and every answer equals, bit for bit, the one
// computed on one thread. The batches (minksum/parallel.hpp) give, bit for bit, the single
// calls' answers on 1 and 2 threads. ci/test also runs this executable under ThreadSanitizer.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>
#include <minksum/parallel.hpp>

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

// A trajectory of n poses that passes near, through and away from the origin's shape, with ties:
// every fourth pose a quarter turn at a lattice point.
std::vector<Isometry3d> batch_poses(long n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::vector<Isometry3d> poses(size_t(n), Isometry3d::Identity());
  for (long k = 0; k < n; ++k) {
    const double t = double(k) / double(n);
    Isometry3d& p = poses[size_t(k)];
    p.linear() = tools::axis_angle(Vector3d(1, 2, 3), 9 * t);
    p.translation() = Vector3d(2.5 * std::cos(40 * t), 2.5 * std::sin(30 * t), 0.4 * std::sin(7 * t));
    if (k % 4 == 3) p.linear() = test::ties::quarter_turn(rng), p.translation() = test::ties::lattice_point(rng, 2, 1);
  }
  return poses;
}

// The batch's answers against the single calls made in order, the cache cleared every block.
TEST(Batches, ProximityAndTimeOfImpactAreTheSingleCallsOnOneAndTwoThreads) {
  ConvexShape a, b;
  ASSERT_EQ(shape_from_points(tools::sphere_points(40, 7), a), Status::Ok);
  ASSERT_EQ(shape_from_box(Box{}, b), Status::Ok);
  const long n = 3 * kBatchBlock + 17;  // a partial last block
  const std::vector<Isometry3d> poses = batch_poses(n, 3), ends = batch_poses(n, 4);
  const Isometry3d here = Isometry3d::Identity();
  std::vector<Proximity> single(static_cast<size_t>(n));
  std::vector<TimeOfImpact> single_toi(static_cast<size_t>(n));
  ProximityCache cache;
  for (long k = 0; k < n; ++k) {
    if (k % kBatchBlock == 0) cache = ProximityCache{};
    ASSERT_EQ(proximity(a, here, b, poses[size_t(k)], cache, single[size_t(k)], Want::All), Status::Ok);
    ASSERT_EQ(time_of_impact(a, here, here, b, poses[size_t(k)], ends[size_t(k)], single_toi[size_t(k)]), Status::Ok);
  }
  EXPECT_GT(cache.warm, 0);
  for (int threads : {1, 2}) {
    std::vector<Proximity> out(static_cast<size_t>(n));
    std::vector<TimeOfImpact> toi(static_cast<size_t>(n));
    const BatchStatus s = proximity_batch(a, {&here, 1}, b, {poses.data(), n}, n, out.data(), Want::All, {threads});
    ASSERT_EQ(s.status, Status::Ok);
    ASSERT_EQ(time_of_impact_batch(a, {&here, 1}, {&here, 1}, b, {poses.data(), n}, {ends.data(), n}, n, toi.data(), 0, {threads})
                  .status,
              Status::Ok);
    for (long k = 0; k < n; ++k) {
      const Proximity &x = out[size_t(k)], &y = single[size_t(k)];
      ASSERT_TRUE(x.distance == y.distance && x.point_a == y.point_a && x.point_b == y.point_b &&
                  x.penetration_depth == y.penetration_depth && x.penetration_direction == y.penetration_direction &&
                  x.max_distance == y.max_distance && x.intersecting == y.intersecting)
          << "item " << k << " on " << threads << " threads";
      ASSERT_TRUE(toi[size_t(k)].time == single_toi[size_t(k)].time && toi[size_t(k)].point_a == single_toi[size_t(k)].point_a)
          << "item " << k << " on " << threads << " threads";
    }
  }
}

TEST(Batches, MeshDistancesAndSumsAreTheSingleCallsOnOneAndTwoThreads) {
  // A lumpy sheet of 2 x 16 x 16 triangles, and a sphere-like hull.
  std::vector<Vector3d> v;
  std::vector<std::array<int, 3>> t;
  for (int i = 0; i <= 16; ++i)
    for (int j = 0; j <= 16; ++j) v.emplace_back(0.25 * i - 2, 0.25 * j - 2, 0.2 * std::sin(i + 2.0 * j));
  for (int i = 0; i < 16; ++i)
    for (int j = 0; j < 16; ++j) {
      const int c = i * 17 + j;
      t.push_back({c, c + 17, c + 1}), t.push_back({c + 1, c + 17, c + 18});
    }
  Octree mesh;
  ASSERT_EQ(build_octree(v, t, mesh), Status::Ok);
  ConvexShape hull, box;
  ASSERT_EQ(shape_from_points(tools::sphere_points(30, 9), hull), Status::Ok);
  ASSERT_EQ(shape_from_box(Box{}, box), Status::Ok);
  const long n = 2 * kBatchBlock + 5;
  std::vector<Isometry3d> poses = batch_poses(n, 5);
  for (Isometry3d& p : poses) p.translation().z() += 1.2;
  const Isometry3d here = Isometry3d::Identity();
  std::vector<MeshDistance> single(static_cast<size_t>(n)), single_shape(static_cast<size_t>(n));
  MeshWorkspace ws;
  make_workspace(mesh, mesh, ws);
  ProximityCache cache, shape_cache;
  for (long k = 0; k < n; ++k) {
    if (k % kBatchBlock == 0) cache = shape_cache = ProximityCache{};
    ASSERT_EQ(mesh_distance(mesh, here, mesh, poses[size_t(k)], ws, cache, single[size_t(k)]), Status::Ok);
    ASSERT_EQ(mesh_distance(mesh, here, hull, poses[size_t(k)], shape_cache, single_shape[size_t(k)]), Status::Ok);
  }
  const std::vector<ConvexShape> as(static_cast<size_t>(n), hull), bs(static_cast<size_t>(n), box);
  for (int threads : {1, 2}) {
    std::vector<MeshDistance> out(static_cast<size_t>(n)), out_shape(static_cast<size_t>(n));
    ASSERT_EQ(mesh_distance_batch(mesh, {&here, 1}, mesh, {poses.data(), n}, n, out.data(), {threads}).status, Status::Ok);
    ASSERT_EQ(mesh_distance_batch(mesh, {&here, 1}, hull, {poses.data(), n}, n, out_shape.data(), {threads}).status, Status::Ok);
    std::vector<MeshDistance> out_ws(static_cast<size_t>(n));  // the caller's workspace, on the caller
    ASSERT_EQ(mesh_distance_batch(mesh, {&here, 1}, mesh, {poses.data(), n}, n, out_ws.data(), ws).status, Status::Ok);
    std::vector<MinkowskiSum> sums(static_cast<size_t>(n));
    ASSERT_EQ(minkowski_sum_batch(as.data(), {&here, 1}, bs.data(), {poses.data(), n}, n, sums.data(), true, SumParts::Whole, {threads})
                  .status,
              Status::Ok);
    for (long k = 0; k < n; ++k) {
      const size_t i = size_t(k);
      ASSERT_TRUE(out[i].distance == single[i].distance && out[i].point_a == single[i].point_a &&
                  out_ws[i].distance == single[i].distance && out_ws[i].point_b == single[i].point_b &&
                  out_shape[i].distance == single_shape[i].distance && out_shape[i].point_b == single_shape[i].point_b)
          << "item " << k << " on " << threads << " threads";
      MinkowskiSum m;
      ASSERT_EQ(minkowski_difference(hull, here, box, poses[i], m), Status::Ok);
      ASSERT_TRUE(identical(m, sums[i])) << "sum " << k << " on " << threads << " threads";
    }
  }
}

// Batches from several threads at once share one pool: a batch that finds it busy runs on its
// caller alone, with the same answers.
TEST(Batches, ConcurrentBatchesShareThePoolAndKeepTheirAnswers) {
  ConvexShape a, b;
  ASSERT_EQ(shape_from_points(tools::sphere_points(30, 11), a), Status::Ok);
  ASSERT_EQ(shape_from_box(Box{}, b), Status::Ok);
  const long n = 6 * kBatchBlock;
  const std::vector<Isometry3d> poses = batch_poses(n, 8);
  const Isometry3d here = Isometry3d::Identity();
  std::vector<Proximity> expected(static_cast<size_t>(n));
  ASSERT_EQ(proximity_batch(a, {&here, 1}, b, {poses.data(), n}, n, expected.data(), Want::Witnesses, {1}).status, Status::Ok);
  std::atomic<int> mismatches{0};
  std::vector<std::thread> callers;
  for (int c = 0; c < 3; ++c)
    callers.emplace_back([&] {
      std::vector<Proximity> out(static_cast<size_t>(n));
      for (int round = 0; round < 4; ++round) {
        if (proximity_batch(a, {&here, 1}, b, {poses.data(), n}, n, out.data(), Want::Witnesses, {2}).status != Status::Ok) ++mismatches;
        for (long k = 0; k < n; ++k)
          if (out[size_t(k)].distance != expected[size_t(k)].distance || out[size_t(k)].point_b != expected[size_t(k)].point_b)
            ++mismatches;
      }
    });
  for (std::thread& t : callers) t.join();
  EXPECT_EQ(mismatches.load(), 0);
}

TEST(Batches, BadArgumentsAndTheFirstFailedItem) {
  ConvexShape a, b;
  ASSERT_EQ(shape_from_box(Box{}, a), Status::Ok);
  ASSERT_EQ(shape_from_box(Box{}, b), Status::Ok);
  const long n = 2 * kBatchBlock;
  std::vector<Isometry3d> poses = batch_poses(n, 6);
  poses[size_t(n - 3)].linear() *= 2;  // not rigid: in the second block
  poses[size_t(kBatchBlock + 2)].translation().x() = std::nan("");
  const Isometry3d here = Isometry3d::Identity();
  std::vector<Proximity> out(static_cast<size_t>(n));
  for (int threads : {1, 2}) {
    const BatchStatus s = proximity_batch(a, {&here, 1}, b, {poses.data(), n}, n, out.data(), Want::Witnesses, {threads});
    EXPECT_EQ(s.status, Status::InvalidPose);
    EXPECT_EQ(s.index, kBatchBlock + 2);
    EXPECT_EQ(out[size_t(kBatchBlock + 2)].distance, 0);  // a failed item keeps the defaults
    EXPECT_FALSE(out[size_t(kBatchBlock + 2)].intersecting);
    Proximity one;
    ASSERT_EQ(proximity(a, here, b, poses[size_t(n - 1)], one), Status::Ok);
    EXPECT_EQ(out[size_t(n - 1)].distance, one.distance);  // the rest are computed
  }
  EXPECT_EQ(proximity_batch(a, {&here, 1}, b, {poses.data(), n - 1}, n, out.data()).status, Status::InvalidArgument);
  EXPECT_EQ(proximity_batch(a, {&here, 1}, b, {nullptr, 1}, n, out.data()).status, Status::InvalidArgument);
  EXPECT_EQ(proximity_batch(a, {&here, 1}, b, {&here, 1}, -1, out.data()).status, Status::InvalidArgument);
  EXPECT_EQ(proximity_batch(a, {&here, 1}, b, {&here, 1}, 0, nullptr).status, Status::Ok);
  // Each item's own status, where the caller asks for them: the two bad poses, and Ok elsewhere,
  // for every batch kind (time of impact and sums too), on 1 and 2 threads.
  for (int threads : {1, 2}) {
    std::vector<Status> each(static_cast<size_t>(n), Status::HullFailed);
    const auto bad = [&](long k) { return k == kBatchBlock + 2 || k == n - 3; };
    const auto expect_each = [&](const char* what) {
      for (long k = 0; k < n; ++k)
        ASSERT_EQ(each[size_t(k)], bad(k) ? Status::InvalidPose : Status::Ok) << what << " item " << k << ", " << threads;
      std::fill(each.begin(), each.end(), Status::HullFailed);
    };
    proximity_batch(a, {&here, 1}, b, {poses.data(), n}, n, out.data(), Want::Witnesses, {threads, each.data()});
    expect_each("proximity");
    std::vector<TimeOfImpact> toi(static_cast<size_t>(n));
    time_of_impact_batch(a, {&here, 1}, {&here, 1}, b, {poses.data(), n}, {poses.data(), n}, n, toi.data(), 0,
                         {threads, each.data()});
    expect_each("time of impact");
    std::vector<ConvexShape> as(static_cast<size_t>(n), a), bs(static_cast<size_t>(n), b);
    std::vector<MinkowskiSum> sums(static_cast<size_t>(n));
    minkowski_sum_batch(as.data(), {&here, 1}, bs.data(), {poses.data(), n}, n, sums.data(), false, SumParts::Whole,
                        {threads, each.data()});
    expect_each("sums");
  }
}

}  // namespace

// run_batch, the batches' runner: every item in exactly one block, blocks of the asked size, the
// worker's index within the threads, and the first failure by index whatever thread found it.
TEST(Batches, RunBatchRunsEachBlockOnceAndReportsTheFirstFailure) {
  const long n = 1000, block = 7;
  for (int threads : {1, 2, 3}) {
    std::vector<std::atomic<int>> seen(static_cast<size_t>(n));
    std::atomic<bool> bad_block{false};
    const BatchStatus s = run_batch(
        n, block,
        [&](int worker, long begin, long end) {
          if (begin % block != 0 || end - begin > block || worker < 0 || worker >= threads) bad_block = true;
          for (long k = begin; k < end; ++k) ++seen[size_t(k)];
          for (long k : {500L, 820L})  // two failures, in different blocks
            if (k >= begin && k < end) return BatchStatus{Status::InvalidPose, k};
          return BatchStatus{};
        },
        {threads});
    EXPECT_FALSE(bad_block) << threads << " threads";
    for (long k = 0; k < n; ++k) ASSERT_EQ(seen[size_t(k)], 1) << "item " << k << " on " << threads << " threads";
    EXPECT_EQ(s.status, Status::InvalidPose);
    EXPECT_EQ(s.index, 500);
  }
  const BatchWork nothing = [](int, long, long) { return BatchStatus{}; };
  EXPECT_EQ(run_batch(0, 4, nothing).status, Status::Ok);
  EXPECT_EQ(run_batch(-1, 4, nothing).status, Status::InvalidArgument);
  EXPECT_EQ(run_batch(10, 0, nothing).status, Status::InvalidArgument);
  EXPECT_EQ(run_batch(10, 4, BatchWork{}).status, Status::InvalidArgument);
  EXPECT_EQ(batch_threads({3}), 3);
  EXPECT_GE(batch_threads({}), 1);
}
