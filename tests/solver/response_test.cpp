// Collision response against closed forms and conservation laws: impulses, restitution,
// the separating-velocity guard, reporting.
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#include <gtest/gtest.h>

#include <cmath>

#include "support/RandomWorlds.h"
#include "support/ReferenceScenes.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

// A frictionless sphere: the closed forms below have no tangential impulse.
RBodyDef Ball(const char* name, RScalar r, RScalar m, const RVec3& x, const RVec3& v, RScalar e) {
  return SphereDef(r).Named(name).Mass(m).At(x).Moving(v).Restitution(e).Friction(0);
}

// The tunnelling shot, frictionless: with friction an oblique hit spins it up to
// 1.7e4 rad/s and it tumbles off (chaotic).
RBodyDef Shot(const RVec3& origin, const RVec3& v) { return ShotDef(origin, v).Friction(0); }

}  // namespace

// Head-on collision of two spheres: v1' = (m1 v1 + m2 v2 - m2 e (v1 - v2)) / (m1 + m2) and
// symmetrically; exact for one contact point, so to rounding (1e-9 relative asked).
TEST(Response, HeadOnCollisionsMatchTheClosedForm) {
  for (RScalar e : {0.0, 0.3, 0.7, 1.0}) {
    for (RScalar m2 : {1.0, 3.0, 1000.0}) {
      const RScalar m1 = 1, v1 = 3, v2 = -1;
      std::vector<RRigidBody> bodies = MakeBodies(HeadOnSpheres(m1, v1, m2, v2, e));
      RIntegrator integrator;
      Step(integrator, bodies, 240, 1.0 / 120);
      const RScalar u1 = (m1 * v1 + m2 * v2 - m2 * e * (v1 - v2)) / (m1 + m2);
      const RScalar u2 = (m1 * v1 + m2 * v2 + m1 * e * (v1 - v2)) / (m1 + m2);
      EXPECT_NEAR(bodies[0].Velocity_W().x(), u1, 1e-9 * std::abs(v1)) << e << " " << m2;
      EXPECT_NEAR(bodies[1].Velocity_W().x(), u2, 1e-9 * std::abs(v1)) << e << " " << m2;
      EXPECT_TRUE(bodies[0].Velocity_W().tail<2>().isZero(1e-15));
    }
  }
}

// Oblique collisions of spheres (friction 0): along the line of centres at contact the
// head-on closed form, across it nothing changes. The impact is found at its moment within
// the step, so the line of centres is the one at contact (at the start of the step it is
// off by up to a step's travel). Sphere 2 is offset by b across the line of motion.
TEST(Response, ObliqueCollisionsMatchTheClosedForm) {
  for (RScalar e : {0.0, 0.5, 1.0}) {
    for (RScalar m2 : {1.0, 7.0}) {
      for (RScalar offset : {0.3, 0.77}) {
        const RScalar m1 = 1, r = 0.5;
        const RVec3 v1(4, 0, 0), v2(-1, 0.5, 0);
        // Start 2.13 m apart along x so that contact falls inside a step, not at its start.
        std::vector<RRigidBody> bodies{RRigidBody(Ball("a", r, m1, RVec3(-2.13, 0, 0), v1, e)),
                                       RRigidBody(Ball("b", r, m2, RVec3(0, offset, 0.1), v2, e))};
        // The closed form: the contact time t* solves |d0 + (v2 - v1) t| = 2r.
        const RVec3 d0 = bodies[1].Position_W() - bodies[0].Position_W(), w = v2 - v1;
        const RScalar qa = w.dot(w), qb = 2 * d0.dot(w), qc = d0.dot(d0) - 4 * r * r;
        const RScalar tc = (-qb - std::sqrt(qb * qb - 4 * qa * qc)) / (2 * qa);
        const RVec3 n = (d0 + w * tc).normalized();
        const RScalar u1 = v1.dot(n), u2 = v2.dot(n);
        const RScalar u1p = (m1 * u1 + m2 * u2 - m2 * e * (u1 - u2)) / (m1 + m2);
        const RScalar u2p = (m1 * u1 + m2 * u2 + m1 * e * (u1 - u2)) / (m1 + m2);
        const RVec3 expect1 = v1 + (u1p - u1) * n, expect2 = v2 + (u2p - u2) * n;
        RIntegrator integrator;
        Step(integrator, bodies, 120);
        SCOPED_TRACE(::testing::Message() << "e " << e << " m2 " << m2 << " offset " << offset);
        EXPECT_LT((bodies[0].Velocity_W() - expect1).norm(), 1e-9 * v1.norm());
        EXPECT_LT((bodies[1].Velocity_W() - expect2).norm(), 1e-9 * v1.norm());
        EXPECT_LT(bodies[0].AngularVelocity_W().norm(), 1e-9) << "no friction, no spin";
      }
    }
  }
}

// Boxes meeting face to face, head-on: the closed form of the 1D collision, no spin.
TEST(Response, BoxesHeadOnMatchTheClosedForm) {
  for (RScalar e : {0.0, 0.4, 1.0}) {
    RBodyDef a = UnitBoxDef(RVec3::Zero());
    a.position_W = RVec3(-3, 0, 0);
    a.velocity_W = RVec3(5, 0, 0);
    a.restitution = e;
    RBodyDef b = UnitBoxDef(RVec3::Zero());
    b.mass = 3;
    b.position_W = RVec3(1.27, 0, 0);
    b.velocity_W = RVec3(-1, 0, 0);
    b.restitution = e;
    std::vector<RRigidBody> bodies{RRigidBody(a), RRigidBody(b)};
    RIntegrator integrator;
    Step(integrator, bodies, 120);
    const RScalar u1 = (5 + 3 * -1 - 3 * e * 6) / 4, u2 = (5 + 3 * -1 + e * 6) / 4;
    EXPECT_NEAR(bodies[0].Velocity_W().x(), u1, 1e-9 * 5) << e;
    EXPECT_NEAR(bodies[1].Velocity_W().x(), u2, 1e-9 * 5) << e;
    EXPECT_LT(bodies[0].AngularVelocity_W().norm() + bodies[1].AngularVelocity_W().norm(), 1e-9);
  }
}

// The reference scene (scenes/), through the scene loader.
TEST(Response, SharedHeadOnElasticScene) {
  const RScene scene = LoadReferenceScene("head_on_elastic");
  std::vector<RRigidBody> bodies = CreateBodies(scene);
  RIntegrator integrator(scene.settings);
  Step(integrator, bodies, scene.steps, scene.dt);
  // m = 1 at 3 m/s against m = 3 at -1 m/s, e = 1: -3 and +1 m/s.
  EXPECT_NEAR(bodies[0].Velocity_W().x(), -3, 1e-12);
  EXPECT_NEAR(bodies[1].Velocity_W().x(), 1, 1e-12);
}

// debris_cloud_1000: 1000 cubes in zero g, restitution 1, no friction. Every impulse is
// applied equal and opposite, so momentum is conserved to rounding (1e-12 relative to the
// sum of |m v|), and no step may gain kinetic energy beyond rounding.
TEST(Response, DebrisCloudConservesMomentumAndNeverGainsEnergy) {
  const RScene scene = LoadReferenceScene("debris_cloud_1000");
  std::vector<RRigidBody> bodies = CreateBodies(scene);
  RIntegrator integrator(scene.settings);
  const RVec3 p0 = Momentum(bodies);
  const RScalar scale = MomentumScale(bodies);
  RScalar ePrev = KineticEnergy(bodies), worstP = 0, worstGain = 0;
  std::uint64_t contacts = 0;
  for (std::uint64_t i = 0; i < scene.steps; ++i) {
    integrator.Update(bodies, scene.dt);
    contacts += integrator.Contacts().size();
    worstP = std::max(worstP, (Momentum(bodies) - p0).norm() / scale);
    const RScalar e = KineticEnergy(bodies);
    worstGain = std::max(worstGain, (e - ePrev) / ePrev);
    ePrev = e;
  }
  std::printf("debris cloud: %llu contacts, max momentum drift %.3g of sum |m v|, max energy "
              "gain per step %.3g\n", static_cast<unsigned long long>(contacts), worstP, worstGain);
  EXPECT_GT(contacts, 100u) << "the scene must actually collide";
  EXPECT_LT(worstP, 1e-12);
  EXPECT_LT(worstGain, 1e-12);
}

// Without position correction (whose pseudo-velocities move bodies without momentum), the
// impulses also conserve angular momentum about any point: equal and opposite at the same
// contact point.
TEST(Response, ImpulsesConserveAngularMomentum) {
  const RScene scene = LoadReferenceScene("debris_cloud_1000");
  std::vector<RRigidBody> bodies = CreateBodies(scene);
  RWorldSettings settings = scene.settings;
  settings.positionCorrection = 0;
  RIntegrator integrator(settings);
  const RVec3 l0 = AngularMomentum(bodies);
  RScalar scale = 0;
  for (const RRigidBody& b : bodies) {
    scale += b.Position_W().norm() * b.Mass() * b.Velocity_W().norm() + b.AngularMomentum_W().norm();
  }
  RScalar worst = 0;
  for (int i = 0; i < 300; ++i) {
    integrator.Update(bodies, scene.dt);
    worst = std::max(worst, (AngularMomentum(bodies) - l0).norm() / scale);
  }
  EXPECT_LT(worst, 1e-12);
}

// Bodies that overlap but already separate get no impulse (the separating-velocity guard),
// and a body with responds = false is reported, not bounced, and pushes nothing.
TEST(Response, SeparatingGuardAndNonRespondingBodies) {
  {
    std::vector<RRigidBody> bodies{
        RRigidBody(Ball("a", 0.5, 1, RVec3(0, 0, 0), RVec3(-1, 0, 0), 1)),
        RRigidBody(Ball("b", 0.5, 1, RVec3(0.9, 0, 0), RVec3(1, 0, 0), 1))};
    RWorldSettings settings;
    settings.positionCorrection = 0;
    RIntegrator integrator(settings);
    integrator.Update(bodies, 1.0 / 60);
    ASSERT_EQ(integrator.Contacts().size(), 1u);
    EXPECT_EQ(integrator.Contacts()[0].normalImpulse[0], 0);
    EXPECT_EQ(bodies[0].Velocity_W(), RVec3(-1, 0, 0));
  }
  {
    RBodyDef missile = Ball("missile", 0.1, 1, RVec3(0, 0, 0.5), RVec3(0, 0, -30), 0);
    missile.responds = false;
    RBodyDef crate = Ball("crate", 0.5, 1, RVec3(0, 0, 0), RVec3::Zero(), 0);
    std::vector<RRigidBody> bodies{RRigidBody(missile), RRigidBody(crate)};
    RIntegrator integrator;
    integrator.Update(bodies, 1.0 / 60);
    ASSERT_EQ(integrator.Contacts().size(), 1u);
    EXPECT_FALSE(integrator.Contacts()[0].resolved);
    EXPECT_EQ(bodies[0].Velocity_W(), RVec3(0, 0, -30));
    EXPECT_EQ(bodies[1].Velocity_W(), RVec3::Zero());
  }
}

// A stack stands for its 600 steps: the top box moves at most 1 mm sideways, no resting
// contact (the second half of the run, after the cold start's transient) overlaps more than
// 2 mm, and the top sinks at most 2 mm per box.
static void ExpectStackStands(const char* label, std::vector<RRigidBody> bodies,
                       RWorldSettings settings, RScalar dt, std::uint64_t steps) {
  // The solver's own standing: asleep, a stack would stand whatever the solver did.
  settings.shortcuts.sleeping = false;
  RIntegrator integrator(settings);
  const RVec3 top0 = bodies.back().ShapePosition_W();
  RScalar worstOverlap = 0, worstSideways = 0, transientOverlap = 0;
  for (std::uint64_t i = 0; i < steps; ++i) {
    integrator.Update(bodies, dt);
    for (const RContact& c : integrator.Contacts()) {
      RScalar& worst = i < steps / 2 ? transientOverlap : worstOverlap;
      worst = std::max(worst, -c.manifold.query.separation);
    }
    const RVec3 d = bodies.back().ShapePosition_W() - top0;
    worstSideways = std::max(worstSideways, std::hypot(d.x(), d.z()));
  }
  const RScalar sink = top0.y() - bodies.back().ShapePosition_W().y();
  const RScalar boxes = static_cast<RScalar>(bodies.size() - 1);
  std::printf("%s: top moved %.3g mm sideways, sank %.3g mm; resting overlap %.3g mm "
              "(%.3g mm in the first %llu steps)\n", label, worstSideways * 1e3, sink * 1e3,
              worstOverlap * 1e3, transientOverlap * 1e3,
              static_cast<unsigned long long>(steps / 2));
  EXPECT_LT(worstSideways, 1e-3) << label;
  EXPECT_LT(worstOverlap, 2e-3) << label;
  EXPECT_LT(sink, 2e-3 * boxes) << label;
  EXPECT_GT(sink, -1e-3) << label << ": no box is pushed up";
  // Reported at rest: the velocities end each step at zero, to the direct solve's
  // regularisation (1e-9 of the impulses, a few 1e-9 m/s here); before the end-of-step
  // impulses every box reported the half-kick g dt / 2 = 0.08 m/s.
  for (const RRigidBody& b : bodies) {
    EXPECT_LT(b.Velocity_W().norm(), 1e-7) << label << ": " << b.Name() << " is reported at rest";
  }
  EXPECT_FALSE(integrator.NonFinite().has_value());
}

TEST(Response, TenBoxStackStands) {
  const RScene scene = LoadReferenceScene("box_stack_10");
  ExpectStackStands("box_stack_10", CreateBodies(scene), scene.settings, scene.dt, scene.steps);
}

// Twenty unit boxes, each resting exactly on the one below at the start.
TEST(Response, TwentyBoxStackStands) {
  // Friction 0.5 on every body (the default).
  ExpectStackStands("box_stack_20", MakeBodies(BoxStackDefs(20)), EarthGravity(), 1.0 / 60, 600);
}

// Newton's cradle: a striker hits a row of four touching equal spheres, restitution 1. The
// impulse travels down the row: the last ball leaves with the striker's speed and the others
// stop (asked: at least 99%, the others at most 1%; sequential impacts give it exactly).
// With the row spaced by a micrometre, the impacts happen in successive steps instead.
TEST(Response, NewtonsCradle) {
  for (RScalar spacing : {0.0, 1e-6}) {
    const RScalar v0 = 2;
    std::vector<RRigidBody> bodies{
        RRigidBody(Ball("striker", 0.5, 1, RVec3(-2, 0, 0), RVec3(v0, 0, 0), 1))};
    for (int i = 0; i < 4; ++i) {
      bodies.emplace_back(Ball("ball", 0.5, 1, RVec3(i * (1 + spacing), 0, 0), RVec3::Zero(), 1));
    }
    RIntegrator integrator;
    Step(integrator, bodies, 120);
    EXPECT_NEAR(bodies.back().Velocity_W().x(), v0, 1e-9 * v0) << spacing;
    for (std::size_t i = 0; i + 1 < bodies.size(); ++i) {
      EXPECT_LT(bodies[i].Velocity_W().norm(), 1e-9 * v0) << spacing << " ball " << i;
    }
    EXPECT_NEAR(KineticEnergy(bodies), 0.5 * v0 * v0, 1e-12);
  }
}

// Mass ratio 1000:1: a 1000 kg box resting on a 1 kg box on the ground. Sequential
// impulses alone pass the heavy box's weight down a fraction 1/1000 per pass, and it sinks
// through; the island's direct solve holds it. Asked: at most 2 mm of overlap per contact.
TEST(Response, HeavyBoxOnLightBoxHolds) {
  for (RScalar heavyMass : {1000.0, 1e4}) {
    RBodyDef ground = GroundDef();
    ground.friction = 0.5;
    RBodyDef light = UnitBoxDef(RVec3(0, 0.5, 0));
    light.friction = 0.5;
    RBodyDef heavy = UnitBoxDef(RVec3(0, 1.5, 0));
    heavy.name = "heavy";
    heavy.mass = heavyMass;
    heavy.friction = 0.5;
    std::vector<RRigidBody> bodies{RRigidBody(ground), RRigidBody(light), RRigidBody(heavy)};
    RWorldSettings settings = EarthGravity();
    settings.shortcuts.sleeping = false;  // the solver's own resting contact
    RIntegrator integrator(settings);
    RScalar worstOverlap = 0;
    for (int i = 0; i < 600; ++i) {
      integrator.Update(bodies, 1.0 / 60);
      for (const RContact& c : integrator.Contacts()) {
        worstOverlap = std::max(worstOverlap, -c.manifold.query.separation);
      }
    }
    const RScalar sink = 1.5 - bodies[2].Position_W().y();
    std::printf("%g:1 mass ratio: the heavy box sank %.3g mm, worst overlap %.3g mm\n",
                heavyMass, sink * 1e3, worstOverlap * 1e3);
    EXPECT_LT(worstOverlap, 2e-3) << heavyMass;
    EXPECT_LT(std::abs(sink), 4e-3) << heavyMass;
    // At rest, reported at rest (to the direct solve's regularisation, 1e-9 of the impulse).
    EXPECT_LT(bodies[2].Velocity_W().norm(), 1e-9 * heavyMass) << heavyMass;
    EXPECT_NEAR(bodies[1].Position_W().y(), 0.5, 2e-3) << heavyMass;
  }
}

// A box spawned 1 m deep in the ground, in zero g: position correction takes it out at most
// maxPositionCorrection (0.2 m) a step, without velocity (split impulses), instead of half
// the depth at once (a box touching a broken hull was once thrown 5e6 m in one step).
TEST(ApiInput, PositionCorrectionIsCappedPerStep) {
  std::vector<RRigidBody> bodies{
      RRigidBody(BoxDef(RVec3(5, 0.5, 5)).Static().At(RVec3(0, -0.5, 0))),
      RRigidBody(UnitBoxDef(RVec3(0, -0.5, 0)))};
  RWorldSettings settings;
  settings.shortcuts.sleeping = false;
  RIntegrator integrator(settings);
  RScalar y = bodies[1].Position_W().y();
  int steps = 0;
  while (bodies[1].Position_W().y() < 0.5 - settings.penetrationSlop - 1e-3 && steps < 100) {
    integrator.Update(bodies, 1.0 / 60);
    const RScalar rise = bodies[1].Position_W().y() - y;
    EXPECT_LE(rise, settings.maxPositionCorrection + 1e-12) << "step " << steps;
    EXPECT_GE(rise, 0) << "step " << steps;
    EXPECT_LE(bodies[1].Velocity_W().norm(), 1e-9) << "correction must not add velocity";
    y = bodies[1].Position_W().y();
    ++steps;
  }
  EXPECT_GE(steps, 5) << "1 m at 0.2 m a step";
  EXPECT_LT(steps, 100) << "it must come out";
}

// Coulomb friction on a 20 degree incline (the floor tilted about z): with mu = 0.5 >
// tan 20 deg = 0.364 the box sticks; with mu = 0.2 it slides down with
// a = g (sin 20 deg - mu cos 20 deg), asked within 1%.
TEST(Response, BoxOnInclineSticksOrSlides) {
  const RScalar theta = 20 * kPi / 180, g = 9.81;
  const RQuat tilt(Eigen::AngleAxis<RScalar>(theta, RVec3::UnitZ()));
  const RVec3 down = tilt * RVec3(-1, 0, 0);  // down the slope
  for (RScalar mu : {0.5, 0.2}) {
    RBodyDef ground = GroundDef();
    ground.q_WS = tilt;
    ground.position_W = tilt * RVec3(0, -0.5, 0);
    ground.friction = mu;
    RBodyDef box = UnitBoxDef(RVec3(0, 0, 0));
    box.q_WS = tilt;
    box.position_W = tilt * RVec3(0, 0.5, 0);
    box.friction = mu;
    std::vector<RRigidBody> bodies{RRigidBody(ground), RRigidBody(box)};
    RWorldSettings settings;
    settings.gravity_W = RVec3(0, -g, 0);
    settings.shortcuts.sleeping = false;  // the solver's own resting contact
    RIntegrator integrator(settings);
    const int steps = 120;
    const RScalar dt = 1.0 / 60, t = steps * dt;
    const RVec3 x0 = bodies[1].Position_W();
    RVec3 x10 = x0;
    for (int i = 0; i < steps; ++i) {
      integrator.Update(bodies, dt);
      if (i == 9) x10 = bodies[1].Position_W();
    }
    const RScalar travelled = (bodies[1].Position_W() - x0).dot(down);
    if (mu == 0.5) {
      // The first steps' cold-started friction lets it creep 1.4 um; then not at all.
      EXPECT_LT(std::abs(travelled), 1e-5) << "sticks";
      EXPECT_LT((bodies[1].Position_W() - x10).norm(), 1e-12) << "sticks";
      EXPECT_LT(bodies[1].Velocity_W().norm(), 1e-12) << "and is reported at rest";
    } else {
      const RScalar a = g * (std::sin(theta) - mu * std::cos(theta));
      std::printf("incline, mu 0.2: travelled %.6g m, closed form %.6g m; speed %.6g, closed "
                  "form %.6g m/s\n", travelled, 0.5 * a * t * t,
                  bodies[1].Velocity_W().dot(down), a * t);
      // Asked: 1%. Kick-drift-kick with the contact impulses shared between the ends of the
      // step is exact for constant accelerations, so the slide matches to rounding.
      EXPECT_NEAR(travelled, 0.5 * a * t * t, 1e-9 * 0.5 * a * t * t);
      EXPECT_NEAR(bodies[1].Velocity_W().dot(down), a * t, 1e-9 * a * t);
      EXPECT_LT(bodies[1].AngularVelocity_W().norm(), 1e-6) << "slides without tipping";
    }
  }
}

// Coulomb friction: a box sliding at v0 on a floor stops after v0^2 / (2 mu g).
TEST(Response, SlidingBoxStopsAtTheCoulombDistance) {
  RBodyDef ground = GroundDef();
  ground.friction = 0.5;
  RBodyDef box = UnitBoxDef(RVec3(0, 0.5, 0));
  box.friction = 0.5;
  box.velocity_W = RVec3(5, 0, 0);
  std::vector<RRigidBody> bodies{RRigidBody(ground), RRigidBody(box)};
  RWorldSettings settings = EarthGravity();
  RIntegrator integrator(settings);
  Step(integrator, bodies, 180);
  const RScalar expected = 25 / (2 * 0.5 * 9.81);
  EXPECT_NEAR(bodies[1].Position_W().x(), expected, 0.01 * expected);
  EXPECT_LT(std::abs(bodies[1].Velocity_W().x()), 1e-9) << "stopped";
}

// Review findings, kept as regressions.
// A box falling flat onto the ground bounces straight up at e times its speed: the bounce
// acts at the centre of the face's leading points, so it adds no spin.
TEST(Response, FlatImpactBouncesWithoutSpin) {
  RBodyDef ground = GroundDef();
  ground.restitution = 0.5;
  RBodyDef box = UnitBoxDef(RVec3(0, 0.55, 0));
  box.restitution = 0.5;
  box.velocity_W = RVec3(0, -5, 0);
  std::vector<RRigidBody> bodies{RRigidBody(ground), RRigidBody(box)};
  RIntegrator integrator;  // zero gravity: the outcome is the closed form -e v
  Step(integrator, bodies, 10);
  EXPECT_NEAR(bodies[1].Velocity_W().y(), 2.5, 1e-9);
  EXPECT_LT(bodies[1].AngularVelocity_W().norm(), 1e-9);
}

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

// broadphase_test's seed-3 world: 305 bodies from 1 cm to 100 m, many spawned deep inside
// others, 5% at 3 km/s, under gravity. Contacts may only take energy out, so after every
// step the kinetic energy should be at most the initial one plus the potential energy
// gravity has released so far (m g . (x - x0) summed over the bodies; position correction
// moves bodies without changing their energy and only spends this margin). It used to grow
// without bound: from 1.2e8 J to 1.6e9 J in the first step and 1e221 J by the twelfth (the
// lever arms after an impact, fixed; FastBoxGlancingOffAStaticSphereGainsNoEnergy).
void StepDeepOverlapWorld(RScalar allowedGain) {
  const RVec3 g_W(0, -9.81, 0);
  std::vector<RRigidBody> bodies = MakeBodies(RandomWorld(3, RVec3::Zero(), 300, 40));
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
    ASSERT_LE(KineticEnergy(bodies), (e0 + released) * (1 + allowedGain) + 1e-12 * e0) << "step " << i;
  }
  EXPECT_FALSE(integrator.NonFinite().has_value());
}

// The world is drawn the same by every compiler (RandomWorlds.h), and the engine steps it
// the same, bit for bit, in the gcc and clang builds. A bounded gain is still known in
// other worlds of deep overlaps (README, "Energy"), so this bound holds for this world, not
// for every such world.
TEST(Response, RandomWorldOfDeepOverlapsGainsNoEnergy) { StepDeepOverlapWorld(0.0); }
