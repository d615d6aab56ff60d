// Sleeping islands (RWorldSettings::RShortcuts::sleeping), checked against physics: a
// resting stack does not move, free fall, uniform drift, and the same run with sleeping off
// where it changes only the residual velocity it zeroes. The shortcuts that claim to be
// exact (bounds rejection, static world forms) are checked in pair_sweep_test.cpp.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;

}  // namespace

// A stack at rest falls asleep once it has rested for the sleep time, and from then on no
// pair of it reaches the narrow phase and it does not move at all. The physics answer is
// that it does not move either way: the top stays within 1e-9 m of where it started (the
// solver holds it to 1e-13 m while awake, the response tests' figure).
TEST(Sleep, RestingStackFallsAsleepAndStaysPut) {
  std::vector<RRigidBody> bodies = MakeBodies(BoxStackDefs(10));
  const RVec3 top0 = bodies.back().Position_W();
  RIntegrator integrator(EarthGravity());
  const int restSteps = static_cast<int>(std::ceil(integrator.Settings().sleepTime / kDt));
  Step(integrator, bodies, restSteps - 1);
  EXPECT_EQ(Sleeping(bodies), 0) << "asleep before resting for the sleep time";
  Step(integrator, bodies, 2);
  EXPECT_EQ(Sleeping(bodies), 10);
  EXPECT_EQ(integrator.PairStats().sleepingBodies, 10u);
  Step(integrator, bodies, 1);
  EXPECT_EQ(integrator.PairStats().narrowPhase, 0u);
  EXPECT_EQ(integrator.PairStats().rejectedSleeping, 55u) << "10 ground-box and 45 box-box pairs";
  const std::vector<RRigidBody> asleep = bodies;
  Step(integrator, bodies, 120);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    EXPECT_EQ(bodies[i].Position_W(), asleep[i].Position_W()) << i;
    EXPECT_EQ(bodies[i].Velocity_W(), RVec3::Zero()) << i;
  }
  EXPECT_LT((bodies.back().Position_W() - top0).norm(), 1e-9);
}

// A box dropped on a sleeping stack wakes it: the stack sleeps while the box falls 10 m,
// its island wakes in the step the box comes within reach, the box comes to rest on top,
// and all sleep again. Inelastic (e = 0) and centred, so the outcome is not chaotic (a
// bouncing drop makes 1e-12 m of difference grow to 1e-5 m): the run matches the same drop
// with sleeping off to 1e-9 m, since the only thing sleeping changes is the residual
// velocity it zeroes, ~1e-12 m/s here; and the top stays centred to 1e-9 m.
TEST(Sleep, DroppedBoxWakesTheStack) {
  std::vector<RRigidBody> result[2];
  for (int sleeping = 0; sleeping < 2; ++sleeping) {
    std::vector<RRigidBody> bodies{RRigidBody(GroundDef())};
    for (int i = 0; i < 6; ++i) {
      RBodyDef d =
          UnitBoxDef(RVec3(0, i < 5 ? 0.5 + i : 15.5, 0)).Named("box" + std::to_string(i));
      d.restitution = 0;
      bodies.emplace_back(d);
    }
    RWorldSettings s = EarthGravity();
    s.shortcuts.sleeping = sleeping != 0;
    RIntegrator integrator(s);
    Step(integrator, bodies, 60);
    if (sleeping) {
      EXPECT_EQ(Sleeping(bodies), 5) << "the stack sleeps while the box falls";
      EXPECT_FALSE(bodies[6].IsSleeping());
    }
    bool woke = false;
    for (int i = 0; i < 240; ++i) {
      const RScalar before = bodies[6].Position_W().y();
      integrator.Update(bodies, kDt);
      if (integrator.PairStats().wakeRuns > 0) {
        woke = true;
        EXPECT_EQ(Sleeping(bodies), 0) << "the island woke";
        EXPECT_GT(before, 5.5) << "before the box reached the stack";
      }
    }
    EXPECT_EQ(woke, sleeping != 0);
    if (sleeping) {
      EXPECT_EQ(Sleeping(bodies), 6) << "all asleep again";
    }
    result[sleeping] = bodies;
  }
  const std::vector<RRigidBody>& withSleep = result[1];
  const RVec3 top = withSleep.back().Position_W();
  EXPECT_LT(std::hypot(top.x(), top.z()), 1e-9) << "a centred drop";
  EXPECT_NEAR(top.y(), 5.5, 6 * 5e-4) << "rests on top, each contact within the slop";
  for (std::size_t i = 0; i < withSleep.size(); ++i) {
    EXPECT_LT((withSleep[i].Position_W() - result[0][i].Position_W()).norm(), 1e-9) << i;
  }
}

// In space nothing holds a drifting body: one slower than the sleep speed keeps drifting,
// exactly (x0 + v t to rounding), and never sleeps; nor do two boxes drifting together.
TEST(Sleep, DriftingBodiesInSpaceNeverSleep) {
  RBodyDef a = UnitBoxDef(RVec3::Zero()).Named("a");
  a.velocity_W = RVec3(1e-3, 0, 0);
  RBodyDef b = UnitBoxDef(RVec3(1, 0, 0)).Named("b");
  b.velocity_W = a.velocity_W;
  std::vector<RRigidBody> bodies{RRigidBody(a), RRigidBody(b)};
  RIntegrator integrator;
  const int steps = 300;
  Step(integrator, bodies, steps);
  EXPECT_EQ(Sleeping(bodies), 0);
  const RScalar t = steps * kDt;
  // Each step's x += v dt rounds by up to half an ulp of x.
  EXPECT_NEAR(bodies[0].Position_W().x(), 1e-3 * t, steps * 1.2e-18);
  EXPECT_NEAR(bodies[1].Position_W().x(), 1 + 1e-3 * t, steps * 2.3e-16);
}

// A body exactly at rest in space sleeps: exact, since it would not have moved.
TEST(Sleep, ExactlyStillBodyInSpaceSleeps) {
  std::vector<RRigidBody> bodies{RRigidBody(UnitBoxDef(RVec3(3, 4, 5)).Named("still"))};
  RIntegrator integrator;
  Step(integrator, bodies, 60);
  EXPECT_TRUE(bodies[0].IsSleeping());
  EXPECT_EQ(bodies[0].Position_W(), RVec3(3, 4, 5));
}

// Game code wakes a body by changing its velocity or giving it an impulse or a force, and
// the next step wakes its whole island; a zero force wakes nothing.
TEST(Sleep, GameCodeWakesTheIsland) {
  std::vector<RRigidBody> bodies = MakeBodies(BoxStackDefs(5));
  RIntegrator integrator(EarthGravity());
  Step(integrator, bodies, 60);
  ASSERT_EQ(Sleeping(bodies), 5);
  bodies[3].AddForce_W(RVec3::Zero());
  Step(integrator, bodies, 1);
  EXPECT_EQ(Sleeping(bodies), 5) << "a zero force";
  bodies[3].AddImpulse_W(RVec3(0, 0.5, 0));
  EXPECT_TRUE(!bodies[3].IsSleeping());
  integrator.Update(bodies, kDt);
  EXPECT_EQ(Sleeping(bodies), 0) << "the whole island woke";
  EXPECT_GT(bodies[5].Position_W().y(), 4.5) << "the impulse lifted the boxes above";
  Step(integrator, bodies, 120);
  ASSERT_EQ(Sleeping(bodies), 5);
  bodies[1].SetVelocity_W(RVec3(0, 0, 0));
  integrator.Update(bodies, kDt);
  EXPECT_EQ(Sleeping(bodies), 0) << "SetVelocity_W wakes, even to zero";
}

// Removing a body changes the indices (island ids) and may remove a support: everything
// wakes. Here the ground goes, and the stack falls freely: g t^2 / 2 to rounding.
TEST(Sleep, RemovingABodyWakesEverything) {
  std::vector<RRigidBody> bodies = MakeBodies(BoxStackDefs(3));
  RIntegrator integrator(EarthGravity());
  Step(integrator, bodies, 60);
  ASSERT_EQ(Sleeping(bodies), 3);
  bodies.erase(bodies.begin());
  std::vector<RVec3> x0;
  for (const RRigidBody& b : bodies) x0.push_back(b.Position_W());
  const int steps = 30;
  Step(integrator, bodies, steps);
  const RScalar t = steps * kDt, fall = 0.5 * 9.81 * t * t;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    EXPECT_FALSE(bodies[i].IsSleeping());
    EXPECT_NEAR(x0[i].y() - bodies[i].Position_W().y(), fall, 1e-12) << i;
  }
}

// Moving static geometry wakes the sleepers about it, where it was and where it is (which
// ones it held is not kept while they sleep), and nothing else: a box on a platform lowered
// by 1 m falls onto it (lands within the slop of its new top) while a box on the ground
// 80 m away sleeps on. Changing gravity wakes everything.
TEST(Sleep, MovingStaticGeometryWakesWhatItTouchesGravityEverything) {
  const RBodyDef platform =
      BoxDef(RVec3(2, 0.5, 2)).Static().At(RVec3(20, -0.5, 0)).Named("platform");
  std::vector<RRigidBody> bodies{RRigidBody(GroundDef(RVec3(-60, -0.5, 0))), RRigidBody(platform),
                                 RRigidBody(UnitBoxDef(RVec3(-60, 0.5, 0)).Named("on ground")),
                                 RRigidBody(UnitBoxDef(RVec3(20, 0.5, 0)).Named("on platform")),
                                 RRigidBody(BoxDef(RVec3(0.5, 1, 1)).Static().At(RVec3(200, 1, 0)).Named("wall"))};
  RIntegrator integrator(EarthGravity());
  Step(integrator, bodies, 60);
  ASSERT_EQ(Sleeping(bodies), 2);
  bodies[1].SetShapePose(RVec3(20, -1.5, 0), RQuat::Identity());
  integrator.Update(bodies, kDt);
  EXPECT_FALSE(bodies[3].IsSleeping()) << "the platform it rested on moved";
  EXPECT_TRUE(bodies[2].IsSleeping()) << "a static body 80 m away moved";
  Step(integrator, bodies, 120);
  EXPECT_NEAR(bodies[3].Position_W().y(), -0.5, 5e-4) << "landed on the lowered platform";
  EXPECT_LT((bodies[2].Position_W() - RVec3(-60, 0.5, 0)).norm(), 1e-12) << "the other box did not move";
  ASSERT_EQ(Sleeping(bodies), 2);
  // A static wall brought from 200 m away and set down beside the sleeping box on the
  // ground, touching it: it wakes (the wall may push it), the box on the platform does not.
  bodies[4].SetShapePose(RVec3(-59, 1, 0), RQuat::Identity());
  integrator.Update(bodies, kDt);
  EXPECT_FALSE(bodies[2].IsSleeping()) << "a static body was set down touching it";
  EXPECT_TRUE(bodies[3].IsSleeping()) << "a static body 80 m away moved";
  Step(integrator, bodies, 120);
  ASSERT_GE(Sleeping(bodies), 1);
  integrator.Settings().gravity_W = RVec3(0, -9.81, 0.1);
  integrator.Update(bodies, kDt);
  EXPECT_EQ(Sleeping(bodies), 0) << "gravity changed";
}

// Static and kinematic bodies added to, removed from or teleported in an RBodies wake the
// sleepers about them, not the world: two sleeping stacks 50 m apart, and each edit near
// one of them wakes that one only. A removed floor drops its stack in free fall.
TEST(Sleep, AddingRemovingOrTeleportingStaticBodiesWakesOnlyTheirNeighbours) {
  RBodies world;
  const RBodyHandle floorA = world.Add(BoxDef(RVec3(3, 0.5, 3)).Static().At(RVec3(0, -0.5, 0)).Named("floor A"));
  world.Add(BoxDef(RVec3(3, 0.5, 3)).Static().At(RVec3(50, -0.5, 0)).Named("floor B"));
  std::vector<RBodyHandle> stackA, stackB;
  for (int k = 0; k < 3; ++k) {
    stackA.push_back(world.Add(UnitBoxDef(RVec3(0, 0.5 + k, 0)).Named("a" + std::to_string(k))));
    stackB.push_back(world.Add(UnitBoxDef(RVec3(50, 0.5 + k, 0)).Named("b" + std::to_string(k))));
  }
  RIntegrator integrator(EarthGravity());
  auto asleep = [&](const std::vector<RBodyHandle>& stack) {
    int n = 0;
    for (RBodyHandle h : stack) n += world[h].IsSleeping();
    return n;
  };
  auto settle = [&] {
    for (int k = 0; k < 240 && (asleep(stackA) < 3 || asleep(stackB) < 3); ++k) integrator.Update(world, kDt);
    ASSERT_EQ(asleep(stackA), 3);
    ASSERT_EQ(asleep(stackB), 3);
  };
  settle();
  // A kinematic pusher appears touching stack A's middle box.
  const RBodyHandle pusher = world.Add(BoxDef(RVec3(0.5, 0.5, 0.5)).Kinematic().At(RVec3(1.0, 1.5, 0)).Named("pusher"));
  integrator.Update(world, kDt);
  EXPECT_EQ(asleep(stackA), 0) << "a kinematic body appeared touching it";
  EXPECT_EQ(asleep(stackB), 3);
  world.Remove(pusher);
  settle();
  // A static post teleported from far away to touch stack B's top box.
  const RBodyHandle post = world.Add(BoxDef(RVec3(0.2, 2, 0.2)).Static().At(RVec3(-100, 2, 0)).Named("post"));
  integrator.Update(world, kDt);
  EXPECT_EQ(asleep(stackA), 3) << "a static body appeared 100 m away";
  EXPECT_EQ(asleep(stackB), 3);
  world[post].SetShapePose(RVec3(50.7, 2, 0), RQuat::Identity());
  integrator.Update(world, kDt);
  EXPECT_EQ(asleep(stackA), 3);
  EXPECT_EQ(asleep(stackB), 0) << "a static body was set down touching it";
  world.Remove(post);
  settle();
  // Stack A's floor goes: A falls freely (g t^2 / 2), B sleeps on.
  std::vector<RScalar> y0;
  for (RBodyHandle h : stackA) y0.push_back(world[h].Position_W().y());
  world.Remove(floorA);
  const int steps = 30;
  for (int k = 0; k < steps; ++k) integrator.Update(world, kDt);
  const RScalar t = steps * kDt, fall = 0.5 * 9.81 * t * t;
  for (std::size_t k = 0; k < stackA.size(); ++k) {
    EXPECT_NEAR(y0[k] - world[stackA[k]].Position_W().y(), fall, 1e-12) << k;
  }
  EXPECT_EQ(asleep(stackB), 3) << "a static body 50 m away was removed";
}

// A floor moved far away and then removed (or disabled) before the next step: where it was
// at the last step is where its sleepers rest, and they fall (found by review: only the
// box at its new pose was kept).
TEST(Sleep, StaticBodyMovedThenRemovedDropsItsSleepers) {
  for (const bool disable : {false, true}) {
    SCOPED_TRACE(disable ? "disabled" : "removed");
    RBodies world;
    const RBodyHandle floor = world.Add(BoxDef(RVec3(3, 0.5, 3)).Static().At(RVec3(0, -0.5, 0)).Named("floor"));
    std::vector<RBodyHandle> stack;
    for (int k = 0; k < 3; ++k) stack.push_back(world.Add(UnitBoxDef(RVec3(0, 0.5 + k, 0)).Named("s" + std::to_string(k))));
    RIntegrator integrator(EarthGravity());
    for (int k = 0; k < 240 && !world[stack[2]].IsSleeping(); ++k) integrator.Update(world, kDt);
    ASSERT_TRUE(world[stack[0]].IsSleeping() && world[stack[2]].IsSleeping());
    const RScalar y0 = world[stack[0]].Position_W().y();
    world[floor].SetShapePose(RVec3(500, -0.5, 0), RQuat::Identity());
    if (disable) {
      world.Disable(floor);
    } else {
      world.Remove(floor);
    }
    const int steps = 30;
    for (int k = 0; k < steps; ++k) integrator.Update(world, kDt);
    const RScalar t = steps * kDt;
    EXPECT_NEAR(y0 - world[stack[0]].Position_W().y(), 0.5 * 9.81 * t * t, 1e-12) << "free fall";
  }
}

// A body that does not respond (a laser, a sensor) passing through a sleeping box is
// reported against it without waking it.
TEST(Sleep, SensorsDoNotWake) {
  std::vector<RRigidBody> bodies = MakeBodies(BoxStackDefs(1));
  RBodyDef laser = BoxDef(RVec3(0.5, 0.05, 0.05)).At(RVec3(-30, 0.5, 0)).Mass(1).Named("laser");
  laser.responds = false;
  bodies.emplace_back(laser);
  RIntegrator integrator(EarthGravity());
  RVec3 x(-30, 0.5, 0);
  auto steer = [&](RScalar speed) {  // game code flies the laser level through gravity
    bodies[2].SetShapePose(x, RQuat::Identity());
    bodies[2].SetVelocity_W(RVec3(speed, 0, 0));
    x.x() += speed * kDt;
  };
  for (int i = 0; i < 60; ++i) steer(0), integrator.Update(bodies, kDt);
  ASSERT_TRUE(bodies[1].IsSleeping());
  x.x() = -3;
  int reported = 0;
  for (int i = 0; i < 8; ++i) {
    steer(60);
    integrator.Update(bodies, kDt);
    for (const RContact& c : integrator.Contacts()) reported += (c.a == 1 && c.b == 2);
    EXPECT_TRUE(bodies[1].IsSleeping()) << i;
  }
  EXPECT_GT(reported, 0) << "the laser's hit is reported";
}

// Game code that moves one box out of a sleeping stack wakes the whole island, not only the
// boxes that box touched: the two above it fall 1 m and come to rest on the one below (each
// contact within the slop).
TEST(Sleep, TakingABoxOutOfASleepingStackDropsTheOnesAbove) {
  std::vector<RRigidBody> bodies = MakeBodies(BoxStackDefs(5));
  RIntegrator integrator(EarthGravity());
  Step(integrator, bodies, 60);
  ASSERT_EQ(Sleeping(bodies), 5);
  bodies[3].SetShapePose(RVec3(10, 0.5, 0), RQuat::Identity());
  integrator.Update(bodies, kDt);
  EXPECT_EQ(integrator.PairStats().wakeRuns, 0u) << "woken by the game, not by a contact";
  EXPECT_EQ(Sleeping(bodies), 0);
  Step(integrator, bodies, 120);
  EXPECT_NEAR(bodies[4].Position_W().y(), 2.5, 3 * 5e-4);
  EXPECT_NEAR(bodies[5].Position_W().y(), 3.5, 4 * 5e-4);
}

// Bodies removed and added in the same frame (the count unchanged) or moved from another
// world: island ids no longer mean anything, so everything wakes. Here the ground goes and a
// box far away comes in its place: the stack falls freely.
TEST(Sleep, RemovingAndAddingInOneFrameWakesEverything) {
  std::vector<RRigidBody> bodies = MakeBodies(BoxStackDefs(3));
  RIntegrator integrator(EarthGravity());
  Step(integrator, bodies, 60);
  ASSERT_EQ(Sleeping(bodies), 3);
  bodies.erase(bodies.begin());
  bodies.emplace_back(UnitBoxDef(RVec3(100, 0.5, 0)).Named("newcomer"));
  const RScalar y0 = bodies[0].Position_W().y();
  Step(integrator, bodies, 30);
  const RScalar t = 30 * kDt;
  EXPECT_NEAR(y0 - bodies[0].Position_W().y(), 0.5 * 9.81 * t * t, 1e-12) << "falls freely";

  // A sleeping body swapped with one of another world, at the same index: both wake.
  std::vector<RRigidBody> a = MakeBodies(BoxStackDefs(2));
  std::vector<RRigidBody> b = MakeBodies(BoxStackDefs(2, RVec3(5, 0, 0)));
  RIntegrator ia(EarthGravity()), ib(EarthGravity());
  Step(ia, a, 60), Step(ib, b, 60);
  ASSERT_EQ(Sleeping(a) + Sleeping(b), 4);
  std::swap(a[2], b[2]);
  ia.Update(a, kDt);
  EXPECT_EQ(Sleeping(a), 0);
}

// A body told to ignore the ground it sleeps on wakes, and falls through it.
TEST(Sleep, ChangingAnIgnoreListWakes) {
  std::vector<RRigidBody> bodies = MakeBodies(BoxStackDefs(1));
  bodies[0] = RRigidBody([] {
    RBodyDef g = GroundDef();
    g.id = 7;
    return g;
  }());
  RIntegrator integrator(EarthGravity());
  Step(integrator, bodies, 60);
  ASSERT_TRUE(bodies[1].IsSleeping());
  bodies[1].IgnoreCollisionsWith(7);
  Step(integrator, bodies, 30);
  EXPECT_LT(bodies[1].Position_W().y(), 0) << "fell through the ignored ground";

  // The other way round: the static ground told to ignore the sleeping box.
  std::vector<RRigidBody> again = MakeBodies(BoxStackDefs(1));
  RBodyDef box = UnitBoxDef(RVec3(0, 0.5, 0));
  box.id = 9;
  again[1] = RRigidBody(box);
  RIntegrator second(EarthGravity());
  Step(second, again, 60);
  ASSERT_TRUE(again[1].IsSleeping());
  again[0].IgnoreCollisionsWith(9);
  Step(second, again, 30);
  EXPECT_LT(again[1].Position_W().y(), 0) << "the ground let it through";
}

// A copy of an integrator with a copy of its bodies is the same world: its sleepers stay
// asleep and it goes on as the original does. Bodies the original stepped after that are
// another world's to the copy (island ids of another world): stepped by the copy, they
// wake.
TEST(Sleep, CopiedIntegratorKeepsItsSleepers) {
  std::vector<RRigidBody> a = MakeBodies(BoxStackDefs(2));
  RIntegrator ia(EarthGravity());
  Step(ia, a, 60);
  ASSERT_EQ(Sleeping(a), 2);
  RIntegrator ib = ia;
  std::vector<RRigidBody> b = a;
  ib.Update(b, kDt);
  ia.Update(a, kDt);
  EXPECT_EQ(Sleeping(b), 2) << "stepped by the copy: the same world";
  EXPECT_EQ(Sleeping(a), 2) << "the original world";
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].Position_W(), b[i].Position_W()) << i;
  std::vector<RRigidBody> fromOriginal = a;
  ib.Update(fromOriginal, kDt);
  EXPECT_EQ(Sleeping(fromOriginal), 0) << "the original's bodies, stepped by the copy";
}

// A static sensor (does not respond) keeps reporting a box that sleeps on it: pressure
// plates see the box stay.
TEST(Sleep, StaticSensorsKeepReportingSleepers) {
  RBodyDef plate = BoxDef(RVec3(1, 0.05, 1)).Static().At(RVec3(0, 0.05, 0)).Named("plate");
  plate.responds = false;
  std::vector<RRigidBody> bodies = MakeBodies(BoxStackDefs(1));
  bodies.emplace_back(plate);
  RIntegrator integrator(EarthGravity());
  int reportedWhileAsleep = 0;
  for (int i = 0; i < 120; ++i) {
    integrator.Update(bodies, kDt);
    if (!bodies[1].IsSleeping()) continue;
    for (const RContact& c : integrator.Contacts()) reportedWhileAsleep += (c.a == 1 && c.b == 2);
  }
  EXPECT_TRUE(bodies[1].IsSleeping());
  EXPECT_GT(reportedWhileAsleep, 60);
}

// Two resting boxes 4 mm apart (beyond the margin two awake resting bodies have, within the
// one a sleeper would get if it were given no motion) both sleep, and stay asleep.
TEST(Sleep, NeighboursJustApartDoNotWakeEachOther) {
  std::vector<RRigidBody> bodies{RRigidBody(GroundDef()),
                                 RRigidBody(UnitBoxDef(RVec3(0, 0.5, 0)).Named("a")),
                                 RRigidBody(UnitBoxDef(RVec3(1.004, 0.5, 0)).Named("b"))};
  RIntegrator integrator(EarthGravity());
  std::uint64_t wakes = 0;
  for (int i = 0; i < 120; ++i) {
    integrator.Update(bodies, kDt);
    wakes += integrator.PairStats().wakeRuns;
  }
  EXPECT_EQ(Sleeping(bodies), 2);
  EXPECT_EQ(wakes, 0u);
}

// In zero gravity a box sliding slowly along a static floor is not held by it (no impulse):
// it slides on, x0 + v t, and never sleeps.
TEST(Sleep, SlidingAlongAFloorInSpaceIsNotRest) {
  RBodyDef box = UnitBoxDef(RVec3(0, 0.5, 0));
  box.velocity_W = RVec3(5e-3, 0, 0);
  std::vector<RRigidBody> bodies{RRigidBody(GroundDef()), RRigidBody(box)};
  RIntegrator integrator;
  const int steps = 120;
  Step(integrator, bodies, steps);
  EXPECT_FALSE(bodies[1].IsSleeping());
  EXPECT_NEAR(bodies[1].Position_W().x(), 5e-3 * steps * kDt, 1e-15);
}

// With the shortcut off nothing ever sleeps.
TEST(Sleep, OffMeansNeverAsleep) {
  std::vector<RRigidBody> bodies = MakeBodies(BoxStackDefs(3));
  RWorldSettings s = EarthGravity();
  s.shortcuts.sleeping = false;
  RIntegrator integrator(s);
  Step(integrator, bodies, 120);
  EXPECT_EQ(Sleeping(bodies), 0);
  EXPECT_EQ(integrator.PairStats().sleepingBodies, 0u);
}
