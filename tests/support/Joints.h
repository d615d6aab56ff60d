// What the joint suites and bench_joints share: a joint definition in one expression, where
// a joint's two anchors are now and how far apart, their gravity, and the complete elliptic
// integral the pendulum's closed form needs (computed here, independently of REngineMath's elliptic functions). Header-only.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RJoint.h>

#include <cmath>
#include <utility>

namespace REngine::test {

// A joint of `type` between a and b (b invalid: the world) acting at anchor_W; the other
// fields at RJointDef's defaults.
inline RJointDef Joint(RJointType type, RBodyHandle a, RBodyHandle b, const RVec3& anchor_W) {
  RJointDef d;
  d.type = type, d.a = a, d.b = b, d.anchor_W = anchor_W;
  return d;
}

// Where a joint's anchors are now, on a and on b (the world's: its point), world, m.
inline std::pair<RVec3, RVec3> Anchors(const RBodies& bodies, RJointHandle h) {
  const RJoint& j = bodies.Joint(h);
  const RRigidBody& a = bodies[j.def.a];
  const RVec3 pA = a.Position_W() + a.Orientation_WB() * j.anchorA_B;
  if (!j.def.b.IsValid()) return {pA, j.anchorB_B};
  const RRigidBody& b = bodies[j.def.b];
  return {pA, b.Position_W() + b.Orientation_WB() * j.anchorB_B};
}

// How far apart a joint's two anchors are now, m (0: the joint holds).
inline RScalar Gap(const RBodies& bodies, RJointHandle h) {
  const auto [pA, pB] = Anchors(bodies, h);
  return (pA - pB).norm();
}

// The joint suites' world: gravity g along -y (m/s^2).
inline RWorldSettings GravityAlongMinusY(RScalar g = 9.81) {
  RWorldSettings s;
  s.gravity_W = RVec3(0, -g, 0);
  return s;
}

// The complete elliptic integral of the first kind K(k), by the arithmetic-geometric mean.
inline RScalar CompleteEllipticK(RScalar k) {
  RScalar a = 1, b = std::sqrt(1 - k * k);
  for (int i = 0; i < 40 && std::abs(a - b) > 1e-16 * a; ++i) {
    const RScalar an = (a + b) / 2;
    b = std::sqrt(a * b), a = an;
  }
  return kPi / (2 * a);
}

}  // namespace REngine::test
