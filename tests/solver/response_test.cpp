// Collision response against closed forms and conservation laws: head-on, oblique and box
// impacts, restitution, Newton's cradle, momentum and angular momentum kept by the impulses,
// the separating-velocity guard and bodies that do not respond. Resting contact and friction:
// response_resting_test.cpp; fast bodies and energy: response_fast_test.cpp.
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RScene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "support/ReferenceScenes.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

// A frictionless sphere: the closed forms below have no tangential impulse.
RBodyDef Ball(const char* name, RScalar r, RScalar m, const RVec3& x, const RVec3& v, RScalar e) {
  return SphereDef(r).Named(name).Mass(m).At(x).Moving(v).Restitution(e).Friction(0);
}

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
