// Impacts in islands with joints (RJointImpacts.cpp): each impact bounces through the joints'
// reaction, one impact after another. Zero gravity, frictionless, so the closed forms are
// those of the impacts alone.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

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

}  // namespace

// A Newton's cradle of five balls, each hung from its own point by a ball joint 1 m above
// it, touching its neighbours; the first swings in at 1 m/s (zero g: each ball circles its
// point at constant speed). With e = 1 and equal pendulums the impulse passes down the row:
// the striker and the middle balls stop, the last leaves at the striker's speed. Shared out
// as one block (the impacts solved together), all five would move.
TEST(JointImpacts, CradleOfPendulumsPassesTheImpulseDownTheRow) {
  RBodies bodies;
  const RScalar r = 0.1, L = 1, v0 = 1;
  std::vector<RBodyHandle> balls;
  std::vector<RJointHandle> rods;
  for (int k = 0; k < 5; ++k) {
    // (The striker 1 mm out: it meets the row within the first step.)
    const RVec3 c(k == 0 ? RScalar(-1e-3) : 2 * r * k, 0, 0);
    balls.push_back(bodies.Add(SphereDef(r).Mass(1).Restitution(1).Friction(0).At(c)));
    rods.push_back(bodies.AddJoint(Joint(RJointType::kBall, balls.back(), RBodyHandle{}, c + RVec3(0, L, 0))));
  }
  // The striker's pendulum motion at the bottom: v at the ball, the point above it still.
  bodies[balls[0]].SetVelocity_W(RVec3(v0, 0, 0));
  bodies[balls[0]].SetAngularVelocity_W(RVec3(0, 0, v0 / L));
  RWorldSettings s;
  s.shortcuts.sleeping = false;
  RIntegrator integrator(s);
  RScalar worstGap = 0;
  for (int k = 0; k < 6; ++k) {
    integrator.Update(bodies, kDt);
    for (RJointHandle h : rods) worstGap = std::max(worstGap, Gap(bodies, h));
  }
  std::printf("cradle of pendulums: speeds");
  for (RBodyHandle b : balls) std::printf(" %.9f", bodies[b].Velocity_W().norm());
  std::printf(" m/s; rods within %.2e m\n", worstGap);
  // The pendulums are alike, so the exchange is exact but for RATTLE's energy error of the
  // circling, (w dt)^2 / 4 = 7e-5, and the joints' tolerance.
  for (int k = 0; k < 4; ++k) EXPECT_LT(bodies[balls[k]].Velocity_W().norm(), 1e-6 * v0) << k;
  EXPECT_NEAR(bodies[balls[4]].Velocity_W().norm(), v0, 1e-4 * v0);
  EXPECT_LT(worstGap, 1e-9);
}

// A pendulum's bob hits a wall square at the bottom of its swing, e = 0.5: the rod meets
// the wall's normal at right angles, so it takes nothing from the bounce, and the bob leaves
// at e times the speed it came in with.
TEST(JointImpacts, PendulumBobBouncesOffAWallAtETimesItsSpeed) {
  RBodies bodies;
  const RScalar r = 0.1, L = 1, v0 = 2, e = 0.5;
  bodies.Add(BoxDef(RVec3(0.1, 1, 1)).Static().Restitution(e).Friction(0).At(RVec3(r + 0.1, 0, 0)));
  // Starting a little before the wall, on the circle about the point above (0, L, 0).
  const RScalar angle = -0.02;
  const RVec3 pivot(0, L, 0);
  const RVec3 at = pivot + RVec3(L * std::sin(angle), -L * std::cos(angle), 0);
  const RBodyHandle bob = bodies.Add(SphereDef(r).Mass(1).Restitution(e).Friction(0).At(at));
  const RVec3 tangent(std::cos(angle), std::sin(angle), 0);
  bodies[bob].SetVelocity_W(v0 * tangent);
  bodies[bob].SetAngularVelocity_W(RVec3(0, 0, v0 / L));
  const RJointHandle rod = bodies.AddJoint(Joint(RJointType::kBall, bob, RBodyHandle{}, pivot));
  RWorldSettings s;
  s.shortcuts.sleeping = false;
  RIntegrator integrator(s);
  RScalar worstGap = 0;
  for (int k = 0; k < 8; ++k) {
    integrator.Update(bodies, kDt);
    worstGap = std::max(worstGap, Gap(bodies, rod));
  }
  const RVec3 v = bodies[bob].Velocity_W();
  std::printf("bob off the wall: speed %.9f m/s (e v0 = %.9f), moving %s; rod within %.2e m\n", v.norm(), e * v0,
              v.x() < 0 ? "back" : "on", worstGap);
  EXPECT_LT(v.x(), 0);
  // In zero g the bob circles at constant speed before and after: e v0, to the joints'
  // tolerance and RATTLE's (w dt)^2 / 4 of the circling.
  EXPECT_NEAR(v.norm(), e * v0, 1e-3 * e * v0);
  EXPECT_LT(worstGap, 1e-9);
}

// A welded pair of boxes, one body, lands flat on the ground at 3 m/s with e = 0.5 (zero
// g: it was thrown down), and leaves as the compound of the same boxes does (the same boxes
// in another world, as one body): its members' contacts with the ground bounce as one
// impact, through the centre of their leading points, as the compound's children's do.
// (Bounced one contact after the other, through the weld, the pair left at 1.567 m/s
// turning at 2.28 rad/s; the compound leaves at 1.322 m/s turning at 2.80 rad/s, its impact
// through the centre of the leading points, which is not under its centre of mass.)
TEST(JointImpacts, WeldedPairLandingFlatBouncesAsItsCompound) {
  const RVec3 he(0.3, 0.2, 0.2);
  const RScalar ma = 2, mb = 5, volume = 8 * he.prod();
  RBodies bodies;
  bodies.Add(GroundDef().Restitution(0.5).Friction(0));
  const RBodyHandle a = bodies.Add(BoxDef(he).Mass(ma).Restitution(0.5).Friction(0).At(RVec3(-0.3, 0.25, 0)));
  const RBodyHandle b = bodies.Add(BoxDef(he).Mass(mb).Restitution(0.5).Friction(0).At(RVec3(0.3, 0.25, 0)));
  bodies.AddJoint(Joint(RJointType::kFixed, a, b, RVec3(0, 0.25, 0)));
  for (RBodyHandle h : {a, b}) bodies[h].SetVelocity_W(RVec3(0, -3, 0));
  RBodies twinWorld;
  twinWorld.Add(GroundDef().Restitution(0.5).Friction(0));
  BodyDef twin;
  twin.shape.type = RShapeType::kCompound;
  for (const auto& [x, m] : {std::pair<RScalar, RScalar>{-0.3, ma}, {0.3, mb}}) {
    RCompoundChild child;
    child.shape = RShape::Box(he);
    child.position_S = RVec3(x, 0, 0), child.density = m / volume;
    twin.shape.children.push_back(child);
  }
  const RBodyHandle t = twinWorld.Add(twin.Restitution(0.5).Friction(0).At(RVec3(0, 0.25, 0)).Moving(RVec3(0, -3, 0)));
  RWorldSettings s;
  s.shortcuts.sleeping = false;
  RIntegrator integrator(s), twinIntegrator(s);
  for (int k = 0; k < 4; ++k) integrator.Update(bodies, kDt), twinIntegrator.Update(twinWorld, kDt);
  const RVec3 centre = (ma * bodies[a].Velocity_W() + mb * bodies[b].Velocity_W()) / (ma + mb);
  const RVec3 spin = bodies[a].AngularVelocity_W(), twinSpin = twinWorld[t].AngularVelocity_W();
  std::printf("welded pair landing flat: centre leaves at %.9f m/s, spin %.6f rad/s; its compound %.9f m/s, %.6f rad/s\n",
              centre.y(), spin.z(), twinWorld[t].Velocity_W().y(), twinSpin.z());
  // The same impact; after it the weld's contact phase works on two bodies held by rows to the
  // Newton tolerance, the compound's on one: 2e-5 m/s and 7e-5 rad/s apart, of an impact of
  // 3 m/s (bounced as two impacts: 0.25 m/s and 0.5 rad/s apart).
  EXPECT_LT((centre - twinWorld[t].Velocity_W()).norm(), 1e-4);
  EXPECT_LT((spin - twinSpin).norm(), 3e-4);
}
