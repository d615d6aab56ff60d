// Adversarial probes of the joints' limits, motors and memory (RJoint.h, RJoints.cpp): hinge
// limits near pi and under either sign of the quaternion, a motor without force, copies and
// thread counts bit for bit, and a pendulum swinging on after its bob's overflow.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "joints/JointsFixtures.h"
#include "support/Joints.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

std::vector<RScalar> Snapshot(const RBodies& bodies) {
  std::vector<RScalar> s;
  for (const RRigidBody& b : bodies) {
    for (int k = 0; k < 3; ++k) {
      s.push_back(b.Position_W()[k]), s.push_back(b.Velocity_W()[k]), s.push_back(b.AngularVelocity_W()[k]);
    }
    for (int k = 0; k < 4; ++k) s.push_back(b.Orientation_WB().coeffs()[k]);
  }
  return s;
}

bool SameBits(const std::vector<RScalar>& a, const std::vector<RScalar>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(RScalar)) == 0;
}

}  // namespace

// ---- limits and motors --------------------------------------------------------------------

// A wheel on a hinge with limits just inside +-pi, spun at 4 rad/s: it turns freely to the
// upper limit (pi - 0.1) and stops there; it never passes it.
TEST(JointsAdversarial, HingeLimitsNearPiStopTheWheelAtTheLimit) {
  RBodies bodies;
  const RBodyHandle wheel = bodies.Add(BoxDef(RVec3(0.5, 0.05, 0.5)).Mass(4).At(RVec3(0, 1, 0)));
  RJointDef d = Joint(RJointType::kHinge, wheel, RBodyHandle{}, RVec3(0, 1, 0));
  d.axis_W = RVec3::UnitY();
  d.hasLimits = true, d.lower = -kPi + 0.1, d.upper = kPi - 0.1;
  const RJointHandle h = bodies.AddJoint(d);
  bodies[wheel].SetAngularVelocity_W(RVec3(0, 4, 0));
  RIntegrator integrator(Gravity());
  RScalar largest = -10;
  for (int s = 0; s < 90; ++s) {
    integrator.Update(bodies, kDt);
    largest = std::max(largest, bodies.JointPosition(h));
  }
  std::printf("wheel near pi: largest angle %.12f (limit %.12f), now %.12f, spin %.3e rad/s\n", largest, kPi - 0.1,
              bodies.JointPosition(h), bodies[wheel].AngularVelocity_W().y());
  EXPECT_LT(largest, kPi - 0.1 + 1e-9);
  EXPECT_NEAR(bodies.JointPosition(h), kPi - 0.1, 1e-9);
  EXPECT_LT(std::abs(bodies[wheel].AngularVelocity_W().y()), 1e-9);
}

// q and -q are one rotation (RQuaternion.h): the game setting a door's pose again, written
// with the other sign, changes nothing. A door at rest on a hinge with limits of +-0.5 rad
// stays at rest at angle 0.
TEST(JointsAdversarial, HingeLimitIgnoresTheSignOfTheQuaternion) {
  RBodies bodies;
  const RBodyHandle door = bodies.Add(BoxDef(RVec3(0.5, 1, 0.05)).Mass(20).At(RVec3(0.5, 0, 0)));
  RJointDef d = Joint(RJointType::kHinge, door, RBodyHandle{}, RVec3::Zero());
  d.axis_W = RVec3::UnitY();
  d.hasLimits = true, d.lower = -0.5, d.upper = 0.5;
  const RJointHandle h = bodies.AddJoint(d);
  RIntegrator integrator(Gravity());
  for (int s = 0; s < 5; ++s) integrator.Update(bodies, kDt);
  // The same pose, written with the other sign.
  RRigidBody& b = bodies[door];
  const RQuat q = b.ShapeOrientation_WS();
  b.SetShapePose(b.ShapePosition_W(), RQuat(-q.w(), -q.x(), -q.y(), -q.z()));
  integrator.Update(bodies, kDt);
  std::printf("door after the same pose with -q: angle %.6f rad, spin %.3e rad/s, speed %.3e m/s\n",
              bodies.JointPosition(h), bodies[door].AngularVelocity_W().norm(), bodies[door].Velocity_W().norm());
  EXPECT_NEAR(bodies.JointPosition(h), 0, 1e-9);
  EXPECT_LT(bodies[door].AngularVelocity_W().norm(), 1e-9);
}

// A motor with no force does nothing: a wheel spinning at 3 rad/s on a hinge whose motor
// asks 10 rad/s with maxForce 0 keeps 3 rad/s.
TEST(JointsAdversarial, MotorWithoutForceDoesNothing) {
  for (const RJointType type : {RJointType::kHinge, RJointType::kSlider}) {
    RBodies bodies;
    const RBodyHandle wheel = bodies.Add(BoxDef(RVec3(0.5, 0.05, 0.5)).Mass(4).At(RVec3(0, 1, 0)));
    RJointDef d = Joint(type, wheel, RBodyHandle{}, RVec3(0, 1, 0));
    d.axis_W = RVec3::UnitY();
    d.motor = {true, 10, 0};
    bodies.AddJoint(d);
    if (type == RJointType::kHinge) bodies[wheel].SetAngularVelocity_W(RVec3(0, 3, 0));
    else bodies[wheel].SetVelocity_W(RVec3(0, 3, 0));
    RIntegrator integrator;
    for (int s = 0; s < 30; ++s) integrator.Update(bodies, kDt);
    const RScalar speed =
        type == RJointType::kHinge ? bodies[wheel].AngularVelocity_W().y() : bodies[wheel].Velocity_W().y();
    EXPECT_NEAR(speed, 3, 1e-12) << int(type);
  }
}

// ---- copies and threads -------------------------------------------------------------------

// Copying the bodies and the integrator mid-run (joints' warm starts included) continues bit
// for bit.
TEST(JointsAdversarial, CopiesMidRunContinueBitForBit) {
  RBodies bodies;
  bodies.Add(GroundDef());
  RBodyHandle previous;
  for (int k = 0; k < 6; ++k) {
    const RVec3 top(0, 3 - 0.5 * k, 0);
    const RBodyHandle link = bodies.Add(BoxDef(RVec3(0.05, 0.25, 0.05)).Mass(1).At(top - RVec3(0, 0.25, 0)));
    RJointDef d = Joint(k % 2 ? RJointType::kHinge : RJointType::kBall, link, previous, top);
    d.axis_W = RVec3(0, 0, 1), d.hasLimits = k % 2, d.lower = -0.3, d.upper = 0.3;
    bodies.AddJoint(d);
    previous = link;
  }
  bodies[previous].SetVelocity_W(RVec3(3, 0, 1));
  for (int k = 0; k < 10; ++k) bodies.Add(BoxDef(RVec3::Constant(0.2)).Mass(1).At(RVec3(0.5 * k - 2, 0.3, 0.1 * k)));
  RIntegrator integrator(Gravity());
  for (int s = 0; s < 40; ++s) integrator.Update(bodies, kDt);
  RBodies copy = bodies;
  RIntegrator copyIntegrator = integrator;
  for (int s = 0; s < 40; ++s) {
    integrator.Update(bodies, kDt);
    copyIntegrator.Update(copy, kDt);
    ASSERT_TRUE(SameBits(Snapshot(bodies), Snapshot(copy))) << "step " << s;
  }
}

// Many islands of jointed bodies lying on the ground and hit by boxes: 1, 2 and 4 threads
// bit for bit.
TEST(JointsAdversarial, JointsOnTheGroundDoNotDependOnTheThreadCount) {
  auto run = [](int threads) {
    RBodies bodies;
    bodies.Add(GroundDef());
    for (int c = 0; c < 12; ++c) {
      RBodyHandle previous;
      for (int k = 0; k < 4; ++k) {
        const RVec3 left(-6 + 1.2 * c, 0.3 + 0.05 * k, 2.1 * k - 4);
        const RBodyHandle link = bodies.Add(BoxDef(RVec3(0.05, 0.05, 1)).Mass(1).At(left + RVec3(0, 0, 1)));
        if (previous.IsValid()) {
          RJointDef d = Joint(c % 3 == 0 ? RJointType::kFixed : c % 3 == 1 ? RJointType::kHinge : RJointType::kSlider,
                              link, previous, left);
          d.axis_W = RVec3(0, 0, 1), d.hasLimits = c % 3 != 0, d.lower = -0.2, d.upper = 0.2;
          bodies.AddJoint(d);
        }
        previous = link;
      }
      bodies.Add(BoxDef(RVec3::Constant(0.2)).Mass(2).At(RVec3(-6 + 1.2 * c, 2, 0)).Spinning(RVec3(1, 2, 3)));
    }
    RWorldSettings s = Gravity();
    s.threads = threads;
    RIntegrator integrator(s);
    std::vector<RScalar> all;
    for (int k = 0; k < 90; ++k) {
      integrator.Update(bodies, kDt);
      const auto snap = Snapshot(bodies);
      all.insert(all.end(), snap.begin(), snap.end());
    }
    return all;
  };
  const auto one = run(1);
  EXPECT_TRUE(SameBits(one, run(2)));
  EXPECT_TRUE(SameBits(one, run(4)));
}

// ---- non-finite ---------------------------------------------------------------------------

// A pendulum's bob is given a force that overflows its velocity: the step puts the bob
// back at its last finite state ("stepping continues for the others"); the joint's memory
// must not carry the overflow on: the pendulum then swings on, finite, its rod closed, its
// energy that of its state when it was put back.
TEST(JointsAdversarial, APendulumWhoseBobOverflowedSwingsOnAfterItIsPutBack) {
  RBodies bodies;
  const RVec3 pivot(0, 3, 0);
  const RBodyHandle link = bodies.Add(BoxDef(RVec3(0.05, 0.5, 0.05)).Mass(1).At(pivot - RVec3(0, 0.5, 0)));
  const RBodyHandle bob = bodies.Add(SphereDef(0.1).Mass(1e-3).At(pivot - RVec3(0, 1.1, 0)));
  const RJointHandle top = bodies.AddJoint(Joint(RJointType::kBall, link, RBodyHandle{}, pivot));
  const RJointHandle low = bodies.AddJoint(Joint(RJointType::kBall, bob, link, pivot - RVec3(0, 1, 0)));
  bodies[link].SetVelocity_W(RVec3(1, 0, 0));
  RWorldSettings s = Gravity();
  s.shortcuts.sleeping = false;
  RIntegrator integrator(s);
  for (int k = 0; k < 10; ++k) integrator.Update(bodies, kDt);
  bodies[bob].AddForce_W(RVec3(1e308, 0, 0));  // 1e311 m/s^2
  integrator.Update(bodies, kDt);
  std::printf("overflow: %zu bodies put back in that step\n", integrator.NonFiniteInLastStep().size());
  EXPECT_FALSE(integrator.NonFiniteInLastStep().empty());
  const RScalar E0 = Energy(bodies);
  RScalar worstE = 0, worstGap = 0;
  bool finite = true;
  for (int k = 0; k < 60; ++k) {
    integrator.Update(bodies, kDt);
    for (const RRigidBody& b : bodies) finite = finite && b.Position_W().allFinite() && b.Velocity_W().allFinite();
    worstE = std::max(worstE, std::abs(Energy(bodies) - E0));
    worstGap = std::max({worstGap, Gap(bodies, top), Gap(bodies, low)});
    for (RJointHandle h : {top, low}) {
      for (int r = 0; r < RJoint::kMaxRows; ++r) {
        finite = finite && std::isfinite(bodies.Joint(h).lambda[r]) && std::isfinite(bodies.Joint(h).lambdaEnd[r]);
      }
    }
  }
  std::printf("after the overflow: finite %d, energy within %.3e J, gap %.3e m, later non-finite %zu\n", int(finite),
              worstE, worstGap, integrator.NonFiniteInLastStep().size());
  EXPECT_TRUE(finite);
  EXPECT_LT(worstGap, 1e-8);
  EXPECT_LT(worstE, 1e-2 * std::max(RScalar(1), std::abs(E0)));
}
