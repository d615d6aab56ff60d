// The broad phase (RShortcuts::broadPhase) against its reference, the all-pairs loop: the
// same pairs, in the same order, every step, and so bit-identical worlds. Worlds are drawn
// to be hard on a tree of boxes: bodies from 1 cm to 100 m, 1e12 m from the origin, at rest
// and at 3 km/s, static, asleep, sensors, touching exactly, and a container whose bodies are
// added, removed and disabled between steps.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include "support/RandomWorlds.h"
#include "support/TestBodies.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

using namespace REngine;
using namespace REngine::test;

namespace {

bool SameState(const RRigidBody& a, const RRigidBody& b) {
  return a.Position_W() == b.Position_W() && a.Velocity_W() == b.Velocity_W() &&
         a.Orientation_WB().coeffs() == b.Orientation_WB().coeffs() &&
         a.AngularVelocity_B() == b.AngularVelocity_B() && a.IsSleeping() == b.IsSleeping();
}

// Steps two copies of a world, broad phase on and off, and requires the same contacts in
// the same order and the same states, bit for bit, every step.
void ExpectSameAsAllPairs(const std::vector<RBodyDef>& defs, const RVec3& gravity, int steps) {
  RWorldSettings on, off;
  on.gravity_W = off.gravity_W = gravity;
  off.shortcuts.broadPhase = false;
  RIntegrator a(on), b(off);
  std::vector<RRigidBody> wa, wb;
  for (const RBodyDef& d : defs) wa.emplace_back(d), wb.emplace_back(d);
  std::uint64_t contacts = 0;
  for (int s = 0; s < steps; ++s) {
    a.Update(wa, 1.0 / 60);
    b.Update(wb, 1.0 / 60);
    ASSERT_EQ(a.Contacts().size(), b.Contacts().size()) << "step " << s;
    for (std::size_t k = 0; k < a.Contacts().size(); ++k) {
      ASSERT_EQ(a.Contacts()[k].a, b.Contacts()[k].a) << "step " << s << " contact " << k;
      ASSERT_EQ(a.Contacts()[k].b, b.Contacts()[k].b) << "step " << s << " contact " << k;
    }
    EXPECT_EQ(a.PairStats().narrowPhase, b.PairStats().narrowPhase) << "step " << s;
    EXPECT_EQ(a.PairStats().rejectedBounds, b.PairStats().rejectedBounds) << "step " << s;
    for (std::size_t i = 0; i < wa.size(); ++i) ASSERT_TRUE(SameState(wa[i], wb[i])) << "step " << s << " body " << i;
    contacts += a.Contacts().size();
  }
  EXPECT_GT(contacts, 0u) << "a world with no contact tests nothing";
  EXPECT_LT(a.PairStats().sphereTests, b.PairStats().sphereTests)
      << "the broad phase tested as many pairs as the all-pairs loop: it was not used";
}

}  // namespace

TEST(BroadPhase, FindsTheAllPairsLoopsPairsNearTheOrigin) {
  for (std::uint64_t seed : {1, 2, 3, 4, 5}) {
    ExpectSameAsAllPairs(RandomWorld(seed, RVec3::Zero(), 300, 40), RVec3(0, -9.81, 0), 60);
  }
}

TEST(BroadPhase, FindsTheAllPairsLoopsPairsFarFromTheOrigin) {
  // 1e12 m out, coordinates carry 1e-4 m of rounding: the boxes' room for it is what keeps
  // touching pairs.
  ExpectSameAsAllPairs(RandomWorld(7, RVec3(1e12, -3e11, 5e11), 200, 30), RVec3::Zero(), 40);
}

// A sparse field (the broad phase's case): a body meets its few neighbours, not every other.
TEST(BroadPhase, TestsFewPairsInASparseField) {
  const std::vector<RBodyDef> defs = RandomWorld(13, RVec3::Zero(), 2000, 2000);
  RWorldSettings on;
  RIntegrator a(on);
  std::vector<RRigidBody> wa;
  for (const RBodyDef& d : defs) wa.emplace_back(d);
  a.Update(wa, 1.0 / 60);
  const RPairStats& st = a.PairStats();
  // About 1800 awake bodies, each with a few neighbours at most: a generous bound of 20
  // sphere tests per body still is 1% of the 2e6 pairs.
  EXPECT_LT(st.sphereTests, 20 * defs.size()) << "of " << st.pairs << " pairs";
  EXPECT_GT(st.pairs, 1000000u);
}

TEST(BroadPhase, FindsTheAllPairsLoopsPairsInZeroGravityCrowds) {
  ExpectSameAsAllPairs(RandomWorld(11, RVec3(-5, 2, 7), 400, 15), RVec3::Zero(), 40);
}

// Sleeping and churn: the passive tree is reused while nothing passive changes and rebuilt
// when something does; an RBodies with bodies added, removed and disabled between steps
// gives the same worlds either way.
TEST(BroadPhase, FindsTheSamePairsThroughChurnAndSleep) {
  RWorldSettings on, off;
  on.gravity_W = off.gravity_W = RVec3(0, -9.81, 0);
  off.shortcuts.broadPhase = false;
  RIntegrator ia(on), ib(off);
  RBodies a, b;
  // A tumbling crowd falling freely 300 m away, beside a floor of 16 small stacks that go to
  // sleep; bodies of both come and go (never a static one: removing that wakes every island,
  // and nothing would stay asleep long enough to test the passive tree).
  std::vector<RBodyDef> defs = RandomWorld(3, RVec3(300, 0, 0), 120, 20);
  defs.push_back(BoxDef(RVec3(20, 0.5, 20)).At(RVec3(0, -0.5, 0)).Static().Named("ground"));
  for (int x = 0; x < 4; ++x) {
    for (int z = 0; z < 4; ++z) {
      for (int k = 0; k < 3; ++k) {
        defs.push_back(BoxDef(RVec3::Constant(0.5))
                           .At(RVec3(3.0 * x - 6, 0.5 + k, 3.0 * z - 6))
                           .Mass(1)
                           .Named("t" + std::to_string(x) + std::to_string(z) + std::to_string(k)));
      }
    }
  }
  std::vector<RBodyHandle> ha, hb;
  std::vector<std::size_t> movable;
  for (std::size_t k = 0; k < defs.size(); ++k) {
    ha.push_back(a.Add(defs[k])), hb.push_back(b.Add(defs[k]));
    if (!defs[k].isStatic) movable.push_back(k);
  }
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<std::size_t> pickMovable(0, movable.size() - 1);
  auto pick = [&](std::mt19937_64& r) { return movable[pickMovable(r)]; };
  int sleepers = 0;
  for (int s = 0; s < 240; ++s) {
    if (s % 7 == 3) {
      const std::size_t k = pick(rng);
      if (a.Contains(ha[k])) {
        a.Remove(ha[k]), b.Remove(hb[k]);
      } else {
        ha[k] = a.Add(defs[k]), hb[k] = b.Add(defs[k]);
      }
    }
    if (s % 11 == 5) {
      const std::size_t k = pick(rng);
      if (a.Contains(ha[k])) {
        if (a.IsEnabled(ha[k])) {
          a.Disable(ha[k]), b.Disable(hb[k]);
        } else {
          a.Enable(ha[k]), b.Enable(hb[k]);
        }
      }
    }
    ia.Update(a, 1.0 / 60);
    ib.Update(b, 1.0 / 60);
    ASSERT_EQ(ia.Contacts().size(), ib.Contacts().size()) << "step " << s;
    for (std::size_t i = 0; i < a.Size(); ++i) {
      ASSERT_TRUE(SameState(a.At(i), b.At(i))) << "step " << s << " body " << i;
    }
    sleepers = std::max(sleepers, static_cast<int>(ia.PairStats().sleepingBodies));
  }
  EXPECT_GT(sleepers, 0) << "nothing ever slept: the passive tree was not exercised";
}
