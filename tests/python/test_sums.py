# Sums and differences against SciPy's ConvexHull (Qhull) of the pairwise sums: the same facet
# planes (coplanar Qhull triangles merged) and the same vertices.
import numpy as np
import pytest
from scipy.spatial import ConvexHull

import minksum as mk
from conftest import placed, pose, random_rotation


def hull_planes(points):
    """Qhull's facet planes, coplanar triangles merged: unit normal and offset, rows sorted."""
    eq = ConvexHull(points).equations
    planes = np.column_stack([eq[:, :3], -eq[:, 3]])
    scale = np.abs(points).max()
    keys = np.round(planes / [1, 1, 1, scale], 7)
    return planes[np.unique(keys, axis=0, return_index=True)[1]]


def assert_same_planes(ours, theirs, scale):
    assert len(ours) == len(theirs)
    for n in theirs:
        d = np.abs(ours[:, :3] - n[:3]).max(axis=1) + np.abs(ours[:, 3] - n[3]) / scale
        assert d.min() < 1e-8, f"Qhull's plane {n} is not a facet of the sum"


def check_against_qhull(a_points, b_points, pa, pb, difference=False):
    a, b = mk.Shape.from_points(a_points), mk.Shape.from_points(b_points)
    s = (mk.minkowski_difference if difference else mk.minkowski_sum)(a, pa, b, pb)
    wa = placed(a.vertices, pa)
    wb = placed(b.vertices, pb) * (-1 if difference else 1)
    pairwise = (wa[:, None, :] + wb[None, :, :]).reshape(-1, 3)
    scale = np.abs(pairwise).max()
    assert_same_planes(s.planes, hull_planes(pairwise), scale)
    hull = ConvexHull(pairwise)
    assert s.V == len(hull.vertices)
    assert s.euler_ok and s.V - s.E + s.F == 2
    # Index tracking: each vertex is a_i (+/-) b_j of its pair.
    np.testing.assert_allclose(s.vertices, wa[s.vertex_pairs[:, 0]] + wb[s.vertex_pairs[:, 1]], atol=1e-12 * scale)
    # Each facet's loop lies on its plane.
    for f in range(s.F):
        loop = s.loop_vertex[s.loop_start[f]:s.loop_start[f + 1]]
        assert len(loop) >= 3
        np.testing.assert_allclose(s.vertices[loop] @ s.planes[f, :3], s.planes[f, 3], atol=1e-9 * scale)


@pytest.mark.parametrize("difference", [False, True])
def test_random_polytopes_under_random_poses(rng, difference):
    for _ in range(20):
        a, b = rng.normal(size=(rng.integers(4, 30), 3)), rng.normal(size=(rng.integers(4, 30), 3))
        pa = pose(random_rotation(rng), rng.normal(size=3))
        pb = pose(random_rotation(rng), rng.normal(size=3))
        check_against_qhull(a, b, pa, pb, difference)


def test_integer_coordinates_tie_everywhere(rng):
    # Parallel edges, shared face normals and faces on faces: the merged facets must match.
    for _ in range(20):
        a = rng.integers(-3, 4, size=(rng.integers(5, 12), 3)).astype(float)
        b = rng.integers(-3, 4, size=(rng.integers(5, 12), 3)).astype(float)
        if np.linalg.matrix_rank(a - a[0]) < 3 or np.linalg.matrix_rank(b - b[0]) < 3:
            continue
        quarter = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])
        check_against_qhull(a, b, None, pose(quarter, [1, 2, 3]))


def test_boxes_and_their_closed_form():
    s = mk.minkowski_sum(mk.Shape.box((1, 2, 3)), None, mk.Shape.box((0.5, 0.5, 0.5), center=(1, 0, 0)), None)
    assert (s.V, s.E, s.F) == (8, 12, 6)
    lo, hi = s.vertices.min(axis=0), s.vertices.max(axis=0)
    np.testing.assert_array_equal(lo, [-0.5, -2.5, -3.5])
    np.testing.assert_array_equal(hi, [2.5, 2.5, 3.5])


def test_rounded_operands_add_their_radii():
    box = mk.Shape.box((1, 1, 1))
    s = mk.minkowski_sum(box.with_radius(0.25), None, mk.Shape.sphere(0.5), (np.eye(3), [3, 0, 0]))
    assert s.radius == 0.75
    # A sphere's core is its centre: the sum's core is the box moved to it.
    np.testing.assert_array_equal(s.vertices.min(axis=0), [2, -1, -1])
    assert s.contains([4.7, 0, 0]) and not s.contains([4.8, 0, 0])


def test_parts_planes_gives_the_same_planes(rng):
    a, b = mk.Shape.from_points(rng.normal(size=(20, 3))), mk.Shape.from_points(rng.normal(size=(20, 3)))
    whole = mk.minkowski_sum(a, None, b, None)
    planes = mk.minkowski_sum(a, None, b, None, parts=mk.SumParts.PLANES)
    assert planes.parts == mk.SumParts.PLANES and len(planes.vertices) == 0
    order = lambda p: p[np.lexsort(np.round(p, 9).T)]
    np.testing.assert_allclose(order(planes.planes), order(whole.planes), atol=1e-12)


def test_written_sum_reads_back(tmp_path):
    s = mk.minkowski_sum(mk.Shape.box(), None, mk.Shape.box((1, 2, 3)), None)
    path = str(tmp_path / "sum.off")
    mk.write_mesh(path, s)
    vertices, triangles = mk.read_mesh(path)
    np.testing.assert_array_equal(np.sort(vertices, axis=0), np.sort(s.vertices, axis=0))
    assert triangles.shape == (12, 3)


def test_out_refills_a_sum_in_place(rng):
    a, b = mk.Shape.from_points(rng.normal(size=(20, 3))), mk.Shape.from_points(rng.normal(size=(15, 3)))
    first = mk.minkowski_sum(a, None, b, None)
    planes = first.planes  # a copy: refilling the sum leaves it as it was
    again = mk.minkowski_difference(a, None, b, None, out=first)
    assert again is first
    np.testing.assert_array_equal(first.planes, mk.minkowski_difference(a, None, b, None).planes)
    assert not np.array_equal(planes, first.planes)
    with pytest.raises(ValueError, match="out: expected a minksum.Sum"):
        mk.minkowski_sum(a, None, b, None, out=mk.ProximityCache())


def test_rounded_cores_of_lower_dimension_sum_to_solids():
    # Two balls are a ball: was "not a solid". Its core is a point (V 1, F 0), and contains
    # answers for the ball of the radii added; a ball and a triangle are a rounded triangle.
    s = mk.minkowski_sum(mk.Shape.sphere(1), None, mk.Shape.sphere(2), (np.eye(3), [5, 0, 0]))
    assert (s.V, s.E, s.F, s.radius) == (1, 0, 0, 3)
    assert s.contains([5, 2.99, 0]) and not s.contains([5, 0, 3.01])
    tri = mk.Shape.triangle([[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    t = mk.minkowski_sum(tri, None, mk.Shape.sphere(0.5), None)
    assert (t.V, t.E, t.F) == (3, 3, 2)
    assert t.contains([0.2, 0.2, 0.49]) and not t.contains([0.2, 0.2, 0.51]) and not t.contains([2, 0, 0])
