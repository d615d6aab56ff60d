// Joints through the API (RBodies): definitions checked field by field, joints removed with
// their bodies, collideConnected, an island that sleeps and wakes as one, a joint to a
// kinematic body, and the same steps on any thread count and after a save and load.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RWorldState.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "joints/JointsFixtures.h"
#include "support/Joints.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

// Joined bodies do not collide unless the joint says they do (collideConnected).
TEST(Joints, JoinedBodiesCollideOnlyWhenAsked) {
  for (const bool collide : {false, true}) {
    RBodies bodies;
    const RBodyHandle a = bodies.Add(BoxDef(RVec3::Constant(0.5)).Mass(1).At(RVec3(0, 0, 0)));
    const RBodyHandle b = bodies.Add(BoxDef(RVec3::Constant(0.5)).Mass(1).At(RVec3(0.9, 0, 0)));
    RJointDef d = Joint(RJointType::kBall, a, b, RVec3(0.45, 0, 0));
    d.collideConnected = collide;
    const RJointHandle h = bodies.AddJoint(d);
    RIntegrator integrator;
    integrator.Update(bodies, kDt);
    EXPECT_EQ(integrator.Contacts().size(), collide ? 1u : 0u) << "collideConnected " << collide;
    // Without the joint they collide again.
    bodies.RemoveJoint(h);
    integrator.Update(bodies, kDt);
    EXPECT_EQ(integrator.Contacts().size(), 1u);
  }
}

// The API's checks (RJointError names the field), and joints that go with their bodies.
TEST(Joints, DefinitionsAreCheckedAndJointsGoWithTheirBodies) {
  RBodies bodies;
  const RBodyHandle a = bodies.Add(SphereDef(0.5).Mass(1));
  const RBodyHandle b = bodies.Add(SphereDef(0.5).Mass(1).At(RVec3(2, 0, 0)));
  const RBodyHandle ground = bodies.Add(GroundDef());
  auto field = [&](const RJointDef& d) -> std::string {
    try {
      bodies.AddJoint(d);
    } catch (const RJointError& e) {
      return e.Field();
    }
    return "accepted";
  };
  RJointDef d = Joint(RJointType::kBall, a, a, RVec3::Zero());
  EXPECT_EQ(field(d), "b");
  d = Joint(RJointType::kBall, ground, RBodyHandle{}, RVec3::Zero());
  EXPECT_EQ(field(d), "a");
  d = Joint(RJointType::kHinge, a, b, RVec3(1, 0, 0));
  d.axis_W = RVec3::Zero();
  EXPECT_EQ(field(d), "axis");
  d.axis_W = RVec3(0, 0, std::nan(""));
  EXPECT_EQ(field(d), "axis");
  // Any length but 0: its norm's square overflows or underflows, the direction does not.
  for (const RScalar length : {1e200, 1e-320}) {
    d.axis_W = RVec3(length, 0, 0);
    const RJointHandle huge = bodies.AddJoint(d);
    EXPECT_EQ(bodies.Joint(huge).def.axis_W, RVec3(1, 0, 0));
    bodies.RemoveJoint(huge);
  }
  d.axis_W = RVec3::UnitZ(), d.hasLimits = true, d.lower = 1, d.upper = -1;
  EXPECT_EQ(field(d), "limits");
  d.lower = -4, d.upper = 0;
  EXPECT_EQ(field(d), "limits");
  d = Joint(RJointType::kBall, a, b, RVec3(1, std::numeric_limits<RScalar>::infinity(), 0));
  EXPECT_EQ(field(d), "anchor");
  d = Joint(RJointType::kBall, a, b, RVec3(1, 0, 0));
  d.hasLimits = true;
  EXPECT_EQ(field(d), "limits");
  d = Joint(RJointType::kSlider, a, b, RVec3(1, 0, 0));
  d.motor = {true, 1, -2};
  EXPECT_EQ(field(d), "motor.max_force");
  d = Joint(RJointType::kDistance, a, b, RVec3(0, 0, 0));
  d.hasAnchorB = true, d.anchorB_W = RVec3(2, 0, 0), d.minDistance = 3, d.maxDistance = 2;
  EXPECT_EQ(field(d), "min_distance");
  d.hasAnchorB = false, d.minDistance = -1, d.maxDistance = -1;  // anchors together: a ball joint
  EXPECT_EQ(field(d), "max_distance");
  EXPECT_THROW(bodies.AddJoint(Joint(RJointType::kBall, a, RBodyHandle{7, 0}, RVec3::Zero())), RHandleError);
  EXPECT_EQ(bodies.JointCount(), 0u);
  // Two joints on a; removing a takes both, and leaves b's other joint.
  const RBodyHandle c = bodies.Add(SphereDef(0.5).Mass(1).At(RVec3(4, 0, 0)));
  const RJointHandle ab = bodies.AddJoint(Joint(RJointType::kBall, a, b, RVec3(1, 0, 0)));
  const RJointHandle aw = bodies.AddJoint(Joint(RJointType::kFixed, a, RBodyHandle{}, RVec3(0, 0, 0)));
  const RJointHandle bc = bodies.AddJoint(Joint(RJointType::kBall, b, c, RVec3(3, 0, 0)));
  EXPECT_EQ(bodies.JointCount(), 3u);
  bodies.Remove(a);
  EXPECT_FALSE(bodies.ContainsJoint(ab));
  EXPECT_FALSE(bodies.ContainsJoint(aw));
  EXPECT_TRUE(bodies.ContainsJoint(bc));
  EXPECT_EQ(bodies.JointCount(), 1u);
  EXPECT_THROW(bodies.RemoveJoint(ab), RHandleError);
  RIntegrator integrator;
  integrator.Update(bodies, kDt);  // steps with what is left
  EXPECT_TRUE(bodies[b].Velocity_W().allFinite());
}

// The same world on 1, 2 and 4 threads: chains and a heap of boxes on the ground, every
// step bit for bit.
TEST(Joints, ResultsDoNotDependOnTheThreadCount) {
  auto build = [](RBodies& bodies) {
    bodies.Add(GroundDef());
    for (int c = 0; c < 6; ++c) {
      RBodyHandle previous;
      for (int k = 0; k < 5; ++k) {
        const RVec3 top(c * 1.5, 6 - k * 0.5, 0);
        const RBodyHandle link = bodies.Add(BoxDef(RVec3(0.05, 0.25, 0.05)).Mass(1).At(top - RVec3(0, 0.25, 0)));
        RJointDef d = Joint(c % 2 ? RJointType::kHinge : RJointType::kBall, link, previous, top);
        d.axis_W = RVec3(0, 0, 1);
        bodies.AddJoint(d);
        previous = link;
      }
      bodies[previous].SetVelocity_W(RVec3(1 + c, 0, 0.5));
    }
    for (int k = 0; k < 40; ++k) bodies.Add(BoxDef(RVec3::Constant(0.2)).Mass(1).At(RVec3((k % 8) * 1.1, 0.3 + (k / 8) * 0.5, 1)));
  };
  std::vector<std::vector<RScalar>> runs;
  for (const int threads : {1, 2, 4}) {
    RBodies bodies;
    build(bodies);
    RWorldSettings s = Gravity();
    s.threads = threads;
    RIntegrator integrator(s);
    std::vector<RScalar> states;
    for (int step = 0; step < 120; ++step) {
      integrator.Update(bodies, kDt);
      for (const RRigidBody& b : bodies) {
        for (int k = 0; k < 3; ++k) states.push_back(b.Position_W()[k]), states.push_back(b.Velocity_W()[k]);
        states.push_back(b.Orientation_WB().w());
      }
    }
    runs.push_back(states);
  }
  EXPECT_EQ(0, std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(RScalar)));
  EXPECT_EQ(0, std::memcmp(runs[0].data(), runs[2].data(), runs[0].size() * sizeof(RScalar)));
}

// A chain hanging at rest from the world sleeps as one island, and wakes as one.
TEST(Joints, AJoinedIslandSleepsAndWakesAsOne) {
  RBodies bodies;
  std::vector<RBodyHandle> links;
  RBodyHandle previous;
  for (int k = 0; k < 4; ++k) {
    const RVec3 top(0, 5 - k * 0.5, 0);
    links.push_back(bodies.Add(BoxDef(RVec3(0.05, 0.25, 0.05)).Mass(1).At(top - RVec3(0, 0.25, 0))));
    bodies.AddJoint(Joint(RJointType::kBall, links.back(), previous, top));
    previous = links.back();
  }
  RIntegrator integrator(Gravity());
  for (int s = 0; s < 60; ++s) integrator.Update(bodies, kDt);
  for (RBodyHandle h : links) EXPECT_TRUE(bodies[h].IsSleeping());
  EXPECT_LT((bodies[links.back()].Position_W() - RVec3(0, 3.25, 0)).norm(), 1e-9);
  bodies[links.back()].SetVelocity_W(RVec3(1, 0, 0));
  integrator.Update(bodies, kDt);
  for (RBodyHandle h : links) EXPECT_FALSE(bodies[h].IsSleeping());
  EXPECT_GT(bodies[links.front()].AngularVelocity_W().norm(), 0);
}

// A crate on a ball joint to a kinematic turntable goes round with it, its anchor on the
// platform's anchor to the Newton tolerance; far from the origin (1e6 m) as well.
TEST(Joints, AJointToAKinematicBodyFollowsIt) {
  for (const RScalar far : {0.0, 1e6}) {
    RBodies bodies;
    const RVec3 centre(far, 0, far);
    const RBodyHandle table =
        bodies.Add(BoxDef(RVec3(3, 0.1, 3)).Kinematic().At(centre).Spinning(RVec3(0, 1, 0)));
    const RBodyHandle crate = bodies.Add(BoxDef(RVec3::Constant(0.3)).Mass(5).At(centre + RVec3(2, 0.4, 0)));
    const RJointHandle h = bodies.AddJoint(Joint(RJointType::kBall, crate, table, centre + RVec3(2, 0.1, 0)));
    RIntegrator integrator(Gravity());
    RScalar worst = 0;
    for (int s = 0; s < 240; ++s) {
      integrator.Update(bodies, kDt);
      const auto [pA, pB] = Anchors(bodies, h);
      worst = std::max(worst, (pA - pB).norm());
    }
    std::printf("turntable at %g m: anchors within %.2e m after two thirds of a turn\n", far, worst);
    EXPECT_LT(worst, far == 0 ? 1e-9 : 1e-8);
    // The table turned 4 rad, and the crate's anchor with it.
    const RVec3 r = Anchors(bodies, h).first - centre;
    EXPECT_NEAR(std::atan2(-r.z(), r.x()), 4 - 2 * kPi, 1e-9);
  }
}

// A world with joints saved mid-run and loaded into another made the same way (whose joints
// the game has since changed) continues bit for bit: the joints, their frames and their
// warm starts come back with the bodies, and the joint handles the game keeps name them.
TEST(Joints, ASavedWorldWithJointsContinuesBitForBit) {
  std::vector<RJointHandle> handles[2];
  auto build = [](RBodies& bodies, std::vector<RJointHandle>& joints) {
    bodies.Add(GroundDef());
    RBodyHandle previous;
    for (int k = 0; k < 6; ++k) {
      const RVec3 top(0.3 * k, 4 - k * 0.5, 0);
      const RBodyHandle link = bodies.Add(BoxDef(RVec3(0.05, 0.25, 0.05)).Mass(1).At(top - RVec3(0, 0.25, 0)));
      RJointDef d = Joint(k % 3 == 1 ? RJointType::kHinge : RJointType::kBall, link, previous, top);
      d.axis_W = RVec3(0, 0, 1);
      d.hasLimits = k % 3 == 1, d.lower = -0.3, d.upper = 0.3;
      joints.push_back(bodies.AddJoint(d));
      previous = link;
    }
    const RBodyHandle weight = bodies.Add(SphereDef(0.3).Mass(20).At(RVec3(1.8, 0.5, 0)));
    RJointDef rope = Joint(RJointType::kDistance, weight, previous, RVec3(1.8, 0.5, 0));
    rope.hasAnchorB = true, rope.anchorB_W = RVec3(1.5, 1.0, 0), rope.minDistance = 0, rope.maxDistance = 1.2;
    joints.push_back(bodies.AddJoint(rope));
  };
  RBodies a, b;
  build(a, handles[0]), build(b, handles[1]);
  RIntegrator ia(Gravity()), ib(Gravity());
  for (int k = 0; k < 40; ++k) ia.Update(a, kDt);
  const std::vector<std::uint8_t> saved = SaveState(ia, a);
  b.RemoveJoint(handles[1][2]);  // the loading world differs: the load puts it back
  LoadState(ib, b, saved);
  ASSERT_EQ(b.JointCount(), a.JointCount());
  for (RJointHandle h : handles[0]) EXPECT_TRUE(b.ContainsJoint(h));
  for (int k = 0; k < 80; ++k) {
    ia.Update(a, kDt), ib.Update(b, kDt);
  }
  for (std::size_t i = 0; i < a.Size(); ++i) {
    EXPECT_EQ(a.At(i).Position_W(), b.At(i).Position_W()) << i;
    EXPECT_EQ(a.At(i).Orientation_WB().coeffs(), b.At(i).Orientation_WB().coeffs()) << i;
  }
  // A state saved before joints were saved (format 1) is refused, not loaded without them.
  std::vector<std::uint8_t> old = saved;
  old[8] = 1;
  EXPECT_THROW(LoadState(ib, b, old), RStateError);
}
