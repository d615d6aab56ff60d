// Kinematic bodies, gravity scales and axis locks (drag: drag_test.cpp), checked
// against closed forms and conservation laws: free fall, a platform and a
// turntable carrying what stands on them, a kinematic body's exact motion whatever it hits,
// what it wakes, and collisions of locked bodies (momentum on the free axes, energy).
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;
constexpr RScalar kG = 9.81;

RWorldSettings ZeroGravity() { return RWorldSettings{}; }

RScalar TotalEnergy(const std::vector<RRigidBody>& bodies) { return KineticEnergy(bodies); }

}  // namespace

// ---- gravity scale --------------------------------------------------------------------------

// Kick-drift-kick is exact for a constant acceleration: x(t) = x0 + v0 t + s g t^2 / 2 to
// rounding (600 steps of a few roundings each: 1e-13 of the distance travelled, 500 m when
// falling up), for s = 0, 0.5 and -1 (falling up).
TEST(GravityScale, FreeFallFollowsTheScaledParabola) {
  for (const RScalar s : {0.0, 0.5, -1.0}) {
    const RVec3 x0(1, 2, 3), v0(0.5, 4, -1);
    std::vector<RRigidBody> bodies =
        MakeBodies(std::vector<BodyDef>{SphereDef(0.5).Mass(1).At(x0).Moving(v0).GravityScale(s)});
    RIntegrator integrator(EarthGravity());
    RScalar worst = 0;
    for (int n = 1; n <= 600; ++n) {
      integrator.Update(bodies, kDt);
      const RScalar t = n * kDt;
      const RVec3 x = x0 + v0 * t + RVec3(0, -kG * s, 0) * (0.5 * t * t);
      worst = std::max(worst, (bodies[0].Position_W() - x).norm() / (1 + (x - x0).norm()));
    }
    EXPECT_LT(worst, 1e-13) << "scale " << s;
    EXPECT_NEAR(bodies[0].Velocity_W().y(), v0.y() - kG * s * 10, 1e-12) << "scale " << s;
  }
}

// A box with gravity scale 0.5 rests on the ground as any box does: the support it needs
// is half, and it sleeps.
TEST(GravityScale, HalfWeightBoxRestsOnTheGround) {
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      GroundDef(), UnitBoxDef(RVec3(0, 0.5, 0)).GravityScale(0.5)});
  RIntegrator integrator(EarthGravity());
  Step(integrator, bodies, 120);
  EXPECT_NEAR(bodies[1].Position_W().y(), 0.5, 1e-9);
  EXPECT_TRUE(bodies[1].IsSleeping());
}

// ---- kinematic bodies -----------------------------------------------------------------------

// A kinematic body spinning at constant angular velocity about a tilted axis follows the
// exact rotation exp(w t) q0, and its centre x0 + v t, to rounding after 600 steps.
TEST(Kinematic, MovesAndSpinsExactly) {
  const RVec3 w(0.3, 1.2, -0.7), v(2, -1, 0.5), x0(1, 2, 3);
  const RQuat q0 = QuatAxisAngle(RVec3(1, 1, 0).normalized(), 0.4);
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      BoxDef(RVec3(0.5, 0.3, 0.1)).Kinematic().At(x0).Oriented(q0).Moving(v).Spinning(w)});
  const RQuat qB0 = bodies[0].Orientation_WB();
  RIntegrator integrator(EarthGravity());
  Step(integrator, bodies, 600);
  const RScalar t = 600 * kDt;
  EXPECT_LT(QuatAngleBetween(bodies[0].Orientation_WB(), QuatExp(w * t) * qB0), 1e-12);
  EXPECT_LT((bodies[0].ShapePosition_W() - (x0 + v * t)).norm(), 1e-12);
  EXPECT_EQ(bodies[0].Velocity_W(), v);
  EXPECT_EQ(bodies[0].AngularVelocity_W(), w);
  EXPECT_EQ(bodies[0].Mass(), 0);
  EXPECT_EQ(bodies[0].Kind(), RBodyKind::kKinematic);
}

// A platform moving at 1 m/s under a box that starts at rest: friction (mu = 1) accelerates
// the box at g until it moves with the platform, within V / (mu g) = 0.1 s (6 steps); from
// then on it rides along, velocity equal to the platform's, and its place on it fixed.
TEST(Kinematic, MovingPlatformCarriesABox) {
  const RVec3 V(1, 0, 0.5);
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      BoxDef(RVec3(3, 0.25, 3)).Kinematic().At(RVec3(0, -0.25, 0)).Moving(V).Friction(1)
          .Named("platform"),
      BoxDef(RVec3::Constant(0.25)).Mass(1).At(RVec3(0, 0.25, 0)).Friction(1).Named("box")});
  RIntegrator integrator(EarthGravity());
  Step(integrator, bodies, 30);
  const RVec3 offset = bodies[1].Position_W() - bodies[0].Position_W();
  // The slip: V^2 / (2 mu g) = 0.064 m, to the steps' resolution.
  const RScalar slip = V.norm() * 30 * kDt - (bodies[1].Position_W() - RVec3(0, 0.25, 0)).norm();
  EXPECT_NEAR(slip, V.squaredNorm() / (2 * kG), V.norm() * kDt);
  Step(integrator, bodies, 570);
  EXPECT_LT((bodies[1].Velocity_W() - V).norm(), 1e-9);
  EXPECT_LT((bodies[1].Position_W() - bodies[0].Position_W() - offset).norm(), 1e-9);
  EXPECT_EQ(bodies[0].Velocity_W(), V);
}

// A turntable (kinematic, 1 rad/s about y) under a crate that starts at rest 1.5 m from the
// axis. Friction (mu = 1) brings the crate up to the table's surface speed V = w r at up to
// mu g, slipping V^2 / (2 mu g) = 0.115 m: the crate then turns with the table, its angle
// behind the table's by that slip over r, 0.0765 rad (within the 0.017 rad of one step's
// slip, V dt / r), and the lag and its radius stay fixed for the next 9 s (to 3e-5: the
// friction solve's residual creep, measured 1e-6 rad/s); it spins with the table (1e-8
// rad/s). A crate that starts moving with the table does not lag (1e-5 rad).
TEST(Kinematic, TurntableTurnsACrateWithIt) {
  const RScalar w = 1, r = 1.5;
  for (const bool moving : {false, true}) {
    BodyDef crate = BoxDef(RVec3::Constant(0.25)).Mass(1).At(RVec3(r, 0.25, 0)).Friction(1)
                        .Named("crate");
    if (moving) crate.Moving(RVec3(0, 0, -w * r)).Spinning(RVec3(0, w, 0));
    std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
        BoxDef(RVec3(3, 0.25, 3)).Kinematic().At(RVec3(0, -0.25, 0)).Spinning(RVec3(0, w, 0))
            .Friction(1).Named("table"),
        crate});
    RIntegrator integrator(EarthGravity());
    auto lag = [&](int steps) {
      const RVec3 x = bodies[1].Position_W();
      const RScalar table = w * steps * kDt, angle = std::atan2(-x.z(), x.x());
      return std::remainder(table - angle, 2 * M_PI);
    };
    Step(integrator, bodies, 60);
    const RScalar lag1 = lag(60);
    const RScalar radius1 = RVec3(bodies[1].Position_W().x(), 0, bodies[1].Position_W().z()).norm();
    Step(integrator, bodies, 540);
    const RScalar radius2 = RVec3(bodies[1].Position_W().x(), 0, bodies[1].Position_W().z()).norm();
    const RScalar expected = moving ? 0 : w * r / (2 * kG);
    std::printf("turntable (crate %s): lag %.6f rad after 1 s, %.6f after 10 s (slip/r %.6f); "
                "radius %.7f -> %.7f m\n", moving ? "moving" : "at rest", lag1, lag(600), expected,
                radius1, radius2);
    EXPECT_NEAR(lag1, expected, moving ? 1e-5 : w * kDt) << moving;
    EXPECT_NEAR(lag(600), lag1, 3e-5) << moving;
    EXPECT_NEAR(radius2, radius1, 3e-5) << moving;
    EXPECT_NEAR(bodies[1].AngularVelocity_W().y(), w, 1e-8) << moving;
    EXPECT_EQ(bodies[0].AngularVelocity_W(), RVec3(0, w, 0));
  }
}

// A kinematic wall at 2 m/s meets a ball at rest in space: an infinitely heavy body, so the
// ball leaves at (1 + e) 2 m/s (1e-9), and the wall's motion is unchanged bit for bit: its
// velocity, and its position x0 + v t to rounding.
TEST(Kinematic, PushesABallAndIsUnaffectedByIt) {
  for (const RScalar e : {0.0, 0.5, 1.0}) {
    const RVec3 v(2, 0, 0);
    std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
        BoxDef(RVec3(0.5, 2, 2)).Kinematic().At(RVec3(-3, 0, 0)).Moving(v).Restitution(e)
            .Spinning(RVec3(0.5, 0, 0)).Named("wall"),
        SphereDef(0.5).Mass(3).Restitution(e).Friction(0).Named("ball")});
    RIntegrator integrator(ZeroGravity());
    Step(integrator, bodies, 120);
    EXPECT_NEAR(bodies[1].Velocity_W().x(), (1 + e) * v.x(), 1e-9) << e;
    EXPECT_EQ(bodies[0].Velocity_W(), v) << e;
    EXPECT_EQ(bodies[0].AngularVelocity_W(), RVec3(0.5, 0, 0)) << e;
    EXPECT_NEAR(bodies[0].Position_W().x(), -3 + 2 * 120 * kDt, 1e-12) << e;
    // e = 0: pushed, the ball keeps in front of the wall, touching.
    if (e == 0) {
      EXPECT_NEAR(bodies[1].Position_W().x() - bodies[0].Position_W().x(), 1, 1e-3);
    }
  }
}

// Two piles of boxes asleep on the ground, 40 m apart, each three columns of three (1.5 m
// apart: three islands), and a kinematic bar driven through the first at the middle boxes'
// height. The bar moving wakes nothing until it reaches the first column; then it wakes that
// column's island only (the box it hits and the two it holds and stands on), the next
// columns as it reaches them; the far pile sleeps throughout. The bar never sleeps.
TEST(Kinematic, WakesOnlyWhatItTouches) {
  std::vector<BodyDef> defs{GroundDef()};
  for (int pile = 0; pile < 2; ++pile) {
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) {
        defs.push_back(UnitBoxDef(RVec3(40 * pile + 1.5 * i, 0.5 + k, 0))
                           .Named("p" + std::to_string(pile) + "_" + std::to_string(3 * i + k)));
      }
    }
  }
  defs.push_back(BoxDef(RVec3(0.2, 0.2, 3)).Kinematic().At(RVec3(-10, 1.5, 0))
                     .Moving(RVec3(2, 0, 0)).Named("bar"));
  std::vector<RRigidBody> bodies = MakeBodies(defs);
  const RRigidBody& bar = bodies.back();
  auto asleep = [&](int pile) {
    int n = 0;
    for (int i = 0; i < 9; ++i) n += bodies[1 + 9 * pile + i].IsSleeping();
    return n;
  };
  RIntegrator integrator(EarthGravity());
  // The bar reaches the first pile's face (x = -0.5) after (10 - 0.7) / 2 = 4.65 s.
  Step(integrator, bodies, 240);
  EXPECT_EQ(asleep(0), 9);
  EXPECT_EQ(asleep(1), 9);
  EXPECT_FALSE(bar.IsSleeping());
  int woken0 = 0;
  for (int n = 240; n < 600; ++n) {
    integrator.Update(bodies, kDt);
    const int woken = 9 - asleep(0);
    if (woken0 == 0 && woken > 0) {
      // The first touch: the first column (boxes 1..3), not the others.
      EXPECT_EQ(woken, 3) << "step " << n + 1;
      for (int k = 0; k < 3; ++k) EXPECT_FALSE(bodies[1 + k].IsSleeping()) << k;
      // Within a step's motion and the contact allowance of the column's face (x = -0.5).
      EXPECT_NEAR(bar.Position_W().x() + 0.2, -0.5, 2 * kDt + 0.01) << "woken too early or late";
    }
    woken0 = std::max(woken0, woken);
    ASSERT_EQ(asleep(1), 9) << "the far pile woke at step " << n + 1;
  }
  // Every box of the first pile is in the bar's way at y = 1.5 or rests on one that is.
  EXPECT_GT(woken0, 0);
  std::printf("kinematic bar: %d of 9 boxes of the near pile woken, far pile asleep\n", woken0);
}

// A box comes to rest and sleeps on a still kinematic platform (which holds as static
// geometry does and does not keep it awake); the game then sets the platform moving: the
// box wakes in that step and rides along (velocity the platform's within 1e-9 after 1 s).
TEST(Kinematic, StillPlatformHoldsASleeperThatWakesWhenItMoves) {
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      BoxDef(RVec3(3, 0.25, 3)).Kinematic().At(RVec3(0, -0.25, 0)).Friction(1).Named("platform"),
      BoxDef(RVec3::Constant(0.25)).Mass(1).At(RVec3(0, 0.25, 0)).Friction(1).Named("box")});
  RIntegrator integrator(EarthGravity());
  Step(integrator, bodies, 60);
  ASSERT_TRUE(bodies[1].IsSleeping());
  EXPECT_EQ(integrator.PairStats().narrowPhase, 0u) << "a still platform is passive";
  bodies[0].SetVelocity_W(RVec3(0, 0.5, 1));
  Step(integrator, bodies, 1);
  EXPECT_FALSE(bodies[1].IsSleeping());
  Step(integrator, bodies, 60);
  EXPECT_LT((bodies[1].Velocity_W() - RVec3(0, 0.5, 1)).norm(), 1e-9);
}

// ---- locks --------------------------------------------------------------------------------

// A box locked in y slides along x over a sphere field under gravity, struck from above at
// an angle: its y never changes, bit for bit, while it moves on the free axes.
TEST(Locks, LockedLinearAxisKeepsItsCoordinateExactly) {
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      BoxDef(RVec3(0.5, 0.2, 0.5)).Mass(2).At(RVec3(0, 1, 0)).Moving(RVec3(1, 0, 0))
          .LockLinear(false, true, false).Named("slider"),
      SphereDef(0.25).Mass(1).At(RVec3(1.2, 3, 0.1)).Moving(RVec3(0, -1, 0)).Named("ball")});
  RIntegrator integrator(EarthGravity());
  const RScalar y0 = bodies[0].Position_W().y();
  bool hit = false;
  for (int n = 0; n < 240; ++n) {
    integrator.Update(bodies, kDt);
    hit = hit || !integrator.Contacts().empty();
    ASSERT_EQ(bodies[0].Position_W().y(), y0) << n;
    ASSERT_EQ(bodies[0].Velocity_W().y(), 0) << n;
  }
  EXPECT_TRUE(hit);
  EXPECT_GT(std::abs(bodies[0].Position_W().x()), 1) << "it moved on its free axes";
}

// A sphere locked along x, struck off-centre by a free sphere (e = 1, no friction, no
// gravity): the lock takes the x momentum, and the momentum along y and z and the kinetic
// energy are conserved (1e-12). The locked sphere never moves along x.
TEST(Locks, CollisionConservesFreeMomentumAndEnergy) {
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      SphereDef(0.5).Mass(2).Restitution(1).Friction(0).LockLinear(true, false, false)
          .Named("locked"),
      SphereDef(0.5).Mass(1).At(RVec3(-3, 0.4, 0.3)).Moving(RVec3(3, 0, 0)).Restitution(1)
          .Friction(0).Named("free")});
  RIntegrator integrator(ZeroGravity());
  const RVec3 p0 = Momentum(bodies);
  const RScalar E0 = TotalEnergy(bodies);
  Step(integrator, bodies, 120);
  const RVec3 p = Momentum(bodies);
  EXPECT_NEAR(p.y(), p0.y(), 1e-12 * MomentumScale(bodies));
  EXPECT_NEAR(p.z(), p0.z(), 1e-12 * MomentumScale(bodies));
  EXPECT_NEAR(TotalEnergy(bodies) / E0, 1, 1e-12);
  EXPECT_EQ(bodies[0].Position_W().x(), 0);
  EXPECT_GT(bodies[0].Velocity_W().norm(), 0.1) << "the hit moved the locked sphere";
  std::printf("locked sphere struck: |dp_yz| %.2g, dE/E %.2g\n", (p - p0).tail<2>().norm(),
              TotalEnergy(bodies) / E0 - 1);
}

// A box turned off the world axes, with its x and y rotations locked, struck off-centre by
// a sphere (e = 1, no friction): its world angular velocity stays exactly on z, the kinetic
// energy is conserved (1e-12: the solver's inverse inertia is that of the inertia restricted
// to z, consistent with the energy), and after the hit it turns about z at a constant rate,
// exactly: q = exp(w t) q1 to rounding.
TEST(Locks, AngularLocksKeepLockedAxesStillAndConserveEnergy) {
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      BoxDef(RVec3(1, 0.3, 0.2)).Mass(2).Restitution(1).Friction(0)
          .Oriented(QuatAxisAngle(RVec3(1, 2, 3).normalized(), 0.7))
          .LockAngular(true, true, false).Named("locked"),
      SphereDef(0.2).Mass(1).At(RVec3(0.6, -3, 0.05)).Moving(RVec3(0, 3, 0)).Restitution(1)
          .Friction(0).Named("ball")});
  RIntegrator integrator(ZeroGravity());
  const RScalar E0 = TotalEnergy(bodies);
  const RVec3 p0 = Momentum(bodies);
  Step(integrator, bodies, 90);
  const RVec3 w1 = bodies[0].AngularVelocity_W();
  EXPECT_EQ(w1.x(), 0);
  EXPECT_EQ(w1.y(), 0);
  EXPECT_GT(std::abs(w1.z()), 0.1) << "the hit turned the box";
  EXPECT_NEAR(TotalEnergy(bodies) / E0, 1, 1e-12);
  EXPECT_LT((Momentum(bodies) - p0).norm(), 1e-12 * MomentumScale(bodies));
  ASSERT_TRUE(integrator.Contacts().empty()) << "still touching: move the ball further";
  const RQuat q1 = bodies[0].Orientation_WB();
  Step(integrator, bodies, 600);
  EXPECT_EQ(bodies[0].AngularVelocity_W(), w1);
  EXPECT_LT(QuatAngleBetween(bodies[0].Orientation_WB(), QuatExp(w1 * (600 * kDt)) * q1), 1e-12);
  EXPECT_NEAR(TotalEnergy(bodies) / E0, 1, 1e-12);
}

// Rows along which neither body can move (a box locked along z and free to turn only about
// z, on a spinning kinematic table: friction along z; a sphere locked along y resting on the
// ground: the normal) have no effective mass: they take no impulse, and nothing becomes NaN
// (it did: a friction step divided by that zero mass).
TEST(Locks, RowsWithoutEffectiveMassStayFinite) {
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      BoxDef(RVec3(3, 0.25, 3)).Kinematic().At(RVec3(0, -0.25, 0)).Spinning(RVec3(0, 1, 0))
          .Moving(RVec3(0, 0.5, 0)).Named("table"),
      BoxDef(RVec3::Constant(0.25)).Mass(1).At(RVec3(1, 0.25, 0)).LockLinear(false, false, true)
          .LockAngular(true, true, false).Named("crate"),
      GroundDef(RVec3(20, -0.5, 0)),
      SphereDef(0.5).Mass(1).At(RVec3(20, 0.5, 0)).LockLinear(false, true, false).Named("ball")});
  RIntegrator integrator(EarthGravity());
  for (int n = 0; n < 120; ++n) {
    integrator.Update(bodies, kDt);
    ASSERT_TRUE(integrator.NonFiniteInLastStep().empty()) << "step " << n + 1;
  }
  EXPECT_EQ(bodies[1].Position_W().z(), 0);
  EXPECT_EQ(bodies[3].Position_W().y(), 0.5);
  for (const RContact& c : integrator.Contacts()) {
    if (c.b != 3 && c.a != 3) continue;
    for (int k = 0; k < c.manifold.pointCount; ++k) EXPECT_EQ(c.normalImpulse[k], 0);
  }
}

// A sphere locked along x and z (and about z) spins on the ground; a kinematic paddle
// sweeps into it along the xz-plane. The normal passes through the centre and lies in what
// the locks hold, but for rounding (a y component of 1e-16): no motion the sphere may make
// answers it, so the contact gives way as between kinematic bodies and the sphere goes on
// exactly as without the paddle. (Its effective mass, 1e-32 of its own, once took an
// impulse of 1e30 N s and flung the pile it sat in to 1e48 m.)
TEST(Locks, ANormalInsideTheLocksGivesWayToAKinematicBody) {
  auto world = [](bool paddle) {
    std::vector<BodyDef> defs = {
        GroundDef(),
        SphereDef(0.3).Mass(1.9).At(RVec3(0.7, 0.3, 0.4)).Spinning(RVec3(-25, 0.65, 0))
            .LockLinear(true, false, true).LockAngular(false, false, true).Named("ball")};
    if (paddle) {
      defs.push_back(BoxDef(RVec3(3, 0.3, 0.3)).Kinematic().At(RVec3(0, 0.3, -1.5))
                         .Spinning(RVec3(0, 1.5, 0)).Named("paddle"));
    }
    return MakeBodies(defs);
  };
  std::vector<RRigidBody> alone = world(false), hit = world(true);
  RIntegrator a(EarthGravity()), b(EarthGravity());
  bool touched = false;
  for (int n = 0; n < 120; ++n) {
    a.Update(alone, kDt), b.Update(hit, kDt);
    for (const RContact& c : b.Contacts()) touched = touched || (c.b == 2 && c.manifold.pointCount > 0 && c.manifold.query.separation < 0);
    ASSERT_TRUE(b.NonFiniteInLastStep().empty()) << "step " << n + 1;
    ASSERT_LT((hit[1].Position_W() - alone[1].Position_W()).norm(), 1e-9) << "step " << n + 1;
    ASSERT_LT((hit[1].AngularVelocity_W() - alone[1].AngularVelocity_W()).norm(), 1e-9) << "step " << n + 1;
  }
  EXPECT_TRUE(touched) << "the paddle never reached the ball: move it";
}

// A box locked along x, turned 30 degrees about y, pushed by a kinematic wall moving along x
// (no gravity, no friction): the wall's face meets the box's face, so the box is squeezed
// out along z, v_z = 5 m/s / tan 30 degrees, and the contact's impulses pass through its centre:
// it never spins. The wall arrives within a step, so the impact phase defers part of the
// change and the contact phase solves the rest with lever arms shifted by it; the lock's
// reaction, at the centre, cancels the shift's moment for the impulse along x. Without it
// the rows weighed a spin about y the box did not get, and it left spinning.
TEST(Locks, WedgedBoxIsSqueezedOutWithoutSpin) {
  const RScalar angle = M_PI / 6;
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      BoxDef(RVec3(0.5, 0.5, 0.5)).Mass(1).Friction(0).Restitution(0)
          .Oriented(QuatAxisAngle(RVec3::UnitY(), angle)).LockLinear(true, false, false).Named("box"),
      BoxDef(RVec3(0.2, 2, 2)).Kinematic().Friction(0).Restitution(0)
          .Oriented(QuatAxisAngle(RVec3::UnitY(), angle))
          .At(RVec3(-0.5 / std::cos(angle) - 0.2 / std::cos(angle) - 0.04, 0, 0)).Moving(RVec3(5, 0, 0))
          .Named("wall")});
  RIntegrator integrator(ZeroGravity());
  for (int n = 0; n < 30; ++n) {
    integrator.Update(bodies, kDt);
    ASSERT_LT(bodies[0].AngularVelocity_W().norm(), 1e-9) << "step " << n + 1;
  }
  EXPECT_EQ(bodies[0].Position_W().x(), 0);
  // The wall's face moves along its normal n = (cos a, 0, -sin a) at 5 cos a m/s; the box,
  // free along z only, keeps up when -sin a v_z = 5 cos a.
  EXPECT_NEAR(bodies[0].Velocity_W().z(), -5 / std::tan(angle), 1e-9);
}

// All six axes locked: the body is kinematic and at rest, with no NaN anywhere: a ball
// bounces off it as off a wall of infinite mass (v -> -e v), and it never moves.
TEST(Locks, AllSixLockedActsAsKinematic) {
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      BoxDef(RVec3(0.5, 2, 2)).Mass(5).Restitution(0.5).Moving(RVec3(1, 2, 3))
          .LockLinear(true, true, true).LockAngular(true, true, true).Named("block"),
      SphereDef(0.5).Mass(1).At(RVec3(-3, 0.3, 0)).Moving(RVec3(4, 0, 0)).Restitution(0.5)
          .Friction(0).Named("ball")});
  EXPECT_EQ(bodies[0].Kind(), RBodyKind::kKinematic);
  EXPECT_EQ(bodies[0].Mass(), 0);
  EXPECT_EQ(bodies[0].InvMass(), 0);
  EXPECT_EQ(bodies[0].Velocity_W(), RVec3::Zero());
  RIntegrator integrator(EarthGravity());
  const RVec3 x0 = bodies[0].Position_W();
  Step(integrator, bodies, 60);
  EXPECT_EQ(bodies[0].Position_W(), x0);
  EXPECT_NEAR(bodies[1].Velocity_W().x(), -2, 1e-9);
}

// ---- bad input ------------------------------------------------------------------------------

// Every invalid new field is refused at the door, naming the field as the scene format does.
TEST(BodyKindsInput, InvalidFieldsThrowNamingTheField) {
  struct Case {
    const char* field;
    BodyDef def;
  };
  const RScalar nan = std::nan("");
  std::vector<Case> cases = {
      {"linear_damping", SphereDef(1).Damping(-1, 0)},
      {"linear_damping", SphereDef(1).Damping(nan, 0)},
      {"angular_damping", SphereDef(1).Damping(0, -0.5)},
      {"angular_damping", SphereDef(1).Damping(0, HUGE_VAL)},
      {"gravity_scale", SphereDef(1).GravityScale(nan)},
      {"gravity_scale", SphereDef(1).GravityScale(-HUGE_VAL)},
  };
  BodyDef unknown = SphereDef(1);
  unknown.kind = static_cast<RBodyKind>(7);
  cases.push_back({"kind", unknown});
  for (const Case& c : cases) {
    try {
      RRigidBody b(c.def);
      ADD_FAILURE() << c.field << ": accepted";
    } catch (const RBodyError& e) {
      EXPECT_EQ(e.Field(), c.field) << e.what();
    }
  }
  // Setters refuse the same values and leave the body as it was.
  RRigidBody b(SphereDef(1).Damping(0.5, 0.25).GravityScale(2));
  EXPECT_THROW(b.SetLinearDamping(-1), RBodyError);
  EXPECT_THROW(b.SetAngularDamping(nan), RBodyError);
  EXPECT_THROW(b.SetGravityScale(HUGE_VAL), RBodyError);
  EXPECT_EQ(b.LinearDamping(), 0.5);
  EXPECT_EQ(b.AngularDamping(), 0.25);
  EXPECT_EQ(b.GravityScale(), 2);
}
