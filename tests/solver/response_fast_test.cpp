// Fast and spinning bodies: no tunnelling through a thin plate or a wall, the same motion
// 1e6 m from the origin, and impacts of spinning, glancing and deeply overlapping bodies that
// gain no energy.
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "support/RandomWorlds.h"
#include "support/ReferenceScenes.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

// The tunnelling shot, frictionless: with friction an oblique hit spins it up to
// 1.7e4 rad/s and it tumbles off (chaotic).
RBodyDef Shot(const RVec3& origin, const RVec3& v) { return ShotDef(origin, v).Friction(0); }

}  // namespace

// A ball launched by an impulse this very step is as fast as one that has been flying: the
// broad phase and the speculative margin use the velocity the body will move with, so it
// stops at the wall instead of passing through it.
TEST(Response, ImpulseLaunchedBallDoesNotTunnel) {
  RBodyDef wall;
  wall.name = "wall";
  wall.shape = RShape::Box(RVec3(0.1, 1, 1));
  wall.kind = RBodyKind::kStatic;
  wall.position_W = RVec3(2, 0, 0);
  RBodyDef ball;
  ball.name = "ball";
  ball.shape = RShape::Sphere(0.1);
  ball.mass = 1;
  ball.restitution = 0;
  wall.restitution = 0;
  std::vector<RRigidBody> bodies{RRigidBody(wall), RRigidBody(ball)};
  bodies[1].AddImpulse_W(RVec3(200, 0, 0));
  RIntegrator integrator;
  integrator.Update(bodies, 1.0 / 60);
  EXPECT_EQ(integrator.Contacts().size(), 1u);
  EXPECT_LE(bodies[1].Position_W().x(), 1.8 + 1e-9) << "stopped at the wall's face";
  EXPECT_LT(bodies[1].Velocity_W().x(), 1e-9);
}

// Fast bodies do not tunnel: a 0.2 m projectile at 2 km/s (33 m per step at 60 Hz, 330 times
// the plate's thickness) against a 0.1 m static plate, at the origin and 1e6 m from it,
// head-on and at 30 degrees. It stops at the plate's face (restitution 0): the impact
// happens at its time within the step, so it is not stopped short either. A projectile
// that does not respond flies on and is reported hitting the plate.
TEST(Response, ProjectileAtTwoKilometresPerSecondStopsAtAThinPlate) {
  for (RScalar offset : {0.0, 1e6}) {
    for (RScalar angle : {0.0, 30.0}) {
      for (bool responds : {true, false}) {
        const RVec3 o(offset, offset, -offset);
        const RBodyDef plate = ThinPlateDef(o + RVec3(50, 0, 0));
        const RScalar a = angle * kPi / 180;
        RBodyDef shot = Shot(o, 2000 * RVec3(std::cos(a), std::sin(a), 0));
        shot.responds = responds;
        std::vector<RRigidBody> bodies{RRigidBody(plate), RRigidBody(shot)};
        RIntegrator integrator;
        bool reported = false;
        for (int i = 0; i < 10; ++i) {
          integrator.Update(bodies, 1.0 / 60);
          for (const RContact& c : integrator.Contacts()) {
            reported = reported || c.timeOfImpact <= 1.0 / 60;
          }
        }
        const RScalar x = bodies[1].Position_W().x() - o.x();
        SCOPED_TRACE(::testing::Message() << "offset " << offset << " angle " << angle
                                          << " responds " << responds);
        EXPECT_TRUE(reported) << "the hit is reported";
        if (responds) {
          // Stopped at the face (x = 49.95 - 0.1), within the position correction's slop,
          // and sliding along it without friction at 30 degrees.
          EXPECT_NEAR(x, 49.85, 1e-3);
          EXPECT_LT(std::abs(bodies[1].Velocity_W().x()), 1e-9 * 2000) << "at rest along the normal, to 1e-9 of the impact speed";
          EXPECT_NEAR(bodies[1].Velocity_W().y(), 2000 * std::sin(a), 1e-9 * 2000);
        } else {
          EXPECT_GT(x, 100.0) << "flies through: it was reported, not stopped";
          EXPECT_EQ(bodies[1].Velocity_W(), shot.velocity_W);
        }
        EXPECT_FALSE(integrator.NonFinite().has_value());
      }
    }
  }
}

// The same scene 1e6 m from the origin moves the same way: every body's offset-corrected
// position within 1e-6 m of the scene at the origin at every step (asked: 1e-6 m; a double
// resolves 1.2e-10 m there, so the solver must not amplify rounding by more than 1e4).
static RScalar WorstOffsetDifference(std::vector<RBodyDef> defs, RWorldSettings settings,
                                     RScalar dt, int steps) {
  settings.shortcuts.sleeping = false;  // the solver's rounding, every step simulated
  const RVec3 offset(1e6, -1e6, 1e6);
  std::vector<RRigidBody> near, far;
  for (const RBodyDef& d : defs) near.emplace_back(d);
  for (RBodyDef& d : defs) d.position_W += offset;
  for (const RBodyDef& d : defs) far.emplace_back(d);
  RIntegrator a(settings), b(settings);
  RScalar worst = 0;
  for (int i = 0; i < steps; ++i) {
    a.Update(near, dt);
    b.Update(far, dt);
    for (std::size_t k = 0; k < near.size(); ++k) {
      worst = std::max(worst, (far[k].Position_W() - offset - near[k].Position_W()).norm());
    }
  }
  return worst;
}

TEST(Response, FarFromTheOriginTheMotionIsTheSame) {
  {
    const RScene scene = LoadReferenceScene("box_stack_10");
    const RScalar worst = WorstOffsetDifference(scene.bodies, scene.settings, scene.dt, 600);
    std::printf("box_stack_10 at 1e6 m: positions within %.3g m of the stack at the origin\n", worst);
    EXPECT_LT(worst, 1e-6);
  }
  {
    // Friction: the box sliding to a stop, and sliding down the incline.
    RBodyDef ground = GroundDef();
    ground.friction = 0.5;
    RBodyDef box = UnitBoxDef(RVec3(0, 0.5, 0));
    box.friction = 0.5;
    box.velocity_W = RVec3(5, 0, 0);
    RWorldSettings settings = EarthGravity();
    const RScalar slide = WorstOffsetDifference({ground, box}, settings, 1.0 / 60, 180);
    const RQuat tilt(Eigen::AngleAxis<RScalar>(20 * kPi / 180, RVec3::UnitZ()));
    ground.q_WS = box.q_WS = tilt;
    ground.position_W = tilt * RVec3(0, -0.5, 0);
    box.position_W = tilt * RVec3(0, 0.5, 0);
    box.velocity_W.setZero();
    ground.friction = box.friction = 0.2;
    const RScalar incline = WorstOffsetDifference({ground, box}, settings, 1.0 / 60, 120);
    std::printf("friction at 1e6 m: sliding box within %.3g m, incline within %.3g m\n", slide,
                incline);
    EXPECT_LT(slide, 1e-6);
    EXPECT_LT(incline, 1e-6);
  }
  {
    // Tunnelling: the 2 km/s projectile and the plate.
    const RBodyDef plate = ThinPlateDef(RVec3(50, 0, 0));
    const RBodyDef shot = Shot(RVec3::Zero(), RVec3(1732.05, 1000, 0));
    const RScalar worst = WorstOffsetDifference({plate, shot}, RWorldSettings{}, 1.0 / 60, 30);
    std::printf("projectile at 1e6 m: within %.3g m\n", worst);
    EXPECT_LT(worst, 1e-6);
  }
}

// Review finding, kept as a regression: two spinning boxes meeting off-centre at 33 m/s
// (corners sweep 10 cm per step). Momentum is exact and the kinetic energy never grows,
// with and without friction. (With restitution 1 the energy should stay too; it does not
// yet: an impact's geometry ignores the rotation within the step, the corners overlap and
// the overlap is resolved inelastically, 1.3% here. Asserted: no gain.)
TEST(Response, SpinningBoxesCollideWithoutGainingEnergy) {
  for (RScalar mu : {0.0, 0.5}) {
    RBodyDef a = UnitBoxDef(RVec3(0, 0, 0));
    a.shape.halfExtents = RVec3(0.5, 0.3, 0.4);
    a.mass = 2;
    a.position_W = RVec3(-2, 0.1, 0.05);
    a.velocity_W = RVec3(30, 0.5, 0.2);
    a.angularVelocity_W = RVec3(1, 7, 3);
    a.restitution = 1, a.friction = mu;
    RBodyDef b = UnitBoxDef(RVec3(0, 0, 0));
    b.shape.halfExtents = RVec3(0.4, 0.5, 0.6);
    b.position_W = RVec3(0.1, 0, 0);
    b.velocity_W = RVec3(-3, 0, 0.1);
    b.angularVelocity_W = RVec3(0, -2, 5);
    b.restitution = 1, b.friction = mu;
    std::vector<RRigidBody> bodies{RRigidBody(a), RRigidBody(b)};
    RIntegrator integrator;
    const RVec3 p0 = Momentum(bodies);
    RScalar e = KineticEnergy(bodies), worstGain = 0;
    bool collided = false;
    for (int i = 0; i < 60; ++i) {
      integrator.Update(bodies, 1.0 / 60);
      collided = collided || !integrator.Contacts().empty();
      const RScalar ek = KineticEnergy(bodies);
      worstGain = std::max(worstGain, (ek - e) / e);
      e = ek;
    }
    EXPECT_TRUE(collided) << mu;
    EXPECT_LT((Momentum(bodies) - p0).norm(), 1e-12 * 63) << mu;
    EXPECT_LT(worstGain, 1e-12) << mu;
    EXPECT_FALSE(integrator.NonFinite().has_value()) << mu;
  }
}

// Two cubes of the debris cloud (state after step 306 of one trajectory), spinning at
// 5.5 rad/s and closing at 8 cm/s, 0.3 mm apart: a speculative contact. The impulse at the
// end of the step, solved with the lever arms of its start, used to be applied with the
// contact point turned 0.08 m further, and the pair gained 1e-5 of its energy in one step.
TEST(Response, SpinningCubesInASpeculativeContactGainNoEnergy) {
  auto cube = [](const RVec3& x, const RQuat& q, const RVec3& v, const RVec3& w) {
    RBodyDef d;
    d.shape = RShape::Box(RVec3::Constant(0.5));
    d.mass = 1, d.restitution = 1, d.friction = 0;
    d.position_W = x, d.q_WS = q, d.velocity_W = v, d.angularVelocity_W = w;
    return RRigidBody(d);
  };
  std::vector<RRigidBody> bodies{
      cube({0x1.4181affc98ae6p+4, 0x1.bb1c9fd3a89c8p+2, 0x1.c3814fc53c9c3p+2},
           RQuat(-0x1.6b1ef790a41f2p-2, 0x1.3b6e6f4be71c7p-2, 0x1.cbf31458699ep-9, 0x1.c3ff867354997p-1),
           {0x1.e680e9c702d19p+0, -0x1.0be5a8377db08p-1, 0x1.6c2e492c22b07p+1},
           {0x1.36c4e846a49abp+2, 0x1.90d2ccaaf69cp-4, 0x1.54e5a31cd349fp+1}),
      cube({0x1.3a4b0c49fe724p+4, 0x1.75cec2d7c9b6p+2, 0x1.8ed6d1c68578fp+2},
           RQuat(0x1.b7b1a47eaa29ep-2, 0x1.c61e7e8b2132ep-1, 0x1.2a666fe8ac288p-3, 0x1.67bb28bd0bcbbp-4),
           {0x1.2dea3356a35p+1, 0x1.81f2ab63847eap-1, -0x1.0cf421a43922fp-2},
           {0x1.fd2871362654fp+0, -0x1.69a70bae8956dp-1, -0x1.7bc107b32c2e8p-3})};
  RIntegrator integrator;
  const RScalar e0 = KineticEnergy(bodies);
  const RVec3 p0 = Momentum(bodies);
  integrator.Update(bodies, RScalar(1) / 60);
  ASSERT_EQ(integrator.Contacts().size(), 1u);
  EXPECT_GT(integrator.Contacts()[0].normalImpulse[0], 0) << "the contact must push";
  EXPECT_LE(KineticEnergy(bodies), e0 * (1 + 1e-14));
  EXPECT_LE((Momentum(bodies) - p0).norm(), 1e-14 * p0.norm());
}

// A 0.4 m box at 1.6 km/s glancing off a static sphere (a pair of the seed-3 world below,
// to the last digit). It bounces 0.0097 s into the step and, along the normal of the step's
// start, still closes on the sphere; the speculative row stops that after the bounce, so
// it acts on the box's post-impact path, whose lever arm is 2.2 m longer than the one it
// was solved with: the box gained 17 times its energy in one step, as spin, and 1.9e5
// times in three. Zero gravity: the kinetic energy may only fall.
TEST(Response, FastBoxGlancingOffAStaticSphereGainsNoEnergy) {
  std::vector<RRigidBody> bodies{
      RRigidBody(SphereDef(0.65644959643761602)
                     .Static()
                     .At({34.746110386475763, 23.680746051324935, 19.275314896108327})
                     .Named("sphere")),
      RRigidBody(BoxDef({0.19871117906568941, 0.17562696044879514, 0.11294405116430083})
                     .Mass(9.4513309353620265)
                     .At({29.243405259829821, 15.274360945822869, 6.1694652463515975})
                     .Oriented(RQuat(0.4140360031576017, -0.50698087935548475,
                                     -0.019209808914879112, 0.75576157569611302))
                     .Moving({603.56755291662466, 779.43264375072067, 1268.8887611559098})
                     .Spinning({1.2805098972975664, -0.92578019668936462, -1.7889169701986285})
                     .Named("box"))};
  RIntegrator integrator;
  const RScalar e0 = KineticEnergy(bodies);
  RScalar previous = e0;
  bool hit = false;
  for (int i = 0; i < 30; ++i) {
    integrator.Update(bodies, RScalar(1) / 60);
    for (const RContact& c : integrator.Contacts()) {
      hit = hit || (std::isfinite(c.timeOfImpact) && c.normalImpulse[0] > 0);
    }
    const RScalar e = KineticEnergy(bodies);
    EXPECT_LE(e, previous * (1 + 1e-14)) << "step " << i;
    previous = e;
  }
  EXPECT_TRUE(hit) << "the box must hit the sphere";
  EXPECT_LE(previous, e0);
  EXPECT_FALSE(integrator.NonFinite().has_value());
}

// Random worlds (RandomWorlds.h): 305 bodies from 1 cm to 100 m, many spawned deep inside
// others, 5% at 3 km/s, with and without gravity. Contacts may only take energy out, so
// after every step the kinetic energy should be at most the initial one plus the potential
// energy gravity has released so far (m g . (x - x0) summed over the bodies; position
// correction moves bodies without changing their energy and only spends this margin).
// Seed 3 once grew without bound (1.2e8 J to 1e221 J by the twelfth step: the lever arms
// after an impact; FastBoxGlancingOffAStaticSphereGainsNoEnergy). Seeds 9 and 22 hold a
// 1 cm hull of 7 kg that an impact sets turning at 1e4 rad/s: last step's impulses, applied
// as the next step's warm start at arms that have swung since, put 45 times the world's
// kinetic energy in within three steps, which the passes could not take out again
// (RContactSolver::WarmStartIslandVelocities).
void StepDeepOverlapWorld(std::uint64_t seed, const RVec3& g_W) {
  std::vector<RRigidBody> bodies = MakeBodies(RandomWorld(seed, RVec3::Zero(), 300, 40));
  RWorldSettings settings;
  settings.gravity_W = g_W;
  RIntegrator integrator(settings);
  std::vector<RVec3> x0_W;
  for (const RRigidBody& b : bodies) x0_W.push_back(b.Position_W());
  const RScalar e0 = KineticEnergy(bodies);
  for (int i = 0; i < 60; ++i) {
    integrator.Update(bodies, RScalar(1) / 60);
    RScalar released = 0;
    for (std::size_t k = 0; k < bodies.size(); ++k) {
      released += bodies[k].Mass() * g_W.dot(bodies[k].Position_W() - x0_W[k]);
    }
    ASSERT_LE(KineticEnergy(bodies), e0 + released + 1e-12 * e0) << "seed " << seed << ", step " << i;
  }
  EXPECT_FALSE(integrator.NonFinite().has_value());
}

// The worlds are drawn the same by every compiler (RandomWorlds.h), and the engine steps them
// the same, bit for bit, in the gcc and clang builds.
TEST(Response, RandomWorldsOfDeepOverlapsGainNoEnergy) {
  for (const std::uint64_t seed : {3, 9, 22}) {
    StepDeepOverlapWorld(seed, RVec3(0, -9.81, 0));
    StepDeepOverlapWorld(seed, RVec3::Zero());
  }
}
