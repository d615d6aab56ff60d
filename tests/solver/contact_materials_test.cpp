// Contact materials (RIntegrator::SetContactCallback, RBodyDef::oneWay) against closed forms:
// a conveyor belt's surface velocity carried to the crate on it, a restitution of 1 given by
// the callback returning the impact speed, a disabled contact passed through, a ball thrown up
// through a one-way slab landing on it, and the same bits on any thread count and after a
// saved state taken while a ball is inside the slab.
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RWorldState.h>
#include <gtest/gtest.h>

#include <cstring>

using namespace REngine;

namespace {

constexpr RScalar kDt = 1.0 / 60, kG = 9.81;

RBodyDef Box(const RVec3& half, const RVec3& at, RBodyKind kind = RBodyKind::kDynamic) {
  RBodyDef d;
  d.shape = RShape::Box(half);
  d.position_W = at;
  d.kind = kind;
  return d;
}

RBodyDef Ball(RScalar r, const RVec3& at, const RVec3& v = RVec3::Zero()) {
  RBodyDef d;
  d.shape = RShape::Sphere(r);
  d.position_W = at;
  d.velocity_W = v;
  return d;
}

struct World {
  RBodies bodies;
  RIntegrator integrator;
  explicit World(int threads = 1) {
    integrator.Settings().gravity_W = RVec3(0, -kG, 0);
    integrator.Settings().threads = threads;
  }
  void Step(int n) {
    for (int k = 0; k < n; ++k) integrator.Update(bodies, kDt);
  }
};

// The belt: b's surface relative to a's moves at 1.5 m/s along x when a is the belt.
struct Belt {
  RBodyHandle belt;
  int calls = 0;
  static void Call(const RRigidBody& a, const RRigidBody&, const RContact& c, RContactSettings& s, void* user) {
    Belt& self = *static_cast<Belt*>(user);
    ++self.calls;
    const RVec3 u(1.5, 0, 0);
    s.relativeSurfaceVelocity_W = c.handleA == self.belt ? u : RVec3(-u);
    (void)a;
  }
};

TEST(ContactMaterials, AConveyorCarriesTheCrateAtItsSurfaceSpeed) {
  World w;
  Belt belt;
  RBodyDef floor = Box(RVec3(20, 0.1, 2), RVec3(0, -0.1, 0), RBodyKind::kStatic);
  belt.belt = w.bodies.Add(floor);
  const RBodyHandle crate = w.bodies.Add(Box(RVec3(0.3, 0.3, 0.3), RVec3(0, 0.3, 0)));
  w.integrator.SetContactCallback(&Belt::Call, &belt);
  w.Step(120);
  // Friction (mu 0.5, 0.5 g of deceleration) brings it to 1.5 m/s within 0.31 s; then it
  // rides at the belt's speed.
  EXPECT_NEAR(w.bodies[crate].Velocity_W().x(), 1.5, 1e-9);
  EXPECT_NEAR(w.bodies[crate].Velocity_W().z(), 0, 1e-12);
  EXPECT_EQ(belt.calls, 1);  // one new contact, kept while it touches
}

TEST(ContactMaterials, TheCallbacksRestitutionReturnsTheImpactSpeed) {
  World w;
  w.bodies.Add(Box(RVec3(5, 0.5, 5), RVec3(0, -0.5, 0), RBodyKind::kStatic));
  const RBodyHandle ball = w.bodies.Add(Ball(0.25, RVec3(0, 2.25, 0)));  // restitution 0 both
  w.integrator.SetContactCallback(
      [](const RRigidBody&, const RRigidBody&, const RContact&, RContactSettings& s, void*) { s.restitution = 1; },
      nullptr);
  RScalar up = 0;
  for (int k = 0; k < 60 && up <= 0; ++k) {
    w.Step(1);
    up = w.bodies[ball].Velocity_W().y();
  }
  // Dropped from 2 m: it meets the floor at sqrt(2 g h), and leaves at that speed (less the
  // gravity of the rest of the step it leaves in).
  const RScalar impact = std::sqrt(2 * kG * 2.0);
  EXPECT_NEAR(up, impact, kG * kDt);
  EXPECT_GT(up, 0.9 * impact);
}

TEST(ContactMaterials, ADisabledContactIsPassedThrough) {
  World w;
  w.bodies.Add(Box(RVec3(5, 0.05, 5), RVec3(0, -0.05, 0), RBodyKind::kStatic));
  const RBodyHandle ghost = w.bodies.Add(Box(RVec3(0.3, 0.3, 0.3), RVec3(0, 1, 0)));
  w.integrator.SetContactCallback(
      [](const RRigidBody&, const RRigidBody&, const RContact&, RContactSettings& s, void*) { s.enabled = false; },
      nullptr);
  w.Step(60);
  // Free fall from 1 m for 1 s: y = 1 - g/2 (kick-drift-kick is exact for constant g).
  EXPECT_NEAR(w.bodies[ghost].Position_W().y(), 1 - kG / 2, 1e-9);

}

TEST(ContactMaterials, ABallThrownUpThroughAOneWaySlabLandsOnIt) {
  World w;
  w.bodies.Add(Box(RVec3(5, 0.5, 5), RVec3(0, -0.5, 0), RBodyKind::kStatic));
  RBodyDef slab = Box(RVec3(2, 0.1, 2), RVec3(0, 2, 0), RBodyKind::kStatic);  // top at 2.1
  slab.oneWay = true;
  w.bodies.Add(slab);
  const RBodyHandle ball = w.bodies.Add(Ball(0.2, RVec3(0, 0.2, 0), RVec3(0, 8, 0)));  // apex 3.46 m
  w.Step(300);
  EXPECT_NEAR(w.bodies[ball].Position_W().y(), 2.1 + 0.2, 1e-3);  // resting on it (within the slop)
  EXPECT_NEAR(w.bodies[ball].Velocity_W().norm(), 0, 1e-6);
  // Thrown sideways into its edge at its height: passes through, in free flight (x = x0 + v t
  // exactly; the other ball it misses by a metre).
  const RBodyHandle side = w.bodies.Add(Ball(0.05, RVec3(-3, 2, 1.5), RVec3(20, 0, 0)));
  w.Step(18);
  EXPECT_NEAR(w.bodies[side].Position_W().x(), -3 + 20 * 0.3, 1e-9);
  EXPECT_NEAR(w.bodies[side].Position_W().y(), 2 - kG * 0.3 * 0.3 / 2, 1e-9);
}

std::vector<RVec3> ThroughSlab(int threads, bool saveAndLoad) {
  World w(threads);
  w.bodies.Add(Box(RVec3(5, 0.5, 5), RVec3(0, -0.5, 0), RBodyKind::kStatic));
  RBodyDef slab = Box(RVec3(2, 0.3, 2), RVec3(0, 2, 0), RBodyKind::kStatic);
  slab.oneWay = true;
  w.bodies.Add(slab);
  for (int i = 0; i < 4; ++i) w.bodies.Add(Ball(0.2, RVec3(-1.2 + 0.8 * i, 0.2, 0), RVec3(0.1 * i, 7 + 0.3 * i, 0)));
  w.Step(14);  // the balls are inside the slab now
  if (saveAndLoad) {
    const std::vector<std::uint8_t> s = SaveState(w.integrator, w.bodies);
    World other(threads);
    other.bodies = w.bodies;
    LoadState(other.integrator, other.bodies, s);
    w.Step(0);
    other.Step(200);
    std::vector<RVec3> out;
    for (const RRigidBody& b : other.bodies) out.push_back(b.Position_W());
    return out;
  }
  w.Step(200);
  std::vector<RVec3> out;
  for (const RRigidBody& b : w.bodies) out.push_back(b.Position_W());
  return out;
}

TEST(ContactMaterials, TheSameOnAnyThreadCountAndAfterASaveInsideTheSlab) {
  const std::vector<RVec3> one = ThroughSlab(1, false), two = ThroughSlab(2, false), loaded = ThroughSlab(1, true);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(std::memcmp(one[i].data(), two[i].data(), sizeof(RVec3)), 0) << i;
    EXPECT_EQ(std::memcmp(one[i].data(), loaded[i].data(), sizeof(RVec3)), 0) << i;
  }
  for (std::size_t i = 2; i < one.size(); ++i) EXPECT_GT(one[i].y(), 2.2) << "ball " << i << " on the slab";
}

TEST(ContactMaterials, SettingsOutOfRangeAreRefused) {
  World w;
  w.bodies.Add(Box(RVec3(5, 0.5, 5), RVec3(0, -0.5, 0), RBodyKind::kStatic));
  w.bodies.Add(Ball(0.25, RVec3(0, 0.25, 0)));
  w.integrator.SetContactCallback(
      [](const RRigidBody&, const RRigidBody&, const RContact&, RContactSettings& s, void*) { s.friction = -1; },
      nullptr);
  try {
    w.Step(1);
    ADD_FAILURE() << "accepted";
  } catch (const RError& e) {
    EXPECT_EQ(std::string(e.Field()), "contact_callback.friction");
  }
}

}  // namespace
