// Contact events (RIntegrator::Events, RContactEvents.h): when they begin, persist and end,
// against closed forms: the step of a free fall's first touch and of an elastic ball's
// bounces, a bounce and a sensor crossing inside one step, a missile through a crate,
// kinematic sensors sweeping through sleeping bodies, and removal, disabling and sleep.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include "support/TestBodies.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "events/EventsFixtures.h"

using namespace REngine;
using namespace REngine::test;

namespace {

// One event as the tests compare it: step, type and the two handles.
struct Seen {
  std::uint64_t step;
  RContactEventType type;
  RBodyHandle a, b;
  RContactEvent event;
};

std::string Describe(const std::vector<Seen>& seen) {
  std::string s;
  for (const Seen& e : seen) {
    s += "  step " + std::to_string(e.step) + " " + ToString(e.type) + " (" + std::to_string(e.a.index) + "," +
         std::to_string(e.b.index) + ")\n";
  }
  return s;
}

// Steps `steps` times, collecting every event with its step (1-based: step k runs from
// (k - 1) dt to k dt).
template <class Bodies>
std::vector<Seen> StepAndCollect(RIntegrator& integrator, Bodies& bodies, int steps, std::uint64_t& step) {
  std::vector<Seen> seen;
  for (int s = 0; s < steps; ++s) {
    integrator.Update(bodies, kDt);
    ++step;
    for (const RContactEvent& e : integrator.Events()) seen.push_back({step, e.type, e.handleA, e.handleB, e});
  }
  return seen;
}

// The free-fall height (of a ball's bottom above the ground) that makes first contact come
// half-way through step 28: t = 27.5 dt, so that no rounding can move it across a boundary.
RScalar DropHeight() { return 0.5 * kG * (27.5 * kDt) * (27.5 * kDt); }

// The closed form: the step during which a body falling from rest through h first touches.
std::uint64_t StepOfTouch(RScalar h) { return static_cast<std::uint64_t>(std::ceil(std::sqrt(2 * h / kG) / kDt)); }

}  // namespace

// A ball (e = 0) dropped on the ground: begin in the step the free fall's closed form gives,
// then persist every step while it rests, never an end. Every event's normal impulse is
// the ball's momentum balance over its step, m (v1 - v0) + m g dt, to rounding.
TEST(ContactEvents, DroppedBallBeginsAtTheStepOfFirstTouchAndPersistsWhileResting) {
  const RScalar h = DropHeight();
  ASSERT_EQ(StepOfTouch(h), 28u);
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      GroundDef(), SphereDef(0.5).Mass(2).Restitution(0).At(RVec3(0, 0.5 + h, 0)).Named("ball")});
  RWorldSettings settings = EarthGravity();
  settings.shortcuts.sleeping = false;
  RIntegrator integrator(settings);
  std::uint64_t step = 0;
  const RScalar m = bodies[1].Mass();
  std::vector<Seen> seen;
  RScalar worst = 0;  // |J - balance| / its scale
  for (int s = 0; s < 120; ++s) {
    const RScalar v0 = bodies[1].Velocity_W().y();
    integrator.Update(bodies, kDt);
    ++step;
    const RScalar v1 = bodies[1].Velocity_W().y();
    for (const RContactEvent& e : integrator.Events()) {
      seen.push_back({step, e.type, e.handleA, e.handleB, e});
      // Momentum balance along y: the contact's impulse is all that acts besides gravity.
      const RScalar balance = m * (v1 - v0) + m * kG * kDt;
      const RScalar scale = m * (std::abs(v0) + kG * kDt);
      EXPECT_NEAR(e.normalImpulse, balance, 16 * kEps * scale) << "step " << step;
      worst = std::max(worst, std::abs(e.normalImpulse - balance) / scale);
      EXPECT_NEAR(e.frictionImpulse, 0, 1e-12 * balance) << "step " << step;
      EXPECT_NEAR(e.normal_W.y(), 1, 1e-12);  // ground (A) to ball (B)
    }
  }
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.front().step, 28u) << Describe(seen);
  EXPECT_EQ(seen.front().type, RContactEventType::kBegin);
  EXPECT_EQ(seen.front().a.index, 0u);
  EXPECT_EQ(seen.front().b.index, 1u);
  EXPECT_NEAR((seen.front().event.point_W - RVec3::Zero()).norm(), 0, 1e-9);  // under the ball
  // Resting: one persist each step from 29 to the end, and no end.
  ASSERT_EQ(seen.size(), 120u - 27u) << Describe(seen);
  for (std::size_t k = 1; k < seen.size(); ++k) {
    EXPECT_EQ(seen[k].type, RContactEventType::kPersist) << "step " << seen[k].step;
    EXPECT_EQ(seen[k].step, 28u + k);
  }
  std::printf("dropped ball: begin in step %llu, worst |J - m dv - m g dt| = %.2g of m (|v0| + g dt)\n",
              static_cast<unsigned long long>(seen.front().step), worst);
  // At rest the impulse is the weight's over a step.
  EXPECT_NEAR(seen.back().event.normalImpulse, m * kG * kDt, 1e-9 * m * kG * kDt);
}

// An elastic ball (e = 1, no friction) bounces with period 2 t1 (t1 = sqrt(2 h / g)): each
// bounce begins and ends inside the step that holds it, at t1, 3 t1, 5 t1 ..., and nothing
// happens between. The impulse is m (1 + e) v = 2 m sqrt(2 g h): the impact is found on the
// ball's parabola and bounces the speed at the moment of contact (to rounding: 1e-9).
TEST(ContactEvents, ElasticBallBeginsAndEndsAtTheClosedFormBounceSteps) {
  const RScalar h = DropHeight();
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      GroundDef().Restitution(1).Friction(0),
      SphereDef(0.5).Mass(3).Restitution(1).Friction(0).At(RVec3(0, 0.5 + h, 0)).Named("ball")});
  RIntegrator integrator(EarthGravity());
  std::uint64_t step = 0;
  const std::vector<Seen> seen = StepAndCollect(integrator, bodies, 200, step);
  const RScalar t1 = std::sqrt(2 * h / kG);
  const RScalar m = bodies[1].Mass();
  std::vector<std::uint64_t> bounces;
  for (int n = 1; (2 * n - 1) * t1 < 200 * kDt; ++n) {
    bounces.push_back(static_cast<std::uint64_t>(std::ceil((2 * n - 1) * t1 / kDt)));
  }
  ASSERT_EQ(bounces, (std::vector<std::uint64_t>{28, 83, 138, 193}));
  ASSERT_EQ(seen.size(), 2 * bounces.size()) << Describe(seen);
  RScalar worst = 0;  // |J - 2 m v| / (m g dt)
  for (std::size_t n = 0; n < bounces.size(); ++n) {
    const Seen& begin = seen[2 * n];
    const Seen& end = seen[2 * n + 1];
    EXPECT_EQ(begin.step, bounces[n]);
    EXPECT_EQ(begin.type, RContactEventType::kBegin);
    EXPECT_EQ(end.step, bounces[n]);
    EXPECT_EQ(end.type, RContactEventType::kEnd);
    EXPECT_NEAR(begin.event.normalImpulse, 2 * m * std::sqrt(2 * kG * h), 1e-9 * 2 * m * std::sqrt(2 * kG * h))
        << "bounce " << n;
    EXPECT_EQ(begin.event.normalImpulse, end.event.normalImpulse);
    // Where the ball met the ground: its top face, under the ball, at the moment of impact.
    EXPECT_NEAR((begin.event.point_W - RVec3::Zero()).norm(), 0, 1e-9) << "bounce " << n;
    EXPECT_NEAR((begin.event.normal_W - RVec3::UnitY()).norm(), 0, 1e-12) << "bounce " << n;
    worst = std::max(worst, std::abs(begin.event.normalImpulse - 2 * m * std::sqrt(2 * kG * h)) / (m * kG * kDt));
  }
  std::printf("elastic ball: bounces in steps 28 83 138 193, worst |J - 2 m v| = %.2g m g dt\n", worst);
}

// In zero g a ball 5 cm from a wall at 10 m/s touches it 5 ms into the first step and leaves
// within it: begin and end in step 1, impulse 2 m v to rounding; then nothing.
TEST(ContactEvents, BallBouncingInsideOneStepBeginsAndEndsInThatStep) {
  RBodies bodies;
  const RBodyHandle wall = bodies.Add(BoxDef(RVec3(0.5, 5, 5)).Static().Restitution(1).Friction(0).At(RVec3(0.5, 0, 0)));
  const RBodyHandle ball = bodies.Add(
      SphereDef(0.5).Mass(1.5).Restitution(1).Friction(0).At(RVec3(-0.55, 0, 0)).Moving(RVec3(10, 0, 0)));
  RIntegrator integrator;
  std::uint64_t step = 0;
  const std::vector<Seen> seen = StepAndCollect(integrator, bodies, 10, step);
  ASSERT_EQ(seen.size(), 2u) << Describe(seen);
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(seen[k].step, 1u);
    EXPECT_EQ(seen[k].a, wall);
    EXPECT_EQ(seen[k].b, ball);
    EXPECT_NEAR(seen[k].event.normalImpulse, 2 * 1.5 * 10, 1e-12 * 30);
    EXPECT_NEAR((seen[k].event.normal_W - RVec3(-1, 0, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((seen[k].event.point_W - RVec3::Zero()).norm(), 0, 1e-9);  // the wall's face
  }
  EXPECT_EQ(seen[0].type, RContactEventType::kBegin);
  EXPECT_EQ(seen[1].type, RContactEventType::kEnd);
  EXPECT_NEAR(bodies[ball].Velocity_W().x(), -10, 1e-12);
  std::printf("bounce inside one step: |J / (2 m v) - 1| = %.2g\n", std::abs(seen[0].event.normalImpulse / 30 - 1));
}

// A 3 km/s missile crosses a 10 cm sensor plate inside one 1/60 s step (50 m): begin and end
// in that step, at the plate's face, with no impulse, and it flies on untouched, whichever of
// the two does not respond. Beside the plate's edge by 5 cm it touches nothing, though its
// deepest point closes within the step (the time of impact alone would call it a hit).
TEST(ContactEvents, MissileCrossingAThinSensorInsideOneStepBeginsAndEnds) {
  struct Case {
    bool missileResponds, plateResponds;
  };
  for (const Case& k : {Case{false, false}, Case{true, false}, Case{false, true}}) {
    for (const RScalar offset : {RScalar(0), RScalar(5.15)}) {
      SCOPED_TRACE(testing::Message() << "missile responds " << k.missileResponds << ", plate responds "
                                      << k.plateResponds << ", offset " << offset);
      RBodies bodies;
      BodyDef plateDef = BoxDef(RVec3(0.05, 5, 5)).Static().At(RVec3::Zero());
      plateDef.responds = k.plateResponds;
      BodyDef missileDef = BoxDef(RVec3(0.2, 0.1, 0.1)).Mass(5).At(RVec3(-20.37, offset, 0)).Moving(RVec3(3000, 0, 0));
      missileDef.responds = k.missileResponds;
      const RBodyHandle plate = bodies.Add(plateDef);
      const RBodyHandle missile = bodies.Add(missileDef);
      RIntegrator integrator;
      integrator.Update(bodies, kDt);
      // The pair was looked at, closing within the step.
      ASSERT_EQ(integrator.Contacts().size(), 1u);
      ASSERT_TRUE(std::isfinite(integrator.Contacts()[0].timeOfImpact));
      std::vector<Seen> seen;
      for (const RContactEvent& e : integrator.Events()) seen.push_back({1, e.type, e.handleA, e.handleB, e});
      std::uint64_t step = 1;
      const std::vector<Seen> later = StepAndCollect(integrator, bodies, 4, step);
      EXPECT_TRUE(later.empty()) << Describe(later);
      EXPECT_EQ(bodies[missile].Velocity_W(), RVec3(3000, 0, 0));
      EXPECT_NEAR(bodies[missile].Position_W().x(), -20.37 + 3000 * 5 * kDt, 1e-9);
      if (offset != 0) {
        EXPECT_TRUE(seen.empty()) << Describe(seen);
        continue;
      }
      ASSERT_EQ(seen.size(), 2u) << Describe(seen);
      EXPECT_EQ(seen[0].type, RContactEventType::kBegin);
      EXPECT_EQ(seen[1].type, RContactEventType::kEnd);
      for (const Seen& e : seen) {
        EXPECT_EQ(e.a, plate);
        EXPECT_EQ(e.b, missile);
        EXPECT_EQ(e.event.normalImpulse, 0);
        // First touch: the plate's face x = -0.05, within the missile's cross-section.
        EXPECT_NEAR(e.event.point_W.x(), -0.05, 1e-9);
        EXPECT_LE(std::abs(e.event.point_W.y()), 0.1 + 1e-9);
        EXPECT_NEAR((e.event.normal_W - RVec3(-1, 0, 0)).norm(), 0, 1e-9);
      }
    }
  }
}

// A missile that does not respond passes through a crate at rest: reported (begin in the
// step its nose reaches the crate, persist while inside, end in the step its tail leaves:
// closed form from its speed) and not bounced: neither body's velocity changes.
TEST(ContactEvents, NonRespondingMissileThroughACrateIsReportedNotBounced) {
  for (const RScalar speed : {RScalar(30), RScalar(3000)}) {
    SCOPED_TRACE(testing::Message() << "speed " << speed);
    RBodies bodies;
    const RBodyHandle crate = bodies.Add(UnitBoxDef(RVec3::Zero()));
    BodyDef missileDef = BoxDef(RVec3::Constant(0.1)).Mass(2).At(RVec3(-2.37, 0.2, 0)).Moving(RVec3(speed, 0, 0));
    missileDef.responds = false;
    const RBodyHandle missile = bodies.Add(missileDef);
    RIntegrator integrator;
    std::uint64_t step = 0;
    const std::vector<Seen> seen = StepAndCollect(integrator, bodies, 12, step);
    // The nose (x + 0.1) reaches the crate's face (-0.5) after 1.77 m, the tail (x - 0.1)
    // leaves the far face (0.5) after 2.97 m.
    const auto stepAt = [&](RScalar distance) {
      return static_cast<std::uint64_t>(std::ceil(distance / speed / kDt));
    };
    const std::uint64_t first = stepAt(1.77), last = stepAt(2.97);
    ASSERT_EQ(seen.size(), last - first + 1 + (first == last)) << Describe(seen);
    EXPECT_EQ(seen.front().step, first);
    EXPECT_EQ(seen.front().type, RContactEventType::kBegin);
    EXPECT_EQ(seen.back().step, last);
    EXPECT_EQ(seen.back().type, RContactEventType::kEnd);
    for (std::size_t k = 1; k + 1 < seen.size(); ++k) EXPECT_EQ(seen[k].type, RContactEventType::kPersist);
    for (const Seen& e : seen) {
      EXPECT_EQ(e.a, crate);
      EXPECT_EQ(e.b, missile);
      EXPECT_EQ(e.event.normalImpulse, 0);
    }
    EXPECT_EQ(bodies[crate].Velocity_W(), RVec3::Zero());
    EXPECT_EQ(bodies[crate].AngularVelocity_W(), RVec3::Zero());
    EXPECT_EQ(bodies[missile].Velocity_W(), RVec3(speed, 0, 0));
  }
}

// Removing or disabling a body ends its contacts in the next step's events, naming its
// (now stale) handle; the other pairs carry on; enabling it again begins anew.
TEST(ContactEvents, RemovingOrDisablingABodyEndsItsContacts) {
  RBodies bodies;
  const RBodyHandle ground = bodies.Add(GroundDef());
  const RBodyHandle box1 = bodies.Add(UnitBoxDef(RVec3(-2, 0.5, 0)));
  const RBodyHandle box2 = bodies.Add(UnitBoxDef(RVec3(2, 0.5, 0)));
  RWorldSettings settings = EarthGravity();
  settings.shortcuts.sleeping = false;
  RIntegrator integrator(settings);
  const auto events = [&] {
    integrator.Update(bodies, kDt);
    std::vector<Seen> seen;
    for (const RContactEvent& e : integrator.Events()) seen.push_back({0, e.type, e.handleA, e.handleB, e});
    return seen;
  };
  std::vector<Seen> seen = events();
  ASSERT_EQ(seen.size(), 2u) << Describe(seen);  // resting from the start: begin, both
  for (int s = 0; s < 5; ++s) seen = events();
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].type, RContactEventType::kPersist);
  EXPECT_EQ(seen[1].type, RContactEventType::kPersist);

  bodies.Remove(box1);
  seen = events();
  ASSERT_EQ(seen.size(), 2u) << Describe(seen);
  EXPECT_EQ(seen[0].type, RContactEventType::kEnd);
  EXPECT_EQ(seen[0].a, ground);
  EXPECT_EQ(seen[0].b, box1);
  EXPECT_EQ(seen[0].event.normalImpulse, 0);
  EXPECT_NEAR(seen[0].event.normal_W.y(), 1, 1e-12);  // the last one reported
  EXPECT_EQ(seen[1].type, RContactEventType::kPersist);
  EXPECT_EQ(seen[1].b, box2);

  bodies.Disable(box2);
  seen = events();
  ASSERT_EQ(seen.size(), 1u) << Describe(seen);
  EXPECT_EQ(seen[0].type, RContactEventType::kEnd);
  EXPECT_EQ(seen[0].b, box2);
  seen = events();
  EXPECT_TRUE(seen.empty()) << Describe(seen);

  bodies.Enable(box2);
  seen = events();
  ASSERT_EQ(seen.size(), 1u) << Describe(seen);
  EXPECT_EQ(seen[0].type, RContactEventType::kBegin);
  EXPECT_EQ(seen[0].b, box2);
}

// A box resting on the ground falls asleep in contact: no end, no events while it sleeps,
// and no begin when it wakes (persist again). Removed while asleep, its contact ends.
TEST(ContactEvents, ASleepingPairStaysInContactAndWakesWithoutABegin) {
  RBodies bodies;
  bodies.Add(GroundDef());
  const RBodyHandle box = bodies.Add(UnitBoxDef(RVec3(0, 0.5, 0)));
  RIntegrator integrator(EarthGravity());
  std::uint64_t step = 0;
  std::vector<Seen> seen = StepAndCollect(integrator, bodies, 1, step);
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].type, RContactEventType::kBegin);
  for (int s = 0; s < 200 && !bodies[box].IsSleeping(); ++s) {
    seen = StepAndCollect(integrator, bodies, 1, step);
    ASSERT_EQ(seen.size(), 1u) << "step " << step;
    ASSERT_EQ(seen[0].type, RContactEventType::kPersist) << "step " << step;
  }
  ASSERT_TRUE(bodies[box].IsSleeping());
  seen = StepAndCollect(integrator, bodies, 30, step);
  EXPECT_TRUE(seen.empty()) << Describe(seen);
  bodies[box].Wake();
  seen = StepAndCollect(integrator, bodies, 1, step);
  ASSERT_EQ(seen.size(), 1u) << Describe(seen);
  EXPECT_EQ(seen[0].type, RContactEventType::kPersist);
  // Asleep again, then removed: its contact ends.
  for (int s = 0; s < 200 && !bodies[box].IsSleeping(); ++s) StepAndCollect(integrator, bodies, 1, step);
  ASSERT_TRUE(bodies[box].IsSleeping());
  bodies.Remove(box);
  seen = StepAndCollect(integrator, bodies, 1, step);
  ASSERT_EQ(seen.size(), 1u) << Describe(seen);
  EXPECT_EQ(seen[0].type, RContactEventType::kEnd);
  EXPECT_EQ(seen[0].b, box);
}

// Kinematic sensors (they do not respond), still until a box has fallen asleep on its
// pedestal, then sweeping at 600 m/s (10 m a step) through a static crate and through the
// box: both pairs begin and end in that step, where each plate meets each face, and the box
// sleeps on (a sensor wakes nothing).
TEST(ContactEvents, KinematicSensorsSweepThroughStaticAndSleepingBodiesWithoutWakingThem) {
  RBodies bodies;
  const RBodyHandle crate = bodies.Add(BoxDef(RVec3::Constant(0.5)).Static());
  bodies.Add(BoxDef(RVec3(0.5, 0.25, 0.5)).Static().At(RVec3(0, 3, 0)));
  const RBodyHandle box = bodies.Add(UnitBoxDef(RVec3(0, 3.75, 0)));
  const auto sensor = [&](RScalar y) {
    BodyDef d = BoxDef(RVec3(0.05, 0.3, 0.3)).Kinematic().At(RVec3(-3.37, y, 0));
    d.responds = false;
    return bodies.Add(d);
  };
  const RBodyHandle low = sensor(0), high = sensor(3.8);
  RIntegrator integrator(EarthGravity());
  for (int s = 0; s < 120 && !bodies[box].IsSleeping(); ++s) integrator.Update(bodies, kDt);
  ASSERT_TRUE(bodies[box].IsSleeping());
  bodies[low].SetVelocity_W(RVec3(600, 0, 0));
  bodies[high].SetVelocity_W(RVec3(600, 0, 0));
  std::uint64_t step = 0;
  const std::vector<Seen> seen = StepAndCollect(integrator, bodies, 3, step);
  ASSERT_EQ(seen.size(), 4u) << Describe(seen);
  const RBodyHandle touched[4] = {crate, crate, box, box}, sensors[4] = {low, low, high, high};
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(seen[k].step, 1u);
    EXPECT_EQ(seen[k].type, k % 2 == 0 ? RContactEventType::kBegin : RContactEventType::kEnd);
    EXPECT_EQ(seen[k].a, touched[k]);
    EXPECT_EQ(seen[k].b, sensors[k]);
    EXPECT_NEAR(seen[k].event.point_W.x(), -0.5, 1e-9);
    EXPECT_NEAR((seen[k].event.normal_W - RVec3(-1, 0, 0)).norm(), 0, 1e-9);
  }
  EXPECT_TRUE(bodies[box].IsSleeping());
  EXPECT_EQ(bodies[box].Velocity_W(), RVec3::Zero());
}
