# Type stubs of the minksum module (kernels/python/*.cpp). tests/python/test_stubs.py checks that
# they name exactly what the module defines.
import os
from enum import IntEnum
from typing import Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

ArrayLike = npt.ArrayLike
Array = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int32]
# None (the identity), a 4x4 array with last row (0, 0, 0, 1), or (rotation 3x3, translation 3).
Pose = Union[None, ArrayLike, Tuple[ArrayLike, ArrayLike]]

class Error(ValueError):
    """A call the library refused; .status says why."""
    status: Status

class Status(IntEnum):
    OK = 0
    NON_FINITE = 1
    TOO_FEW_POINTS = 2
    COLLINEAR = 3
    INVALID_MESH = 4
    NOT_CONVEX = 5
    INVALID_BOX = 6
    DEGENERATE_RESULT = 7
    HULL_FAILED = 8
    OUT_OF_RANGE = 9
    INVALID_POSE = 10
    INVALID_ARGUMENT = 11
    CAPACITY_EXCEEDED = 12
    UNSUPPORTED = 13
    EMPTY_MESH = 14
    WORKSPACE_MISMATCH = 15

class Want(IntEnum):
    VERDICT = 1
    DISTANCE = 3
    WITNESSES = 7
    PATCH = 15
    MAX_DISTANCE = 16
    ALL = 31

class SumParts(IntEnum):
    PLANES = 0
    VERTICES = 1
    WHOLE = 2

class Shape:
    """An immutable convex shape: a core swept by a ball of `radius`, placed by a pose per call."""
    @staticmethod
    def from_points(points: ArrayLike) -> Shape: ...
    @staticmethod
    def from_mesh(vertices: ArrayLike, faces: Sequence[Sequence[int]]) -> Shape: ...
    @staticmethod
    def box(half_extents: ArrayLike = (1.0, 1.0, 1.0), center: Optional[ArrayLike] = None,
            rotation: Optional[ArrayLike] = None) -> Shape: ...
    @staticmethod
    def triangle(corners: ArrayLike) -> Shape: ...
    @staticmethod
    def sphere(radius: float) -> Shape: ...
    @staticmethod
    def capsule(half_length: float, radius: float) -> Shape: ...
    def with_radius(self, radius: float) -> Shape: ...
    @property
    def radius(self) -> float: ...
    @property
    def vertices(self) -> Array: ...
    @property
    def input_index(self) -> IntArray: ...
    @property
    def faces(self) -> Tuple[Array, IntArray, IntArray]: ...

class Proximity:
    """The fields the call's `want` did not ask for are NaN."""
    intersecting: bool
    distance: float
    point_a: Array
    point_b: Array
    max_distance: float
    far_a: Array
    far_b: Array
    penetration_depth: float
    penetration_direction: Array
    searched: bool

class ProximityCache:
    def __init__(self) -> None: ...
    warm: int
    cold: int
    searched: int

class ContactPatch:
    points: Array
    normal: Array
    depth: float
    feature_a: Tuple[str, int, int]
    feature_b: Tuple[str, int, int]

class TimeOfImpact:
    hit: bool
    time: float
    distance: float
    normal: Array
    point_a: Array
    point_b: Array
    tolerance: float
    converged: bool
    iterations: int
    triangle: int

class Sum:
    planes: Array
    plane_pairs: IntArray
    vertices: Array
    vertex_pairs: IntArray
    loop_start: IntArray
    loop_vertex: IntArray
    V: int
    E: int
    F: int
    euler_ok: bool
    radius: float
    parts: SumParts
    def contains(self, point: ArrayLike) -> bool: ...

class Mesh:
    def __init__(self, vertices: ArrayLike, triangles: ArrayLike, leaf_size: int = 64) -> None: ...
    @staticmethod
    def from_points(points: ArrayLike, leaf_size: int = 64) -> Mesh: ...
    vertices: Array
    triangles: IntArray
    is_cloud: bool

class MeshWorkspace:
    def __init__(self, a: Mesh, b: Mesh) -> None: ...

class MeshDistance:
    distance: float
    point_a: Array
    point_b: Array
    triangle_a: int
    triangle_b: int
    intersecting: bool

class MeshContact:
    intersecting: bool
    penetration_depth: float
    penetration_direction: Array
    point: Array
    triangle: int
    area: float
    centre: Array
    overflow: bool

def proximity(a: Shape, pose_a: Pose, b: Shape, pose_b: Pose, want: Optional[Want] = None,
              cache: Optional[ProximityCache] = None) -> Proximity: ...
def contact_patch(a: Shape, pose_a: Pose, b: Shape, pose_b: Pose, margin: float = 0.0,
                  cache: Optional[ProximityCache] = None, reduce: bool = False) -> ContactPatch: ...
@overload
def time_of_impact(a: Shape, a0: Pose, a1: Pose, b: Shape, b0: Pose, b1: Pose, tolerance: float = 0.0) -> TimeOfImpact: ...
@overload
def time_of_impact(a: Mesh, pose_a: Pose, tool: Shape, t0: Pose, t1: Pose, tolerance: float = 0.0) -> TimeOfImpact: ...
def minkowski_sum(a: Shape, pose_a: Pose, b: Shape, pose_b: Pose, parts: SumParts = SumParts.WHOLE,
                  out: Optional[Sum] = None) -> Sum: ...
def minkowski_difference(a: Shape, pose_a: Pose, b: Shape, pose_b: Pose, parts: SumParts = SumParts.WHOLE,
                         out: Optional[Sum] = None) -> Sum: ...
@overload
def mesh_distance(a: Mesh, pose_a: Pose, b: Mesh, pose_b: Pose, workspace: Optional[MeshWorkspace] = None,
                  cache: Optional[ProximityCache] = None) -> MeshDistance: ...
@overload
def mesh_distance(a: Mesh, pose_a: Pose, b: Shape, pose_b: Pose, workspace: None = None,
                  cache: Optional[ProximityCache] = None) -> MeshDistance: ...
def mesh_contact(a: Mesh, pose_a: Pose, tool: Shape, pose_tool: Pose,
                 workspace: Optional[MeshWorkspace] = None) -> MeshContact: ...
PathLike = Union[str, bytes, "os.PathLike[str]"]
def read_mesh(path: PathLike, cloud_ok: bool = False) -> Tuple[Array, IntArray]: ...
def read_points(path: PathLike) -> Array: ...
def write_mesh(path: PathLike, sum: Sum, core: bool = False) -> None: ...

# Batches: N poses as an (N, 4, 4) array (or one pose for all; N may be 0), results as arrays
# of N rows, every item answered: `status` is each item's Status code, and a failed item's
# numbers are NaN. threads 0 is one per core. The same answers on any number of threads.
class _ProximityBatch:
    intersecting: npt.NDArray[np.bool_]
    distance: Array
    point_a: Array
    point_b: Array
    penetration_depth: Array
    penetration_direction: Array
    max_distance: Array
    status: IntArray

class _TimeOfImpactBatch:
    hit: npt.NDArray[np.bool_]
    time: Array
    distance: Array
    normal: Array
    point_a: Array
    point_b: Array
    status: IntArray

class _MeshDistanceBatch:
    distance: Array
    point_a: Array
    point_b: Array
    triangle_a: IntArray
    triangle_b: IntArray
    intersecting: npt.NDArray[np.bool_]
    status: IntArray

class SumList(list[Sum]):
    """A list of Sum, one per pair (a failed pair's is empty), and each pair's Status code."""
    status: IntArray

# out: a result of an earlier call with the same N, refilled in place and returned.
def proximity_batch(a: Shape, poses_a: ArrayLike, b: Shape, poses_b: ArrayLike, want: Want = Want.WITNESSES,
                    threads: int = 0, out: Optional[_ProximityBatch] = None) -> _ProximityBatch: ...
def time_of_impact_batch(a: Shape, a0: ArrayLike, a1: ArrayLike, b: Shape, b0: ArrayLike, b1: ArrayLike,
                         tolerance: float = 0.0, threads: int = 0,
                         out: Optional[_TimeOfImpactBatch] = None) -> _TimeOfImpactBatch: ...
@overload
def mesh_distance_batch(a: Mesh, poses_a: ArrayLike, b: Mesh, poses_b: ArrayLike, threads: int = 0,
                        out: Optional[_MeshDistanceBatch] = None) -> _MeshDistanceBatch: ...
@overload
def mesh_distance_batch(a: Mesh, poses_a: ArrayLike, b: Shape, poses_b: ArrayLike, threads: int = 0,
                        out: Optional[_MeshDistanceBatch] = None) -> _MeshDistanceBatch: ...
def minkowski_sum_batch(a: Sequence[Shape], poses_a: ArrayLike, b: Sequence[Shape], poses_b: ArrayLike,
                        parts: SumParts = SumParts.WHOLE, threads: int = 0) -> SumList: ...
def minkowski_difference_batch(a: Sequence[Shape], poses_a: ArrayLike, b: Sequence[Shape], poses_b: ArrayLike,
                               parts: SumParts = SumParts.WHOLE, threads: int = 0) -> SumList: ...
