// Joints (RJoint.h) against closed forms at 60 Hz: the pendulum's exact period, a motor's
// spin-up, a chain holding a heavy weight, a rope, a slider's limit, a weld tumbling as one
// body, a door stopped by its hinge's limits.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "joints/JointsFixtures.h"
#include "support/Joints.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

// A ball of radius 5 cm hung 1 m below a ball joint to the world and released from 30
// degrees. The joint holds a point of the ball: the ball turns with the rod, a physical
// pendulum of moment I = I_cm + m L^2 about the pivot, whose period is
// 4 sqrt(I / (m g L)) K(sin(theta0/2)) exactly. RATTLE, the step's method, keeps it to
// (w dt)^2/24 = 1.1e-4 and the energy (translation, rotation and height) to within
// (w dt)^2/4 = 6.8e-4 of the swing's (w = sqrt(m g L / I)); each step ends on the
// constraint to the Newton tolerance. Asserted: 0.1%, 0.1% and 0.1 mm.
TEST(Joints, PendulumKeepsTheExactPeriodEnergyAndLength) {
  const RScalar L = 1, theta0 = kPi / 6, m = 1, radius = 0.05;
  const RVec3 pivot(0, 2, 0);
  RBodies bodies;
  const RBodyHandle bob =
      bodies.Add(SphereDef(radius).Mass(m).At(pivot + L * RVec3(std::sin(theta0), -std::cos(theta0), 0)));
  const RJointHandle h = bodies.AddJoint(Joint(RJointType::kBall, bob, RBodyHandle{}, pivot));
  RIntegrator integrator(Gravity());
  const RScalar Icm = 0.4 * m * radius * radius, I = Icm + m * L * L;
  const RScalar swing = m * kG * L * (1 - std::cos(theta0));  // J
  auto energy = [&] {
    const RRigidBody& b = bodies[bob];
    return b.LinearKineticEnergy() + b.RotationalKineticEnergy() + m * kG * (b.Position_W().y() - (pivot.y() - L));
  };
  const RScalar period = 4 * std::sqrt(I / (m * kG * L)) * CompleteEllipticK(std::sin(theta0 / 2));
  const int steps = static_cast<int>(std::ceil(20.5 * period / kDt));
  std::vector<RScalar> crossings;  // times x goes from + to - (interpolated)
  RScalar worstEnergy = 0, worstLength = 0;
  RScalar xPrev = bodies[bob].Position_W().x();
  for (int s = 1; s <= steps; ++s) {
    integrator.Update(bodies, kDt);
    const RScalar x = bodies[bob].Position_W().x();
    if (xPrev > 0 && x <= 0) crossings.push_back((s - 1 + xPrev / (xPrev - x)) * kDt);
    xPrev = x;
    worstEnergy = std::max(worstEnergy, std::abs(energy() - swing) / swing);
    worstLength = std::max(worstLength, std::abs((bodies[bob].Position_W() - pivot).norm() - L));
  }
  ASSERT_GE(crossings.size(), 21u);
  const RScalar measured = (crossings[20] - crossings[0]) / 20;
  std::printf("pendulum: period %.9f s, closed form %.9f s (rel %.2e); energy within %.2e of the swing's; "
              "length within %.2e m\n",
              measured, period, measured / period - 1, worstEnergy, worstLength);
  EXPECT_NEAR(measured / period, 1, 1e-3);
  EXPECT_LT(worstEnergy, 1e-3);
  EXPECT_LT(worstLength, 1e-4);
  // The method's own figures, with room for the amplitude's effect on them.
  EXPECT_NEAR(measured / period, 1, 2e-4);
  EXPECT_LT(worstLength, 1e-8);
  const auto [pA, pB] = Anchors(bodies, h);
  EXPECT_LT((pA - pB).norm(), 1e-8);
}

// A wheel on a hinge to the world, driven by a motor whose torque is limited to tau: it
// spins up at alpha = tau / I, exactly (the motor's impulse is tau dt a step), and then
// holds the motor's speed.
TEST(Joints, HingeMotorSpinsUpAtTauOverIAndHoldsItsSpeed) {
  RBodies bodies;
  const RVec3 centre(0, 1, 0);
  const RBodyHandle wheel = bodies.Add(BoxDef(RVec3(0.5, 0.1, 0.5)).Mass(4).At(centre));
  const RScalar I = bodies[wheel].Inertia_B().y();  // about y: 4 (0.25 + 0.25) / 3
  const RScalar tau = 2, target = 10;
  RJointDef d = Joint(RJointType::kHinge, wheel, RBodyHandle{}, centre);
  d.axis_W = RVec3(0, 3, 0);
  d.motor = {true, target, tau};
  const RJointHandle h = bodies.AddJoint(d);
  RIntegrator integrator(Gravity());
  const int spinUp = static_cast<int>(target * I / (tau * kDt));
  for (int s = 1; s <= spinUp - 1; ++s) {
    integrator.Update(bodies, kDt);
    const RScalar w = bodies[wheel].AngularVelocity_W().y();
    ASSERT_NEAR(w, s * tau * kDt / I, 1e-12 * target) << "step " << s;
    // Half the motor's impulse at each end of the step: a constant torque, whose angle
    // kick-drift-kick integrates exactly, alpha t^2 / 2.
    if (s == 60) {
      EXPECT_NEAR(bodies.JointPosition(h), 0.5 * tau / I * 1.0, 1e-9);
    }
  }
  const RScalar alpha = bodies[wheel].AngularVelocity_W().y() / ((spinUp - 1) * kDt);
  for (int s = 0; s < 300; ++s) integrator.Update(bodies, kDt);
  const RRigidBody& b = bodies[wheel];
  std::printf("motor: alpha %.12f rad/s^2 (tau/I %.12f); held at %.12f rad/s (target %g)\n", alpha, tau / I,
              b.AngularVelocity_W().y(), target);
  EXPECT_NEAR(alpha, tau / I, 1e-3 * tau / I);
  EXPECT_NEAR(b.AngularVelocity_W().y(), target, 1e-3 * target);
  EXPECT_NEAR(b.AngularVelocity_W().y(), target, 1e-12 * target);
  EXPECT_LT(b.AngularVelocity_W().cwiseProduct(RVec3(1, 0, 1)).norm(), 1e-9);
  EXPECT_LT((b.Position_W() - centre).norm(), 1e-8);
}

// Ten 1 kg links hanging from the world by ball joints, a 100 kg weight at the end: the
// joints are solved exactly together, so no joint stretches (an iterative solver's chain
// sags here by the mass ratio).
TEST(Joints, ChainHoldsAHundredTimesItsLinksWithoutStretching) {
  RBodies bodies;
  const int links = 10;
  const RScalar len = 0.5;
  std::vector<RBodyHandle> chain;
  std::vector<RJointHandle> joints;
  RBodyHandle previous;
  for (int k = 0; k < links; ++k) {
    const RVec3 top(0, 10 - k * len, 0);
    chain.push_back(bodies.Add(BoxDef(RVec3(0.05, len / 2, 0.05)).Mass(1).At(top - RVec3(0, len / 2, 0))));
    joints.push_back(bodies.AddJoint(Joint(RJointType::kBall, chain.back(), previous, top)));
    previous = chain.back();
  }
  const RVec3 end(0, 10 - links * len, 0);
  const RBodyHandle weight = bodies.Add(SphereDef(0.2).Mass(100).At(end - RVec3(0, 0.2, 0)));
  joints.push_back(bodies.AddJoint(Joint(RJointType::kBall, weight, previous, end)));
  // A sideways push, so the chain swings and the joints carry more than the weight.
  bodies[weight].SetVelocity_W(RVec3(2, 0, 1));
  RIntegrator integrator(Gravity());
  RScalar worst = 0;
  for (int s = 0; s < 300; ++s) {
    integrator.Update(bodies, kDt);
    for (RJointHandle h : joints) {
      const auto [pA, pB] = Anchors(bodies, h);
      worst = std::max(worst, (pA - pB).norm());
    }
  }
  std::printf("chain: largest gap at a joint over 5 s: %.3e m\n", worst);
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(worst, 1e-7);
}

// A weight on a rope (a distance joint, min 0) dropped from halfway: it falls freely until
// the rope is taut, stops there at once (an inelastic jerk) and does not bounce back.
TEST(Joints, RopeStopsItsWeightAtItsLengthWithoutBouncing) {
  RBodies bodies;
  const RVec3 pivot(0, 5, 0);
  const RScalar L = 2;
  const RBodyHandle w = bodies.Add(SphereDef(0.1).Mass(5).At(pivot - RVec3(0, 1, 0)));
  RJointDef d = Joint(RJointType::kDistance, w, RBodyHandle{}, pivot - RVec3(0, 1, 0));
  d.hasAnchorB = true, d.anchorB_W = pivot;
  d.minDistance = 0, d.maxDistance = L;
  bodies.AddJoint(d);
  RIntegrator integrator(Gravity());
  RScalar longest = 0, shortestAfter = 1e9;
  bool taut = false;
  for (int s = 0; s < 240; ++s) {
    integrator.Update(bodies, kDt);
    const RScalar dist = (bodies[w].Position_W() - pivot).norm();
    longest = std::max(longest, dist);
    if (taut) shortestAfter = std::min(shortestAfter, dist);
    taut = taut || dist > L - 1e-9;
  }
  std::printf("rope: longest %.12f m (length %g), shortest after taut %.12f m, speed at the end %.3e m/s\n",
              longest, L, shortestAfter, bodies[w].Velocity_W().norm());
  EXPECT_TRUE(taut);
  EXPECT_LT(longest - L, 1e-8);
  EXPECT_GT(shortestAfter, L - 1e-8);
  EXPECT_LT(bodies[w].Velocity_W().norm(), 1e-8);
}

// A car on a vertical slider with a lower limit 1 m down: it falls freely, stops at the
// limit within 1 mm (here to the Newton tolerance) and moves on no other axis.
TEST(Joints, SliderLimitStopsAFallingCar) {
  RBodies bodies;
  const RVec3 start(3, 4, -2);
  const RBodyHandle car = bodies.Add(BoxDef(RVec3(0.4, 0.2, 0.7)).Mass(800).At(start));
  RJointDef d = Joint(RJointType::kSlider, car, RBodyHandle{}, start);
  d.axis_W = RVec3(0, 1, 0);
  d.hasLimits = true, d.lower = -1, d.upper = 0.5;
  bodies.AddJoint(d);
  RIntegrator integrator(Gravity());
  RScalar lowest = 0, offAxis = 0, turned = 0;
  for (int s = 0; s < 180; ++s) {
    integrator.Update(bodies, kDt);
    const RRigidBody& b = bodies[car];
    lowest = std::min(lowest, b.Position_W().y() - start.y());
    offAxis = std::max(offAxis, (b.Position_W() - start).cwiseProduct(RVec3(1, 0, 1)).norm());
    turned = std::max(turned, QuatAngleBetween(b.Orientation_WB(), RQuat::Identity()));
  }
  const RRigidBody& b = bodies[car];
  std::printf("slider: lowest %.12f m (limit -1), off the axis %.2e m, turned %.2e rad, speed %.2e m/s\n",
              lowest, offAxis, turned, b.Velocity_W().norm());
  EXPECT_NEAR(lowest, -1, 1e-3);
  EXPECT_NEAR(lowest, -1, 1e-8);
  EXPECT_NEAR(b.Position_W().y() - start.y(), -1, 1e-8);
  EXPECT_LT(offAxis, 1e-9);
  EXPECT_LT(turned, 1e-9);
  EXPECT_LT(b.Velocity_W().norm(), 1e-8);
}

namespace {

// Angular momentum about the origin and kinetic energy of a set of bodies.
std::pair<RVec3, RScalar> MomentAndEnergy(const RBodies& bodies, const std::vector<RBodyHandle>& hs) {
  RVec3 L = RVec3::Zero();
  RScalar E = 0;
  for (RBodyHandle h : hs) {
    const RRigidBody& b = bodies[h];
    L += b.Position_W().cross(b.Mass() * b.Velocity_W()) + b.AngularMomentum_W();
    E += b.LinearKineticEnergy() + b.RotationalKineticEnergy();
  }
  return {L, E};
}

}  // namespace

// Two boxes welded (a fixed joint) tumbling in zero g: the pair is one rigid body, and moves
// as one (RWeldGroups.cpp): the exact free flow of its composite inertia. Its momentum,
// energy and shape are conserved to rounding, and it follows the same boxes as one compound
// body (in another world) to rounding.
TEST(Joints, WeldedPairTumblesAsTheOneBodyItForms) {
  const RVec3 h1(0.5, 0.2, 0.3), h2(0.3, 0.4, 0.2);
  const RVec3 c1(-0.5, 0, 0), c2(0.3, 0.1, 0.05);
  const RScalar rho = 1000;
  const RScalar m1 = rho * 8 * h1.prod(), m2 = rho * 8 * h2.prod();
  const RVec3 com = (m1 * c1 + m2 * c2) / (m1 + m2);
  const RVec3 w(0.3, 1.0, 0.5), v(0.2, -0.1, 0.05);
  RBodies bodies;
  const RBodyHandle a = bodies.Add(BoxDef(h1).Density(rho).At(c1).Moving(v + w.cross(c1 - com)).Spinning(w));
  const RBodyHandle b = bodies.Add(BoxDef(h2).Density(rho).At(c2).Moving(v + w.cross(c2 - com)).Spinning(w));
  const RJointHandle weld = bodies.AddJoint(Joint(RJointType::kFixed, a, b, RVec3(0, 0.05, 0)));
  // The compound twin, in another world.
  BodyDef twin;
  twin.shape.type = RShapeType::kCompound;
  for (const auto& [he, c] : {std::pair{h1, c1}, std::pair{h2, c2}}) {
    RCompoundChild child;
    child.shape = RShape::Box(he);
    child.position_S = c, child.density = rho;
    twin.shape.children.push_back(child);
  }
  twin.Moving(v).Spinning(w);
  RBodies twinWorld;
  const RBodyHandle t = twinWorld.Add(twin);
  RIntegrator integrator, twinIntegrator;
  const auto [L0, E0] = MomentAndEnergy(bodies, {a, b});
  const RQuat relative0 = bodies[a].Orientation_WB().conjugate() * bodies[b].Orientation_WB();
  RScalar worstL = 0, worstE = 0, worstGap = 0, worstTurn = 0, worstTwin = 0;
  for (int s = 0; s < 600; ++s) {
    integrator.Update(bodies, kDt);
    twinIntegrator.Update(twinWorld, kDt);
    const auto [L, E] = MomentAndEnergy(bodies, {a, b});
    worstL = std::max(worstL, (L - L0).norm() / L0.norm());
    worstE = std::max(worstE, std::abs(E - E0) / E0);
    const auto [pA, pB] = Anchors(bodies, weld);
    worstGap = std::max(worstGap, (pA - pB).norm());
    worstTurn = std::max(worstTurn, QuatAngleBetween(bodies[a].Orientation_WB() * relative0, bodies[b].Orientation_WB()));
    // Box a's centre where the compound carries it.
    const RRigidBody& tw = twinWorld[t];
    const RVec3 c1Twin = tw.ShapePosition_W() + tw.ShapeOrientation_WS() * c1;
    worstTwin = std::max(worstTwin, (bodies[a].Position_W() - c1Twin).norm());
  }
  std::printf("weld: over 10 s, angular momentum within %.2e, energy within %.2e, anchors within %.2e m, "
              "turned apart %.2e rad; box a %.2e m from where the compound carries it\n",
              worstL, worstE, worstGap, worstTurn, worstTwin);
  // Rounding: a few ulps a step of the sums, over 600 steps; the compound's inertia is summed
  // in another order (its children's), a rounding apart.
  EXPECT_LT(worstL, 1e-11);
  EXPECT_LT(worstE, 1e-11);
  EXPECT_LT(worstGap, 1e-12);
  EXPECT_LT(worstTurn, 1e-12);
  EXPECT_LT(worstTwin, 1e-10);
}

// A door on a hinge with limits of +-0.5 rad, swung at 3 rad/s: it stops at the limit
// (inelastic: no bounce), and a motor then drives it back to the other one.
TEST(Joints, HingeLimitsStopADoor) {
  RBodies bodies;
  const RVec3 hinge(1, 0, 0);
  const RBodyHandle door = bodies.Add(BoxDef(RVec3(0.5, 1, 0.05)).Mass(20).At(hinge + RVec3(0.5, 0, 0)));
  RJointDef d = Joint(RJointType::kHinge, door, RBodyHandle{}, hinge);
  d.axis_W = RVec3(0, 1, 0);
  d.hasLimits = true, d.lower = -0.5, d.upper = 0.5;
  const RJointHandle h = bodies.AddJoint(d);
  bodies[door].SetVelocity_W(RVec3(0, 0, -1.5));  // the door's centre, 0.5 m out: 3 rad/s
  bodies[door].SetAngularVelocity_W(RVec3(0, 3, 0));
  RIntegrator integrator(Gravity());
  RScalar largest = 0;
  for (int s = 0; s < 60; ++s) {
    integrator.Update(bodies, kDt);
    largest = std::max(largest, bodies.JointPosition(h));
  }
  const RScalar angle = bodies.JointPosition(h);
  std::printf("door: largest angle %.12f rad (limit 0.5), at rest at %.12f rad, spin %.2e rad/s\n", largest, angle,
              bodies[door].AngularVelocity_W().norm());
  EXPECT_LT(largest, 0.5 + 1e-9);
  EXPECT_NEAR(angle, 0.5, 1e-9);
  EXPECT_LT(bodies[door].AngularVelocity_W().norm(), 1e-9);
  // A motor back at 1 rad/s (plenty of torque): it turns at that speed to the lower limit.
  RJointMotor motor;
  motor.enabled = true, motor.speed = -1, motor.maxForce = 1e4;
  bodies.SetJointMotor(h, motor);
  integrator.Update(bodies, kDt);
  EXPECT_NEAR(bodies[door].AngularVelocity_W().y(), -1, 1e-9);
  for (int s = 0; s < 120; ++s) integrator.Update(bodies, kDt);
  EXPECT_NEAR(bodies.JointPosition(h), -0.5, 1e-9);
}
