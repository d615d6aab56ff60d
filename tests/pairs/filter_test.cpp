// Collision filter bits and user data on bodies (RBodyDef::category, mask, userData): Box2D's
// rule in the pair loop (both directions must agree), checked against the closed form of a
// head-on elastic collision: an allowed pair swaps velocities, a masked pair passes through.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

// Equal spheres, e = 1, closing at 2 m/s from 3 m apart (HeadOnSpheres): after 2 s an allowed
// pair has swapped velocities; a pair that does not collide flies on untouched.
struct HeadOn {
  RVec3 va, vb, xa, xb;
};
HeadOn RunHeadOn(std::uint32_t catA, std::uint32_t maskA, std::uint32_t catB,
                 std::uint32_t maskB) {
  std::vector<BodyDef> defs = HeadOnSpheres(1, 1, 1, -1, 1);
  defs[0].category = catA, defs[0].mask = maskA;
  defs[1].category = catB, defs[1].mask = maskB;
  std::vector<RRigidBody> bodies = MakeBodies(defs);
  RIntegrator integrator;
  for (int k = 0; k < 200; ++k) integrator.Update(bodies, 0.01);
  return {bodies[0].Velocity_W(), bodies[1].Velocity_W(), bodies[0].Position_W(),
          bodies[1].Position_W()};
}

}  // namespace

TEST(Filter, AllowedPairSwapsVelocitiesMaskedPairPassesThrough) {
  // Defaults: they collide and, being equal and elastic, swap velocities exactly.
  const HeadOn hit = RunHeadOn(1, 0xFFFFFFFFu, 1, 0xFFFFFFFFu);
  EXPECT_NEAR(hit.va.x(), -1, 1e-12);
  EXPECT_NEAR(hit.vb.x(), 1, 1e-12);
  // Either direction refusing is enough: a's mask leaves out b's category, or b's leaves out
  // a's. Then both fly on at their velocities: x0 + v t after 2 s, to rounding.
  for (const HeadOn& pass : {RunHeadOn(1, ~2u, 2, 0xFFFFFFFFu), RunHeadOn(1, 0xFFFFFFFFu, 2, ~1u),
                             RunHeadOn(0, 0xFFFFFFFFu, 1, 0xFFFFFFFFu)}) {
    EXPECT_EQ(pass.va.x(), 1);
    EXPECT_EQ(pass.vb.x(), -1);
    EXPECT_NEAR(pass.xa.x(), -2 + 2, 1e-12);
    EXPECT_NEAR(pass.xb.x(), 2 - 2, 1e-12);
  }
  // Bits that agree both ways, other than the defaults: they collide.
  const HeadOn agree = RunHeadOn(4, 8, 8, 4);
  EXPECT_NEAR(agree.va.x(), -1, 1e-12);
  EXPECT_NEAR(agree.vb.x(), 1, 1e-12);
}

TEST(Filter, ShouldCheckCollisionIsBox2DsRuleBesideTheIgnoreLists) {
  auto body = [](std::uint32_t category, std::uint32_t mask, std::uint32_t id) {
    BodyDef d = SphereDef(1);
    d.category = category, d.mask = mask, d.id = id;
    return RRigidBody(d);
  };
  struct Case {
    std::uint32_t catA, maskA, catB, maskB;
    bool check;
  };
  const Case cases[] = {{1, ~0u, 1, ~0u, true},  {1, 2, 2, 1, true},   {1, 2, 2, 2, false},
                        {1, 1, 2, 1, false},     {3, 4, 4, 1, true},   {0, ~0u, ~0u, ~0u, false},
                        {~0u, 0, 1, ~0u, false}, {0x80000000u, 0x80000000u, 0x80000000u, 0x80000000u, true}};
  for (const Case& c : cases) {
    const RRigidBody a = body(c.catA, c.maskA, 1), b = body(c.catB, c.maskB, 2);
    EXPECT_EQ(a.ShouldCheckCollision(b), c.check) << c.catA << " " << c.maskA << " " << c.catB
                                                  << " " << c.maskB;
    EXPECT_EQ(b.ShouldCheckCollision(a), c.check) << "not symmetric";
  }
  // Agreeing bits do not override an ignore list.
  RRigidBody a = body(1, ~0u, 1);
  const RRigidBody b = body(1, ~0u, 2);
  a.IgnoreCollisionsWith(2);
  EXPECT_FALSE(a.ShouldCheckCollision(b));
  EXPECT_FALSE(b.ShouldCheckCollision(a));
}

// A body has no id unless given one, and an ignore list never matches a body without one:
// `ignore = {launcherId}` cannot silently take in every body. IgnoreCollisions by handle
// gives ids unused in the container and ignores exactly the pair named.
TEST(Filter, IgnoreListsNameOnlyBodiesGivenIds) {
  RBodies bodies;
  const RBodyHandle ship = bodies.Add(SphereDef(0.5).Mass(1).At(RVec3(0, 0, 0)));
  const RBodyHandle rock = bodies.Add(SphereDef(0.5).Mass(1).At(RVec3(5, 0, 0)));
  const RBodyHandle crate = bodies.Add(SphereDef(0.5).Mass(1).At(RVec3(10, 0, 0)));
  EXPECT_FALSE(bodies[ship].Id().has_value());
  RBodyDef missileDef = SphereDef(0.1).Mass(1).At(RVec3(0, 5, 0));
  missileDef.ignore = {0};  // names no body here: none has an id
  const RBodyHandle missile = bodies.Add(missileDef);
  for (RBodyHandle other : {ship, rock, crate}) {
    EXPECT_TRUE(bodies[missile].ShouldCheckCollision(bodies[other]));
  }
  bodies[crate].IgnoreCollisionsWith(7);
  bodies.IgnoreCollisions(missile, ship);
  ASSERT_TRUE(bodies[ship].Id().has_value() && bodies[missile].Id().has_value());
  EXPECT_NE(*bodies[ship].Id(), *bodies[missile].Id());
  EXPECT_FALSE(bodies[missile].ShouldCheckCollision(bodies[ship]));
  EXPECT_FALSE(bodies[ship].ShouldCheckCollision(bodies[missile]));
  EXPECT_TRUE(bodies[missile].ShouldCheckCollision(bodies[rock]));
  EXPECT_TRUE(bodies[missile].ShouldCheckCollision(bodies[crate]));
  EXPECT_FALSE(bodies[rock].Id().has_value());
  // Refused: the reserved id, a body ignoring itself.
  RBodyDef reserved = SphereDef(0.5).Mass(1);
  reserved.id = 0xFFFFFFFFu;
  EXPECT_THROW(bodies.Add(reserved), RBodyError);
  EXPECT_THROW(bodies[rock].IgnoreCollisionsWith(0xFFFFFFFFu), RBodyError);
  EXPECT_THROW(bodies.IgnoreCollisions(rock, rock), RBodyError);
}

// A pair allowed by SetCollisionFilter before they meet collides: the body takes its new
// bits at once, and the change is counted for the queries' caches.
TEST(Filter, SetCollisionFilterAppliesFromTheNextStep) {
  std::vector<BodyDef> defs = HeadOnSpheres(1, 1, 1, -1, 1);
  defs[0].mask = ~2u, defs[1].category = 2;
  RBodies bodies;
  const RBodyHandle a = bodies.Add(defs[0]);
  const RBodyHandle b = bodies.Add(defs[1]);
  RIntegrator integrator;
  for (int k = 0; k < 50; ++k) integrator.Update(bodies, 0.01);  // 0.5 s: still 1 m apart
  const std::uint64_t edits = BodyEditCount();
  bodies[a].SetCollisionFilter(1, ~0u);
  EXPECT_EQ(bodies[a].Category(), 1u);
  EXPECT_EQ(bodies[a].Mask(), ~0u);
  EXPECT_GT(BodyEditCount(), edits);
  for (int k = 0; k < 150; ++k) integrator.Update(bodies, 0.01);
  EXPECT_NEAR(bodies[a].Velocity_W().x(), -1, 1e-12);
  EXPECT_NEAR(bodies[b].Velocity_W().x(), 1, 1e-12);
}

TEST(Filter, UserDataIsKeptAndNeverRead) {
  BodyDef d = SphereDef(0.5);
  d.velocity_W = RVec3(1, 2, 3);
  RBodies plain, tagged;
  const RBodyHandle hp = plain.Add(d);
  int marker = 0;
  d.userData = reinterpret_cast<std::uintptr_t>(&marker);
  const RBodyHandle ht = tagged.Add(d);
  EXPECT_EQ(tagged[ht].UserData(), reinterpret_cast<std::uintptr_t>(&marker));
  RIntegrator i1, i2;
  for (int k = 0; k < 10; ++k) i1.Update(plain, 0.1), i2.Update(tagged, 0.1);
  EXPECT_EQ(tagged[ht].UserData(), reinterpret_cast<std::uintptr_t>(&marker));
  EXPECT_EQ(plain[hp].Position_W(), tagged[ht].Position_W());
  tagged[ht].SetUserData(42);
  EXPECT_EQ(tagged[ht].UserData(), 42u);
}
