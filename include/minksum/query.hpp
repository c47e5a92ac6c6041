// minksum: proximity queries on Minkowski differences (the paper's Sections 1 and 5.1): collision,
// exact minimum distance with closest points, maximum distance, penetration depth.
#pragma once

#include <minksum/sum.hpp>

namespace minksum {

/// Everything a collision or haptics caller asks of two convex objects A and B.
/// A field past what the call's Want asked for keeps its default (0, or the zero vector), which
/// is no answer: read only the fields asked for (the Python module sets them to NaN).
struct Proximity {
  bool intersecting = false;  ///< A and B share a point (touching counts)
  double distance = 0;        ///< length of the shortest segment between A and B; 0 if intersecting
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  ///< its end on A (separated), or A's deepest point
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  ///< its end on B (separated), or B's deepest point
  double max_distance = 0;                            ///< the farthest pair of points (the paper's Fig. 8, red)
  Eigen::Vector3d far_a = Eigen::Vector3d::Zero();    ///< that pair's point on A
  Eigen::Vector3d far_b = Eigen::Vector3d::Zero();    ///< that pair's point on B
  double penetration_depth = 0;                       ///< minimum translation distance when intersecting, else 0
  /// Unit direction: translating B by penetration_depth * direction makes them touch (zero when
  /// separated).
  Eigen::Vector3d penetration_direction = Eigen::Vector3d::Zero();
  /// True when no certificate held and the answer came from the exhaustive search (the last
  /// resort: O(F_A F_B) face pairs and O(E_A E_B) edge pairs; statistics).
  bool searched = false;
};

/// What a proximity call computes, as a bit mask: each level includes the ones above it, and
/// the fields a call does not ask for keep their defaults. Combine with `|`
/// (`Want::Witnesses | Want::MaxDistance`). The costs are callgrind's, per call, from
/// tests/budgets.tsv's operations (box pairs; prepared convex shapes pay the same for the
/// first four levels: their certificate reads what the witnesses need).
enum class Want : unsigned {
  /// `intersecting` alone (touching counts). Boxes: the separating axis test alone, the cold
  /// query's verdict exactly (box_box.verdict: 1,337 instructions, both boxes' checks
  /// included, against 1,862 for Witnesses cold).
  Verdict = 1,
  /// And the distance, or the penetration depth and direction. Overlapping boxes skip the walk
  /// that finds the deepest points' preimages.
  Distance = 3,
  /// And the witnesses point_a, point_b: a closest (or deepest) pair, where several are, any
  /// one of them (the default, as FCL and Bullet give).
  Witnesses = 7,
  /// Witnesses on the contact patch: where the nearest (or deepest) sets are a face or an edge
  /// across from each other (resting, sliding), a point of their overlap, so that the
  /// witnesses do not jump between corners and the coherent query's equal the cold one's. Box
  /// pairs: about 700 more a query along the budgets' path (box_box.coherent.patch: 2,131
  /// against 1,424), more where they rest face or edge on face.
  Patch = 15,
  /// max_distance, far_a, far_b: the farthest pair, which reads every vertex pair of polytopes.
  MaxDistance = 16,
  /// Everything: the patch's witnesses and the farthest pair (the CLI's).
  All = 31,
};

/// Both sets of fields.
constexpr Want operator|(Want a, Want b) { return Want(unsigned(a) | unsigned(b)); }

/// True if `want` asks for all of `part` (a level includes the levels above it).
constexpr bool has(Want want, Want part) { return (unsigned(want) & unsigned(part)) == unsigned(part); }

/// What a query keeps from one call to the next on one pair of objects (coherence: a 1 kHz
/// loop moves them little per tick, so the nearest features rarely change). Caller-owned,
/// fixed size, no allocation; a value-initialised cache ({}) is cold. A query starts from it,
/// proves the answer it reaches (the KKT conditions of the box pair's active set, GJK's
/// supporting planes for convex shapes, the octree's bounds for meshes) and otherwise answers
/// cold: the answer is the cold query's whatever the cache holds. A cache filled by another
/// pair, another kind of query or shapes that have since changed only costs a cold query's
/// time (its indices are checked against the shapes). One cache per pair; not shared between
/// threads.
struct ProximityCache {
  unsigned kind = 0;     ///< the kind of query that filled it (0: none, cold)
  unsigned active = 0;   ///< box pairs: the active set of the last answer
  int a[3] = {0, 0, 0};  ///< the last answer's features on A (vertices, or a mesh triangle)
  int b[3] = {0, 0, 0};  ///< and on B
  long warm = 0;         ///< answers proven from the cache (statistics)
  long cold = 0;         ///< answers computed cold (statistics)
  long searched = 0;     ///< answers that needed the exhaustive search (statistics)
};

/// True if p lies in the closed polytope m; stops at the first plane that separates p by more
/// than m.radius. A rounded sum (radius > 0): within the radius of the polytope, by the
/// distance to the facets whose planes p lies beyond. False for an empty m (a sum that failed)
/// and for a point with a NaN coordinate.
bool contains(const MinkowskiSum& m, const Eigen::Vector3d& p);

/// The proximity of A and B read off M = A (-) B (from minkowski_difference(a, b, m)): the
/// origin's Voronoi region of M (facet, edge or vertex) gives the exact distance, and the
/// support pairs of that feature give the closest points on A and B. TooFewPoints for an empty
/// m; InvalidMesh when m's support pairs index past a's or b's vertices (m is not their sum);
/// Unsupported for a rounded m (how its radius splits between A and B is not known here:
/// proximity of the posed shapes answers it).
Status proximity(const MinkowskiSum& m, const ConvexPolytope& a, const ConvexPolytope& b, Proximity& out);

/// The proximity of two convex polytopes (exact), to the fields `want` asks for.
Status proximity(const ConvexPolytope& a, const ConvexPolytope& b, Proximity& out, Want want = Want::Witnesses);
/// The proximity of two prepared shapes, each placed by its rigid pose inside the call (the
/// same exact query as for polytopes; points in the world frame). Rounded shapes (a radius,
/// spheres, capsules): their cores' answer with the radii added, exactly (distance less the
/// radii, depth plus them, witnesses on the surfaces). TooFewPoints for an empty shape,
/// InvalidPose for a pose that is not rigid (check_pose).
Status proximity(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                 const Eigen::Isometry3d& pose_b, Proximity& out, Want want = Want::Witnesses);
/// Two posed shapes, starting from the last answer's features (see ProximityCache): GJK from
/// the cached simplex, then the same certificate as the cold query.
Status proximity(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                 const Eigen::Isometry3d& pose_b, ProximityCache& cache, Proximity& out, Want want = Want::Witnesses);
/// The proximity of two boxes, exact without building A (-) B: the separating axis test, then
/// an active-set walk on A (-) B's generators from the nearest facet.
Status proximity(const Box& a, const Box& b, Proximity& out, Want want = Want::Witnesses);
/// The two boxes' proximity starting from the last answer's active set (see ProximityCache):
/// the same answer as the cold query, at a fraction of its cost while the boxes stay apart.
Status proximity(const Box& a, const Box& b, ProximityCache& cache, Proximity& out, Want want = Want::Witnesses);
/// The proximity of a box and a triangle.
Status proximity(const Box& a, const Triangle& b, Proximity& out, Want want = Want::Witnesses);
/// A box and a triangle, starting from the last answer's features (see ProximityCache).
Status proximity(const Box& a, const Triangle& b, ProximityCache& cache, Proximity& out, Want want = Want::Witnesses);
/// The proximity of two triangles (coplanar triangles included).
Status proximity(const Triangle& a, const Triangle& b, Proximity& out, Want want = Want::Witnesses);

/// Where two convex shapes touch, or would within a margin: the overlap, seen along the contact
/// normal, of A's supporting set (its points highest along the normal) and B's (lowest). Both
/// sets lie in planes orthogonal to the normal, so every point of the patch has the one depth.
struct ContactPatch {
  static constexpr int kCapacity = 128;  ///< the most points a patch holds
  /// The supporting feature of one shape: a face (index into its polytope's faces), an edge (its
  /// two vertices), a vertex, or None (vertices of nearly coplanar faces, within rounding).
  struct Feature {
    enum class Kind : unsigned char { None, Vertex, Edge, Face } kind = Kind::None;  ///< what it is
    int index[2] = {-1, -1};  ///< the face; the edge's two vertices; the vertex
  };
  int size = 0;  ///< points in `points` (0: farther apart than the margin)
  /// Unit normal of both supporting planes, from A towards B (the penetration direction, or the
  /// direction of the closest points when apart).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  /// How far B's plane lies below A's along the normal: the penetration depth (0 touching), or
  /// minus the distance when apart.
  double depth = 0;
  Eigen::Vector3d points[kCapacity];  ///< the patch on A's supporting plane, counter-clockwise about the normal
  Feature feature_a;                  ///< A's supporting feature
  Feature feature_b;                  ///< B's supporting feature
};

/// The contact patch of two posed shapes that overlap, touch or lie within `margin` of each
/// other (size 0 farther apart), exact to rounding: A's and B's supporting sets along the exact
/// query's normal, clipped to each other in O(n_A + n_B) (a face, an edge or a vertex of each).
/// A point (size 1), a segment (2) or a convex polygon. Rounded shapes: the cores' patch within
/// the margin plus the radii, on A's surface, its depth grown by the radii (a sphere's is a
/// point; a capsule's a point, or a segment where it lies level with the other's face or axis).
/// TooFewPoints for an empty shape, InvalidPose for a pose that is not rigid, InvalidArgument
/// for a margin < 0 or NaN, CapacityExceeded where the two supporting sets have more than
/// kCapacity points together.
Status contact_patch(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                     const Eigen::Isometry3d& pose_b, double margin, ContactPatch& out);
/// The contact patch through the pair's cache (see ProximityCache): the exact query starts from
/// the last answer's features and proves its answer as the cold one does, so the patch is the
/// cold one's (to rounding, where several normals prove the same depth: either). Box pairs
/// answer by their axes and leave the cache as it is.
Status contact_patch(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                     const Eigen::Isometry3d& pose_b, double margin, ProximityCache& cache, ContactPatch& out);
/// Reduces a patch to at most 4 of its points, the quadrilateral of largest area among them
/// (counter-clockwise as before), as contact solvers take it. Every point of a patch lies at
/// the patch's depth, so the deepest point stays. Patches of 4 points or fewer are unchanged.
void reduce_contact_patch(ContactPatch& patch);

/// The motion time_of_impact sweeps a shape along within a tick (and the mesh sweep a tool):
/// its origin along the segment from `from` to `to`, its rotation about one body axis at a
/// constant rate (the shorter way; as a quaternion slerp). Rigid poses.
struct Motion {
  Eigen::Isometry3d from = Eigen::Isometry3d::Identity();  ///< the pose at time 0
  Eigen::Isometry3d to = Eigen::Isometry3d::Identity();    ///< the pose at time 1
  /// The pose at time t (0 at `from`, 1 at `to`): where a time of impact's hit places the shape.
  Eigen::Isometry3d at(double t) const;
};

/// When two shapes moving within a tick first touch. Each moves from pose0 to pose1: its
/// origin along the segment, its rotation about one axis at a constant rate. Conservative
/// advancement with certified bounds. The band's contract (convex pairs, a tool against a mesh,
/// and so the haptic proxy): a motion that brings the shapes closer than tolerance / 2 always
/// hits, at a time no later than the first such pass; a hit never comes while they are farther
/// apart than `tolerance`; a pass whose closest approach lies between the two may hit or not.
struct TimeOfImpact {
  bool hit = false;                                   ///< they come within the tolerance at some time in [0, 1]
  double time = 1;                                    ///< that time (0: already touching or overlapping; 1: no hit)
  double distance = 0;  ///< |point_b - point_a| then (<= tolerance; 0 overlapping): at least the distance
  /// Unit, from A towards B: a separating plane's normal then (the two supporting planes along
  /// it lie between 0 and `distance` apart), or at time 0 the contact patch's. Where it is the
  /// nearest points' direction, their rounding turns it by about eps reach / d (reach: the
  /// scene's largest coordinate; d: their distance, at time 0 the exact one, which `distance`
  /// bounds from above), which is all the planes' overlap along it can be.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  ///< a point on A then, within the tolerance of B (world frame)
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  ///< and on B (overlapping at time 0: the deepest points)
  double tolerance = 0;                               ///< the stopping distance used
  /// false: the advancement stopped short of the tolerance, at the iteration cap or where the
  /// gap rounds to zero (a tolerance below the coordinates' rounding); no contact before `time`
  bool converged = true;
  int iterations = 0;  ///< GJK iterations made (each a support point of each shape)
  int triangle = -1;   ///< against a mesh: the triangle of the answer (else -1)
};

/// The most GJK iterations time_of_impact makes.
constexpr int kTimeOfImpactIterations = 256;

/// The time of impact of A moving from a0 to a1 and B from b0 to b1 (see TimeOfImpact). A pure
/// translation is exact to the tolerance: each step lands on the supporting plane the relative
/// motion's ray meets. With rotation, the steps are bounded by the rotation's reach. `tolerance` 0: 1e-12 of
/// the scene's size translating, 1e-6 turning. Rounded shapes: their cores advance until they
/// come within the radii (and the tolerance), and the points lie on the surfaces. TooFewPoints for an empty shape, InvalidPose
/// for a pose that is not rigid, InvalidArgument for a tolerance < 0, NaN or infinite.
Status time_of_impact(const ConvexShape& a, const Eigen::Isometry3d& a0, const Eigen::Isometry3d& a1,
                      const ConvexShape& b, const Eigen::Isometry3d& b0, const Eigen::Isometry3d& b1, TimeOfImpact& out,
                      double tolerance = 0);

/// How far B must move along the unit direction u for A and B to stop overlapping (0 if they
/// are separated, or already would be after any move along u), from M = A (-) B. A rounded M:
/// where the ray leaves the balls, cylinders and slabs about M's vertices, edges and facets.
double penetration_along(const MinkowskiSum& m, const Eigen::Vector3d& u);

}  // namespace minksum
