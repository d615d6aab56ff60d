// Bodies, worlds and whole-world sums shared by the tests and the bench tools, so that a
// "unit box on the ground" or "the kinetic energy of the world" is written once.
//
// A body is built in one expression from a shape and the fields that differ from RBodyDef's
// defaults (density 1 kg/m^3, friction 0.5, at the origin, at rest), except restitution, 0.5
// here (RBodyDef's is 0): the tests' worlds bounce unless they say otherwise:
//
//   BoxDef(RVec3::Constant(0.5)).At(RVec3(0, 0.5, 0)).Mass(1).Named("box")
//
// BodyDef is an RBodyDef, so it goes wherever one does (RRigidBody's constructor, a vector of
// definitions) and its fields can still be set one by one. Header-only.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RRigidBody.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace REngine::test {

// ---- bodies -------------------------------------------------------------------------------

// An RBodyDef with setters that chain. Each sets one field and says nothing of the others.
struct BodyDef : RBodyDef {
  BodyDef() { restitution = 0.5; }
  BodyDef& Named(std::string n) { return name = std::move(n), *this; }
  BodyDef& At(const RVec3& x_W) { return position_W = x_W, *this; }          // shape frame, m
  BodyDef& Oriented(const RQuat& q) { return q_WS = q, *this; }              // q_WS
  BodyDef& Mass(RScalar kg) { return mass = kg, *this; }
  BodyDef& Density(RScalar kgPerM3) { return density = kgPerM3, *this; }
  BodyDef& Moving(const RVec3& v_W) { return velocity_W = v_W, *this; }      // m/s
  BodyDef& Spinning(const RVec3& w_W) { return angularVelocity_W = w_W, *this; }  // rad/s
  BodyDef& Restitution(RScalar e) { return restitution = e, *this; }
  BodyDef& Friction(RScalar mu) { return friction = mu, *this; }
  // Static: never moves, mass 0 whatever `mass` says.
  BodyDef& Static() { return kind = RBodyKind::kStatic, *this; }
  // Kinematic: moves with its velocities (Moving, Spinning) and nothing else, mass 0.
  BodyDef& Kinematic() { return kind = RBodyKind::kKinematic, *this; }
  BodyDef& Damping(RScalar linear, RScalar angular) {  // 1/s
    return linearDamping = linear, angularDamping = angular, *this;
  }
  BodyDef& GravityScale(RScalar s) { return gravityScale = s, *this; }
  // World axes locked, x y z.
  BodyDef& LockLinear(bool x, bool y, bool z) { return locks.linear = {x, y, z}, *this; }
  BodyDef& LockAngular(bool x, bool y, bool z) { return locks.angular = {x, y, z}, *this; }
};

inline BodyDef SphereDef(RScalar radius) {
  BodyDef d;
  d.shape = RShape::Sphere(radius);
  return d;
}

inline BodyDef BoxDef(const RVec3& halfExtents) {
  BodyDef d;
  d.shape = RShape::Box(halfExtents);
  return d;
}

// The convex hull of `points_S`, in the shape frame.
inline BodyDef HullDef(std::vector<RVec3> points_S) {
  BodyDef d;
  d.shape = RShape::Hull(std::move(points_S));
  return d;
}

// A 1 kg cube of edge 1 m named "box": the unit box of the stacks and slides.
inline BodyDef UnitBoxDef(const RVec3& position_W) {
  return BoxDef(RVec3::Constant(0.5)).Mass(1).At(position_W).Named("box");
}

// A static slab named "ground", 100 m square and 1 m thick: its top face is y = 0 when it
// stands at the default position.
inline BodyDef GroundDef(const RVec3& position_W = RVec3(0, -0.5, 0)) {
  return BoxDef(RVec3(50, 0.5, 50)).Static().At(position_W).Named("ground");
}

// A stack of n cubes of edge `size` (1 kg each, named box0, box1, ... from the bottom), each
// resting exactly on the one below, on a ground slab scaled by `size` whose top face is at
// base_W: the ground first, then the cubes.
inline std::vector<BodyDef> BoxStackDefs(int n, const RVec3& base_W = RVec3::Zero(),
                                         RScalar size = 1) {
  std::vector<BodyDef> defs{BoxDef(RVec3(50, 0.5, 50) * size)
                                .Static()
                                .At(base_W + RVec3(0, -0.5, 0) * size)
                                .Named("ground")};
  for (int i = 0; i < n; ++i) {
    defs.push_back(BoxDef(RVec3::Constant(0.5 * size))
                       .At(base_W + RVec3(0, 0.5 + i, 0) * size)
                       .Mass(1)
                       .Named("box" + std::to_string(i)));
  }
  return defs;
}

// Two spheres of radius 0.5 m, "a" at x = -2 m and "b" at x = 2 m, meeting head-on along x:
// the closed form of a 1D collision with restitution e (the same on both, so any combine
// gives e) and no friction. They close a 3 m gap at v1 - v2.
inline std::vector<BodyDef> HeadOnSpheres(RScalar m1, RScalar v1, RScalar m2, RScalar v2,
                                          RScalar e) {
  return {SphereDef(0.5).Named("a").Mass(m1).At(RVec3(-2, 0, 0)).Moving(RVec3(v1, 0, 0))
              .Restitution(e).Friction(0),
          SphereDef(0.5).Named("b").Mass(m2).At(RVec3(2, 0, 0)).Moving(RVec3(v2, 0, 0))
              .Restitution(e).Friction(0)};
}

// A static plate 0.1 m thick and 200 m square, its normal along x, restitution 0; and a
// 0.2 m, 1 kg box shot at it from origin_W + (0.37, 0, 0) (not a whole number of steps from
// a plate at a round distance), restitution 0: the tunnelling case.
inline BodyDef ThinPlateDef(const RVec3& position_W) {
  return BoxDef(RVec3(0.05, 100, 100)).Static().Restitution(0).At(position_W).Named("plate");
}
inline BodyDef ShotDef(const RVec3& origin_W, const RVec3& v_W) {
  return BoxDef(RVec3::Constant(0.1)).Mass(1).Restitution(0).Moving(v_W)
      .At(origin_W + RVec3(0.37, 0, 0)).Named("shot");
}

// Bodies from their definitions, in order.
template <class Def>
std::vector<RRigidBody> MakeBodies(const std::vector<Def>& defs) {
  std::vector<RRigidBody> bodies;
  bodies.reserve(defs.size());
  for (const RBodyDef& d : defs) bodies.emplace_back(d);
  return bodies;
}

// ---- stepping -----------------------------------------------------------------------------

// `steps` steps of dt (s).
inline void Step(RIntegrator& integrator, std::vector<RRigidBody>& bodies, std::uint64_t steps,
                 RScalar dt = RScalar(1) / 60) {
  for (std::uint64_t i = 0; i < steps; ++i) integrator.Update(bodies, dt);
}

// Settings with Earth's gravity along -y and every other setting at its default.
inline RWorldSettings EarthGravity() {
  RWorldSettings s;
  s.gravity_W = RVec3(0, -9.81, 0);
  return s;
}

// ---- sums over a world ----------------------------------------------------------------------

// Translational plus rotational, J.
inline RScalar KineticEnergy(const std::vector<RRigidBody>& bodies) {
  RScalar e = 0;
  for (const RRigidBody& b : bodies) e += b.LinearKineticEnergy() + b.RotationalKineticEnergy();
  return e;
}

inline RVec3 Momentum(const std::vector<RRigidBody>& bodies) {
  RVec3 p = RVec3::Zero();
  for (const RRigidBody& b : bodies) p += b.Mass() * b.Velocity_W();
  return p;
}

// Sum of m |v|, kg m/s: what a momentum drift is relative to (the total may cancel).
inline RScalar MomentumScale(const std::vector<RRigidBody>& bodies) {
  RScalar scale = 0;
  for (const RRigidBody& b : bodies) scale += b.Mass() * b.Velocity_W().norm();
  return scale;
}

// About the world origin: orbital plus spin, kg m^2/s.
inline RVec3 AngularMomentum(const std::vector<RRigidBody>& bodies) {
  RVec3 l = RVec3::Zero();
  for (const RRigidBody& b : bodies) {
    l += b.Position_W().cross(b.Mass() * b.Velocity_W()) + b.AngularMomentum_W();
  }
  return l;
}

// How many bodies sleep.
inline int Sleeping(const std::vector<RRigidBody>& bodies) {
  int n = 0;
  for (const RRigidBody& b : bodies) n += b.IsSleeping();
  return n;
}

// The worst relative drift over a run of a free body's rotational energy and world angular
// momentum, which the exact torque-free flow keeps: Observe after every step.
struct RotationDrift {
  explicit RotationDrift(const RRigidBody& body)
      : E0(body.RotationalKineticEnergy()), L0(body.AngularMomentum_W()) {}
  void Observe(const RRigidBody& body) {
    worstE = std::max(worstE, std::abs(body.RotationalKineticEnergy() / E0 - 1));
    worstL = std::max(worstL, (body.AngularMomentum_W() - L0).norm() / L0.norm());
  }
  RScalar E0;
  RVec3 L0;
  RScalar worstE = 0, worstL = 0;  // max |E / E0 - 1|, max |L - L0| / |L0|
};

// ---- random numbers -------------------------------------------------------------------------

// A uniform number in [lo, hi) from the top 53 bits of one draw: the standard fixes
// mt19937_64's sequence and this mapping (not std::uniform_real_distribution's), so a seed
// gives the same bodies on every platform.
inline RScalar UniformIn(std::mt19937_64& rng, RScalar lo, RScalar hi) {
  return lo + (hi - lo) * (static_cast<RScalar>(rng() >> 11) * RScalar(0x1.0p-53));
}

// A unit quaternion from four normal deviates: uniform over rotations.
inline RQuat RandomRotation(std::mt19937_64& rng) {
  std::normal_distribution<RScalar> g;
  RQuat q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  return q;
}

// n points in a ball of radius `scale` (uniform in its volume), or on its sphere.
inline std::vector<RVec3> RandomCloud(std::mt19937_64& rng, int n, RScalar scale, bool onSphere) {
  std::normal_distribution<RScalar> g;
  std::uniform_real_distribution<RScalar> u(0, 1);
  std::vector<RVec3> p;
  for (int i = 0; i < n; ++i) {
    RVec3 v(g(rng), g(rng), g(rng));
    v.normalize();
    if (!onSphere) v *= std::cbrt(u(rng));
    p.push_back(scale * v);
  }
  return p;
}

}  // namespace REngine::test
