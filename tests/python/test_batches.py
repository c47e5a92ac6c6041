# Batches from Python: bit for bit the single calls (made in order, the cache cleared every 256
# items), on 1 and 2 threads; one pose broadcast to every item; a bad item named by its index.
import numpy as np
import pytest

import minksum as mk
from conftest import pose, random_rotation

BLOCK = 256
QUARTER = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])  # a quarter turn about z


def trajectory(rng, n, lift=0.0):
    poses = np.tile(np.eye(4), (n, 1, 1))
    t = np.linspace(0, 1, n)
    poses[:, 0, 3], poses[:, 1, 3], poses[:, 2, 3] = 2.5 * np.cos(40 * t), 2.5 * np.sin(30 * t), lift + 0.4 * np.sin(7 * t)
    for k in range(3, n, 4):  # ties: quarter turns at lattice points
        poses[k] = pose(np.linalg.matrix_power(QUARTER, k % 4), rng.integers(-2, 3, size=3) / 2)
    return poses


def test_proximity_batch_is_the_single_calls(rng):
    a, b = mk.Shape.from_points(rng.normal(size=(30, 3))), mk.Shape.box((0.5, 0.5, 0.5))
    poses = trajectory(rng, 2 * BLOCK + 9)
    cache, single = None, []
    for k, p in enumerate(poses):
        cache = mk.ProximityCache() if k % BLOCK == 0 else cache
        single.append(mk.proximity(a, None, b, p, want=mk.Want.ALL, cache=cache))
    for threads in (1, 2):
        batch = mk.proximity_batch(a, None, b, poses, want=mk.Want.ALL, threads=threads)
        for field in ("intersecting", "distance", "point_a", "point_b", "penetration_depth", "penetration_direction", "max_distance"):
            np.testing.assert_array_equal(getattr(batch, field), np.array([getattr(s, field) for s in single]), err_msg=field)


def test_time_of_impact_and_mesh_batches_are_the_single_calls(rng):
    box, ball = mk.Shape.box(), mk.Shape.sphere(0.3)
    starts, ends = trajectory(rng, BLOCK + 3, lift=3), trajectory(rng, BLOCK + 3, lift=-3)
    toi = [mk.time_of_impact(box, None, None, ball, s, e) for s, e in zip(starts, ends)]
    grid = np.array([[x, y, 0.2 * np.sin(x + 2 * y)] for x in range(8) for y in range(8)], float) - [3.5, 3.5, 0]
    tris = np.array([[i * 8 + j, i * 8 + j + 8, i * 8 + j + 1] for i in range(7) for j in range(7)])
    mesh = mk.Mesh(grid, tris)
    lifted = trajectory(rng, BLOCK + 3, lift=1.5)
    cache, near = None, []
    for k, p in enumerate(lifted):
        cache = mk.ProximityCache() if k % BLOCK == 0 else cache
        near.append(mk.mesh_distance(mesh, None, ball, p, cache=cache).distance)
    for threads in (1, 2):
        batch = mk.time_of_impact_batch(box, None, None, ball, starts, ends, threads=threads)
        np.testing.assert_array_equal(batch.time, [t.time for t in toi])
        np.testing.assert_array_equal(batch.hit, [t.hit for t in toi])
        distances = mk.mesh_distance_batch(mesh, None, ball, lifted, threads=threads)
        np.testing.assert_array_equal(distances.distance, near)


def test_sum_batch_is_the_single_sums(rng):
    shapes = [mk.Shape.from_points(rng.normal(size=(12, 3))) for _ in range(40)]
    others = [mk.Shape.from_points(rng.integers(-2, 3, size=(10, 3)).astype(float) + [0, 0, 0.5 * k % 3]) for k in range(40)]
    poses = np.stack([pose(random_rotation(rng), rng.normal(size=3)) for _ in range(40)])
    for threads in (1, 2):
        batch = mk.minkowski_difference_batch(shapes, poses, others, None, threads=threads)
        for s, a, b, p in zip(batch, shapes, others, poses):
            one = mk.minkowski_difference(a, p, b, None)
            np.testing.assert_array_equal(s.planes, one.planes)
            np.testing.assert_array_equal(s.vertices, one.vertices)
            np.testing.assert_array_equal(s.loop_vertex, one.loop_vertex)


def test_long_batches_keep_the_answers_and_every_items_status(rng):
    # Many blocks over two threads, each converting its own poses and storing its own rows: the
    # answers are the single calls'. Two bad poses: those items say INVALID_POSE and hold NaN,
    # and every other item keeps its answer (as the C++ batch does), on 1 and 2 threads.
    a, b = mk.Shape.from_points(rng.normal(size=(20, 3))), mk.Shape.sphere(0.4)
    poses = trajectory(rng, 9000)
    batch = mk.proximity_batch(a, None, b, poses, threads=2)
    cache = None
    for k, p in enumerate(poses):
        cache = mk.ProximityCache() if k % BLOCK == 0 else cache
        assert batch.distance[k] == mk.proximity(a, None, b, p, cache=cache).distance, k
    assert not batch.status.any()
    poses[8500, 0, 3] = np.inf
    poses[8900, 1, 3] = np.nan
    for threads in (1, 2):
        bad = mk.proximity_batch(a, None, b, poses, threads=threads)
        assert list(np.flatnonzero(bad.status)) == [8500, 8900]
        assert mk.Status(bad.status[8500]) == mk.Status.INVALID_POSE
        assert np.isnan(bad.distance[[8500, 8900]]).all() and np.isnan(bad.point_a[8500]).all()
        good = np.ones(9000, bool)
        good[[8500, 8900]] = False
        np.testing.assert_array_equal(bad.distance[:8500], batch.distance[:8500])  # (8500's block starts cold anyway)
        assert np.isfinite(bad.distance[good]).all()


def test_mesh_mesh_batch_is_the_single_calls(rng):
    grid = np.array([[x, y, 0.3 * np.sin(x + 2 * y)] for x in range(8) for y in range(8)], float) - [3.5, 3.5, 0]
    tris = np.array([[i * 8 + j, i * 8 + j + 8, i * 8 + j + 1] for i in range(7) for j in range(7)])
    mesh = mk.Mesh(grid, tris)
    poses = trajectory(rng, BLOCK + 9, lift=1.5)
    ws, cache, near = mk.MeshWorkspace(mesh, mesh), None, []
    for k, p in enumerate(poses):
        cache = mk.ProximityCache() if k % BLOCK == 0 else cache
        near.append(mk.mesh_distance(mesh, None, mesh, p, workspace=ws, cache=cache))
    for threads in (1, 2):
        batch = mk.mesh_distance_batch(mesh, None, mesh, poses, threads=threads)
        np.testing.assert_array_equal(batch.distance, [d.distance for d in near])
        np.testing.assert_array_equal(batch.point_a, [d.point_a for d in near])
        np.testing.assert_array_equal(batch.triangle_b, [d.triangle_b for d in near])


def test_out_is_refilled_in_place(rng):
    a, b = mk.Shape.box(), mk.Shape.sphere(0.5)
    first, second = trajectory(rng, 700), trajectory(rng, 700, lift=1)
    out = mk.proximity_batch(a, None, b, first)
    distance = out.distance
    again = mk.proximity_batch(a, None, b, second, out=out)
    assert again is out and out.distance is distance  # the same arrays, refilled
    np.testing.assert_array_equal(out.distance, mk.proximity_batch(a, None, b, second).distance)
    with pytest.raises(ValueError, match="out: its intersecting is not the array a batch of 699 items returns"):
        mk.proximity_batch(a, None, b, second[:699], out=out)
    out.point_a = np.asfortranarray(out.point_a)  # C order or nothing
    with pytest.raises(ValueError, match="out: its point_a"):
        mk.proximity_batch(a, None, b, second, out=out)


def test_a_forked_child_runs_batches_alone(rng):
    # The pool's threads stay in the parent: a child of fork() (multiprocessing's default on
    # Linux) must neither hang waiting for them nor answer differently.
    import os
    import signal
    a, b = mk.Shape.box(), mk.Shape.sphere(0.5)
    poses = trajectory(rng, 2000)
    expected = mk.proximity_batch(a, None, b, poses, threads=2).distance  # the pool is running
    pid = os.fork()
    if pid == 0:
        signal.alarm(60)  # a hang kills the child, and fails the test
        same = np.array_equal(mk.proximity_batch(a, None, b, poses, threads=2).distance, expected)
        os._exit(0 if same else 1)
    _, status = os.waitpid(pid, 0)
    assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0


def test_batch_refusals(rng):
    box = mk.Shape.box()
    poses = trajectory(rng, 600)
    poses[400, :3, :3] *= 2  # not rigid
    poses[300, 0, 3] = np.nan
    answered = mk.proximity_batch(box, None, box, poses)  # (each item's status; no exception)
    assert list(np.flatnonzero(answered.status)) == [300, 400]
    assert {mk.Status(s) for s in answered.status[[300, 400]]} == {mk.Status.INVALID_POSE}
    with pytest.raises(ValueError, match="one pose or the same N"):
        mk.proximity_batch(box, poses[:5], box, poses)
    bad_row = poses.copy()
    bad_row[7, 3, 3] = 2
    with pytest.raises(ValueError, match="pose 7: the last row"):
        mk.proximity_batch(box, None, box, bad_row)
    with pytest.raises(ValueError, match=r"\(N, 4, 4\)"):
        mk.proximity_batch(box, None, box, np.zeros((3, 3, 3)))
    with pytest.raises(ValueError, match="as many shapes"):
        mk.minkowski_sum_batch([box, box], None, [box], None)


def test_empty_batches_are_empty_results():
    box = mk.Shape.box()
    none = np.zeros((0, 4, 4))
    r = mk.proximity_batch(box, None, box, none)
    assert r.distance.shape == (0,) and r.point_a.shape == (0, 3) and r.status.shape == (0,)
    assert mk.time_of_impact_batch(box, None, None, box, none, none).time.shape == (0,)
    assert len(mk.minkowski_sum_batch([], None, [], None)) == 0


def test_fields_not_asked_for_and_failed_items_are_nan(rng):
    # A separated pair's distance at Want.VERDICT was 0.0, a real distance; the batch's
    # max_distance column was zeros unless asked for.
    box = mk.Shape.box()
    poses = trajectory(rng, 300, lift=3)
    verdict = mk.proximity_batch(box, None, box, poses, want=mk.Want.VERDICT)
    assert np.isnan(verdict.distance).all() and np.isnan(verdict.point_a).all() and np.isnan(verdict.max_distance).all()
    distance = mk.proximity_batch(box, None, box, poses, want=mk.Want.DISTANCE)
    assert np.isfinite(distance.distance).all() and np.isnan(distance.point_b).all()
    everything = mk.proximity_batch(box, None, box, poses, want=mk.Want.ALL)
    assert np.isfinite(everything.max_distance).all()
    np.testing.assert_array_equal(everything.intersecting, verdict.intersecting)
    motions = trajectory(rng, 40)
    motions[5, 2, 3] = np.inf
    toi = mk.time_of_impact_batch(box, None, None, box, motions, motions[::-1].copy())
    assert mk.Status(toi.status[5]) == mk.Status.INVALID_POSE and np.isnan(toi.time[5]) and not toi.hit[5]
    assert mk.Status(toi.status[34]) == mk.Status.INVALID_POSE  # (its end pose is item 5's start)
    sums = mk.minkowski_sum_batch([box] * 3, motions[3:6], [box] * 3, None)
    assert list(sums.status) == [0, 0, int(mk.Status.INVALID_POSE)] and sums[2].V == 0 and sums[0].V > 0


def test_float32_poses_are_projected_onto_rotations(rng):
    # 0 of 1,000 rotations rounded to float32 passed the 1e-9 check; each within float32
    # rounding of a rotation is now taken as the nearest rotation, singly and in batches.
    from scipy.spatial.transform import Rotation
    box, ball = mk.Shape.box(), mk.Shape.from_points(rng.normal(size=(12, 3)))
    poses = np.tile(np.eye(4), (1000, 1, 1))
    poses[:, :3, :3] = Rotation.random(1000, random_state=7).as_matrix()
    poses[:, :3, 3] = rng.normal(size=(1000, 3)) * 4
    single = poses.astype(np.float32)
    assert not any(abs(p[:3, :3].astype(np.float64).T @ p[:3, :3] - np.eye(3)).max() <= 1e-9 for p in single[:50])
    batch = mk.proximity_batch(box, None, ball, single)
    assert not batch.status.any()
    reference = mk.proximity_batch(box, None, ball, poses)  # (the float64 poses they were rounded from)
    np.testing.assert_allclose(batch.distance, reference.distance, atol=1e-5)
    for k in range(0, 1000, 97):
        p = mk.proximity(box, None, ball, single[k])
        assert p.distance == batch.distance[k]
        assert mk.proximity(box, None, ball, (single[k, :3, :3], single[k, :3, 3])).distance == p.distance
    # A float64 rotation off by 1e-6 is no rotation; the message says by how much, and the tolerance.
    with pytest.raises(mk.Error, match=r"pose_b: not a rigid motion: its rotation is 2\.0\d*e-06 from a rotation .*1e-09"):
        mk.proximity(box, None, ball, (np.eye(3) * (1 + 1e-6), [3, 0, 0]))
    # Nor is a float32 matrix scaled by 1e-3: projecting is for rounding, not for repair.
    with pytest.raises(mk.Error, match="pose_b"):
        mk.proximity(box, None, ball, (np.eye(3, dtype=np.float32) * np.float32(1.001), [3, 0, 0]))
