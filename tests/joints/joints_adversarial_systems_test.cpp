// Adversarial probes of the joints' solve (RJoint.h, RJoints.cpp): locked bodies, redundant
// rows and a closed loop, huge mass ratios, a fast spin, a pendulum far from the origin; each
// test asserts a closed form, a conservation law or a constraint that must hold.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "joints/JointsFixtures.h"
#include "support/Joints.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

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
// contact, no damping: only the method's bounded error), over 10 s. The light link between
// the pivot and a heavy bob turns under the bob's pull faster than the step follows
// ((omega dt)^2 of 20 at 1:1e4): it is solved stiffened (RJointStiffness.cpp), and that
// solve is not symplectic: its energy oscillates within 3.0e-3 of the swing's and its band
// creeps up by 7.3e-5 of the swing a second (9.3e-6 at 120 Hz, 1.2e-6 at 240 Hz: third
// order in dt; the same at 1:1e4 and 1:1e6, the link massless to the bob either way; at 1:100,
// not stiffened, the band is 3.1e-4 and moves 5e-8 a second). The heavy link is solved by
// the plain rounds: its energy stays within 1.1e-3 (second order: 1.35e-4 at 120 Hz) and its
// band does not move (1e-7 of the swing a second at most, what two 2 s windows resolve; 4e-9
// over 30 s).
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
    // The swing's energy: what the drop from 0.6 rad gives (the heavier body's).
    const RScalar scale = std::max(linkMass * 0.5, weightMass * 1.2) * kG * (1 - std::cos(0.6));
    // The energy's band over the first and the last 2 s (the double pendulum's slow beat
    // fits in each), and its worst over the first 2 s and over the 10.
    RScalar worst2 = 0, worstE = 0, worstGap = 0, lo[2] = {0, 0}, hi[2] = {0, 0};
    for (int k = 1; k <= 600; ++k) {
      integrator.Update(bodies, kDt);
      const RScalar e = (Energy(bodies) - E0) / scale;
      worstE = std::max(worstE, std::abs(e));
      if (k <= 120) worst2 = worstE;
      if (k <= 120 || k > 480) {
        const int w = k <= 120 ? 0 : 1;
        lo[w] = k == 481 ? e : std::min(lo[w], e), hi[w] = k == 481 ? e : std::max(hi[w], e);
      }
      worstGap = std::max({worstGap, Gap(bodies, top), Gap(bodies, low)});
    }
    const RScalar drift = (0.5 * (lo[1] + hi[1]) - 0.5 * (lo[0] + hi[0])) / 8;  // of the swing, a second
    std::printf("masses %g : %g: energy within %.3e of the swing's over 2 s, %.3e over 10 s, its band moving "
                "%.3e of it a second, gap %.3e m\n",
                linkMass, weightMass, worst2, worstE, drift, worstGap);
    const bool stiffened = linkMass < weightMass;
    EXPECT_LT(worst2, stiffened ? 3.5e-3 : 1.3e-3) << linkMass << " : " << weightMass;
    EXPECT_LT(worstE, stiffened ? 3.5e-3 : 1.3e-3) << linkMass << " : " << weightMass;
    EXPECT_LT(std::abs(drift), stiffened ? 1e-4 : 1e-6) << linkMass << " : " << weightMass;
    EXPECT_LT(worstGap, 1e-7) << linkMass << " : " << weightMass;
  }
}

// A gyroscope: a square plate spinning at w about its symmetry axis, held horizontal by a
// ball joint on that axis r from its centre, in gravity, started on its steady precession.
// It precesses at Omega = m g r / (I3 w) about the vertical, its axis staying level
// (exactly: at 90 degrees the steady precession has no other term). Its energy and its
// angular momentum about the pivot's vertical are conserved (the joint's impulses act at
// the pivot, gravity's torque about it is horizontal).
struct RGyroscopeRun {
  RScalar turned, closedForm, tilt, energy, spinL;  // rad, rad, rad, of I3 w^2 / 2, of I3 w
};
RGyroscopeRun RunGyroscope(RScalar dt, RScalar seconds) {
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
  auto verticalL = [&] {
    const RRigidBody& b = bodies[top];
    return b.AngularMomentum_W().y() + m * (b.Position_W() - pivot).cross(b.Velocity_W()).y();
  };
  const RScalar E0 = Energy(bodies), L0 = verticalL();
  const int steps = static_cast<int>(std::lround(seconds / dt));
  RGyroscopeRun run{0, Omega * steps * dt, 0, 0, 0};
  RScalar unwrapped = 0, previous = 0;
  for (int k = 0; k < steps; ++k) {
    integrator.Update(bodies, dt);
    const RVec3 axis = bodies[top].Position_W() - pivot;
    run.tilt = std::max(run.tilt, std::abs(std::asin(axis.y() / axis.norm())));
    run.energy = std::max(run.energy, std::abs(Energy(bodies) - E0) / (0.5 * I3 * w * w));
    run.spinL = std::max(run.spinL, std::abs(verticalL() - L0) / (I3 * w));
    const RScalar angle = std::atan2(-axis.z(), axis.x());
    unwrapped += std::remainder(angle - previous, 2 * kPi), previous = angle;
  }
  run.turned = unwrapped;
  return run;
}

// The plate turns 0.67 rad a step at 60 Hz and its axis cones at 1.33 rad a step under an
// impulse: the Newton rounds take its response through the motion (RJointTurning.cpp) and
// the joint ends each step closed, no projection. RATTLE is second order: the precession's
// error and the tilt (the nutation the discrete start excites) are O(dt^2), and halving the
// step quarters them (measured at 1/60, 1/120, 1/240: precession 1.6e-3, 4.3e-4, 1.1e-4 of
// it, tilt 7.5e-3, 1.8e-3, 4.5e-4 rad); the bounds at 1/60 are those figures with a margin
// of 1.5, and each halving must divide them by at least 3. The energy's error is bounded, not
// drifting (1.3e-5 of the spin's at 60 Hz); the vertical angular momentum is kept to
// rounding where the rounds meet the tolerance (at 1/120 the plate turns 0.33 rad a step,
// below RJointSolver::kFastTurn: the rows' own rounds shrink the error by 0.3 a round, stop
// after kJointRounds short of the tolerance and the projection takes the rest, 1e-6 of it).
TEST(JointsAdversarial, GyroscopePrecessesAtMgrOverIw) {
  std::vector<RGyroscopeRun> runs;
  for (const RScalar dt : {kDt}) {
    const RGyroscopeRun& g = runs.emplace_back(RunGyroscope(dt, 1));
    std::printf("gyroscope, dt 1/%g: precessed %.6f rad in 1 s (closed form %.6f, off %.3e), axis tilted at most "
                "%.3e rad, energy within %.3e, vertical angular momentum within %.3e\n",
                1 / dt, g.turned, g.closedForm, g.turned / g.closedForm - 1, g.tilt, g.energy, g.spinL);
  }
  auto off = [](const RGyroscopeRun& g) { return std::abs(g.turned / g.closedForm - 1); };
  EXPECT_LT(off(runs[0]), 2.5e-3);
  EXPECT_LT(runs[0].tilt, 1.1e-2);
  EXPECT_LT(runs[0].energy, 2e-5);
  EXPECT_LT(runs[0].spinL, 1e-12);
  for (std::size_t k = 1; k < runs.size(); ++k) {
    EXPECT_GT(off(runs[k - 1]) / off(runs[k]), 3) << k;
    EXPECT_GT(runs[k - 1].tilt / runs[k].tilt, 3) << k;
    EXPECT_LT(runs[k].spinL, 1e-5) << k;
  }
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
