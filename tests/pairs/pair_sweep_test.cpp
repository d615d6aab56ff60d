// The pair sweep and the caches it reads: which pairs reach the narrow phase (static pairs,
// ignore lists, the game's pair filter, bounding volumes), the shortcuts that claim to be
// exact (bounds rejection and static world forms: turning either off gives the same
// trajectory to the bit), and each body's world form, cached against the integrator's stamp.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;

// Boxes and spheres at random in a 12 m cube, moving at up to 8 m/s and spinning, with a
// static floor: some collide, most pairs are far apart.
std::vector<RRigidBody> Jumble(int n) {
  std::mt19937_64 rng(12345);
  auto uniform = [&rng](RScalar lo, RScalar hi) { return UniformIn(rng, lo, hi); };
  std::vector<RRigidBody> bodies{RRigidBody(GroundDef(RVec3(0, -7, 0)))};
  for (int i = 0; i < n; ++i) {
    // The position is drawn before the size: the jumble as it was first drawn.
    const RVec3 x(uniform(-6, 6), uniform(-6, 6), uniform(-6, 6));
    const RVec3 halfExtents(uniform(0.2, 0.6), uniform(0.2, 0.6), uniform(0.2, 0.6));
    RBodyDef d = BoxDef(halfExtents).At(x).Mass(1).Named("b" + std::to_string(i));
    if (i % 3 == 0) d.shape = RShape::Sphere(uniform(0.2, 0.6));
    d.velocity_W = RVec3(uniform(-8, 8), uniform(-8, 8), uniform(-8, 8));
    d.angularVelocity_W = RVec3(uniform(-3, 3), uniform(-3, 3), uniform(-3, 3));
    d.restitution = 0.5;
    bodies.emplace_back(d);
  }
  return bodies;
}

}  // namespace

// The pair loop: static pairs and ignore lists never reach the narrow phase, far pairs
// are rejected by bounding spheres, and each body's world form is computed once per step.
TEST(Collision, PairLoopFiltersAndCaches) {
  std::vector<RRigidBody> bodies;
  RBodyDef ground = BoxDef(RVec3(10, 0.5, 10)).At(RVec3(0, -0.5, 0)).Named("ground");
  ground.kind = RBodyKind::kStatic;
  ground.id = 0;
  RBodyDef wall = BoxDef(RVec3(0.5, 5, 10)).At(RVec3(10, 5, 0)).Named("wall");
  wall.kind = RBodyKind::kStatic;
  wall.id = 1;
  RBodyDef crate = BoxDef(RVec3(0.5, 0.5, 0.5)).At(RVec3(0, 0.45, 0)).Named("crate");
  crate.id = 2;
  // Inside its launcher's reach.
  RBodyDef missile = SphereDef(0.2).At(RVec3(0, 0.45, 0.6)).Named("missile");
  missile.id = 3;
  missile.ignore = {2};
  RBodyDef far = SphereDef(0.2).At(RVec3(100, 100, 100)).Named("far");
  far.id = 4;
  for (const RBodyDef& d : {ground, wall, crate, missile, far}) bodies.emplace_back(d);
  RIntegrator integrator;
  integrator.Update(bodies, 1.0 / 60);
  const RPairStats& s = integrator.PairStats();
  EXPECT_EQ(s.pairs, 10u);
  EXPECT_EQ(s.rejectedFilter, 2u);  // ground-wall (static), crate-missile (ignored)
  EXPECT_GE(s.rejectedBounds, 4u);  // the far ball against all four others
  // crate on ground penetrates by 0.05; the missile touches the ground? (0.45 - 0.2 > 0)
  bool crateGround = false;
  for (const RContact& c : integrator.Contacts()) {
    EXPECT_LT(c.a, c.b);
    EXPECT_FALSE(c.a == 2 && c.b == 3) << "ignored pair reported";
    if (c.a == 0 && c.b == 2) {
      crateGround = true;
      EXPECT_NEAR(c.manifold.query.separation, -0.05, 1e-12);
      EXPECT_LT((c.manifold.query.normal - RVec3(0, 1, 0)).norm(), 1e-12);
    }
  }
  EXPECT_TRUE(crateGround);
  for (const RRigidBody& b : bodies) EXPECT_LE(b.WorldFormComputations(), 1u) << b.Name();
  // The game's filter vetoes a pair.
  integrator.SetPairFilter([](const RRigidBody& a, const RRigidBody& b, void*) {
    return !(a.Id() == 0 && b.Id() == 2);
  }, nullptr);
  integrator.Update(bodies, 1.0 / 60);
  for (const RContact& c : integrator.Contacts()) EXPECT_FALSE(c.a == 0 && c.b == 2);
  for (const RRigidBody& b : bodies) EXPECT_LE(b.WorldFormComputations(), 2u) << b.Name();
}

// Bounds rejection and static world forms are exact: turning either off changes the work,
// not one bit of the trajectory.
TEST(Shortcuts, BoundsAndStaticFormsAreExact) {
  RWorldSettings on = EarthGravity();
  on.shortcuts.sleeping = false;
  for (int variant = 0; variant < 2; ++variant) {
    RWorldSettings off = on;
    (variant == 0 ? off.shortcuts.boundsRejection : off.shortcuts.staticForms) = false;
    std::vector<RRigidBody> a = Jumble(60), b = Jumble(60);
    RIntegrator ia(on), ib(off);
    std::uint64_t narrowOn = 0, narrowOff = 0, contacts = 0;
    for (int i = 0; i < 120; ++i) {
      ia.Update(a, kDt);
      ib.Update(b, kDt);
      narrowOn += ia.PairStats().narrowPhase, narrowOff += ib.PairStats().narrowPhase;
      contacts += ia.PairStats().contacts;
    }
    EXPECT_GT(contacts, 0u) << "the scene has collisions";
    if (variant == 0) {
      EXPECT_GT(narrowOff, 10 * narrowOn) << "off: every pair is tested";
    }
    for (std::size_t k = 0; k < a.size(); ++k) {
      EXPECT_EQ(a[k].Position_W(), b[k].Position_W()) << variant << " " << k;
      EXPECT_EQ(a[k].Orientation_WB().coeffs(), b[k].Orientation_WB().coeffs())
          << variant << " " << k;
      EXPECT_EQ(a[k].Velocity_W(), b[k].Velocity_W()) << variant << " " << k;
    }
    if (variant == 1) {
      EXPECT_EQ(a[0].WorldFormComputations(), 1u) << "the floor's form, once";
      EXPECT_GT(b[0].WorldFormComputations(), 100u) << "off: once per step";
    }
  }
}

// A static body's form is recomputed after the game moves it.
TEST(Shortcuts, MovedStaticBodyGetsANewForm) {
  RRigidBody ground(GroundDef());
  const RWorldForm& f1 = ground.WorldForm(NextCacheStamp());
  EXPECT_NEAR(f1.aabbMax_W.y(), 0, 1e-15);
  ground.WorldForm(NextCacheStamp());
  EXPECT_EQ(ground.WorldFormComputations(), 1u);
  ground.SetShapePose(RVec3(0, 2, 0), RQuat::Identity());
  const RWorldForm& f2 = ground.WorldForm(NextCacheStamp());
  EXPECT_EQ(ground.WorldFormComputations(), 2u);
  EXPECT_NEAR(f2.aabbMax_W.y(), 2.5, 1e-15);
}

// The world form is computed at most once per body per step, however often it is asked for.
TEST(Polyhedron, WorldFormIsCachedAgainstTheStamp) {
  std::vector<RRigidBody> bodies{RRigidBody(
      BoxDef(RVec3(0.5, 1, 1.5)).Spinning(RVec3(0.3, 0.2, 0.1)).Moving(RVec3(1, 0, 0)))};
  RIntegrator integrator;
  integrator.Update(bodies, 0.01);
  const RRigidBody& b = bodies[0];
  EXPECT_EQ(b.WorldFormComputations(), 0u);  // nothing asked yet: nothing computed
  for (int i = 0; i < 5; ++i) b.WorldForm(integrator.CacheStamp());
  EXPECT_EQ(b.WorldFormComputations(), 1u);
  // Its contents: the bounds of the body's vertices, rotated and translated (the box is
  // their extremes in each axis, and holds every vertex; the sphere about the centre of
  // mass holds them too).
  const RWorldForm& wf = b.WorldForm(integrator.CacheStamp());
  const RMat3 R = b.Orientation_WB().toRotationMatrix();
  RVec3 lo = RVec3::Constant(1e300), hi = -lo;
  for (const RVec3& v_B : b.Polyhedron_B()->Vertices()) {
    const RVec3 v = R * v_B + b.Position_W();
    lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    EXPECT_LE((v - wf.sphereCenter_W).norm(), wf.sphereRadius * (1 + 1e-15));
  }
  EXPECT_LT((wf.aabbMin_W - lo).norm(), 1e-15);
  EXPECT_LT((wf.aabbMax_W - hi).norm(), 1e-15);
  integrator.Update(bodies, 0.01);
  b.WorldForm(integrator.CacheStamp());
  b.WorldForm(integrator.CacheStamp());
  EXPECT_EQ(b.WorldFormComputations(), 2u);
  bodies[0].SetShapePose(RVec3(5, 0, 0), RQuat::Identity());  // moved by game code
  b.WorldForm(integrator.CacheStamp());
  EXPECT_EQ(b.WorldFormComputations(), 3u);
  EXPECT_NEAR(b.WorldForm(integrator.CacheStamp()).aabbMin_W.x(), 4.5, 1e-15);
}

// Between steps the stamp describes the bodies' present poses: a world form asked for after
// Update shows where the body is now, even if collision detection cached it during the step.
TEST(Polyhedron, WorldFormAfterUpdateIsThePostStepPose) {
  std::vector<RRigidBody> bodies;
  for (RScalar x : {0.0, 1.1}) {  // 0.1 m apart, moving together: near, never touching
    bodies.emplace_back(BoxDef(RVec3(0.5, 0.5, 0.5)).At(RVec3(x, 0, 0)).Moving(RVec3(10, 0, 0)));
  }
  RIntegrator integrator;
  integrator.Update(bodies, 0.1);
  EXPECT_GE(bodies[0].WorldFormComputations(), 1u) << "detection asked for it";
  const RWorldForm& wf = bodies[0].WorldForm(integrator.CacheStamp());
  EXPECT_NEAR(wf.aabbMin_W.x(), bodies[0].Position_W().x() - 0.5, 1e-14);
  EXPECT_NEAR(bodies[0].Position_W().x(), 1.0, 1e-14);
}

// Every step draws a new stamp, and no two integrators share one.
TEST(FreeMotion, CacheStampAdvancesEveryStep) {
  std::vector<RRigidBody> bodies;
  RIntegrator a, b;
  a.Update(bodies, 0.1);
  const auto s1 = a.CacheStamp();
  b.Update(bodies, 0.1);
  a.Update(bodies, 0.1);
  EXPECT_GT(a.CacheStamp(), s1);
  EXPECT_NE(a.CacheStamp(), b.CacheStamp());
}

// Manifold reuse (RShortcuts::contactReuse): a settled stack keeps its manifolds, moved with
// the bodies, and their blocks' inverses, and ends where it ends without the shortcut to
// within what the touching band allows; a sliding box, whose pose changes by far more than the band, never reuses one and
// moves bit for bit as without the shortcut.
TEST(Shortcuts, ContactReuseKeepsASettledStackWithinTheTouchingBand) {
  RWorldSettings on = EarthGravity();
  on.shortcuts.sleeping = false;
  RWorldSettings off = on;
  off.shortcuts.contactReuse = false;
  auto stack = [] {
    std::vector<RRigidBody> bodies{RRigidBody(GroundDef())};
    for (int k = 0; k < 10; ++k) {
      bodies.emplace_back(BoxDef(RVec3::Constant(0.5)).At(RVec3(0, 0.5 + k, 0)).Mass(1).Named("b" + std::to_string(k)));
    }
    return bodies;
  };
  std::vector<RRigidBody> a = stack(), b = stack();
  RIntegrator ia(on), ib(off);
  std::uint64_t reused = 0, reusedInverses = 0, computedOn = 0, computedOff = 0;
  for (int i = 0; i < 300; ++i) {
    ia.Update(a, kDt);
    ib.Update(b, kDt);
    reused += ia.PairStats().reusedManifolds;
    reusedInverses += ia.PairStats().reusedInverses;
    computedOn += ia.PairStats().computedInverses;
    computedOff += ib.PairStats().computedInverses;
    EXPECT_EQ(ib.PairStats().reusedManifolds, 0u);
    EXPECT_EQ(ib.PairStats().reusedInverses, 0u);
  }
  // At rest every contact keeps its manifold. The solver keeps a block's inverse with it
  // while the stack settles, and works out almost none (at rest the blocks are solved
  // already and need none, with the shortcut or without): 11 eigen-solves against 1731
  // without it, 1250 inverses kept, when written; a K comparison that never matched would
  // work out as many as without.
  EXPECT_EQ(ia.PairStats().reusedManifolds, 10u);
  EXPECT_GT(reusedInverses, 100u);
  EXPECT_LT(10 * computedOn, computedOff);
  EXPECT_GT(reused, 2000u);
  // A reused point is off by at most the band, 1e-9 of the pair's size (1.7e-9 m for two
  // unit cubes); ten contacts in series: 2e-8 m. The bound is five times that.
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_LT((a[k].Position_W() - b[k].Position_W()).norm(), 1e-7) << k;
    EXPECT_LT(a[k].Orientation_WB().angularDistance(b[k].Orientation_WB()), 1e-7) << k;
    EXPECT_NEAR(a[k].Position_W().y(), b[k].Position_W().y(), 1e-7) << k;
  }
  EXPECT_NEAR(a.back().Position_W().y(), 9.5, 1e-3) << "the stack stands";
}

TEST(Shortcuts, ContactReuseLeavesASlidingBoxExact) {
  RWorldSettings on = EarthGravity();
  RWorldSettings off = on;
  off.shortcuts.contactReuse = false;
  auto scene = [] {
    std::vector<RRigidBody> bodies{RRigidBody(GroundDef())};
    RBodyDef d = BoxDef(RVec3::Constant(0.5)).At(RVec3(0, 0.5, 0)).Mass(1);
    d.velocity_W = RVec3(2, 0, 0);
    bodies.emplace_back(d);
    return bodies;
  };
  std::vector<RRigidBody> a = scene(), b = scene();
  RIntegrator ia(on), ib(off);
  for (int i = 0; i < 20; ++i) {  // it slides for 2 / (0.5 g) = 0.41 s = 24 steps
    ia.Update(a, kDt);
    ib.Update(b, kDt);
    EXPECT_EQ(ia.PairStats().reusedManifolds, 0u) << i;
    EXPECT_EQ(a[1].Position_W(), b[1].Position_W()) << i;
    EXPECT_EQ(a[1].Velocity_W(), b[1].Velocity_W()) << i;
  }
  EXPECT_GT(a[1].Velocity_W().x(), 0.1) << "still sliding";
}

// A body the game replaces in its place (same index, same pose, another shape) is a new
// body to the contact memory: the taller crate is pushed out of the ground as it would be
// without reuse, not held by the old crate's manifold.
TEST(Shortcuts, ContactReuseForgetsABodyReplacedInPlace) {
  for (bool reuse : {true, false}) {
    RWorldSettings s = EarthGravity();
    s.shortcuts.sleeping = false;
    s.shortcuts.contactReuse = reuse;
    RIntegrator integrator(s);
    std::vector<RRigidBody> bodies{RRigidBody(GroundDef()),
                                   RRigidBody(BoxDef(RVec3::Constant(0.5)).At(RVec3(0, 0.5, 0)).Mass(1))};
    for (int k = 0; k < 120; ++k) integrator.Update(bodies, kDt);
    if (reuse) {
      EXPECT_EQ(integrator.PairStats().reusedManifolds, 1u) << "the crate rests";
    }
    const RVec3 x = bodies[1].Position_W();
    bodies[1] = RRigidBody(BoxDef(RVec3(0.5, 0.6, 0.5)).At(x).Mass(1));  // 0.1 m into the ground
    for (int k = 0; k < 120; ++k) integrator.Update(bodies, kDt);
    EXPECT_NEAR(bodies[1].Position_W().y(), 0.6, 1e-3) << "reuse " << reuse;
  }
}
