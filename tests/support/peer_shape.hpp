// A shape as the peers build it (FCL, Bullet): a sphere, a capsule along z, a box or a convex
// polytope, with a radius swept around it where the peer has one.
#pragma once

#include <minksum/model.hpp>

namespace minksum::peers {

/// One operand of a peer pair, in its body frame.
struct PeerShape {
  enum class Kind { Sphere, Capsule, Box, Polytope } kind = Kind::Sphere;  ///< what it is
  double radius = 0;       ///< the sphere's or capsule's radius, or the one swept around a box or polytope
  double half_length = 0;  ///< the capsule's segment runs from -half_length to half_length on z
  Eigen::Vector3d half = Eigen::Vector3d::Ones();  ///< the box's half extents
  ConvexPolytope polytope;                         ///< the polytope
};

}  // namespace minksum::peers
