// The character in a moving world (RCharacter.h) against closed forms: a jump's apex v^2/2g
// and air time 2v/g, a turning, moving platform that carries it without drift, a frictionless
// crate pushed at its speed and a heavy one at maxPushForce, a kinematic wall that pushes it,
// one-way platforms, thin walls at any speed, filters; and its determinism, copies and
// refusals.
//
// Tolerances. In the air the character moves by the exact parabola over each Update (kick-
// drift-kick with constant gravity), so sampled heights lie on it to rounding: the highest
// sample is below the apex by at most g (dt/2)^2 / 2 (the apex falls at most half a step from
// a sample). Carrying applies the platform's pose change exactly, so the place held on it is
// exact to the rounding of poses (1e-15 m per step).
#include <gtest/gtest.h>

#include <REnginePhysics/RWorldState.h>

#include "character/CharacterWorld.h"

#include <cstring>

using namespace REngine;
using namespace REngine::test;

namespace {

TEST(CharacterWorld, JumpsToTheApexAndLandsAfterTwoVOverG) {
  CharacterWorld w;
  w.Tiles(6);
  RCharacter c(Capsule());
  w.Step({&c}, 30);
  ASSERT_TRUE(c.OnGround());
  const RScalar y0 = c.Position_W().y(), v = 5;
  c.Jump(v);
  RScalar top = y0;
  int airborne = 0;
  for (int k = 0; k < 120; ++k) {
    w.Step({&c});
    top = std::max(top, c.Position_W().y());
    if (c.OnGround()) break;
    ++airborne;
  }
  const RScalar apex = v * v / (2 * kG);
  EXPECT_LE(top - y0, apex + 1e-12);
  EXPECT_GE(top - y0, apex - kG * kDt * kDt / 8 - 1e-12);
  // Lands within the update that holds t = 2v/g.
  EXPECT_NEAR((airborne + 1) * kDt, 2 * v / kG, kDt);
  EXPECT_NEAR(c.Position_W().y(), y0, 1e-9);
}

TEST(CharacterWorld, AMovingTurningPlatformCarriesItWithoutDrift) {
  CharacterWorld w;
  const RBodyHandle deck = w.Box(RVec3(3, 0.1, 3), RVec3(0, -0.1, 0), RBodyKind::kKinematic);
  w.bodies[deck].SetVelocity_W(RVec3(1, 0, 0));
  w.bodies[deck].SetAngularVelocity_W(RVec3(0, 0.5, 0));
  RCharacter c(Capsule(0.3, 0.6, 0, 1.5));
  w.Step({&c}, 30);
  ASSERT_TRUE(c.OnGround());
  const auto local = [&] {
    const RRigidBody& d = w.bodies[deck];
    return RVec3(d.Orientation_WB().conjugate() * (c.Position_W() - d.Position_W()));
  };
  const RVec3 place = local();
  for (int k = 0; k < 300; ++k) {  // 5 s: 2.5 rad of turn, 5 m of travel
    w.Step({&c});
    ASSERT_TRUE(c.OnGround()) << k;
    ASSERT_LT((local() - place).norm(), 1e-6) << "update " << k;
  }
  // Its surface velocity is the deck's at its place: v + w x r.
  const RRigidBody& d = w.bodies[deck];
  const RVec3 expect = d.Velocity_W() + d.AngularVelocity_W().cross(c.Ground().contact.point_W - d.Position_W());
  EXPECT_LT((c.Ground().contact.surfaceVelocity_W - expect).norm(), 1e-12);
}

// A crate of `mass` (half height 0.501: its centre at the height of the sphere's, so the push
// has no lever) on a frictionless floor, a sphere character walking into it at 2 m/s.
struct CratePush {
  CharacterWorld w;
  RBodyHandle crate;
  RCharacter c;
  explicit CratePush(RScalar mass, RScalar maxPush = 1000) : c(Sphere(maxPush)) {
    RBodyDef floor;
    floor.shape = RShape::Box(RVec3(50, 0.1, 3));
    floor.kind = RBodyKind::kStatic;
    floor.position_W = RVec3(40, -0.1, 0);
    floor.friction = 0;
    w.bodies.Add(floor);
    RBodyDef box;
    box.shape = RShape::Box(RVec3(0.5, 0.501, 0.5));
    box.mass = mass;
    box.friction = 0;
    box.position_W = RVec3(2, 0.501, 0);
    crate = w.bodies.Add(box);
  }
  static RCharacterDef Sphere(RScalar maxPush) {
    RCharacterDef def;
    def.shape = RShape::Sphere(0.5);
    def.position_W = RVec3(0, 0.51, 0);
    def.maxPushForce = maxPush;
    return def;
  }
};

TEST(CharacterWorld, PushesAFrictionlessCrateAtItsOwnSpeed) {
  CratePush p(50);
  p.w.Step({&p.c}, 30);
  p.c.SetDesiredVelocity(RVec3(2, 0, 0));
  p.w.Step({&p.c}, 120);
  const RRigidBody& crate = p.w.bodies[p.crate];
  EXPECT_NEAR(crate.Velocity_W().x(), 2, 1e-9);
  EXPECT_NEAR(p.c.MovedVelocity_W().x(), 2, 1e-9);
  // In contact, the offset apart: the crate's face 0.5 + offset ahead of the sphere's centre.
  EXPECT_NEAR(crate.Position_W().x() - 0.5 - p.c.Position_W().x(), 0.5 + 1e-3, 1e-6);
}

TEST(CharacterWorld, PushesAHeavyCrateWithAtMostMaxPushForce) {
  // 5000 kg, 1000 N: the crate gains F dt / m each update, 0.2 m/s^2, and the character,
  // blocked, follows it.
  CratePush p(5000, 1000);
  p.w.Step({&p.c}, 30);
  p.c.SetDesiredVelocity(RVec3(2, 0, 0));
  p.w.Step({&p.c}, 60);  // reaches the crate within the first second
  const RScalar v0 = p.w.bodies[p.crate].Velocity_W().x();
  p.w.Step({&p.c}, 60);
  EXPECT_NEAR(p.w.bodies[p.crate].Velocity_W().x() - v0, 1000.0 / 5000 * 1.0, 1e-9);
}

TEST(CharacterWorld, AKinematicWallPushesIt) {
  CharacterWorld w;
  w.Tiles(10);
  const RBodyHandle wall = w.Box(RVec3(0.1, 1, 2), RVec3(-1, 1, 0), RBodyKind::kKinematic);
  w.bodies[wall].SetVelocity_W(RVec3(1.5, 0, 0));
  RCharacter c(Capsule());
  w.Step({&c}, 120);
  // The wall's face at -0.9 + 1.5 t: the character one radius and about the offset ahead.
  const RScalar face = w.bodies[wall].Position_W().x() + 0.1;
  EXPECT_NEAR(c.Position_W().x() - 0.3 - face, 1e-3, 1e-3);
  EXPECT_GT(c.Position_W().x(), 1.0);
  EXPECT_TRUE(c.OnGround());
}

TEST(CharacterWorld, PassesUpThroughAOneWayPlatformAndLandsOnIt) {
  CharacterWorld w;
  w.Tiles(6);
  RBodyDef ledge;
  ledge.shape = RShape::Box(RVec3(2, 0.1, 2));
  ledge.kind = RBodyKind::kStatic;
  ledge.position_W = RVec3(0, 2, 0);  // top at 2.1
  ledge.oneWay = true;
  const RBodyHandle h = w.bodies.Add(ledge);
  RCharacter c(Capsule());
  w.Step({&c}, 30);
  c.Jump(8);  // apex 3.26 m: the feet pass 2.1 m going up
  w.Step({&c}, 150);
  ASSERT_TRUE(c.OnGround());
  EXPECT_EQ(c.Ground().contact.body, h);
  EXPECT_NEAR(c.Position_W().y(), 2.1 + 0.9 + 1e-3, 1e-6);
  // Walking into its side passes through it too: a character under it walks on.
  RCharacter d(Capsule(0.3, 0.6, 0, -4));
  d.SetDesiredVelocity(RVec3(2, 0, 0));
  w.Step({&d}, 180);
  EXPECT_GT(d.Position_W().x(), 1.5);
}

TEST(CharacterWorld, NeverPassesAThinWallAtAnySpeed) {
  for (RScalar speed : {10.0, 1e3, 1e5}) {
    CharacterWorld w;
    w.Tiles(6);
    w.Box(RVec3(0.005, 1, 2), RVec3(2, 1, 0));  // 1 cm thick, face at 1.995
    RCharacter c(Capsule());
    w.Step({&c}, 30);
    c.SetDesiredVelocity(RVec3(speed, 0, 0));
    w.Step({&c}, 20);
    EXPECT_NEAR(c.Position_W().x(), 1.995 - 0.3 - 1e-3, 1e-6) << speed;
  }
  // Falling at 1 km/s onto a 1 cm floor.
  CharacterWorld w;
  w.Box(RVec3(2, 0.005, 2), RVec3(0, -0.005, 0));
  RCharacter c(Capsule(0.3, 0.6, 0, 0, 50));
  c.SetVelocity(RVec3(0, -1000, 0));
  w.Step({&c}, 5);
  EXPECT_TRUE(c.OnGround());
  EXPECT_NEAR(c.Position_W().y(), 0.9 + 1e-3, 1e-6);
}

TEST(CharacterWorld, HonoursFiltersAndIgnoreLists) {
  CharacterWorld w;
  w.Tiles(6);
  RBodyDef glass;
  glass.shape = RShape::Box(RVec3(0.1, 1, 2));
  glass.kind = RBodyKind::kStatic;
  glass.position_W = RVec3(1, 1, 0);
  glass.category = 4;
  w.bodies.Add(glass);
  RBodyDef door = glass;
  door.category = 1;
  door.position_W = RVec3(3, 1, 0);
  door.id = 7;
  w.bodies.Add(door);
  RCharacterDef def = Capsule();
  def.mask = ~4u;   // passes the glass
  def.ignore = {7};  // and the door
  RCharacter c(def);
  c.SetDesiredVelocity(RVec3(2, 0, 0));
  w.Step({&c}, 150);
  EXPECT_GT(c.Position_W().x(), 3.5);
  RCharacter blocked(Capsule());
  blocked.SetDesiredVelocity(RVec3(2, 0, 0));
  w.Step({&blocked}, 150);
  EXPECT_NEAR(blocked.Position_W().x(), 0.9 - 0.3 - 1e-3, 1e-6);
}

// A busy scene: a pile of crates on a turning deck, a character walking, jumping and pushing.
std::vector<RVec3> Busy(int threads, int steps, RCharacter* copyAt = nullptr, int copyStep = -1) {
  CharacterWorld w(threads);
  w.Tiles(12);
  const RBodyHandle deck = w.Box(RVec3(2, 0.1, 2), RVec3(6, 0.1, 0), RBodyKind::kKinematic);
  w.bodies[deck].SetAngularVelocity_W(RVec3(0, 0.7, 0));
  for (int i = 0; i < 12; ++i) w.Box(RVec3(0.25, 0.25, 0.25), RVec3(2 + 0.55 * (i % 3), 0.26 + 0.55 * (i / 3), 0.1 * (i % 2)), RBodyKind::kDynamic);
  RCharacter c(Capsule());
  std::vector<RVec3> out;
  for (int k = 0; k < steps; ++k) {
    c.SetDesiredVelocity(RVec3(1.5, 0, std::sin(0.05 * k)));
    if (k % 70 == 10) c.Jump(4);
    w.Step({&c});
    out.push_back(c.Position_W());
    if (k == copyStep && copyAt) *copyAt = c;
  }
  return out;
}

TEST(CharacterWorld, TheSameOnAnyThreadCount) {
  const std::vector<RVec3> one = Busy(1, 400), two = Busy(2, 400), four = Busy(4, 400);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t k = 0; k < one.size(); ++k) {
    ASSERT_EQ(std::memcmp(one[k].data(), two[k].data(), sizeof(RVec3)), 0) << k;
    ASSERT_EQ(std::memcmp(one[k].data(), four[k].data(), sizeof(RVec3)), 0) << k;
  }
  EXPECT_GT(one.back().x(), 3);
}

TEST(CharacterWorld, StateRestoredContinuesBitForBit) {
  CharacterWorld w;
  w.Tiles(12);
  const RBodyHandle deck = w.Box(RVec3(2, 0.1, 2), RVec3(4, 0.1, 0), RBodyKind::kKinematic);
  w.bodies[deck].SetAngularVelocity_W(RVec3(0, 0.7, 0));
  RCharacter c(Capsule());
  c.SetDesiredVelocity(RVec3(1, 0, 0.2));
  w.Step({&c}, 200);  // on the deck by now
  const std::vector<std::uint8_t> world = SaveState(w.integrator, w.bodies);
  const RCharacter::RState saved = c.State();
  w.Step({&c}, 100);
  const RVec3 first = c.Position_W();
  LoadState(w.integrator, w.bodies, world);
  c.Restore(saved);
  w.Step({&c}, 100);
  EXPECT_EQ(std::memcmp(first.data(), c.Position_W().data(), sizeof(RVec3)), 0);
}

TEST(CharacterWorld, RefusesBadDefinitionsNamingTheField) {
  const auto field = [](RCharacterDef def) {
    try {
      RCharacter c(def);
    } catch (const RCharacterError& e) {
      return std::string(e.Field());
    }
    return std::string("accepted");
  };
  RCharacterDef d = Capsule();
  EXPECT_EQ(field(d), "accepted");
  { RCharacterDef b = d; b.shape = RShape::Sphere(-1); EXPECT_EQ(field(b), "shape.radius"); }
  { RCharacterDef b = d; b.maxSlope = 2; EXPECT_EQ(field(b), "max_slope"); }
  { RCharacterDef b = d; b.stepHeight = -0.1; EXPECT_EQ(field(b), "step_height"); }
  { RCharacterDef b = d; b.mass = 0; EXPECT_EQ(field(b), "mass"); }
  { RCharacterDef b = d; b.maxPushForce = NAN; EXPECT_EQ(field(b), "max_push_force"); }
  { RCharacterDef b = d; b.contactOffset = 0; EXPECT_EQ(field(b), "contact_offset"); }
  { RCharacterDef b = d; b.up_W = RVec3(0, 2, 0); EXPECT_EQ(field(b), "up"); }
  { RCharacterDef b = d; b.position_W.x() = INFINITY; EXPECT_EQ(field(b), "position"); }
  { RCharacterDef b = d; b.ignore = {0xFFFFFFFFu}; EXPECT_EQ(field(b), "ignore"); }
  {
    RCharacterDef b = d;
    b.shape = RShape::Mesh({{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, 1, 2}});
    EXPECT_EQ(field(b), "shape");
  }
  // Zero gravity and no up: Update says so.
  CharacterWorld w;
  w.SetGravity(RVec3::Zero());
  RCharacter c(d);
  try {
    c.Update(w.bodies, w.queries, kDt, RVec3::Zero());
    ADD_FAILURE() << "accepted";
  } catch (const RCharacterError& e) {
    EXPECT_EQ(std::string(e.Field()), "up");
  }
  EXPECT_THROW(c.Update(w.bodies, w.queries, 0, RVec3(0, -1, 0)), RCharacterError);
  EXPECT_THROW(c.Jump(-1), RCharacterError);
}

}  // namespace
