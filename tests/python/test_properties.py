# Property-based tests of the Python boundary (Hypothesis): arrays of every dtype and layout,
# shapes, poses and radii, NaN, Inf and 1e300, empty and huge arrays, objects of the wrong type.
# The oracles are not minksum: SciPy's hull of the pairwise sums, closed forms, cKDTree.
#
# Profiles (MINKSUM_HYPOTHESIS_PROFILE): "ci" (the default: seconds, derandomized, no example
# database) and "campaign" (12,500 examples a test, MINKSUM_HYPOTHESIS_EXAMPLES to change it;
# pytest --hypothesis-seed=S repeats one). Campaigns are recorded in tests/fuzz/LEDGER.md.
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from scipy.spatial import ConvexHull, cKDTree

import minksum as mk
from conftest import closest_on_triangle, hull_distance_to_origin

settings.register_profile("ci", max_examples=40, deadline=None, derandomize=True, database=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("campaign", max_examples=int(os.environ.get("MINKSUM_HYPOTHESIS_EXAMPLES", 12500)),
                          deadline=None, database=None,
                          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
settings.load_profile(os.environ.get("MINKSUM_HYPOTHESIS_PROFILE", "ci"))

# Coordinates: small integers (ties: coplanar and collinear points, duplicates) or floats.
small = st.integers(-4, 4).map(float)
wide = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False)
coordinate = st.one_of(small, wide)


@st.composite
def point_sets(draw, min_size=4, max_size=24):
    n = draw(st.integers(min_size, max_size))
    return np.array(draw(st.lists(st.tuples(coordinate, coordinate, coordinate), min_size=n, max_size=n)), float)


def solid(points):
    """SciPy's hull, or None where the points span no volume (Qhull refuses them)."""
    try:
        return ConvexHull(points)
    except Exception:
        return None


def spans_beyond_exact_range(points):
    """A nonzero coordinate under 2^-300 of the largest: Shape.from_points may refuse the set as
    OUT_OF_RANGE (nearly coplanar faces its Gauss map cannot tell apart; shape.hpp)."""
    a = np.abs(np.asarray(points, float))
    return bool(((a > 0) & (a < 2.0**-300 * a.max(initial=0))).any())


def shape_of(points):
    """Shape.from_points, the example rejected only where the documented refusal applies."""
    try:
        return mk.Shape.from_points(points)
    except mk.Error as e:
        if e.status == mk.Status.OUT_OF_RANGE and spans_beyond_exact_range(points):
            assume(False)
        raise


@st.composite
def rotations(draw):
    q = np.array(draw(st.tuples(*[st.floats(-1, 1)] * 4)))
    assume(np.linalg.norm(q) > 0.1)
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


@st.composite
def poses(draw, reach=20.0):
    p = np.eye(4)
    p[:3, :3] = draw(rotations())
    p[:3, 3] = draw(st.tuples(*[st.floats(-reach, reach)] * 3))
    return p


def layouts(a):
    """The same numbers as every layout the boundary takes: C and Fortran order, a strided view,
    nested lists, and the narrower dtypes where they hold the values exactly."""
    out = [a, np.asfortranarray(a), np.repeat(a, 2, axis=0)[::2], a.tolist()]
    if np.all(a == np.round(a)) and np.abs(a).max(initial=0) < 2**31:
        out += [a.astype(np.int64), a.astype(np.int32)]
    if np.all(a.astype(np.float32) == a):
        out.append(a.astype(np.float32))
    return out


def pose_forms(p):
    """One pose in each form: 4x4 (C, Fortran, nested lists) and the pair (rotation, translation)."""
    return [p, np.asfortranarray(p), p.tolist(), (p[:3, :3], p[:3, 3]), (p[:3, :3].tolist(), list(p[:3, 3]))]


def placed(points, p):
    return points @ p[:3, :3].T + p[:3, 3]


def expect_extreme_points(vertices, planes, points, hull):
    """`vertices` (with facet planes (F, 4)) are the extreme points of `points`, SciPy's hull
    their oracle: the same set but for points Qhull merges (it is exact to its tolerance only),
    which lie on a facet plane of the other's hull."""
    scale = np.abs(points).max() + 1
    ours, theirs = set(map(tuple, vertices)), set(map(tuple, points[hull.vertices]))
    for v in ours - theirs:
        assert np.abs(hull.equations[:, :3] @ v + hull.equations[:, 3]).min() <= 1e-9 * scale, v
    for v in theirs - ours:
        assert np.abs(planes[:, :3] @ v - planes[:, 3]).min() <= 1e-9 * scale, v


@given(point_sets())
def test_every_layout_and_dtype_builds_the_same_shape(points):
    hull = solid(points)
    assume(hull is not None)
    shape = shape_of(points)
    expect_extreme_points(shape.vertices, shape.faces[0], points, hull)
    # input_index maps the vertices back to the rows given.
    np.testing.assert_array_equal(points[shape.input_index], shape.vertices)
    for form in layouts(points):
        again = mk.Shape.from_points(form)
        np.testing.assert_array_equal(again.vertices, shape.vertices)


@given(point_sets(), point_sets(), poses(), st.sampled_from(["sum", "difference"]))
def test_sums_are_the_hull_of_the_pairwise_sums(a_points, b_points, pose_b, op):
    assume(solid(a_points) is not None and solid(b_points) is not None)
    a, b = shape_of(a_points), shape_of(b_points)
    sign = 1 if op == "sum" else -1
    call = mk.minkowski_sum if op == "sum" else mk.minkowski_difference
    s = call(a, None, b, pose_b)
    pairs = (a_points[:, None, :] + sign * placed(b_points, pose_b)[None, :, :]).reshape(-1, 3)
    scale = np.abs(pairs).max() + 1
    hull = ConvexHull(pairs)
    # Every pairwise sum lies inside every plane; the vertices are the hull's extreme points, but
    # for those Qhull merges (it is exact only to its tolerance; the sum is exact), which lie on
    # a facet plane of the other's hull.
    inside = pairs @ s.planes[:, :3].T - s.planes[:, 3]
    assert inside.max() <= 1e-9 * scale
    expect_extreme_points(s.vertices, s.planes, pairs, hull)
    rows = s.vertex_pairs
    np.testing.assert_allclose(s.vertices, a.vertices[rows[:, 0]] + sign * placed(b.vertices[rows[:, 1]], pose_b),
                               atol=1e-12 * scale)


@given(point_sets(), point_sets(), poses(), st.sampled_from(range(5)))
def test_proximity_is_the_distance_of_the_difference_to_the_origin(a_points, b_points, pose_b, form):
    assume(solid(a_points) is not None and solid(b_points) is not None)
    a, b = shape_of(a_points), shape_of(b_points)
    p = mk.proximity(a, None, b, pose_forms(pose_b)[form])
    difference = (a_points[:, None, :] - placed(b_points, pose_b)[None, :, :]).reshape(-1, 3)
    expected = hull_distance_to_origin(difference)
    scale = np.abs(difference).max() + 1
    if expected > 1e-9 * scale:
        assert not p.intersecting and p.distance == pytest.approx(expected, abs=1e-9 * scale)
        assert np.linalg.norm(p.point_b - p.point_a) == pytest.approx(p.distance, abs=1e-9 * scale)
    elif expected == 0 and not p.intersecting:
        assert p.distance <= 1e-9 * scale  # (touching: either verdict)


@given(st.floats(0.01, 5), st.floats(0.01, 5), st.tuples(*[st.floats(-10, 10)] * 3), poses(), poses())
def test_spheres_meet_their_closed_form(ra, rb, centre, pose_a, pose_b):
    pose_b[:3, 3] = centre
    p = mk.proximity(mk.Shape.sphere(ra), pose_a, mk.Shape.sphere(rb), pose_b)
    gap = np.linalg.norm(pose_b[:3, 3] - pose_a[:3, 3]) - ra - rb
    if gap > 1e-9:
        assert not p.intersecting and p.distance == pytest.approx(gap, abs=1e-12 * (1 + gap))
    elif gap < -1e-9:
        assert p.intersecting and p.penetration_depth == pytest.approx(-gap, abs=1e-12 * (1 + ra + rb))


@given(st.tuples(*[st.floats(0.1, 3)] * 3), st.tuples(*[st.floats(-8, 8)] * 3), st.floats(0, 2))
def test_a_rounded_box_against_a_point_is_the_closed_form(half, point, radius):
    box = mk.Shape.box(half)
    rounded = box.with_radius(radius) if radius > 0 else box
    dot = mk.Shape.sphere(1e-9)
    p = mk.proximity(rounded, None, dot, (np.eye(3), point))
    outside = np.maximum(np.abs(point) - np.array(half), 0)
    gap = np.linalg.norm(outside) - radius - 1e-9
    if gap > 1e-9:
        assert p.distance == pytest.approx(gap, abs=1e-9)


@given(point_sets(1, 60), point_sets(1, 60), st.tuples(*[st.floats(-50, 50)] * 3))
def test_point_clouds_meet_kd_trees(a_points, b_points, shift):
    def under_min_extent(p):  # distinct points all within kMinExtent of the origin: OutOfRange
        lo, hi = p.min(axis=0), p.max(axis=0)
        extent = (hi - lo).max()
        return extent > 0 and max(extent, np.abs((lo + hi) / 2).max()) < 1e-100
    if under_min_extent(a_points) or under_min_extent(b_points):
        with pytest.raises(mk.Error, match="under 1e-100"):
            mk.Mesh.from_points(a_points if under_min_extent(a_points) else b_points)
        return
    a, b = mk.Mesh.from_points(a_points), mk.Mesh.from_points(b_points)
    d = mk.mesh_distance(a, None, b, (np.eye(3), shift))
    nearest, _ = cKDTree(a_points).query(b_points + np.array(shift))
    assert d.distance == pytest.approx(nearest.min(), abs=1e-9 * (1 + np.abs(b_points).max() + np.abs(shift).max()))


@given(point_sets(), st.tuples(*[st.floats(-30, 30)] * 3), st.floats(0.05, 3))
def test_a_triangle_mesh_against_a_ball_is_the_nearest_triangle(points, centre, radius):
    hull = solid(points)
    assume(hull is not None)
    mesh = mk.Mesh(points, hull.simplices.astype(np.int64))
    d = mk.mesh_distance(mesh, None, mk.Shape.sphere(radius), (np.eye(3), centre))
    c = np.array(centre)
    nearest = min(np.linalg.norm(closest_on_triangle(c, *points[t]) - c) for t in hull.simplices)
    expected = max(0.0, nearest - radius)
    if abs(nearest - radius) > 1e-9 * (1 + np.abs(points).max()):
        assert d.distance == pytest.approx(expected, abs=1e-9 * (1 + np.abs(points).max() + np.abs(c).max()))


@given(st.lists(poses(), min_size=0, max_size=40), st.sets(st.integers(0, 39), max_size=4),
       st.sampled_from(["nan", "inf", "scale", "1e300"]), st.sampled_from([1, 2]))
def test_batches_answer_every_item_as_the_single_calls(items, bad, how, threads):
    a, b = mk.Shape.box((1, 2, 0.5)), mk.Shape.from_points(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.5]]))
    stack = np.array(items).reshape(-1, 4, 4)
    bad = sorted(k for k in bad if k < len(stack))
    for k in bad:
        if how == "nan":
            stack[k, 1, 3] = np.nan
        elif how == "inf":
            stack[k, 0, 0] = np.inf
        elif how == "scale":
            stack[k, :3, :3] *= 1.5
        else:
            stack[k, 2, 3] = 1e300
    r = mk.proximity_batch(a, None, b, stack, threads=threads)
    assert r.distance.shape == (len(stack),) and r.status.shape == (len(stack),)
    assert list(np.flatnonzero(r.status)) == bad
    for k in range(len(stack)):
        if k in bad:
            assert mk.Status(r.status[k]) == mk.Status.INVALID_POSE and np.isnan(r.distance[k])
            with pytest.raises(mk.Error):
                mk.proximity(a, None, b, stack[k])
        else:
            one = mk.proximity(a, None, b, stack[k])
            assert r.intersecting[k] == one.intersecting
            assert r.distance[k] == pytest.approx(one.distance, abs=1e-9 * (1 + abs(one.distance)))


@given(hnp.arrays(np.float64, st.tuples(st.integers(0, 12), st.just(3)),
                  elements=st.one_of(st.just(np.nan), st.just(np.inf), st.just(-np.inf), st.just(1e300),
                                     st.just(-1e300), small)))
def test_bad_numbers_are_refused_never_crashing(points):
    finite = np.isfinite(points).all() and (np.abs(points) <= 1e100).all()
    try:
        shape = mk.Shape.from_points(points)
    except mk.Error as e:
        assert e.status in {mk.Status.NON_FINITE, mk.Status.OUT_OF_RANGE, mk.Status.TOO_FEW_POINTS,
                            mk.Status.COLLINEAR} and str(e)
        if not finite:
            assert e.status in {mk.Status.NON_FINITE, mk.Status.OUT_OF_RANGE}
        return
    assert finite and np.isfinite(shape.vertices).all()
    p = mk.proximity(shape, None, mk.Shape.box(), (np.eye(3), [30, 0, 0]))
    assert np.isfinite(p.distance)


@given(st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=16, max_size=16))
def test_any_pose_gets_an_answer_or_a_clear_refusal(entries):
    m = np.array(entries).reshape(4, 4)
    box = mk.Shape.box()
    try:
        p = mk.proximity(box, None, box, m)
    except mk.Error as e:
        assert e.status == mk.Status.INVALID_POSE and "pose_b" in str(e)
        return
    except ValueError as e:
        assert "last row" in str(e)
        return
    assert np.isfinite(p.distance) and np.isfinite(p.point_a).all()


wrong = st.one_of(st.none(), st.integers(), st.text(max_size=5), st.dictionaries(st.text(max_size=2), st.integers()),
                  st.just(object()), st.just(mk.ProximityCache()), st.just(mk.Shape.box()), st.lists(st.integers(), max_size=5))


@given(wrong, st.sampled_from(range(6)))
def test_objects_of_the_wrong_type_are_a_type_or_value_error(value, slot):
    box = mk.Shape.box()
    calls = [
        lambda v: mk.proximity(v, None, box, None),
        lambda v: mk.proximity(box, v, box, None),
        lambda v: mk.Shape.from_points(v),
        lambda v: mk.minkowski_sum(box, None, box, v),
        lambda v: mk.proximity_batch(box, None, box, v),
        lambda v: mk.read_points(v),
    ]
    try:
        calls[slot](value)
    except (TypeError, ValueError, OSError):
        pass  # (a clear refusal: minksum.Error is a ValueError)


@given(st.integers(100_000, 300_000))
@settings(max_examples=3)
def test_huge_arrays(n):
    rng = np.random.default_rng(n)
    points = rng.normal(size=(n, 3))
    shape = mk.Shape.from_points(points)
    expect_extreme_points(shape.vertices, shape.faces[0], points, ConvexHull(points))
