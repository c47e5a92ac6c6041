# Shared by the Python tests: random rigid poses and shapes, and the oracles that are not minksum
# (SciPy's Qhull, closed forms, brute force in NumPy).
import numpy as np
import pytest


@pytest.fixture
def rng():
    return np.random.default_rng(20261130)


def random_rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q @ np.diag(np.sign(np.diag(r)))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def pose(rotation, translation):
    p = np.eye(4)
    p[:3, :3] = rotation
    p[:3, 3] = translation
    return p


def placed(points, p):
    if p is None:
        return points
    return points @ p[:3, :3].T + p[:3, 3]


def closest_on_triangle(p, a, b, c):
    """The point of triangle abc nearest p (Ericson, Real-Time Collision Detection, 5.1.5)."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = ab @ ap, ac @ ap
    if d1 <= 0 and d2 <= 0:
        return a
    bp = p - b
    d3, d4 = ab @ bp, ac @ bp
    if d3 >= 0 and d4 <= d3:
        return b
    vc = d1 * d4 - d3 * d2
    if vc <= 0 and d1 >= 0 and d3 <= 0:
        return a + d1 / (d1 - d3) * ab
    cp = p - c
    d5, d6 = ab @ cp, ac @ cp
    if d6 >= 0 and d5 <= d6:
        return c
    vb = d5 * d2 - d1 * d6
    if vb <= 0 and d2 >= 0 and d6 <= 0:
        return a + d2 / (d2 - d6) * ac
    va = d3 * d6 - d5 * d4
    if va <= 0 and d4 - d3 >= 0 and d5 - d6 >= 0:
        return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b)
    denom = 1 / (va + vb + vc)
    return a + ab * vb * denom + ac * vc * denom


def hull_distance_to_origin(points):
    """Distance from the origin to the convex hull of `points` (0 inside), by Qhull's facets:
    outside, the nearest point lies on a facet's triangle that the origin sees."""
    from scipy.spatial import ConvexHull
    hull = ConvexHull(points)
    if np.all(hull.equations[:, 3] <= 0):
        return 0.0
    best = np.inf
    for simplex in hull.simplices:
        a, b, c = points[simplex]
        best = min(best, np.linalg.norm(closest_on_triangle(np.zeros(3), a, b, c)))
    return best
