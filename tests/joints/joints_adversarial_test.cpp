// Adversarial probes of the joints (RJoint.h, RJoints.cpp) with the world around them: each
// test asserts a physics answer (a closed form, a conservation law, a constraint that must
// hold) for joints whose bodies sleep, wake or are disabled, and joints through contacts.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "joints/JointsFixtures.h"
#include "support/Joints.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

// ---- sleeping ------------------------------------------------------------------------------

// A bob hangs at rest from a kinematic hook on a ball joint, and falls asleep (the joint
// holds it as static geometry would). The hook then starts to move at 1 m/s: the joint must
// carry the bob along. The hook touches nothing, so only the joint can wake the bob.
TEST(JointsAdversarial, SleeperHungFromAKinematicHookFollowsItWhenItStartsMoving) {
  RBodies bodies;
  const RBodyHandle hook = bodies.Add(BoxDef(RVec3::Constant(0.1)).Kinematic().At(RVec3(0, 5, 0)));
  const RBodyHandle bob = bodies.Add(BoxDef(RVec3::Constant(0.2)).Mass(3).At(RVec3(0, 4, 0)));
  const RJointHandle h = bodies.AddJoint(Joint(RJointType::kBall, bob, hook, RVec3(0, 5, 0)));
  RIntegrator integrator(Gravity());
  for (int s = 0; s < 60; ++s) integrator.Update(bodies, kDt);
  ASSERT_TRUE(bodies[bob].IsSleeping());
  bodies[hook].SetVelocity_W(RVec3(1, 0, 0));
  RScalar worst = 0;
  for (int s = 0; s < 30; ++s) {
    integrator.Update(bodies, kDt);
    worst = std::max(worst, Gap(bodies, h));
  }
  std::printf("kinematic hook moved 0.5 m: bob asleep %d, bob x %.6f m, largest anchor gap %.3e m\n",
              int(bodies[bob].IsSleeping()), bodies[bob].Position_W().x(), worst);
  EXPECT_FALSE(bodies[bob].IsSleeping());
  EXPECT_LT(Gap(bodies, h), 1e-6);
}

// The same, with the hook teleported by the game (SetShapePose) 1 m sideways: the bob must
// be pulled after it (the joint holds the anchors together), not left asleep in the air.
TEST(JointsAdversarial, SleeperHungFromATeleportedStaticHookIsPulledAfterIt) {
  RBodies bodies;
  const RBodyHandle hook = bodies.Add(BoxDef(RVec3::Constant(0.1)).Static().At(RVec3(0, 5, 0)));
  const RBodyHandle bob = bodies.Add(BoxDef(RVec3::Constant(0.2)).Mass(3).At(RVec3(0, 4, 0)));
  const RJointHandle h = bodies.AddJoint(Joint(RJointType::kBall, bob, hook, RVec3(0, 5, 0)));
  RIntegrator integrator(Gravity());
  for (int s = 0; s < 60; ++s) integrator.Update(bodies, kDt);
  ASSERT_TRUE(bodies[bob].IsSleeping());
  bodies[hook].SetShapePose(RVec3(1, 5, 0), RQuat::Identity());
  for (int s = 0; s < 5; ++s) integrator.Update(bodies, kDt);
  std::printf("static hook teleported 1 m: bob asleep %d, anchor gap %.3e m\n", int(bodies[bob].IsSleeping()),
              Gap(bodies, h));
  EXPECT_LT(Gap(bodies, h), 1e-6);
}

// A bob asleep on a rope from a static hook; the game disables the hook ("a joint whose
// body is disabled does nothing until it is enabled again"): nothing holds the bob, which
// must fall freely, g t^2 / 2.
TEST(JointsAdversarial, SleeperFallsWhenTheHookItHangsFromIsDisabled) {
  RBodies bodies;
  const RBodyHandle hook = bodies.Add(BoxDef(RVec3::Constant(0.1)).Static().At(RVec3(0, 5, 0)));
  const RBodyHandle bob = bodies.Add(BoxDef(RVec3::Constant(0.2)).Mass(3).At(RVec3(0, 3, 0)));
  RJointDef d = Joint(RJointType::kDistance, bob, hook, RVec3(0, 3, 0));
  d.hasAnchorB = true, d.anchorB_W = RVec3(0, 5, 0), d.minDistance = 0, d.maxDistance = 2;
  bodies.AddJoint(d);
  RIntegrator integrator(Gravity());
  for (int s = 0; s < 60; ++s) integrator.Update(bodies, kDt);
  ASSERT_TRUE(bodies[bob].IsSleeping());
  const RScalar y0 = bodies[bob].Position_W().y();
  bodies.Disable(hook);
  const int steps = 30;
  for (int s = 0; s < steps; ++s) integrator.Update(bodies, kDt);
  const RScalar t = steps * kDt, fall = y0 - bodies[bob].Position_W().y();
  std::printf("hook disabled: bob asleep %d, fell %.6f m in %.2f s (free fall %.6f m)\n",
              int(bodies[bob].IsSleeping()), fall, t, 0.5 * kG * t * t);
  EXPECT_NEAR(fall, 0.5 * kG * t * t, 0.02 * 0.5 * kG * t * t);
}

// ---- joints and contacts ------------------------------------------------------------------

// A door on a vertical hinge to the world (no gravity) is hit square on its face by a
// frictionless ball, restitution e = 0.5. About the hinge the door is a body of effective
// mass M = I / d^2 at the contact, d = 0.8 m out (I = m (a^2 + b^2) / 3 + m a^2 about its
// edge); the ball's velocity after the impact is (m - e M) / (m + M) v, the door's turn
// (1 + e) m v / ((m + M) d); the hinge's forces act on the axis, so the angular momentum
// about it is conserved, and the hinge never opens. (The joints act in the impact phase:
// RJointImpacts.cpp. Without them the pair met inelastically, ball -0.80 m/s, door 1.005
// rad/s.)
TEST(JointsAdversarial, DoorHitByABallBouncesAsTheHingedDoorDictates) {
  RBodies bodies;
  const RScalar e = 0.5, md = 10, mb = 1, v = -5, dist = 0.8;
  const RBodyHandle door =
      bodies.Add(BoxDef(RVec3(0.5, 1, 0.05)).Mass(md).Friction(0).Restitution(e).At(RVec3(0.5, 0, 0)));
  const RBodyHandle ball =
      bodies.Add(SphereDef(0.1).Mass(mb).Friction(0).Restitution(e).At(RVec3(dist, 0.3, 1)).Moving(RVec3(0, 0, v)));
  RJointDef d = Joint(RJointType::kHinge, door, RBodyHandle{}, RVec3::Zero());
  d.axis_W = RVec3::UnitY();
  const RJointHandle h = bodies.AddJoint(d);
  const RScalar I = md * (0.25 + 0.0025) / 3 + md * 0.25, M = I / (dist * dist);
  const RScalar ballAfter = (mb - e * M) / (mb + M) * v, doorAfter = -(1 + e) * mb * v / ((mb + M) * dist);
  auto Ly = [&] {
    RScalar L = 0;
    for (RBodyHandle k : {door, ball}) {
      const RRigidBody& b = bodies[k];
      L += b.Position_W().cross(b.Mass() * b.Velocity_W()).y() + b.AngularMomentum_W().y();
    }
    return L;
  };
  const RScalar L0 = Ly();
  RIntegrator integrator;
  RScalar worstL = 0, worstGap = 0;
  for (int s = 0; s < 20; ++s) {
    integrator.Update(bodies, kDt);
    worstL = std::max(worstL, std::abs(Ly() - L0));
    worstGap = std::max(worstGap, Gap(bodies, h));
  }
  std::printf("door and ball: ball %.6f m/s (closed form %.6f), door %.6f rad/s (closed form %.6f); L_y off by "
              "%.3e; largest hinge gap %.3e m\n",
              bodies[ball].Velocity_W().z(), ballAfter, bodies[door].AngularVelocity_W().y(), doorAfter, worstL,
              worstGap);
  EXPECT_NEAR(bodies[ball].Velocity_W().z(), ballAfter, 1e-3 * std::abs(v));
  EXPECT_NEAR(bodies[door].AngularVelocity_W().y(), doorAfter, 1e-3 * std::abs(doorAfter));
  EXPECT_LT(worstL, 1e-9 * std::abs(L0));
  EXPECT_LT(worstGap, 1e-8);
}

namespace {

// Eight 1 kg links on alternate hinges (about z) and ball joints, a little above the
// ground, each a little higher and further along z than the last.
std::vector<RJointHandle> ChainAbove(RBodies& bodies, RScalar height, std::vector<RBodyHandle>& links) {
  bodies.Add(GroundDef());
  std::vector<RJointHandle> joints;
  RBodyHandle previous;
  for (int k = 0; k < 8; ++k) {
    const RVec3 c(0.5 * k + 0.25, height + 0.02 * k, 0.01 * k);
    links.push_back(bodies.Add(BoxDef(RVec3(0.25, 0.05, 0.05)).Mass(1).At(c)));
    if (previous.IsValid()) {
      RJointDef d = Joint(k % 2 ? RJointType::kBall : RJointType::kHinge, links.back(), previous, c - RVec3(0.25, 0, 0));
      d.axis_W = RVec3::UnitZ();
      joints.push_back(bodies.AddJoint(d));
    }
    previous = links.back();
  }
  return joints;
}

}  // namespace

// The chain dropped from 0.3 m lands at 2.4 m/s (its links hit the ground through the
// impact phase): no joint may open when they do.
TEST(JointsAdversarial, ChainDroppedOnTheGroundKeepsItsJointsClosedThroughTheImpacts) {
  RBodies bodies;
  std::vector<RBodyHandle> links;
  const std::vector<RJointHandle> joints = ChainAbove(bodies, 0.3, links);
  RIntegrator integrator(Gravity());
  RScalar worstGap = 0;
  int worstStep = -1;
  for (int s = 0; s < 40; ++s) {
    integrator.Update(bodies, kDt);
    for (RJointHandle h : joints) {
      if (Gap(bodies, h) > worstGap) worstGap = Gap(bodies, h), worstStep = s;
    }
  }
  std::printf("chain landing: largest joint gap %.3e m (step %d)\n", worstGap, worstStep);
  EXPECT_LT(worstGap, 1e-6);
}

// The same chain landing without the impact phase (restitutionThreshold above any speed):
// once it lies still on the ground (its poses no longer change), its velocities must be
// zero and it must go to sleep. (The joints' end-of-step projection solves the contacts
// closed at the end against the ground and their friction with them: without the contacts
// the links ended each step at 6.2 cm/s, without the friction at 1.0 cm/s, never asleep.)
TEST(JointsAdversarial, ChainLyingStillOnTheGroundHasNoVelocityAndSleeps) {
  RBodies bodies;
  std::vector<RBodyHandle> links;
  ChainAbove(bodies, 0.3, links);
  RWorldSettings settings = Gravity();
  settings.restitutionThreshold = 1e9;
  RIntegrator integrator(settings);
  for (int s = 0; s < 150; ++s) integrator.Update(bodies, kDt);
  std::vector<RVec3> before;
  for (RBodyHandle l : links) before.push_back(bodies[l].Position_W());
  for (int s = 0; s < 60; ++s) integrator.Update(bodies, kDt);
  RScalar moved = 0, fastest = 0;
  for (std::size_t k = 0; k < links.size(); ++k) {
    moved = std::max(moved, (bodies[links[k]].Position_W() - before[k]).norm());
    fastest = std::max(fastest, bodies[links[k]].Velocity_W().norm());
  }
  std::printf("chain lying on the ground: moved %.3e m in 1 s, yet fastest link %.3e m/s; asleep %d\n", moved, fastest,
              int(bodies[links[0]].IsSleeping()));
  EXPECT_LT(moved, 1e-6);
  EXPECT_LT(fastest, 1e-3);
  EXPECT_TRUE(bodies[links[0]].IsSleeping());
}

// Four "ragdolls" (a torso with a head on a ball joint and two legs on hinges with limits)
// dropped in a heap on the ground: the heap's energy (kinetic plus potential) never exceeds
// what it started with, and the joints stay closed.
TEST(JointsAdversarial, RagdollPileFallsOnTheFloorWithItsJointsClosed) {
  RBodies bodies;
  bodies.Add(GroundDef());
  std::vector<RJointHandle> joints;
  for (int r = 0; r < 4; ++r) {
    const RVec3 base(0.1 * r, 1 + 1.6 * r, 0.05 * r);  // 1.6 m apart: no two overlap
    const RQuat q = QuatAxisAngle(RVec3(0.3, 1, 0.2).normalized(), 0.7 * r);
    auto at = [&](const RVec3& local) { return RVec3(base + q * local); };
    const RBodyHandle torso = bodies.Add(BoxDef(RVec3(0.2, 0.3, 0.1)).Mass(10).At(at(RVec3(0, 0, 0))).Oriented(q));
    const RBodyHandle head = bodies.Add(SphereDef(0.1).Mass(2).At(at(RVec3(0, 0.42, 0))));
    joints.push_back(bodies.AddJoint(Joint(RJointType::kBall, head, torso, at(RVec3(0, 0.31, 0)))));
    for (const RScalar side : {-0.1, 0.1}) {
      const RBodyHandle leg =
          bodies.Add(BoxDef(RVec3(0.06, 0.25, 0.06)).Mass(4).At(at(RVec3(side, -0.56, 0))).Oriented(q));
      RJointDef d = Joint(RJointType::kHinge, leg, torso, at(RVec3(side, -0.31, 0)));
      d.axis_W = q * RVec3::UnitX();
      d.hasLimits = true, d.lower = -1, d.upper = 1;
      joints.push_back(bodies.AddJoint(d));
    }
  }
  RIntegrator integrator(Gravity());
  const RScalar E0 = Energy(bodies);
  RScalar worstE = -1e9, worstGap = 0;
  for (int s = 0; s < 180; ++s) {
    integrator.Update(bodies, kDt);
    worstE = std::max(worstE, Energy(bodies) - E0);
    for (RJointHandle h : joints) worstGap = std::max(worstGap, Gap(bodies, h));
  }
  std::printf("ragdoll pile: energy above the start at most %.3e J, largest joint gap %.3e m\n", worstE, worstGap);
  EXPECT_LT(worstE, 1e-6 * std::abs(E0) + 1e-6);
  EXPECT_LT(worstGap, 1e-6);
}
