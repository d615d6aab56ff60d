// RBodies, the body container: handles (stale ones detected, never aliased), dense storage
// in a deterministic order, and what adding, removing, disabling and enabling do to the
// world: contact memory and sleeping keyed by handle, so that churn elsewhere wakes nothing
// and a body that takes over a freed slot inherits nothing. Shared prepared shapes.
// Answers come from physics (a resting stack does not move, free fall is exact to rounding,
// a body nothing touches drifts uniformly) or from the plain-vector path on the same bodies.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace REngine;

namespace {

constexpr RScalar kDt = 1.0 / 60;
const RVec3 kGravity_W(0, -9.81, 0);

RBodyDef Box(const std::string& name, const RVec3& x, RScalar half = 0.5) {
  RBodyDef d;
  d.restitution = 0.5;
  d.name = name;
  d.shape = RShape::Box(RVec3::Constant(half));
  d.position_W = x;
  d.mass = 1;
  return d;
}

RBodyDef Sphere(const std::string& name, const RVec3& x, RScalar r = 0.25) {
  RBodyDef d;
  d.restitution = 0.5;
  d.name = name;
  d.shape = RShape::Sphere(r);
  d.position_W = x;
  d.mass = 1;
  return d;
}

RBodyDef Ground() {
  RBodyDef g = Box("ground", RVec3(0, -0.5, 0));
  g.shape.halfExtents = RVec3(50, 0.5, 50);
  g.kind = RBodyKind::kStatic;
  g.mass.reset();
  return g;
}

RWorldSettings Gravity() {
  RWorldSettings s;
  s.gravity_W = kGravity_W;
  return s;
}

// A ground and a stack of n unit boxes resting exactly on each other at x; their handles.
std::vector<RBodyHandle> AddStack(RBodies& bodies, int n, const RVec3& x = RVec3::Zero()) {
  std::vector<RBodyHandle> h{bodies.Add(Ground())};
  for (int i = 0; i < n; ++i) h.push_back(bodies.Add(Box("box" + std::to_string(i), x + RVec3(0, 0.5 + i, 0))));
  return h;
}

void Step(RIntegrator& integrator, RBodies& bodies, int steps) {
  for (int i = 0; i < steps; ++i) integrator.Update(bodies, kDt);
}

int RestSteps(const RIntegrator& integrator) {
  return static_cast<int>(std::ceil(integrator.Settings().sleepTime / kDt)) + 2;
}

}  // namespace

TEST(Bodies, HandlesNameTheirBodyUntilRemovedAndStaleOnesAreDetected) {
  RBodies bodies;
  const RBodyHandle a = bodies.Add(Box("a", RVec3(0, 0, 0)));
  const RBodyHandle b = bodies.Add(Box("b", RVec3(5, 0, 0)));
  const RBodyHandle c = bodies.Add(Box("c", RVec3(10, 0, 0)));
  EXPECT_EQ(bodies.Size(), 3u);
  EXPECT_EQ(bodies[b].Name(), "b");
  bodies.Remove(a);
  // The others keep their handles, whatever moved in storage.
  EXPECT_EQ(bodies[b].Name(), "b");
  EXPECT_EQ(bodies[c].Name(), "c");
  EXPECT_FALSE(bodies.Contains(a));
  EXPECT_EQ(bodies.Find(a), nullptr);
  EXPECT_THROW(bodies[a], RHandleError);
  EXPECT_THROW(bodies.Remove(a), RHandleError);
  EXPECT_THROW(bodies.Disable(a), RHandleError);
  EXPECT_THROW(bodies[RBodyHandle{}], RHandleError);
  // The freed slot is reused with a new generation: the old handle stays stale.
  const RBodyHandle d = bodies.Add(Box("d", RVec3(15, 0, 0)));
  EXPECT_EQ(d.index, a.index);
  EXPECT_NE(d.generation, a.generation);
  EXPECT_FALSE(bodies.Contains(a));
  EXPECT_EQ(bodies[d].Name(), "d");
  // A definition that cannot make a body adds nothing.
  RBodyDef bad = Box("bad", RVec3(0, 0, 0));
  bad.shape.halfExtents.x() = -1;
  EXPECT_THROW(bodies.Add(bad), RBodyError);
  EXPECT_EQ(bodies.Size(), 3u);
}

TEST(Bodies, StorageIsDenseInAnOrderSetByTheCallsAlone) {
  RBodies bodies;
  std::vector<RBodyHandle> h;
  for (int i = 0; i < 5; ++i) h.push_back(bodies.Add(Sphere(std::to_string(i), RVec3(3.0 * i, 0, 0))));
  bodies.Remove(h[1]);   // 4 takes 1's place: 0 4 2 3
  bodies.Disable(h[0]);  // 0 goes after the enabled ones: 3 4 2 | 0
  bodies.Add(Sphere("5", RVec3(20, 0, 0)));  // 3 4 2 5 | 0
  std::string order;
  for (const RRigidBody& b : bodies) order += b.Name();
  EXPECT_EQ(order, "3425");
  EXPECT_EQ(bodies.EnabledCount(), 4u);
  ASSERT_EQ(bodies.Size(), 5u);
  EXPECT_EQ(bodies.At(4).Name(), "0");
  for (std::size_t i = 0; i < bodies.Size(); ++i) {
    EXPECT_EQ(&bodies[bodies.HandleAt(i)], &bodies.At(i));
  }
}

// The container steps exactly as the plain vector does for the same bodies in the same
// order: bit for bit (a stack settling under gravity, with contacts and warm starts).
TEST(Bodies, StepsBitForBitLikeAPlainVector) {
  RBodies bodies;
  std::vector<RRigidBody> vec;
  for (int i = 0; i < 4; ++i) {
    RBodyDef d = Box("box" + std::to_string(i), RVec3(0.1 * i, 0.5 + 1.001 * i, 0));
    d.angularVelocity_W = RVec3(0.1, 0.2 * i, 0);
    bodies.Add(d);
    vec.emplace_back(d);
  }
  bodies.Add(Ground());
  vec.emplace_back(Ground());
  RIntegrator a(Gravity()), b(Gravity());
  for (int s = 0; s < 120; ++s) {
    a.Update(bodies, kDt);
    b.Update(vec, kDt);
  }
  for (std::size_t i = 0; i < vec.size(); ++i) {
    EXPECT_EQ(bodies.At(i).Position_W(), vec[i].Position_W()) << i;
    EXPECT_EQ(bodies.At(i).Velocity_W(), vec[i].Velocity_W()) << i;
    EXPECT_EQ(bodies.At(i).Orientation_WB().coeffs(), vec[i].Orientation_WB().coeffs()) << i;
    EXPECT_EQ(bodies.At(i).IsSleeping(), vec[i].IsSleeping()) << i;
  }
}

// Churn (as bench_churn measures it): a sleeping stack, and a small body added and removed
// far away every 10 steps. The stack stays asleep and does not move at all; nothing but the
// newcomer is ever looked at by the narrow phase.
TEST(Bodies, ChurnElsewhereLeavesASleepingStackAsleepAndUntouched) {
  RBodies bodies;
  RIntegrator integrator(Gravity());
  const std::vector<RBodyHandle> stack = AddStack(bodies, 5);
  Step(integrator, bodies, RestSteps(integrator));
  for (std::size_t i = 1; i < stack.size(); ++i) ASSERT_TRUE(bodies[stack[i]].IsSleeping()) << i;
  std::vector<RVec3> x0;
  for (RBodyHandle h : stack) x0.push_back(bodies[h].Position_W());
  RBodyHandle debris;
  for (int s = 0; s < 200; ++s) {
    if (s % 10 == 0) {
      if (debris.IsValid()) bodies.Remove(debris);
      debris = bodies.Add(Sphere("debris", RVec3(40, 10, 40)));
    }
    integrator.Update(bodies, kDt);
    EXPECT_EQ(integrator.PairStats().sleepingBodies, 5u) << "step " << s;
    EXPECT_EQ(integrator.PairStats().narrowPhase, 0u) << "step " << s;
  }
  for (std::size_t i = 0; i < stack.size(); ++i) {
    EXPECT_EQ(bodies[stack[i]].Position_W(), x0[i]) << i;
    if (i > 0) {
      EXPECT_TRUE(bodies[stack[i]].IsSleeping()) << i;
    }
  }
}

// Removing the body a sleeping stack rests on wakes the stack, and the boxes above fall
// freely: after k steps their centre of mass moves at exactly -g k dt (kick-drift-kick is
// exact for a constant acceleration, and the impulses between them cancel) until they meet
// the ground. Each box alone is within 1e-6 m/s of it: the warm start they slept with
// (m g dt between them) is released by the solver to a residual of 3e-8 m/s.
TEST(Bodies, RemovingASupportWakesItsIslandWhichFalls) {
  RBodies bodies;
  RIntegrator integrator(Gravity());
  // A pedestal box on the ground and two boxes on it; a far stack that must stay asleep.
  const std::vector<RBodyHandle> stack = AddStack(bodies, 3);
  const std::vector<RBodyHandle> far{bodies.Add(Box("far0", RVec3(20, 0.5, 0))),
                                     bodies.Add(Box("far1", RVec3(20, 1.5, 0)))};
  Step(integrator, bodies, RestSteps(integrator));
  ASSERT_TRUE(bodies[stack[3]].IsSleeping());
  ASSERT_TRUE(bodies[far[1]].IsSleeping());
  const RVec3 farTop = bodies[far[1]].Position_W();
  bodies.Remove(stack[1]);  // the pedestal
  for (int k = 1; k <= 10; ++k) {
    integrator.Update(bodies, kDt);
    EXPECT_FALSE(bodies[stack[2]].IsSleeping());
    const RScalar free = kGravity_W.y() * kDt * k;
    const RScalar v2 = bodies[stack[2]].Velocity_W().y(), v3 = bodies[stack[3]].Velocity_W().y();
    EXPECT_NEAR((v2 + v3) / 2, free, 1e-12) << k;
    EXPECT_NEAR(v2, free, 1e-6) << k;
    EXPECT_NEAR(v3, free, 1e-6) << k;
  }
  EXPECT_TRUE(bodies[far[1]].IsSleeping());
  EXPECT_EQ(bodies[far[1]].Position_W(), farTop);
}

// A removed static body (the ground) wakes everything that might rest on it.
TEST(Bodies, RemovingStaticGeometryWakesEverySleeper) {
  RBodies bodies;
  RIntegrator integrator(Gravity());
  const std::vector<RBodyHandle> stack = AddStack(bodies, 2);
  Step(integrator, bodies, RestSteps(integrator));
  ASSERT_TRUE(bodies[stack[1]].IsSleeping());
  bodies.Remove(stack[0]);
  integrator.Update(bodies, kDt);
  // Falling together (see RemovingASupportWakesItsIslandWhichFalls for the tolerances).
  const RScalar v1 = bodies[stack[1]].Velocity_W().y(), v2 = bodies[stack[2]].Velocity_W().y();
  EXPECT_NEAR((v1 + v2) / 2, kGravity_W.y() * kDt, 1e-12);
  EXPECT_NEAR(v1, kGravity_W.y() * kDt, 1e-6);
  EXPECT_FALSE(bodies[stack[1]].IsSleeping());
}

// A body that takes over a freed slot in the same frame (same count, same slot) inherits no
// impulse: its first step finds no warm start, while the untouched pairs keep theirs.
TEST(Bodies, ABodyInAFreedSlotInheritsNoContactMemory) {
  RWorldSettings settings = Gravity();
  settings.shortcuts.sleeping = false;
  RIntegrator integrator(settings);
  RBodies bodies;
  AddStack(bodies, 1, RVec3(0, 0, 0));
  const RBodyHandle victim = bodies.Add(Box("victim", RVec3(10, 0.5, 0)));
  Step(integrator, bodies, 30);
  // Ground-box and ground-victim manifolds, four points each, all warm.
  ASSERT_EQ(integrator.PairStats().contactPoints, 8u);
  ASSERT_EQ(integrator.PairStats().warmStarted, 8u);
  bodies.Remove(victim);
  const RBodyHandle heir = bodies.Add(Box("heir", RVec3(10, 0.5, 0)));
  ASSERT_EQ(heir.index, victim.index);
  integrator.Update(bodies, kDt);
  EXPECT_EQ(integrator.PairStats().contactPoints, 8u);
  EXPECT_EQ(integrator.PairStats().warmStarted, 4u) << "only the untouched pair is warm";
  for (const RContact& c : integrator.Contacts()) {
    EXPECT_EQ(&bodies[c.handleA], &bodies.At(c.a));
    EXPECT_EQ(&bodies[c.handleB], &bodies.At(c.b));
    EXPECT_LT(c.handleA.index, c.handleB.index);
  }
}

// A removal that moves another body in storage (the last takes the gap) keeps that body's
// pairs' contact memory: every point of the resting stack starts warm.
TEST(Bodies, ABodyMovedInStorageKeepsItsWarmStarts) {
  RWorldSettings settings = Gravity();
  settings.shortcuts.sleeping = false;
  RIntegrator integrator(settings);
  RBodies bodies;
  const RBodyHandle early = bodies.Add(Sphere("early", RVec3(30, 5, 0)));
  AddStack(bodies, 3);
  Step(integrator, bodies, 30);
  const std::uint64_t points = integrator.PairStats().contactPoints;
  ASSERT_EQ(integrator.PairStats().warmStarted, points);
  bodies.Remove(early);  // the top box moves to position 0, below the ground
  integrator.Update(bodies, kDt);
  EXPECT_EQ(integrator.PairStats().contactPoints, points);
  EXPECT_EQ(integrator.PairStats().warmStarted, points);
}

// A disabled body is parked: not moved, not touched, costing nothing; enabled again it
// carries on from its state. A ball flies through where a disabled wall stands.
TEST(Bodies, ADisabledBodyIsParkedAndTouchesNothing) {
  RIntegrator integrator;  // zero g
  RBodies bodies;
  RBodyDef wallDef = Box("wall", RVec3(5, 0, 0));
  wallDef.shape.halfExtents = RVec3(0.5, 5, 5);
  const RBodyHandle wall = bodies.Add(wallDef);
  RBodyDef ballDef = Sphere("ball", RVec3(0, 0, 0));
  ballDef.velocity_W = RVec3(10, 0, 0);
  const RBodyHandle ball = bodies.Add(ballDef);
  bodies.Disable(wall);
  EXPECT_FALSE(bodies.IsEnabled(wall));
  bodies[wall].AddImpulse_W(RVec3(1, 0, 0));  // kept for when it is enabled
  const int steps = 60;
  Step(integrator, bodies, steps);
  EXPECT_EQ(integrator.PairStats().pairs, 0u) << "one enabled body: no pair";
  EXPECT_NEAR(bodies[ball].Position_W().x(), 10 * kDt * steps, 1e-12);
  EXPECT_EQ(bodies[ball].Velocity_W(), RVec3(10, 0, 0));
  EXPECT_EQ(bodies[wall].Position_W(), RVec3(5, 0, 0));
  // Enabled, the wall moves off with the impulse given while parked (1 N s on 1 kg: 1 m/s)
  // and meets nothing: the ball is far past it.
  bodies.Enable(wall);
  integrator.Update(bodies, kDt);
  EXPECT_EQ(integrator.PairStats().pairs, 1u);
  EXPECT_EQ(integrator.PairStats().contacts, 0u);
  EXPECT_EQ(bodies[wall].Velocity_W(), RVec3(1, 0, 0));
}

// Bodies made from one prepared shape share its polyhedron (no hull is built) and have the
// mass properties a body made from the shape itself has.
TEST(Bodies, PreparedShapesAreSharedNotRebuilt) {
  RShape hull;
  hull = RShape::Hull({RVec3(0, 0, 0), RVec3(2, 0, 0), RVec3(0, 1, 0), RVec3(0, 0, 3), RVec3(1, 1, 1)});
  const std::shared_ptr<const RPreparedShape> prepared = PrepareShape(hull);
  RBodyDef own;
  own.restitution = 0.5;
  own.shape = hull;
  own.density = 7;
  own.position_W = RVec3(1, 2, 3);
  RBodyDef shared = own;
  shared.shape = RShape{};  // not read
  shared.prepared = prepared;
  RBodies bodies;
  const RBodyHandle a = bodies.Add(own), b = bodies.Add(shared), c = bodies.Add(shared);
  EXPECT_EQ(bodies[b].Polyhedron_B().get(), prepared->polyhedron_B.get());
  EXPECT_EQ(bodies[c].Polyhedron_B().get(), prepared->polyhedron_B.get());
  EXPECT_EQ(bodies[b].Mass(), bodies[a].Mass());
  EXPECT_EQ(bodies[b].Inertia_B(), bodies[a].Inertia_B());
  EXPECT_EQ(bodies[b].Position_W(), bodies[a].Position_W());
  EXPECT_EQ(bodies[b].ShapePosition_W(), RVec3(1, 2, 3));
  EXPECT_EQ(bodies[b].Shape().points.size(), hull.points.size());
  // A bad shape is refused when prepared, naming the field.
  RShape bad;
  bad = RShape::Sphere(-1);
  try {
    PrepareShape(bad);
    ADD_FAILURE() << "a negative radius was accepted";
  } catch (const RBodyError& e) {
    EXPECT_EQ(e.Field(), "shape.radius");
  }
}
