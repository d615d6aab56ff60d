// Welds: bodies joined by fixed joints move as the one rigid body they form (RWeldGroups.cpp).
// Each test compares the welded bodies with what physics gives that one body: the compound
// body of the same mass properties in another world, or a closed form.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RWorldState.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "support/Joints.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;
constexpr RScalar kG = 9.81;

RWorldSettings Gravity() { return GravityAlongMinusY(kG); }

// A compound of boxes (half extents, centre in the compound's frame) of one density.
BodyDef CompoundOf(const std::vector<std::pair<RVec3, RVec3>>& boxes, RScalar rho) {
  BodyDef d;
  d.shape.type = RShapeType::kCompound;
  for (const auto& [he, c] : boxes) {
    RCompoundChild child;
    child.shape = RShape::Box(he);
    child.position_S = c, child.density = rho;
    d.shape.children.push_back(child);
  }
  return d;
}

// Linear momentum, angular momentum about their centre of mass (not about a far origin,
// where it would be dwarfed by the lever arm) and kinetic energy of some bodies.
struct Sums {
  RVec3 P = RVec3::Zero(), L = RVec3::Zero();
  RScalar E = 0;
  RVec3 centre = RVec3::Zero();  // of mass, m
};
Sums SumsOf(const RBodies& bodies, const std::vector<RBodyHandle>& hs) {
  Sums s;
  RScalar M = 0;
  RVec3 c = RVec3::Zero();
  for (RBodyHandle h : hs) M += bodies[h].Mass(), c += bodies[h].Mass() * bodies[h].Position_W();
  c /= M;
  s.centre = c;
  for (RBodyHandle h : hs) {
    const RRigidBody& b = bodies[h];
    s.P += b.Mass() * b.Velocity_W();
    s.L += (b.Position_W() - c).cross(b.Mass() * b.Velocity_W()) + b.AngularMomentum_W();
    s.E += b.LinearKineticEnergy() + b.RotationalKineticEnergy();
  }
  return s;
}

}  // namespace

// Three boxes welded in a triangle (three joints: one more than holds them, closing a
// cycle) tumbling in zero g far from the origin: one rigid body, whose exact free flow
// conserves energy and momentum to rounding and is the compound body's motion.
TEST(Welds, WeldedTriangleTumblesAsItsCompound) {
  const RVec3 far(1e6, -2e6, 5e5);
  const std::vector<std::pair<RVec3, RVec3>> boxes = {
      {RVec3(0.5, 0.2, 0.3), RVec3(-0.5, 0, 0)}, {RVec3(0.3, 0.4, 0.2), RVec3(0.3, 0.1, 0.05)},
      {RVec3(0.2, 0.2, 0.6), RVec3(-0.1, 0.6, 0.2)}};
  const RScalar rho = 700;
  RScalar M = 0;
  RVec3 com = RVec3::Zero();
  for (const auto& [he, c] : boxes) M += rho * 8 * he.prod(), com += rho * 8 * he.prod() * c;
  com /= M;
  const RVec3 w(0.7, -1.9, 0.6), v(3, -1, 2);
  RBodies bodies;
  std::vector<RBodyHandle> hs;
  for (const auto& [he, c] : boxes) {
    hs.push_back(bodies.Add(BoxDef(he).Density(rho).At(far + c).Moving(v + w.cross(c - com)).Spinning(w)));
  }
  std::vector<RJointHandle> welds;
  welds.push_back(bodies.AddJoint(Joint(RJointType::kFixed, hs[0], hs[1], far + RVec3(-0.1, 0.05, 0))));
  welds.push_back(bodies.AddJoint(Joint(RJointType::kFixed, hs[1], hs[2], far + RVec3(0.1, 0.45, 0.1))));
  welds.push_back(bodies.AddJoint(Joint(RJointType::kFixed, hs[2], hs[0], far + RVec3(-0.3, 0.3, 0.1))));
  RBodies twinWorld;
  const RBodyHandle t = twinWorld.Add(CompoundOf(boxes, rho).At(far).Moving(v).Spinning(w));
  RIntegrator integrator, twinIntegrator;
  const Sums s0 = SumsOf(bodies, hs);
  RScalar worstP = 0, worstL = 0, worstE = 0, worstGap = 0, worstTwin = 0;
  for (int s = 0; s < 600; ++s) {
    integrator.Update(bodies, kDt);
    twinIntegrator.Update(twinWorld, kDt);
    const Sums si = SumsOf(bodies, hs);
    worstP = std::max(worstP, (si.P - s0.P).norm() / s0.P.norm());
    worstL = std::max(worstL, (si.L - s0.L).norm() / s0.L.norm());
    worstE = std::max(worstE, std::abs(si.E - s0.E) / s0.E);
    for (RJointHandle h : welds) worstGap = std::max(worstGap, Gap(bodies, h));
    const RRigidBody& tw = twinWorld[t];
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      const RVec3 where = tw.ShapePosition_W() + tw.ShapeOrientation_WS() * boxes[k].second;
      worstTwin = std::max(worstTwin, (bodies[hs[k]].Position_W() - where).norm());
    }
  }
  std::printf("welded triangle, 10 s at 1e6 m: P within %.2e, L within %.2e, E within %.2e; joints within %.2e m; "
              "%.2e m from the compound\n",
              worstP, worstL, worstE, worstGap, worstTwin);
  // Rounding. The sums' own: P and E to a few ulps a step. L is summed over arms that are
  // differences of coordinates of 2e6 m (ulp 2.3e-10 m, 5e-10 of a 0.5 m arm): that is the
  // figure's own noise. Positions: a rounding of the coordinates a step at most, a random
  // walk of sqrt(600) ulps = 6e-9 m (the same world at the origin: 3e-12 m).
  EXPECT_LT(worstP, 1e-12);
  EXPECT_LT(worstL, 1e-8);
  EXPECT_LT(worstE, 1e-11);
  EXPECT_LT(worstGap, 1e-9);
  EXPECT_LT(worstTwin, 1e-8);
}

// A welded pair hung from a ball joint, swinging and spinning in gravity: the composite's
// prediction is what the ball joint's Newton rounds see, so the pair swings as its compound
// twin hung the same way, the ball joint holds to the Newton tolerance, and the energy error
// is the twin's (RATTLE's on the ball joint, the one joint left).
TEST(Welds, WeldedPairOnABallJointSwingsAsItsCompound) {
  const std::vector<std::pair<RVec3, RVec3>> boxes = {{RVec3(0.4, 0.1, 0.2), RVec3(0, -0.5, 0)},
                                                      {RVec3(0.1, 0.3, 0.1), RVec3(0.3, -1.0, 0.1)}};
  const RScalar rho = 500;
  const RVec3 pivot(0, 3, 0);
  const RQuat tilt = QuatAxisAngle(RVec3(1, 0, 0.4).normalized(), 0.5);
  const RVec3 spin = tilt * RVec3(0, 2.0, 0);
  RBodies bodies;
  std::vector<RBodyHandle> hs;
  for (const auto& [he, c] : boxes) {
    hs.push_back(bodies.Add(BoxDef(he).Density(rho).At(pivot + tilt * c).Oriented(tilt).Moving(spin.cross(tilt * c)).Spinning(spin)));
  }
  const RJointHandle weld = bodies.AddJoint(Joint(RJointType::kFixed, hs[0], hs[1], pivot + tilt * RVec3(0.1, -0.65, 0.05)));
  const RJointHandle ball = bodies.AddJoint(Joint(RJointType::kBall, hs[0], RBodyHandle{}, pivot));
  RBodies twinWorld;
  const RBodyHandle t = twinWorld.Add(CompoundOf(boxes, rho).At(pivot).Oriented(tilt).Spinning(spin));
  // The twin's centre of mass is not its shape frame's origin: its velocity is the spin's.
  twinWorld[t].SetVelocity_W(spin.cross(twinWorld[t].Position_W() - pivot));
  const RJointHandle twinBall = twinWorld.AddJoint(Joint(RJointType::kBall, t, RBodyHandle{}, pivot));
  RWorldSettings s = Gravity();
  s.shortcuts.sleeping = false;
  RIntegrator integrator(s), twinIntegrator(s);
  auto energy = [](const RBodies& w) {
    RScalar E = 0;
    for (const RRigidBody& b : w) E += b.LinearKineticEnergy() + b.RotationalKineticEnergy() + b.Mass() * kG * b.Position_W().y();
    return E;
  };
  const RScalar E0 = energy(bodies), twinE0 = energy(twinWorld);
  ASSERT_NEAR(E0, twinE0, 1e-9 * std::abs(E0));
  RScalar worstE = 0, twinWorstE = 0, worstBall = 0, worstWeld = 0, worstTwin = 0;
  for (int k = 0; k < 240; ++k) {
    integrator.Update(bodies, kDt);
    twinIntegrator.Update(twinWorld, kDt);
    worstE = std::max(worstE, std::abs(energy(bodies) - E0));
    twinWorstE = std::max(twinWorstE, std::abs(energy(twinWorld) - twinE0));
    worstBall = std::max({worstBall, Gap(bodies, ball), Gap(twinWorld, twinBall)});
    worstWeld = std::max(worstWeld, Gap(bodies, weld));
    const RRigidBody& tw = twinWorld[t];
    for (std::size_t j = 0; j < boxes.size(); ++j) {
      const RVec3 where = tw.ShapePosition_W() + tw.ShapeOrientation_WS() * boxes[j].second;
      worstTwin = std::max(worstTwin, (bodies[hs[j]].Position_W() - where).norm());
    }
  }
  std::printf("welded pair on a ball joint, 4 s: energy off by %.3e J (compound twin %.3e J), ball joint %.2e m, "
              "weld %.2e m, %.2e m from the twin\n",
              worstE, twinWorstE, worstBall, worstWeld, worstTwin);
  // Both bodies are RATTLE on one ball joint, whose rounds stop at 1e-10 m: the same motion
  // to that tolerance, at worst accumulated over the 240 steps (5e-8 m), the same bounded
  // energy error.
  EXPECT_LT(worstBall, 1e-9);
  EXPECT_LT(worstWeld, 1e-12);
  EXPECT_LT(worstTwin, 5e-8);
  EXPECT_LT(worstE, 1.1 * twinWorstE + 1e-9 * std::abs(E0));
}

// A dumbbell of two welded boxes of one height dropped tilted on the ground: it lands on one
// end, tips onto the other and comes to rest level as one body, its weld never opened, then
// sleeps.
TEST(Welds, WeldedDumbbellLandsAndSleeps) {
  RBodies bodies;
  bodies.Add(GroundDef());
  const RQuat tilt = QuatAxisAngle(RVec3(0, 0, 1), 0.3);
  const RVec3 centre(0, 1.5, 0);
  const RBodyHandle a = bodies.Add(BoxDef(RVec3(0.3, 0.2, 0.2)).Mass(2).At(centre + tilt * RVec3(-0.5, 0, 0)).Oriented(tilt));
  const RBodyHandle b = bodies.Add(BoxDef(RVec3(0.2, 0.2, 0.3)).Mass(3).At(centre + tilt * RVec3(0.4, 0, 0)).Oriented(tilt));
  const RJointHandle weld = bodies.AddJoint(Joint(RJointType::kFixed, a, b, centre + tilt * RVec3(-0.2, 0, 0)));
  RIntegrator integrator(Gravity());
  RScalar worstGap = 0;
  int asleepAt = -1;
  for (int k = 0; k < 600 && asleepAt < 0; ++k) {
    integrator.Update(bodies, kDt);
    worstGap = std::max(worstGap, Gap(bodies, weld));
    if (bodies[a].IsSleeping() && bodies[b].IsSleeping()) asleepAt = k;
  }
  std::printf("welded dumbbell: asleep after %d steps, weld within %.2e m, centres %.4f and %.4f m high; speeds %.2e %.2e\n", asleepAt,
              worstGap, bodies[a].Position_W().y(), bodies[b].Position_W().y(), bodies[a].Velocity_W().norm(), bodies[b].Velocity_W().norm());
  EXPECT_GE(asleepAt, 0);
  EXPECT_LT(worstGap, 1e-9);
  // Level on the ground (both feet down), within the contact slop.
  EXPECT_NEAR(bodies[a].Position_W().y(), 0.2, 0.01);
  EXPECT_NEAR(bodies[b].Position_W().y(), 0.2, 0.01);
}

// Two welded spheres, one feeling gravity and the other not, released level: the pair falls
// at g/2 (kick-drift-kick is exact for a constant acceleration) and swings like a pendulum
// about its centre in gravity g/2. From level at rest, when the rod is upright
// w^2 = 2 (m1 + m2) (g/2) r / I.
TEST(Welds, DifferentGravityScalesFallAndTurnTheWeldAsOne) {
  RBodies bodies;
  const RScalar r = 0.5, radius = 0.1, m = 1;
  const RBodyHandle heavy = bodies.Add(SphereDef(radius).Mass(m).At(RVec3(-r, 10, 0)));
  const RBodyHandle light = bodies.Add(SphereDef(radius).Mass(m).At(RVec3(r, 10, 0)).GravityScale(0));
  const RJointHandle weld = bodies.AddJoint(Joint(RJointType::kFixed, heavy, light, RVec3(0, 10, 0)));
  RWorldSettings s = Gravity();
  s.shortcuts.sleeping = false;
  RIntegrator integrator(s);
  const RScalar I = 2 * (0.4 * m * radius * radius + m * r * r);
  const RScalar wUpright = std::sqrt(2 * (2 * m) * (kG / 2) * r / I);
  RScalar worstFall = 0, fastest = 0, worstGap = 0;
  for (int k = 1; k <= 120; ++k) {
    integrator.Update(bodies, kDt);
    const RScalar t = k * kDt;
    const RScalar centreY = 0.5 * (bodies[heavy].Position_W().y() + bodies[light].Position_W().y());
    worstFall = std::max(worstFall, std::abs(centreY - (10 - 0.25 * kG * t * t)));
    fastest = std::max(fastest, std::abs(bodies[heavy].AngularVelocity_W().z()));
    worstGap = std::max(worstGap, Gap(bodies, weld));
  }
  std::printf("gravity scales 1 and 0: centre off g/2's fall by %.2e m; fastest turn %.6f rad/s (closed form %.6f); "
              "weld %.2e m\n",
              worstFall, fastest, wUpright, worstGap);
  EXPECT_LT(worstFall, 1e-12);
  // The swing's period is 2.1 s: the 2 s run passes upright; kick-drift-kick's error in the
  // speed there is O((w dt)^2) = 1e-3 relative.
  EXPECT_NEAR(fastest, wUpright, 2e-3 * wUpright);
  EXPECT_LT(worstGap, 1e-12);
}

// A weld whose members share one drag rate decays as one body with it: momentum and angular
// momentum fall as e^(-c t) exactly. Members with different rates are left to the joint
// solver, which still holds them together.
TEST(Welds, DragDecaysTheWeldAsOneBodyAndDifferentRatesStillHold) {
  for (const bool alike : {true, false}) {
    RBodies bodies;
    const RScalar c = 0.3;
    const RVec3 w(0.4, 1.1, -0.3), v(1, 2, 0);
    const RBodyHandle a = bodies.Add(BoxDef(RVec3(0.5, 0.2, 0.3)).Mass(4).At(RVec3(-0.5, 0, 0)).Damping(c, c));
    const RBodyHandle b = bodies.Add(BoxDef(RVec3(0.3, 0.3, 0.3)).Mass(3).At(RVec3(0.3, 0, 0)).Damping(c, alike ? c : 2 * c));
    const RVec3 com = (4 * RVec3(-0.5, 0, 0) + 3 * RVec3(0.3, 0, 0)) / 7;
    for (RBodyHandle h : {a, b}) {
      bodies[h].SetVelocity_W(v + w.cross(bodies[h].Position_W() - com));
      bodies[h].SetAngularVelocity_W(w);
    }
    const RJointHandle weld = bodies.AddJoint(Joint(RJointType::kFixed, a, b, RVec3(0, 0, 0)));
    RIntegrator integrator;
    const Sums s0 = SumsOf(bodies, {a, b});
    RScalar worstP = 0, worstL = 0, worstGap = 0, worstX = 0;
    for (int k = 1; k <= 300; ++k) {
      integrator.Update(bodies, kDt);
      const RScalar decay = std::exp(-c * k * kDt);
      const Sums sk = SumsOf(bodies, {a, b});
      // The centre of mass on the exact flow: x0 + v0 (1 - e^(-ct))/c.
      const RVec3 x = s0.centre + v * (-std::expm1(-c * k * kDt) / c);
      worstX = std::max(worstX, (sk.centre - x).norm() / (1 + (x - s0.centre).norm()));
      worstP = std::max(worstP, (sk.P - decay * s0.P).norm() / s0.P.norm());
      worstL = std::max(worstL, (sk.L - decay * s0.L).norm() / s0.L.norm());
      worstGap = std::max(worstGap, Gap(bodies, weld));
    }
    std::printf("weld with drag (%s rates): centre off the flow by %.2e, P off e^(-ct) by %.2e, L by %.2e; weld %.2e m\n",
                alike ? "equal" : "different", worstX, worstP, worstL, worstGap);
    EXPECT_LT(worstGap, 1e-9);
    if (alike) {
      EXPECT_LT(worstX, 1e-12);
      EXPECT_LT(worstP, 1e-13);
      EXPECT_LT(worstL, 1e-12);
    }
  }
}

// Welded pairs of debris falling on the ground and on each other: the same state bit for bit
// on 1, 2 and 4 threads, and after a save and load mid-run; every weld closed throughout.
TEST(Welds, WeldedDebrisIsTheSameOnAnyThreadsAndAfterALoad) {
  auto build = [](RBodies& bodies, std::vector<RJointHandle>& welds) {
    bodies.Add(GroundDef());
    for (int k = 0; k < 24; ++k) {
      const RVec3 at(0.9 * (k % 4) + 0.05 * (k / 8), 0.6 + 0.7 * (k / 4), 0.3 * (k % 3));
      const RQuat q = QuatAxisAngle(RVec3(0.2 * k, 1, 0.5).normalized(), 0.4 * k);
      const RBodyHandle x = bodies.Add(BoxDef(RVec3(0.2, 0.1, 0.1)).Mass(1).At(at).Oriented(q));
      const RBodyHandle y = bodies.Add(SphereDef(0.12).Mass(0.5).At(at + q * RVec3(0.3, 0, 0)));
      welds.push_back(bodies.AddJoint(Joint(RJointType::kFixed, x, y, at + q * RVec3(0.2, 0, 0))));
    }
  };
  std::vector<std::vector<RScalar>> runs;
  for (const int threads : {1, 2, 4}) {
    RBodies bodies;
    std::vector<RJointHandle> welds;
    build(bodies, welds);
    RWorldSettings s = Gravity();
    s.threads = threads;
    RIntegrator integrator(s);
    std::vector<RScalar> states;
    RScalar worstGap = 0;
    for (int step = 0; step < 150; ++step) {
      integrator.Update(bodies, kDt);
      for (RJointHandle h : welds) worstGap = std::max(worstGap, Gap(bodies, h));
      for (const RRigidBody& b : bodies) {
        for (int k = 0; k < 3; ++k) states.push_back(b.Position_W()[k]), states.push_back(b.Velocity_W()[k]);
        for (int k = 0; k < 4; ++k) states.push_back(b.Orientation_WB().coeffs()[k]);
      }
    }
    EXPECT_LT(worstGap, 1e-8) << threads << " threads";
    runs.push_back(std::move(states));
  }
  EXPECT_EQ(runs[0], runs[1]);
  EXPECT_EQ(runs[0], runs[2]);

  RBodies a, b;
  std::vector<RJointHandle> wa, wb;
  build(a, wa), build(b, wb);
  RIntegrator ia(Gravity()), ib(Gravity());
  for (int k = 0; k < 50; ++k) ia.Update(a, kDt);
  LoadState(ib, b, SaveState(ia, a));
  for (int k = 0; k < 60; ++k) ia.Update(a, kDt), ib.Update(b, kDt);
  for (std::size_t i = 0; i < a.Size(); ++i) {
    EXPECT_EQ(a.At(i).Position_W(), b.At(i).Position_W()) << i;
    EXPECT_EQ(a.At(i).Orientation_WB().coeffs(), b.At(i).Orientation_WB().coeffs()) << i;
  }
}

// A weld removed mid-flight: from then on each body moves on its own, with the velocities
// the weld left it (momentum and angular momentum are the pair's, kept).
TEST(Welds, RemovingAWeldLetsItsBodiesGoTheirOwnWays) {
  RBodies bodies;
  const RBodyHandle a = bodies.Add(BoxDef(RVec3(0.3, 0.2, 0.2)).Mass(2).At(RVec3(-0.3, 0, 0)));
  const RBodyHandle b = bodies.Add(BoxDef(RVec3(0.2, 0.2, 0.2)).Mass(1).At(RVec3(0.2, 0, 0)));
  const RJointHandle weld = bodies.AddJoint(Joint(RJointType::kFixed, a, b, RVec3(0, 0, 0)));
  bodies[a].SetAngularVelocity_W(RVec3(0, 0, 3));
  bodies[b].SetAngularVelocity_W(RVec3(0, 0, 3));
  RIntegrator integrator;
  for (int k = 0; k < 30; ++k) integrator.Update(bodies, kDt);
  const Sums s0 = SumsOf(bodies, {a, b});
  bodies.RemoveJoint(weld);
  const RVec3 va = bodies[a].Velocity_W(), xa = bodies[a].Position_W();
  const RVec3 vb = bodies[b].Velocity_W(), xb = bodies[b].Position_W();
  for (int k = 1; k <= 30; ++k) {
    integrator.Update(bodies, kDt);
    EXPECT_LT((bodies[a].Position_W() - (xa + va * (k * kDt))).norm(), 1e-12) << k;
    EXPECT_LT((bodies[b].Position_W() - (xb + vb * (k * kDt))).norm(), 1e-12) << k;
  }
  const Sums s1 = SumsOf(bodies, {a, b});
  EXPECT_LT((s1.P - s0.P).norm(), 1e-12);
  EXPECT_LT((s1.L - s0.L).norm(), 1e-12 * s0.L.norm());
  EXPECT_NEAR(s1.E, s0.E, 1e-12 * s0.E);
}
