// The random pairs of the round shapes' FCL cross-checks (capsule_tests, cylinder_tests): a
// partner shape of a given kind with its FCL twin, and poses near each other. Header-only;
// the draws from the generator come in a fixed order, so a seed gives the same pairs.
#pragma once

#include <REnginePhysics/RCollision.h>

#include "CollisionOracles.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

namespace REngine::test {

inline RConvexShape CapsuleShape(RScalar r, RScalar h) {
  RConvexShape s;
  s.radius = r, s.halfHeight = h, s.boundingRadius = r + h;
  return s;
}

inline RConvexShape CylinderShape(RScalar r, RScalar h) {
  RConvexShape s;
  s.cylinderRadius = r, s.halfHeight = h, s.boundingRadius = std::hypot(r, h);
  return s;
}

// The exact signed distance of a point from a cylinder (radius r about y, ends at +-h): the
// 2-D box distance in (distance from the axis, height).
inline RScalar CylinderSdf(RScalar r, RScalar h, const RVec3& p) {
  const RScalar qx = std::hypot(p.x(), p.z()) - r, qy = std::abs(p.y()) - h;
  const RScalar outside = std::hypot(std::max(qx, RScalar(0)), std::max(qy, RScalar(0)));
  return outside + std::min(std::max(qx, qy), RScalar(0));
}

// Signed distance of a point from a convex shape in its own frame, exact on the surface (0)
// and inside (the depth): a polyhedron's largest face-plane distance (outside only a lower
// bound), a cylinder's exact one, a sphere's or capsule's distance from its core less the
// radius. Independent of the narrow phase: each shape by its definition.
inline RScalar SurfaceDistance(const RConvexShape& s, const RVec3& p) {
  if (s.cylinderRadius > 0) return CylinderSdf(s.cylinderRadius, s.halfHeight, p);
  if (s.polyhedron) {
    RScalar most = -std::numeric_limits<RScalar>::infinity();
    for (const RFace& f : s.polyhedron->Faces()) most = std::max(most, f.plane.SignedDistance(p));
    return most;
  }
  return (p - RVec3(0, std::clamp(p.y(), -s.halfHeight, s.halfHeight), 0)).norm() - s.radius;
}

inline RQuat RandomQuat(std::mt19937_64& rng) {
  std::normal_distribution<RScalar> n(0, 1);
  RQuat q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q;
}

// FCL's capsules and cylinders lie along z, REngine's along y: FCL's frame is REngine's
// turned by -90 degrees about x (alongZ).
inline fcl::Transform3d FclPose(const RVec3& x, const RQuat& q, bool alongZ) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  RMat3 R = q.toRotationMatrix();
  if (alongZ) R = R * Eigen::AngleAxisd(-kPi / 2, RVec3::UnitX()).toRotationMatrix();
  tf.linear() = R;
  tf.translation() = x;
  return tf;
}

enum class PartnerKind { kBox, kSphere, kCapsule, kCylinder, kHull };

// A partner: a box (half extents 0.2 to 1.2), a sphere or capsule or cylinder (radius 0.1 to
// 1.1, half height 0.05 to 1.05), or the given hull; five draws whatever the kind.
struct Partner {
  RConvexPolyhedron box;
  RConvexShape shape;
  std::shared_ptr<fcl::CollisionGeometryd> owned;
  const fcl::CollisionGeometryd* fcl = nullptr;
  bool alongZ = false;  // FCL's twin lies along z (capsules, cylinders)

  Partner(PartnerKind kind, std::mt19937_64& rng, const OracleHull& hull) {
    std::uniform_real_distribution<RScalar> u(0, 1);
    const RVec3 half(0.2 + u(rng), 0.2 + u(rng), 0.2 + u(rng));
    box = RConvexPolyhedron::Box(half);
    const RScalar r = 0.1 + u(rng), h = 0.05 + u(rng);
    fcl = &hull.FclConvex();
    switch (kind) {
      case PartnerKind::kBox:
        shape.polyhedron = &box, shape.boundingRadius = box.MaxRadius();
        fcl = (owned = std::make_shared<fcl::Boxd>(2 * half.x(), 2 * half.y(), 2 * half.z())).get();
        break;
      case PartnerKind::kSphere:
        shape.radius = r, shape.boundingRadius = r;
        fcl = (owned = std::make_shared<fcl::Sphered>(r)).get();
        break;
      case PartnerKind::kCapsule:
        shape = CapsuleShape(r, h), alongZ = true;
        fcl = (owned = std::make_shared<fcl::Capsuled>(r, 2 * h)).get();
        break;
      case PartnerKind::kCylinder:
        shape = CylinderShape(r, h), alongZ = true;
        fcl = (owned = std::make_shared<fcl::Cylinderd>(r, 2 * h)).get();
        break;
      case PartnerKind::kHull:
        shape.polyhedron = &hull.Polyhedron(), shape.boundingRadius = hull.Radius();
        break;
    }
  }
  Partner(const Partner&) = delete;  // shape may point at box
};

// Two poses near each other: orientations uniform, A's centre in the unit cube, B's at
// 0.2 to 1.1 times the sum of the bounding radii from it in a random direction.
struct PairPose {
  RQuat qA, qB;
  RVec3 xA, xB;
  PairPose(std::mt19937_64& rng, RScalar reach) {
    std::uniform_real_distribution<RScalar> u(0, 1);
    qA = RandomQuat(rng), qB = RandomQuat(rng);
    xA = RVec3(u(rng), u(rng), u(rng));
    xB = xA + RVec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized() * reach * (0.2 + 0.9 * u(rng));
  }
  // B's pose in A's frame.
  RRelativePose Relative() const {
    RRelativePose X;
    X.R_AB = (qA.conjugate() * qB).toRotationMatrix();
    X.t_AB = qA.conjugate() * (xB - xA);
    return X;
  }
};

}  // namespace REngine::test
