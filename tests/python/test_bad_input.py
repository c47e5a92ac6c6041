# Bad input from Python: a clear exception naming the argument, never a crash. Arrays that are
# only laid out differently (Fortran order, strided, integer dtype, lists) are accepted and give
# the same answer.
import os

import numpy as np
import pytest

import minksum as mk

CUBE = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
SHEET = (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float), np.array([[0, 1, 2]]))


@pytest.mark.parametrize("points, message", [
    (np.zeros((4, 2)), r"points: expected an \(n, 3\) array, got shape \(4, 2\)"),
    (np.zeros(12), r"points: expected an \(n, 3\) array, got shape \(12,\)"),
    (np.zeros((0, 3)), "fewer than 3 distinct points"),
    (np.array([["a", "b", "c"]]), "points: expected an array of numbers"),
    (np.array([[True, False, True]]), "points: expected an array of numbers"),
    ([[0, 0, 0], [1, 0, 0], [2, 0, 0]], "collinear"),
    ([[0, 0, np.nan], [1, 0, 0], [0, 1, 0], [0, 0, 1]], "NaN or Inf"),
    ([[0, 0, np.inf], [1, 0, 0], [0, 1, 0], [0, 0, 1]], "NaN or Inf"),
    ([[0, 0, 1e300], [1, 0, 0], [0, 1, 0], [0, 0, 1]], "exceeds 1e100"),
])
def test_bad_points(points, message):
    with pytest.raises(ValueError, match=message):
        mk.Shape.from_points(points)


def test_status_travels_with_the_error():
    with pytest.raises(mk.Error) as caught:
        mk.Shape.from_points([[0, 0, 0], [1, 0, 0], [2, 0, 0]])
    assert caught.value.status == mk.Status.COLLINEAR
    assert isinstance(caught.value, ValueError)


@pytest.mark.parametrize("bad_pose, message", [
    (np.eye(4) * 2, r"last row of a 4x4 pose must be \(0, 0, 0, 1\)"),
    (np.diag([2.0, 1, 1, 1]), "not a rigid motion"),
    (np.diag([-1.0, 1, 1, 1]), "not a rigid motion"),
    (np.full((4, 4), np.nan), r"last row"),
    (np.eye(3), r"expected a 4x4 array"),
    ((np.eye(3), [0, 0]), "expected 3 numbers"),
    ((np.eye(3),), "expected a 4x4 array or a pair"),
    ([[1, 0, 0, 0]] * 3, "expected a 4x4 array or a pair"),
    ((np.eye(3), [np.nan, 0, 0]), "not a rigid motion"),
])
def test_bad_poses(bad_pose, message):
    with pytest.raises(ValueError, match=message):
        mk.proximity(mk.Shape.box(), None, mk.Shape.box(), bad_pose)


def test_shear_pose_is_refused_with_its_status():
    p = np.eye(4)
    p[0, 1] = 0.1
    with pytest.raises(mk.Error) as caught:
        mk.minkowski_sum(mk.Shape.box(), p, mk.Shape.box(), None)
    assert caught.value.status == mk.Status.INVALID_POSE


@pytest.mark.parametrize("make", [
    lambda: mk.Shape.sphere(-1), lambda: mk.Shape.sphere(np.nan), lambda: mk.Shape.sphere(np.inf),
    lambda: mk.Shape.capsule(-1, 1), lambda: mk.Shape.box().with_radius(-0.5), lambda: mk.Shape.sphere(1e300),
    lambda: mk.Shape.box((1, 0, 1)), lambda: mk.Shape.box((1, 1, 1), rotation=np.ones((3, 3))),
    lambda: mk.Shape.triangle(np.zeros((3, 3))), lambda: mk.Shape.triangle(np.eye(4)[:, :3]),
    lambda: mk.Shape.from_mesh(CUBE, [[0, 1, 2]]), lambda: mk.Shape.from_mesh(CUBE, [[0, 1, 99]]),
])
def test_bad_shapes(make):
    with pytest.raises(ValueError):
        make()


@pytest.mark.parametrize("triangles, message", [
    (np.array([[0, 1, 3]]), r"index 3, outside \[0, 3\)"),
    (np.array([[0, 1, -1]]), r"index -1"),
    (np.array([[0, 1, 2**40]]), r"outside \[0, 3\)"),
    (np.array([[0, 1, 2.0]]), "expected an integer array"),
    (np.array([0, 1, 2]), r"expected an \(m, 3\) array"),
    (np.zeros((0, 3), int), r"Mesh: no triangles \(Mesh.from_points builds a point cloud\)"),
])
def test_bad_meshes(triangles, message):
    with pytest.raises(ValueError, match=message):
        mk.Mesh(SHEET[0], triangles)


def test_bad_numbers():
    box = mk.Shape.box()
    with pytest.raises(mk.Error, match="outside its documented range"):
        mk.contact_patch(box, None, box, None, margin=-1)
    with pytest.raises(mk.Error, match="outside its documented range"):
        mk.time_of_impact(box, None, None, box, None, None, tolerance=np.nan)
    with pytest.raises(ValueError, match="want"):
        mk.proximity(box, None, box, None, want=mk.Want(64))
    with pytest.raises(TypeError):
        mk.proximity(box, None, box, None, want=7)


@pytest.mark.parametrize("call, message", [
    (lambda box: mk.proximity(box), "missing required argument 'pose_a'"),
    (lambda box: mk.proximity(box, None, box, None, cach=None), "unexpected keyword argument 'cach'"),
    (lambda box: mk.proximity(box, None, box, None, a=box), "multiple values for argument 'a'"),
    (lambda box: mk.proximity(box, None, box, None, None, None, None), "at most 6 arguments"),
    (lambda box: mk.proximity(CUBE, None, box, None), "a must be a minksum.Shape, not numpy.ndarray"),
    (lambda box: mk.proximity(box, None, box, None, cache="x"), "cache must be a minksum.ProximityCache, not str"),
])
def test_proximity_arguments(call, message):
    with pytest.raises(TypeError, match=message):
        call(mk.Shape.box())


def test_bad_files(tmp_path):
    with pytest.raises(ValueError, match="cannot open"):
        mk.read_mesh(str(tmp_path / "missing.off"))
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
    with pytest.raises(ValueError, match="bad.off:"):
        mk.read_mesh(str(bad))


def test_layouts_are_accepted_and_agree():
    rows = np.array([[0, 0, 0], [2, 0, 0], [0, 2, 0], [0, 0, 2], [1, 1, 1]], dtype=np.int64)
    pose = np.eye(4)
    pose[:3, 3] = [5, 0, 0]
    expected = mk.proximity(mk.Shape.from_points(rows.astype(float)), None, mk.Shape.box(), pose).distance
    strided = np.zeros((10, 6))
    strided[::2, ::2] = rows
    for points in [rows, np.asfortranarray(rows.astype(float)), strided[::2, ::2], rows.tolist(), rows.astype(np.float32)]:
        for p in [pose, np.asfortranarray(pose), pose.tolist(), (pose[:3, :3], pose[:3, 3])]:
            assert mk.proximity(mk.Shape.from_points(points), None, mk.Shape.box(), p).distance == expected


# What a new user met (issue "Trust, part 3"): each was a crash, a misleading message or an
# impossible piece of advice, and each test fails on the code before its fix.
def test_writing_a_sum_without_loops_is_refused(tmp_path):
    box = mk.Shape.box()
    planes = mk.minkowski_sum(box, None, box, None, parts=mk.SumParts.PLANES)
    target = str(tmp_path / "p.off")
    with pytest.raises(ValueError, match="no facet loops"):  # was a segmentation fault and an empty file
        mk.write_mesh(target, planes)
    assert not os.path.exists(target)


def test_a_rounded_sums_core_can_be_written(tmp_path):
    box = mk.Shape.box()
    rounded = mk.minkowski_sum(box, None, mk.Shape.sphere(1), None)
    target = str(tmp_path / "r.off")
    with pytest.raises(ValueError, match=r"core=True"):  # the advice was "set its radius to 0": no setter
        mk.write_mesh(target, rounded)
    mk.write_mesh(target, rounded, core=True)
    written = mk.read_points(target)
    np.testing.assert_array_equal(np.sort(written, axis=0), np.sort(rounded.vertices, axis=0))


def test_paths_may_be_path_objects(tmp_path):
    f = tmp_path / "t.xyz"  # a pathlib.Path: was TypeError
    f.write_text("0 0 0\n1 0 0\n0 1 0\n0 0 1\n")
    assert mk.read_points(f).shape == (4, 3)
    assert mk.read_mesh(f, cloud_ok=True)[0].shape == (4, 3)


def test_a_missing_shape_is_a_type_error():
    with pytest.raises(TypeError, match="a must be a minksum.Shape, not NoneType"):  # was RuntimeError('')
        mk.proximity(None, None, mk.Shape.box(), None)


def test_lengths_say_which_and_what_they_are():
    with pytest.raises(mk.Error, match=r"radius must be > 0 and finite, got 0\.0"):  # was "negative, NaN or infinite"
        mk.Shape.sphere(0)
    with pytest.raises(mk.Error, match=r"half_length must be >= 0 and finite, got -1\.0"):
        mk.Shape.capsule(-1, 1)


def test_a_leaf_size_is_no_invalid_mesh():
    with pytest.raises(mk.Error, match="leaf_size must be at least 1, got 0") as caught:  # was "invalid mesh"
        mk.Mesh(*SHEET, leaf_size=0)
    assert caught.value.status == mk.Status.INVALID_ARGUMENT


def test_a_foreign_workspace_says_so():
    sheet, other = mk.Mesh(*SHEET), mk.Mesh(CUBE, np.array([[0, 1, 2], [1, 3, 2]]))
    with pytest.raises(mk.Error, match="workspace was not made for these meshes") as caught:  # was "invalid mesh"
        mk.mesh_distance(other, None, other, None, workspace=mk.MeshWorkspace(sheet, sheet))
    assert caught.value.status == mk.Status.WORKSPACE_MISMATCH


def test_a_sums_pairs_map_back_to_the_rows_given(rng):
    points = rng.normal(size=(40, 3))
    a, b = mk.Shape.from_points(points), mk.Shape.box()
    s = mk.minkowski_sum(a, None, b, None)
    rows = a.input_index[s.vertex_pairs[:, 0]]
    np.testing.assert_array_equal(s.vertices, points[rows] + b.vertices[s.vertex_pairs[:, 1]])
    np.testing.assert_array_equal(mk.Shape.box().input_index, np.arange(8))
