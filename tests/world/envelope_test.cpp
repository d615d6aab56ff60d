// The stability envelope, quick version (the documented table in README.md, "Stability
// envelope", gives where each axis was pushed and what held; these tests check that it
// still holds). "Holds" per axis: no body goes non-finite, nothing tunnels, stacks stand
// (top within 1 mm sideways), resting overlap within its tolerance, energy of free motion
// kept. No speed is asserted here.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

struct StackResult {
  RScalar sideways = 0, sink = 0, overlap = 0;  // relative to the box size
  bool finite = true;
};

// n boxes of edge `size` resting on a static slab, each exactly on the one below, run for
// `seconds`; the overlap is the worst of the second half (after the cold start).
StackResult Stack(int n, RScalar size, RScalar dt, RScalar seconds, const RVec3& origin,
                  RScalar bottomMass = 0, RScalar topMass = 0) {
  std::vector<BodyDef> defs = BoxStackDefs(n, origin, size);
  if (bottomMass > 0) defs[1].mass = bottomMass;
  if (topMass > 0) defs[n].mass = topMass;
  std::vector<RRigidBody> bodies = MakeBodies(defs);
  RWorldSettings settings = EarthGravity();
  settings.shortcuts.sleeping = false;  // the solver's own envelope: every step simulated
  RIntegrator integrator(settings);
  const RVec3 top0 = bodies.back().Position_W();
  const int steps = static_cast<int>(std::lround(seconds / dt));
  StackResult r;
  for (int k = 0; k < steps; ++k) {
    integrator.Update(bodies, dt);
    if (k < steps / 2) continue;
    for (const RContact& c : integrator.Contacts()) {
      r.overlap = std::max(r.overlap, -c.manifold.query.separation / size);
    }
  }
  const RVec3 d = bodies.back().Position_W() - top0;
  r.sideways = std::hypot(d.x(), d.z()) / size;
  r.sink = -d.y() / size;
  r.finite = !integrator.NonFinite().has_value();
  return r;
}

}  // namespace

// Stack heights 5 to 50 at 60 Hz, 10 iterations: every stack stands. Up to 30 boxes (an
// island of 120 rows, solved directly) the overlap stays at rounding (1e-14 m); beyond the
// direct solve's 128 rows the iterations alone hold them with some sinking: 50 boxes
// overlap 3.7 mm.
TEST(Envelope, StackHeights) {
  for (int n : {5, 10, 20, 30, 40, 50}) {
    const StackResult r = Stack(n, 1, 1.0 / 60, 10, RVec3::Zero());
    std::printf("stack %d: sideways %.3g m, sank %.3g m, resting overlap %.3g m\n", n, r.sideways,
                r.sink, r.overlap);
    EXPECT_TRUE(r.finite) << n;
    EXPECT_LT(r.sideways, 1e-3) << n << " stands";
    EXPECT_LT(r.overlap, n <= 30 ? 1e-9 : 5e-3) << n;
  }
}

// Time steps 1/1000 s to 1/10 s: a 10-box stack stands and holds its overlap below 1e-6 m.
TEST(Envelope, TimeSteps) {
  for (RScalar dt : {1.0 / 1000, 1.0 / 240, 1.0 / 60, 1.0 / 20, 1.0 / 10}) {
    const StackResult r = Stack(10, 1, dt, 10, RVec3::Zero());
    EXPECT_TRUE(r.finite) << dt;
    EXPECT_LT(r.sideways, 1e-3) << dt;
    EXPECT_LT(r.overlap, 1e-6) << dt;
  }
}

// Coordinates up to 1e9 m: the 10-box stack stands there as at the origin.
TEST(Envelope, FarFromTheOrigin) {
  for (RScalar o : {1e6, 1e7, 1e8, 1e9}) {
    const StackResult r = Stack(10, 1, 1.0 / 60, 10, RVec3(o, o, -o));
    EXPECT_TRUE(r.finite) << o;
    EXPECT_LT(r.sideways, 1e-3) << o;
    EXPECT_LT(r.overlap, 1e-6) << o;
  }
}

// Box sizes 1 cm to 1 km (the whole scene scaled; gravity not): a 5-box stack stands with
// overlaps below 1e-6 of the box size.
TEST(Envelope, Sizes) {
  for (RScalar size : {0.01, 0.1, 1.0, 10.0, 100.0, 1000.0}) {
    const StackResult r = Stack(5, size, 1.0 / 60, 10, RVec3::Zero());
    EXPECT_TRUE(r.finite) << size;
    EXPECT_LT(r.sideways, 1e-3) << size;
    EXPECT_LT(r.overlap, 1e-6) << size;
  }
}

// Mass ratios 1:10 to 1:1e9 (asked: to 1:100 000): a heavy box on a light one on the
// ground holds, the overlap at rounding (asked of the response: 2 mm). Up to 1:1e7 below
// 1e-8 m; at 1:1e9 the heavy box's 1.6e8 N s impulse per step rounds to ~1e-8 m/s of
// velocity, and the overlap stays below 1e-6 m. 1:1e10 breaks (README, envelope table).
TEST(Envelope, MassRatios) {
  for (RScalar ratio : {10.0, 100.0, 1e3, 1e4, 1e5, 1e7, 1e9}) {
    const StackResult r = Stack(2, 1, 1.0 / 60, 10, RVec3::Zero(), 1, ratio);
    std::printf("mass ratio %g: overlap %.3g m, sank %.3g m\n", ratio, r.overlap, r.sink);
    EXPECT_TRUE(r.finite) << ratio;
    EXPECT_LT(r.overlap, ratio > 1e7 ? 1e-6 : 1e-8) << ratio;
    EXPECT_LT(r.sink, ratio > 1e7 ? 1e-6 : 1e-8) << ratio;
    EXPECT_LT(r.sideways, 1e-3) << ratio;
  }
}

// Spin rates up to 1000 rad/s: a free box with three distinct moments keeps its energy and
// angular momentum to 1e-9 over 10 s at 60 Hz (the rotation is the closed form).
TEST(Envelope, SpinRates) {
  for (RScalar w : {1.0, 10.0, 100.0, 1000.0}) {
    const RBodyDef spinner = BoxDef(RVec3(0.5, 0.3, 0.1)).Mass(1).Named("spinner").Spinning(
        w * RVec3(0.01, 1, 0.02).normalized());
    std::vector<RRigidBody> bodies{RRigidBody(spinner)};
    RIntegrator integrator;
    const RScalar e0 = bodies[0].RotationalKineticEnergy();
    const RVec3 l0 = bodies[0].AngularMomentum_W();
    RScalar worstE = 0, worstL = 0;
    for (int k = 0; k < 600; ++k) {
      integrator.Update(bodies, 1.0 / 60);
      worstE = std::max(worstE, std::abs(bodies[0].RotationalKineticEnergy() - e0) / e0);
      worstL = std::max(worstL, (bodies[0].AngularMomentum_W() - l0).norm() / l0.norm());
    }
    std::printf("spin %g rad/s: |dE/E| %.3g, |dL|/|L| %.3g\n", w, worstE, worstL);
    EXPECT_LT(worstE, 1e-9) << w;
    EXPECT_LT(worstL, 1e-9) << w;
  }
}

// Speeds up to 10 km/s (167 m per step at 60 Hz): a 0.2 m box stops at a 0.1 m plate.
TEST(Envelope, Speeds) {
  for (RScalar v : {100.0, 1000.0, 3000.0, 10000.0}) {
    std::vector<RRigidBody> bodies{RRigidBody(ThinPlateDef(RVec3(500, 0, 0))),
                                   RRigidBody(ShotDef(RVec3::Zero(), RVec3(v, 0, 0)))};
    RIntegrator integrator;
    Step(integrator, bodies, 600);
    EXPECT_FALSE(integrator.NonFinite().has_value()) << v;
    EXPECT_NEAR(bodies[1].Position_W().x(), 499.85, 1e-3) << v << ": stopped at the face";
  }
}
