# Queries against oracles that are not minksum: Qhull's hull of the pairwise differences with a
# point-triangle distance written here, closed forms of boxes, spheres and capsules, and
# SciPy's cKDTree for point clouds.
import numpy as np
import pytest
from scipy.spatial import ConvexHull, cKDTree

import minksum as mk
from conftest import closest_on_triangle, hull_distance_to_origin, placed, pose, random_rotation


def differences(a, pa, b, pb):
    wa, wb = placed(a.vertices, pa), placed(b.vertices, pb)
    return (wa[:, None, :] - wb[None, :, :]).reshape(-1, 3)


def test_polytope_distance_and_depth_match_the_hull_of_differences(rng):
    for k in range(40):
        a = mk.Shape.from_points(rng.normal(size=(rng.integers(4, 20), 3)))
        b = mk.Shape.from_points(rng.normal(size=(rng.integers(4, 20), 3)))
        pa = pose(random_rotation(rng), rng.normal(size=3))
        pb = pose(random_rotation(rng), rng.normal(size=3) * (1 + k % 3))
        p = mk.proximity(a, pa, b, pb)
        m = differences(a, pa, b, pb)
        if p.intersecting:
            eq = ConvexHull(m).equations
            assert p.penetration_depth == pytest.approx(np.min(-eq[:, 3]), abs=1e-9)
            assert np.linalg.norm(p.penetration_direction) == pytest.approx(1)
        else:
            assert p.distance == pytest.approx(hull_distance_to_origin(m), abs=1e-9)
            assert np.linalg.norm(p.point_b - p.point_a) == pytest.approx(p.distance, abs=1e-9)


def test_integer_boxes_closed_form():
    # Boxes on a lattice: face on face, edge on edge, corner on corner; the distance by clamping.
    a = mk.Shape.box((1, 1, 1))
    for t in [(3, 0, 0), (3, 3, 0), (3, 3, 3), (2, 0.5, 0), (1, 1, 1)]:
        p = mk.proximity(a, None, mk.Shape.box((1, 1, 1)), (np.eye(3), t))
        gap = np.maximum(np.abs(t) - 2, 0)
        assert p.distance == np.linalg.norm(gap)
        assert p.intersecting == (np.linalg.norm(gap) == 0)


def test_spheres_capsules_and_rounded_boxes_closed_forms(rng):
    for _ in range(50):
        r1, r2, h = rng.uniform(0.1, 1, size=3)
        c = rng.normal(size=3) * 3
        p = mk.proximity(mk.Shape.sphere(r1), None, mk.Shape.sphere(r2), (np.eye(3), c))
        assert p.distance == pytest.approx(max(np.linalg.norm(c) - r1 - r2, 0), abs=1e-12)
        # Sphere against a capsule along z: the distance to the clamped axis point.
        q = mk.proximity(mk.Shape.capsule(h, r1), None, mk.Shape.sphere(r2), (np.eye(3), c))
        axis = np.array([0, 0, np.clip(c[2], -h, h)])
        assert q.distance == pytest.approx(max(np.linalg.norm(c - axis) - r1 - r2, 0), abs=1e-12)
        # A rounded box against a point-like sphere: clamp to the box, less both radii.
        b = mk.proximity(mk.Shape.box((1, 1, 1)).with_radius(r1), None, mk.Shape.sphere(r2), (np.eye(3), c))
        outside = np.linalg.norm(c - np.clip(c, -1, 1))
        if outside > r1 + r2:
            assert b.distance == pytest.approx(outside - r1 - r2, abs=1e-12)
        if not b.intersecting:
            assert np.linalg.norm(b.point_b - c) == pytest.approx(r2, abs=1e-12)


def test_cache_gives_the_cold_answer_along_a_path(rng):
    a, b = mk.Shape.from_points(rng.normal(size=(30, 3))), mk.Shape.box((0.5, 0.5, 0.5))
    cache = mk.ProximityCache()
    for t in np.linspace(0, 1, 50):
        pb = pose(np.eye(3), [3 - 3 * t, 0.2, 0.1])
        cold, warm = mk.proximity(a, None, b, pb), mk.proximity(a, None, b, pb, cache=cache)
        assert warm.intersecting == cold.intersecting
        assert warm.distance == pytest.approx(cold.distance, abs=1e-12)
        assert warm.penetration_depth == pytest.approx(cold.penetration_depth, abs=1e-12)
    assert cache.warm + cache.cold == 50 and cache.warm > 0


def test_want_levels_leave_the_rest_nan():
    # Not computed is NaN: 0.0 was a real distance (a separated pair's, at Want.VERDICT).
    a, b = mk.Shape.box(), (mk.Shape.box(), (np.eye(3), [3, 0, 0]))
    verdict = mk.proximity(a, None, *b, want=mk.Want.VERDICT)
    assert not verdict.intersecting and np.isnan(verdict.distance) and np.isnan(verdict.penetration_depth)
    assert np.isnan(verdict.point_a).all() and np.isnan(verdict.max_distance)
    distance = mk.proximity(a, None, *b, want=mk.Want.DISTANCE)
    assert distance.distance == 1 and np.isnan(distance.point_b).all()
    full = mk.proximity(a, None, *b, want=mk.Want.WITNESSES | mk.Want.MAX_DISTANCE)
    assert full.distance == 1 and full.max_distance == pytest.approx(np.sqrt(25 + 4 + 4))  # (-1, -1, -1) to (4, 1, 1)


def test_contact_patch_of_resting_boxes_is_their_overlap():
    patch = mk.contact_patch(mk.Shape.box(), None, mk.Shape.box(), (np.eye(3), [0.5, 0.5, 2]))
    assert len(patch.points) == 4 and patch.depth == 0
    np.testing.assert_array_equal(patch.normal, [0, 0, 1])
    np.testing.assert_array_equal(np.sort(patch.points[:, 0]), [-0.5, -0.5, 1, 1])
    np.testing.assert_array_equal(np.sort(patch.points[:, 1]), [-0.5, -0.5, 1, 1])
    assert np.all(patch.points[:, 2] == 1)
    far = mk.contact_patch(mk.Shape.box(), None, mk.Shape.box(), (np.eye(3), [0, 0, 5]), margin=1)
    assert far.points.shape == (0, 3)


def test_time_of_impact_of_a_translation_is_exact():
    # A unit sphere falling from z = 5 to z = -5 onto the box [-1, 1]^3: it touches at z = 2.
    toi = mk.time_of_impact(mk.Shape.box(), None, None, mk.Shape.sphere(1), (np.eye(3), [0, 0, 5]), (np.eye(3), [0, 0, -5]))
    assert toi.hit and toi.time == pytest.approx(0.3, abs=1e-9)
    miss = mk.time_of_impact(mk.Shape.box(), None, None, mk.Shape.sphere(1), (np.eye(3), [3, 0, 5]), (np.eye(3), [3, 0, -5]))
    assert not miss.hit and miss.time == 1


def test_point_clouds_against_ckdtree(rng):
    a, b = rng.normal(size=(500, 3)), rng.normal(size=(400, 3)) + [3, 0, 0]
    ma, mb = mk.Mesh.from_points(a), mk.Mesh.from_points(b)
    ws = mk.MeshWorkspace(ma, mb)
    for _ in range(5):
        pb = pose(random_rotation(rng), rng.normal(size=3))
        d = mk.mesh_distance(ma, None, mb, pb, workspace=ws)
        expected = cKDTree(a).query(placed(b, pb))[0].min()
        assert d.distance == pytest.approx(expected, abs=1e-12)


def test_mesh_against_sphere_brute_force(rng):
    grid = np.array([[x, y, 0.3 * np.sin(x + y)] for x in range(6) for y in range(6)], float)
    tris = np.array([[i * 6 + j, i * 6 + j + 6, i * 6 + j + 1] for i in range(5) for j in range(5)]
                    + [[i * 6 + j + 1, i * 6 + j + 6, i * 6 + j + 7] for i in range(5) for j in range(5)])
    mesh = mk.Mesh(grid, tris)
    sphere = mk.Shape.sphere(0.25)
    for _ in range(20):
        c = rng.uniform([0, 0, 0.5], [5, 5, 2])
        d = mk.mesh_distance(mesh, None, sphere, (np.eye(3), c))
        expected = min(np.linalg.norm(c - closest_on_triangle(c, *grid[t])) for t in tris) - 0.25
        assert d.distance == pytest.approx(max(expected, 0), abs=1e-12)


def test_sphere_tool_pressed_into_a_flat_sheet():
    sheet = mk.Mesh(np.array([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], float), np.array([[0, 1, 2], [0, 2, 3]]))
    c = mk.mesh_contact(sheet, None, mk.Shape.sphere(0.5), (np.eye(3), [0.3, -0.2, 0.2]))
    assert c.intersecting and c.penetration_depth == pytest.approx(0.3, abs=1e-12)
    np.testing.assert_allclose(c.penetration_direction, [0, 0, 1], atol=1e-12)
