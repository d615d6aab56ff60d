// What contact events carry and cost (RIntegrator::Events, RContactEvents.h): the impulses
// against the bodies' momentum balance and Coulomb's law, the switch that turns them off,
// the per-body and per-pair views, and steady steps that allocate nothing.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include "support/TestBodies.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <new>
#include <vector>

#include "events/EventsFixtures.h"
#include "support/CountingNew.h"  // this binary's operator new counts allocations

using namespace REngine;
using namespace REngine::test;

// A box resting on the ground: the normal impulse of each step is its weight's, m g dt. By
// the box's momentum balance over the step, J - m g dt = m (v1 - v0)_y exactly, so the
// tolerance is the box's change of velocity, which the solver at rest holds to rounding
// (asserted too), plus the rounding of the sum (a few ulps of m g dt).
TEST(ContactEvents, RestingBoxNormalImpulseIsItsWeightTimesTheStep) {
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{GroundDef(), UnitBoxDef(RVec3(0, 0.5, 0)).Mass(2.5)});
  RWorldSettings settings = EarthGravity();
  settings.shortcuts.sleeping = false;
  RIntegrator integrator(settings);
  const RScalar m = bodies[1].Mass(), weight = m * kG * kDt;
  RScalar worst = 0;
  for (int s = 0; s < 120; ++s) {
    const RScalar v0 = bodies[1].Velocity_W().y();
    integrator.Update(bodies, kDt);
    const RScalar dv = bodies[1].Velocity_W().y() - v0;
    ASSERT_EQ(integrator.Events().size(), 1u);
    const RContactEvent& e = integrator.Events()[0];
    EXPECT_EQ(e.type, s == 0 ? RContactEventType::kBegin : RContactEventType::kPersist);
    EXPECT_LE(std::abs(dv), 1e-12 * kG * kDt) << "step " << s + 1;
    EXPECT_NEAR(e.normalImpulse, weight, m * std::abs(dv) + 8 * kEps * weight) << "step " << s + 1;
    worst = std::max(worst, std::abs(e.normalImpulse / weight - 1));
  }
  std::printf("resting box: worst |J / (m g dt) - 1| = %.2e\n", worst);
}

// A box sliding on the ground (mu 0.5): while it slides, the friction impulse of each step
// is mu times its normal impulse (Coulomb), and equals the box's loss of momentum.
TEST(ContactEvents, SlidingBoxFrictionImpulseIsMuTimesTheNormalImpulse) {
  std::vector<RRigidBody> bodies =
      MakeBodies(std::vector<BodyDef>{GroundDef(), UnitBoxDef(RVec3(0, 0.5, 0)).Moving(RVec3(3, 0, 0))});
  RWorldSettings settings = EarthGravity();
  RIntegrator integrator(settings);
  const RScalar m = bodies[1].Mass();
  int sliding = 0;
  RScalar worstCoulomb = 0, worstMomentum = 0;
  for (int s = 0; s < 30; ++s) {
    const RScalar v0 = bodies[1].Velocity_W().x();
    integrator.Update(bodies, kDt);
    const RScalar v1 = bodies[1].Velocity_W().x();
    ASSERT_EQ(integrator.Events().size(), 1u);
    const RContactEvent& e = integrator.Events()[0];
    EXPECT_NEAR(e.frictionImpulse, m * (v0 - v1), 1e-12 * m * v0) << "step " << s + 1;
    worstMomentum = std::max(worstMomentum, std::abs(e.frictionImpulse - m * (v0 - v1)) / (m * v0));
    if (v1 > 0.1) {  // slid the whole step
      ++sliding;
      EXPECT_NEAR(e.frictionImpulse, 0.5 * e.normalImpulse, 1e-12 * e.normalImpulse) << "step " << s + 1;
      worstCoulomb = std::max(worstCoulomb, std::abs(e.frictionImpulse / e.normalImpulse - 0.5));
    }
  }
  EXPECT_GT(sliding, 20);
  std::printf("sliding box: worst |F/N - mu| = %.2g, |F - m dv| = %.2g of m v0\n", worstCoulomb, worstMomentum);
}

// Events off: none, and the motion is the same bit for bit.
TEST(ContactEvents, TurnedOffThereAreNoneAndTheMotionIsTheSame) {
  const std::vector<BodyDef> defs{GroundDef(), UnitBoxDef(RVec3(0, 0.7, 0)).Moving(RVec3(1, 0, 0)).Spinning(RVec3(0, 2, 1))};
  std::vector<RRigidBody> on = MakeBodies(defs), off = MakeBodies(defs);
  RWorldSettings settings = EarthGravity();
  RIntegrator withEvents(settings);
  settings.contactEvents = false;
  RIntegrator without(settings);
  std::size_t events = 0;
  for (int s = 0; s < 120; ++s) {
    withEvents.Update(on, kDt);
    without.Update(off, kDt);
    events += withEvents.Events().size();
    EXPECT_TRUE(without.Events().empty());
    ASSERT_EQ(on[1].Position_W(), off[1].Position_W()) << "step " << s + 1;
    ASSERT_EQ(on[1].Orientation_WB().coeffs(), off[1].Orientation_WB().coeffs()) << "step " << s + 1;
  }
  EXPECT_GT(events, 30u);
}

// Events keep their vectors' capacity: once a world's contacts have been seen, a step
// allocates nothing, events on or off (boxes resting, elastic balls bouncing: begins, ends
// and persists every few steps). The balls start at one height: exact bounces keep their
// periods equal, so the warm-up sees the most contacts any measured step has (balls of
// different periods would first land together at some later step, and the solver's
// arrays grow once then, as for any world that reaches a new size).
TEST(ContactEvents, SteadyStepsAllocateNothing) {
  RBodies bodies;
  bodies.Add(GroundDef().Restitution(1));
  for (int i = 0; i < 5; ++i) bodies.Add(UnitBoxDef(RVec3(3 * i, 0.5, 0)));
  for (int i = 0; i < 3; ++i) bodies.Add(SphereDef(0.5).Mass(1).Restitution(1).At(RVec3(3 * i, 3, 4)));
  RWorldSettings settings = EarthGravity();
  settings.shortcuts.sleeping = false;
  settings.threads = 1;
  for (const bool events : {false, true}) {
    settings.contactEvents = events;
    RIntegrator integrator(settings);
    RBodies world = bodies;
    for (int s = 0; s < 300; ++s) integrator.Update(world, kDt);
    std::size_t seen = 0, begins = 0;
    g_allocations = 0;
    g_countAllocations = true;
    for (int s = 0; s < 300; ++s) {
      integrator.Update(world, kDt);
      seen += integrator.Events().size();
      for (const RContactEvent& e : integrator.Events()) begins += e.type == RContactEventType::kBegin;
    }
    g_countAllocations = false;
    EXPECT_EQ(g_allocations.load(), 0) << "events " << events;
    if (events) {
      EXPECT_GT(seen, 1500u);
      EXPECT_GT(begins, 5u);
    }
  }
}

// The per-body and per-pair views give exactly the events of Events() that name the body
// or the pair, in its order, whichever order the pair's handles are given in, also for a
// slot that names two bodies in one step (a removed box's end, the begin of the body added
// in its place); and looking them up allocates nothing.
TEST(ContactEvents, PerBodyAndPerPairViewsSelectFromEventsInOrder) {
  RBodies bodies;
  const RBodyHandle ground = bodies.Add(GroundDef());
  std::vector<RBodyHandle> boxes;
  for (int i = 0; i < 4; ++i) boxes.push_back(bodies.Add(UnitBoxDef(RVec3(1.01 * i, 0.5, 0))));
  boxes.push_back(bodies.Add(UnitBoxDef(RVec3(0, 1.5, 0))));
  RIntegrator integrator(EarthGravity());
  std::vector<RBodyHandle> named = {ground};
  const auto check = [&] {
    const std::vector<RContactEvent>& all = integrator.Events();
    for (RBodyHandle h : named) {
      std::vector<const RContactEvent*> expected, seen;
      for (const RContactEvent& e : all) {
        if (e.handleA == h || e.handleB == h) expected.push_back(&e);
      }
      for (const RContactEvent& e : integrator.EventsOf(h)) seen.push_back(&e);
      EXPECT_EQ(seen, expected) << h.index << " " << h.generation;
      EXPECT_EQ(integrator.EventsOf(h).size(), expected.size());
      for (RBodyHandle other : named) {
        std::vector<const RContactEvent*> pair;
        for (const RContactEvent& e : all) {
          if ((e.handleA == h && e.handleB == other) || (e.handleA == other && e.handleB == h)) pair.push_back(&e);
        }
        const RContactEventSpan span = integrator.EventsBetween(h, other);
        std::vector<const RContactEvent*> between;
        for (const RContactEvent& e : span) between.push_back(&e);
        EXPECT_EQ(between, pair);
        for (const RContactEvent& e : span) EXPECT_EQ(OtherBody(e, h), other);
      }
    }
  };
  for (RBodyHandle h : boxes) named.push_back(h);
  for (int s = 0; s < 10; ++s) integrator.Update(bodies, kDt), check();
  // The top box goes, and a ball takes its slot in the same step.
  bodies.Remove(boxes.back());
  const RBodyHandle ball = bodies.Add(SphereDef(0.5).Mass(1).At(RVec3(3.03, 1.5, 0)));
  ASSERT_EQ(ball.index, boxes.back().index);
  named.push_back(ball);
  integrator.Update(bodies, kDt);
  EXPECT_FALSE(integrator.EventsOf(boxes.back()).empty());
  check();
  for (int s = 0; s < 30; ++s) integrator.Update(bodies, kDt), check();
  EXPECT_FALSE(integrator.EventsOf(ball).empty());
  EXPECT_TRUE(integrator.EventsOf(RBodyHandle{}).empty());
  g_allocations = 0;
  g_countAllocations = true;
  std::size_t total = 0;
  for (RBodyHandle h : named) {
    total += integrator.EventsOf(h).size();
    for (RBodyHandle other : named) total += integrator.EventsBetween(h, other).size();
  }
  g_countAllocations = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_GT(total, 0u);
}
