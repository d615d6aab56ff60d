// Adversarial probes of the joints (RJoint.h, RJoints.cpp): each test asserts a physics
// answer (a closed form, a conservation law, a constraint that must hold) in a scene the
// joints' own tests do not cover: joints with contacts, sleeping, locks, redundant rows,
// large mass ratios, fast spins, far from the origin, copies and threads.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "support/Joints.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;
constexpr RScalar kG = 9.81;

RWorldSettings Gravity() { return GravityAlongMinusY(kG); }




// Kinetic plus potential energy (gravity along -y) of the enabled dynamic bodies.
RScalar Energy(const RBodies& bodies) {
  RScalar E = 0;
  for (const RRigidBody& b : bodies) {
    if (b.IsStatic() || b.IsKinematic()) continue;
    E += b.LinearKineticEnergy() + b.RotationalKineticEnergy() + b.Mass() * kG * b.Position_W().y();
  }
  return E;
}

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

// ---- locks --------------------------------------------------------------------------------

// A flywheel whose centre is locked (linear locks on all three axes) carries a weight on a
// weld 1 m below its centre: together they are a compound pendulum turning about the
// flywheel's centre, period 4 sqrt(I / (m g d)) K(sin(theta0 / 2)), with
// I = I_wheel + I_weight + m d^2 about the axis. The locks do no work: energy is conserved.
TEST(JointsAdversarial, WeldToALinearlyLockedFlywheelIsACompoundPendulum) {
  RBodies bodies;
  const RScalar theta0 = 0.4, d = 1, m = 2;
  const RBodyHandle wheel =
      bodies.Add(BoxDef(RVec3(0.3, 0.3, 0.05)).Mass(5).At(RVec3(0, 2, 0)).LockLinear(true, true, true));
  const RVec3 arm = d * RVec3(std::sin(theta0), -std::cos(theta0), 0);
  const RBodyHandle weight = bodies.Add(BoxDef(RVec3::Constant(0.1)).Mass(m).At(RVec3(0, 2, 0) + arm));
  // The weight turned with the arm, so the compound is rigid from the start.
  bodies[weight].SetShapePose(RVec3(0, 2, 0) + arm, QuatAxisAngle(RVec3::UnitZ(), theta0));
  const RJointHandle h = bodies.AddJoint(Joint(RJointType::kFixed, weight, wheel, RVec3(0, 2, 0) + 0.5 * arm));
  // Box moments about z: M (a^2 + b^2) / 3 with half extents a, b.
  const RScalar I = 5 * (0.09 + 0.09) / 3 + m * (0.01 + 0.01) / 3 + m * d * d;
  const RScalar period = 4 * std::sqrt(I / (m * kG * d)) * CompleteEllipticK(std::sin(theta0 / 2));
  RIntegrator integrator(Gravity());
  const RScalar E0 = Energy(bodies);
  std::vector<RScalar> crossings;
  RScalar xPrev = bodies[weight].Position_W().x(), worstE = 0, worstGap = 0;
  const int steps = static_cast<int>(std::ceil(3.2 * period / kDt));
  for (int s = 1; s <= steps; ++s) {
    integrator.Update(bodies, kDt);
    const RScalar x = bodies[weight].Position_W().x();
    if (xPrev > 0 && x <= 0) crossings.push_back((s - 1 + xPrev / (xPrev - x)) * kDt);
    xPrev = x;
    worstE = std::max(worstE, std::abs(Energy(bodies) - E0));
    worstGap = std::max(worstGap, Gap(bodies, h));
  }
  const RScalar swing = m * kG * d * (1 - std::cos(theta0));
  ASSERT_GE(crossings.size(), 3u);
  const RScalar measured = (crossings[2] - crossings[0]) / 2;
  std::printf("locked flywheel: period %.6f s (closed form %.6f), energy within %.3e of the swing, gap %.3e m, "
              "wheel centre moved %.3e m\n",
              measured, period, worstE / swing, worstGap, (bodies[wheel].Position_W() - RVec3(0, 2, 0)).norm());
  EXPECT_NEAR(measured / period, 1, 2e-3);
  EXPECT_LT(worstE / swing, 2e-3);
  EXPECT_LT(worstGap, 1e-8);
  EXPECT_LT((bodies[wheel].Position_W() - RVec3(0, 2, 0)).norm(), 1e-12);
}

// A bob that cannot turn (angular locks on all axes) on a rope whose anchor is 0.1 m above
// its centre: it translates along a circle, a simple pendulum of the rope's length,
// period 4 sqrt(L / g) K(sin(theta0 / 2)).
TEST(JointsAdversarial, AngularlyLockedBobOnARodIsASimplePendulum) {
  RBodies bodies;
  const RScalar L = 1, theta0 = 0.5;
  const RVec3 pivot(0, 3, 0);
  const RVec3 anchor = pivot + L * RVec3(std::sin(theta0), -std::cos(theta0), 0);
  const RBodyHandle bob =
      bodies.Add(BoxDef(RVec3::Constant(0.1)).Mass(2).At(anchor - RVec3(0, 0.1, 0)).LockAngular(true, true, true));
  RJointDef d = Joint(RJointType::kDistance, bob, RBodyHandle{}, anchor);
  d.hasAnchorB = true, d.anchorB_W = pivot;
  const RJointHandle h = bodies.AddJoint(d);
  const RScalar period = 4 * std::sqrt(L / kG) * CompleteEllipticK(std::sin(theta0 / 2));
  RIntegrator integrator(Gravity());
  std::vector<RScalar> crossings;
  RScalar xPrev = bodies[bob].Position_W().x(), worstLen = 0;
  const int steps = static_cast<int>(std::ceil(3.2 * period / kDt));
  for (int s = 1; s <= steps; ++s) {
    integrator.Update(bodies, kDt);
    const RScalar x = bodies[bob].Position_W().x();
    if (xPrev > 0 && x <= 0) crossings.push_back((s - 1 + xPrev / (xPrev - x)) * kDt);
    xPrev = x;
    const auto [pA, pB] = Anchors(bodies, h);
    worstLen = std::max(worstLen, std::abs((pA - pB).norm() - L));
  }
  ASSERT_GE(crossings.size(), 3u);
  const RScalar measured = (crossings[2] - crossings[0]) / 2;
  std::printf("locked bob: period %.6f s (closed form %.6f), length within %.3e m, turned %.3e rad\n", measured, period,
              worstLen, QuatAngleBetween(bodies[bob].Orientation_WB(), RQuat::Identity()));
  EXPECT_NEAR(measured / period, 1, 1e-3);
  EXPECT_LT(worstLen, 1e-8);
  EXPECT_LT(QuatAngleBetween(bodies[bob].Orientation_WB(), RQuat::Identity()), 1e-12);
}

// ---- redundant rows -----------------------------------------------------------------------

// A door on two hinges on the same vertical axis (top and bottom: the rows are redundant),
// in gravity, turning at 1 rad/s: gravity has no moment about the axis, so it turns on at
// 1 rad/s, and both hinges hold.
TEST(JointsAdversarial, DoorOnTwoHingesOnOneAxisTurnsSteadily) {
  RBodies bodies;
  const RBodyHandle door = bodies.Add(BoxDef(RVec3(0.5, 1, 0.05)).Mass(20).At(RVec3(0.5, 0, 0)));
  std::vector<RJointHandle> hs;
  for (const RScalar y : {-0.9, 0.9}) {
    RJointDef d = Joint(RJointType::kHinge, door, RBodyHandle{}, RVec3(0, y, 0));
    d.axis_W = RVec3::UnitY();
    hs.push_back(bodies.AddJoint(d));
  }
  bodies[door].SetAngularVelocity_W(RVec3(0, 1, 0));
  bodies[door].SetVelocity_W(RVec3(0, 0, -0.5));
  RIntegrator integrator(Gravity());
  RScalar worstW = 0, worstGap = 0;
  for (int s = 0; s < 120; ++s) {
    integrator.Update(bodies, kDt);
    worstW = std::max(worstW, std::abs(bodies[door].AngularVelocity_W().y() - 1));
    for (RJointHandle h : hs) worstGap = std::max(worstGap, Gap(bodies, h));
  }
  std::printf("two hinges: spin off by %.3e rad/s, gap %.3e m, turned %.6f rad (2 expected)\n", worstW, worstGap,
              bodies.JointPosition(hs[0]));
  EXPECT_LT(worstW, 1e-6);
  EXPECT_LT(worstGap, 1e-8);
}

// A parallelogram linkage (a closed loop: two hanging links hinged to the world, a bar
// hinged to both lower ends): the bar translates without turning, the energy is conserved
// to the method's error and no hinge opens.
TEST(JointsAdversarial, ParallelogramLoopKeepsItsBarLevelAndItsEnergy) {
  RBodies bodies;
  std::vector<RJointHandle> hs;
  auto hinge = [&](RBodyHandle a, RBodyHandle b, const RVec3& p) {
    RJointDef d = Joint(RJointType::kHinge, a, b, p);
    d.axis_W = RVec3::UnitZ();
    hs.push_back(bodies.AddJoint(d));
  };
  const RBodyHandle left = bodies.Add(BoxDef(RVec3(0.03, 0.5, 0.03)).Mass(1).At(RVec3(0, 2.5, 0)));
  const RBodyHandle right = bodies.Add(BoxDef(RVec3(0.03, 0.5, 0.03)).Mass(1).At(RVec3(1, 2.5, 0)));
  const RBodyHandle bar = bodies.Add(BoxDef(RVec3(0.5, 0.03, 0.03)).Mass(3).At(RVec3(0.5, 2, 0)));
  hinge(left, RBodyHandle{}, RVec3(0, 3, 0));
  hinge(right, RBodyHandle{}, RVec3(1, 3, 0));
  hinge(bar, left, RVec3(0, 2, 0));
  hinge(bar, right, RVec3(1, 2, 0));
  // Swing it: the bar at 2 m/s, the links turning at 2 rad/s about their tops.
  bodies[bar].SetVelocity_W(RVec3(2, 0, 0));
  for (RBodyHandle l : {left, right}) bodies[l].SetVelocity_W(RVec3(1, 0, 0)), bodies[l].SetAngularVelocity_W(RVec3(0, 0, 2));
  RIntegrator integrator(Gravity());
  const RScalar E0 = Energy(bodies);
  const RScalar swingE = 0.5 * 5 * 4;  // about the kinetic energy at the bottom (bar 6 J + links 2*2/3 J)
  RScalar worstE = 0, worstGap = 0, worstTurn = 0;
  for (int s = 0; s < 180; ++s) {
    integrator.Update(bodies, kDt);
    worstE = std::max(worstE, std::abs(Energy(bodies) - E0));
    for (RJointHandle h : hs) worstGap = std::max(worstGap, Gap(bodies, h));
    worstTurn = std::max(worstTurn, QuatAngleBetween(bodies[bar].Orientation_WB(), RQuat::Identity()));
  }
  std::printf("parallelogram: energy within %.3e J, gap %.3e m, bar turned %.3e rad\n", worstE, worstGap, worstTurn);
  EXPECT_LT(worstE, 2e-3 * swingE);
  EXPECT_LT(worstGap, 1e-8);
  EXPECT_LT(worstTurn, 1e-8);
}

// ---- mass ratios, spins, far from the origin ----------------------------------------------

// A 1e6 (1e4) kg weight on a 1 kg link on ball joints from the world, and the other way
// round (a 1 kg ball on a 1e4 or 1e6 kg link), released at rest from 0.6 rad (a double
// pendulum, consistent from the start): the joints hold and the energy is conserved (no
// contact, no damping: only the method's bounded error). The light link between the pivot
// and a heavy bob turns under the bob's pull faster than the step follows ((omega dt)^2 of
// 20 at 1:1e4): it is solved stiffened (RJointStiffness.cpp).
TEST(JointsAdversarial, HugeMassRatiosHoldTheJointsAndTheEnergy) {
  for (const auto& [linkMass, weightMass] : {std::pair<RScalar, RScalar>{1, 1e6}, {1, 1e4}, {1e4, 1}, {1e6, 1}}) {
    RBodies bodies;
    const RVec3 pivot(0, 5, 0);
    const RQuat q = QuatAxisAngle(RVec3(0.3, 0, 1).normalized(), 0.6);
    const RBodyHandle link =
        bodies.Add(BoxDef(RVec3(0.05, 0.5, 0.05)).Mass(linkMass).At(pivot + q * RVec3(0, -0.5, 0)).Oriented(q));
    const RBodyHandle weight = bodies.Add(SphereDef(0.2).Mass(weightMass).At(pivot + q * RVec3(0, -1.2, 0)));
    const RJointHandle top = bodies.AddJoint(Joint(RJointType::kBall, link, RBodyHandle{}, pivot));
    const RJointHandle low = bodies.AddJoint(Joint(RJointType::kBall, weight, link, pivot + q * RVec3(0, -1, 0)));
    RWorldSettings s = Gravity();
    s.shortcuts.sleeping = false;
    RIntegrator integrator(s);
    const RScalar E0 = Energy(bodies);
    RScalar worstE = 0, worstGap = 0;
    for (int k = 0; k < 120; ++k) {
      integrator.Update(bodies, kDt);
      worstE = std::max(worstE, std::abs(Energy(bodies) - E0));
      worstGap = std::max({worstGap, Gap(bodies, top), Gap(bodies, low)});
    }
    // The swing's energy: what the drop from 0.6 rad gives (the heavier body's).
    const RScalar scale = std::max(linkMass * 0.5, weightMass * 1.2) * kG * (1 - std::cos(0.6));
    std::printf("masses %g : %g: energy within %.3e of the swing's, gap %.3e m\n", linkMass, weightMass,
                worstE / scale, worstGap);
    EXPECT_LT(worstE / scale, 5e-3) << linkMass << " : " << weightMass;
    EXPECT_LT(worstGap, 1e-7) << linkMass << " : " << weightMass;
  }
}

// A gyroscope: a square plate spinning at w about its symmetry axis, held horizontal by a
// ball joint on that axis r from its centre, in gravity, started on its steady precession.
// It precesses at Omega = m g r / (I3 w) about the vertical, its axis staying level
// (exactly: at 90 degrees the steady precession has no other term).
// KNOWN DEFECT, disabled until fixed: a body turning more than about 0.5 rad a step makes the
// Newton rounds (rows of the step's start) converge too slowly; the fallback loses the
// gyroscopic coupling (precessed 1.70 rad of 2.04, axis tilted 0.73 rad). Rounds with rows
// rebuilt at the predicted poses are the fix.
TEST(JointsAdversarial, DISABLED_GyroscopePrecessesAtMgrOverIw) {
  RBodies bodies;
  const RScalar m = 2, r = 0.5, w = 40;
  const RVec3 pivot(0, 3, 0);
  const RBodyHandle top = bodies.Add(BoxDef(RVec3(0.02, 0.3, 0.3)).Mass(m).At(pivot + RVec3(r, 0, 0)));
  const RScalar I3 = m * (0.09 + 0.09) / 3;  // about the plate's normal
  const RScalar Omega = m * kG * r / (I3 * w);
  bodies[top].SetAngularVelocity_W(RVec3(w, Omega, 0));
  bodies[top].SetVelocity_W(RVec3(0, Omega, 0).cross(RVec3(r, 0, 0)));
  bodies.AddJoint(Joint(RJointType::kBall, top, RBodyHandle{}, pivot));
  RWorldSettings s = Gravity();
  s.shortcuts.sleeping = false;
  RIntegrator integrator(s);
  const int steps = 60;
  RScalar worstTilt = 0;
  for (int k = 0; k < steps; ++k) {
    integrator.Update(bodies, kDt);
    const RVec3 axis = bodies[top].Position_W() - pivot;
    worstTilt = std::max(worstTilt, std::abs(axis.y()) / r);
  }
  const RVec3 axis = bodies[top].Position_W() - pivot;
  const RScalar turned = std::atan2(-axis.z(), axis.x());
  std::printf("gyroscope: precessed %.6f rad in 1 s (closed form %.6f), axis tilted at most %.3e rad\n", turned,
              Omega * steps * kDt, worstTilt);
  // At half the step the method is within 1.7e-3 rad of level (4e-4 at a quarter): second
  // order, so 7e-3 here.
  EXPECT_NEAR(turned / (Omega * steps * kDt), 1, 2e-2);
  EXPECT_LT(worstTilt, 2e-2);
}

// A pendulum 1e6 m from the origin: the same period as at the origin, to the rounding the
// coordinates allow.
TEST(JointsAdversarial, PendulumFarFromTheOriginKeepsItsPeriod) {
  for (const RScalar far : {0.0, 1e6}) {
    const RScalar L = 1, theta0 = kPi / 6, m = 1, radius = 0.05;
    const RVec3 pivot(far, 2, -far);
    RBodies bodies;
    const RBodyHandle bob =
        bodies.Add(SphereDef(radius).Mass(m).At(pivot + L * RVec3(std::sin(theta0), -std::cos(theta0), 0)));
    const RJointHandle h = bodies.AddJoint(Joint(RJointType::kBall, bob, RBodyHandle{}, pivot));
    RIntegrator integrator(Gravity());
    const RScalar I = 0.4 * m * radius * radius + m * L * L;
    const RScalar period = 4 * std::sqrt(I / (m * kG * L)) * CompleteEllipticK(std::sin(theta0 / 2));
    std::vector<RScalar> crossings;
    RScalar xPrev = bodies[bob].Position_W().x() - far, worstGap = 0;
    for (int s = 1; s <= static_cast<int>(3.2 * period / kDt); ++s) {
      integrator.Update(bodies, kDt);
      const RScalar x = bodies[bob].Position_W().x() - far;
      if (xPrev > 0 && x <= 0) crossings.push_back((s - 1 + xPrev / (xPrev - x)) * kDt);
      xPrev = x;
      worstGap = std::max(worstGap, Gap(bodies, h));
    }
    ASSERT_GE(crossings.size(), 3u);
    const RScalar measured = (crossings[2] - crossings[0]) / 2;
    std::printf("pendulum at %g m: period %.9f (closed form %.9f), gap %.3e m\n", far, measured, period, worstGap);
    EXPECT_NEAR(measured / period, 1, 3e-4) << far;
    EXPECT_LT(worstGap, far == 0 ? 1e-9 : 1e-7) << far;
  }
}

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
