// Linear motion, forces, torques and impulses against their closed forms.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cmath>

#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {
// A 2 kg ball of radius 0.25 m.
RBodyDef Ball(const RVec3& x, const RVec3& v) {
  return SphereDef(0.25).Mass(2.0).At(x).Moving(v).Named("ball");
}
}  // namespace

// Kick-drift-kick is exact for constant acceleration, so after n steps the error is rounding
// alone: ~n ulps of the largest term. Checked at the origin and 1e7 m from it.
TEST(FreeMotion, FreeFallFollowsTheClosedForm) {
  for (RScalar offset : {0.0, 1e7}) {
    const RVec3 x0(offset + 1, 2, -3), v0(4, 5, -6), g(0, -9.81, 0);
    std::vector<RRigidBody> bodies{RRigidBody(Ball(x0, v0))};
    RWorldSettings settings;
    settings.gravity_W = g;
    RIntegrator integrator(settings);
    const RScalar h = 1.0 / 60;
    const int n = 600;
    Step(integrator, bodies, n, h);
    const RScalar t = n * h;
    const RVec3 x = x0 + v0 * t + 0.5 * g * t * t;
    const RVec3 v = v0 + g * t;
    const RScalar scale = x0.norm() + v0.norm() * t + g.norm() * t * t;
    EXPECT_LT((bodies[0].Position_W() - x).norm(), n * 4 * RTol::kEpsilon * scale) << offset;
    EXPECT_LT((bodies[0].Velocity_W() - v).norm(), n * 4 * RTol::kEpsilon * (v0.norm() + 100));
  }
}

TEST(FreeMotion, ConstantForceFollowsTheClosedForm) {
  const RVec3 f(3, -1, 2), g(0, -9.81, 0);
  std::vector<RRigidBody> bodies{RRigidBody(Ball(RVec3::Zero(), RVec3(1, 0, 0)))};
  RWorldSettings settings;
  settings.gravity_W = g;
  RIntegrator integrator(settings);
  const RScalar h = 0.01;
  for (int i = 0; i < 500; ++i) {
    bodies[0].AddForce_W(f);
    integrator.Update(bodies, h);
  }
  const RScalar t = 5.0;
  const RVec3 a = f / 2.0 + g;
  // Rounding alone: ~4 ulps per step of the largest term (|a| t^2 / 2 ~ 120 m).
  const RScalar tol = 500 * 4 * RTol::kEpsilon * (a.norm() * t * t);
  EXPECT_LT((bodies[0].Position_W() - (RVec3(1, 0, 0) * t + 0.5 * a * t * t)).norm(), tol);
  EXPECT_LT((bodies[0].Velocity_W() - (RVec3(1, 0, 0) + a * t)).norm(), tol);
}

TEST(FreeMotion, StaticBodiesNeverMove) {
  RBodyDef def = Ball(RVec3(1, 2, 3), RVec3(5, 5, 5));
  def.kind = RBodyKind::kStatic;
  def.angularVelocity_W = RVec3(1, 1, 1);
  std::vector<RRigidBody> bodies{RRigidBody(def)};
  EXPECT_EQ(bodies[0].Mass(), 0);
  EXPECT_EQ(bodies[0].InvMass(), 0);
  EXPECT_TRUE(bodies[0].InvInertia_B().isZero(0));
  RIntegrator integrator(EarthGravity());
  bodies[0].AddForce_W(RVec3(100, 0, 0));
  bodies[0].AddImpulse_W(RVec3(100, 0, 0));
  Step(integrator, bodies, 10, 0.1);
  EXPECT_EQ(bodies[0].Position_W(), RVec3(1, 2, 3));
  EXPECT_TRUE(bodies[0].Velocity_W().isZero(0));
  EXPECT_TRUE(bodies[0].AngularVelocity_W().isZero(0));
}

// An impulse J at a point r from the centre of mass changes v by J/m and L by r x J.
TEST(FreeMotion, ImpulseAtPointChangesMomentumExactly) {
  std::vector<RRigidBody> bodies{
      RRigidBody(BoxDef(RVec3(0.5, 1.0, 1.5)).Mass(3.0).Oriented(QuatExp(RVec3(0.3, -0.2, 0.9))))};
  const RVec3 J(1, 2, -0.5), p(0.3, -0.4, 1.0);
  bodies[0].AddImpulseAtPoint_W(J, p);
  RIntegrator integrator;
  integrator.Update(bodies, 1e-3);
  EXPECT_LT((bodies[0].Velocity_W() - J / 3.0).norm(), 1e-15);
  // World angular momentum is conserved by the free flow after the kick.
  EXPECT_LT((bodies[0].AngularMomentum_W() - p.cross(J)).norm(), 1e-14);
}

// A constant torque along a principal axis of a body at rest: omega = tau t / I and the
// angle tau t^2 / (2 I), which the half-kick / exact-flow / half-kick split reproduces
// exactly (the flow about one principal axis is a pure rotation).
TEST(FreeMotion, ConstantTorqueAboutPrincipalAxis) {
  std::vector<RRigidBody> bodies{RRigidBody(BoxDef(RVec3(0.5, 1.0, 1.5)).Mass(1.0))};
  const RScalar tau = 0.7, I = bodies[0].Inertia_B().y();
  RIntegrator integrator;
  const RScalar h = 0.01;
  for (int i = 0; i < 300; ++i) {
    bodies[0].AddTorque_W(RVec3(0, tau, 0));
    integrator.Update(bodies, h);
  }
  const RScalar t = 3.0;
  EXPECT_NEAR(bodies[0].AngularVelocity_W().y(), tau * t / I, 1e-13);
  const RQuat expected = QuatExp(RVec3(0, tau * t * t / (2 * I), 0));
  EXPECT_LT(QuatAngleBetween(bodies[0].Orientation_WB(), expected), 1e-12);
}

// The engine never silently produces a non-finite state, nor one beyond the positions it
// accepts: the body is reported by name and step and put back at its last pose, at rest.
TEST(FreeMotion, NonFiniteBodyIsReportedAndKeptFinite) {
  // From 1e15 m (the largest position accepted) at 1.5e308 m/s: 7.5e307 m after 0.5 s, and
  // beyond the largest double a second later, were it carried on.
  std::vector<RRigidBody> bodies{RRigidBody(Ball(RVec3::Zero(), RVec3::Zero())),
                                 RRigidBody(Ball(RVec3(1e15, 0, 0), RVec3(1.5e308, 0, 0)))};
  bodies[1] = RRigidBody([] {
    RBodyDef d = Ball(RVec3(1e15, 0, 0), RVec3(1.5e308, 0, 0));
    d.name = "runaway";
    return d;
  }());
  RIntegrator integrator;
  integrator.Update(bodies, 0.5);
  ASSERT_TRUE(integrator.NonFinite().has_value());
  EXPECT_EQ(integrator.NonFinite()->bodyName, "runaway");
  EXPECT_EQ(integrator.NonFinite()->bodyIndex, 1u);
  EXPECT_EQ(integrator.NonFinite()->step, 1u);
  EXPECT_EQ(bodies[1].Position_W(), RVec3(1e15, 0, 0));
  EXPECT_EQ(bodies[1].Velocity_W(), RVec3::Zero());
  integrator.Update(bodies, 1.0);
  EXPECT_TRUE(integrator.NonFiniteInLastStep().empty());
  EXPECT_TRUE(AllFinite(bodies[1].Position_W()));
}

