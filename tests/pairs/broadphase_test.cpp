// The broad phase (RShortcuts::broadPhase) against its reference, the all-pairs loop: the
// same pairs, in the same order, every step, and so bit-identical worlds. Worlds are drawn
// to be hard on a tree of boxes: bodies from 1 cm to 100 m, 1e12 m from the origin, at rest
// and at 3 km/s, static, asleep, sensors, touching exactly, and a container whose bodies are
// added, removed and disabled between steps.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include "support/RandomWorlds.h"
#include "support/TestBodies.h"

#include "pairs/RBoundsTree.h"  // private to the engine: tested directly below

#include <algorithm>

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
  on.shortcuts.broadPhaseAlways = true;  // small worlds: the sweep alone would keep the loop
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
    // The trees skip pairs whose boxes are apart without testing them: those are counted
    // as rejected by the bounds; the filters see exactly the loop's pairs.
    EXPECT_EQ(a.PairStats().rejectedBounds + a.PairStats().rejectedBoxes,
              b.PairStats().rejectedBounds + b.PairStats().rejectedBoxes) << "step " << s;
    EXPECT_EQ(a.PairStats().rejectedFilter, b.PairStats().rejectedFilter) << "step " << s;
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

// A sparse field (the broad phase's case): a body meets its few neighbours, not every other;
// the sweep takes the trees by itself. A small pile keeps the loop.
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
  EXPECT_TRUE(st.broadPhase) << "a sparse field of 2000 bodies should take the trees";
}

TEST(BroadPhase, ASmallPileKeepsTheLoop) {
  RWorldSettings settings;
  settings.gravity_W = RVec3(0, -9.81, 0);
  RIntegrator integrator(settings);
  std::vector<RRigidBody> pile;
  pile.emplace_back(BoxDef(RVec3(20, 0.5, 20)).At(RVec3(0, -0.5, 0)).Static().Named("ground"));
  for (int k = 0; k < 40; ++k) {
    pile.emplace_back(BoxDef(RVec3::Constant(0.5)).At(RVec3(1.01 * (k % 5), 0.5 + k / 25, 1.01 * (k / 5 % 5))).Mass(1).Named("b" + std::to_string(k)));
  }
  for (int s = 0; s < 3; ++s) integrator.Update(pile, 1.0 / 60);
  EXPECT_FALSE(integrator.PairStats().broadPhase);
  EXPECT_GE(integrator.Contacts().size(), 40u);  // each box on the one below, or the ground
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
  on.shortcuts.broadPhaseAlways = true;
  off.shortcuts.broadPhase = false;
  RIntegrator ia(on), ib(off);
  RBodies a, b;
  // A tumbling crowd falling freely 300 m away, beside a floor of 16 small stacks that go to
  // sleep; bodies of both come and go (never the ground: removing it wakes every island on it,
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
    if (defs[k].kind != RBodyKind::kStatic) movable.push_back(k);
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

// The tree itself (private to the engine) against brute force: every overlapping pair of
// boxes found exactly once, however the search is split; queries find every overlapping
// box above the index asked for. Boxes are drawn with many exact touches (coordinates on a
// coarse grid), duplicates, and a far-away cluster.
TEST(BoundsTree, FindsEveryOverlapOnceAgainstBruteForce) {
  std::mt19937_64 rng(17);
  auto draw = [&](std::size_t count, RScalar offset) {
    std::vector<RBoundsTree::RBox> boxes(count);
    for (RBoundsTree::RBox& b : boxes) {
      for (int a = 0; a < 3; ++a) {
        b.lo[a] = offset + RScalar(rng() % 40);
        b.hi[a] = b.lo[a] + RScalar(rng() % 4);
      }
    }
    boxes[count / 2] = boxes[count / 3];  // a duplicate
    return boxes;
  };
  auto overlap = [](const RBoundsTree::RBox& x, const RBoundsTree::RBox& y) {
    for (int a = 0; a < 3; ++a) {
      if (x.lo[a] > y.hi[a] || y.lo[a] > x.hi[a]) return false;
    }
    return true;
  };
  for (std::size_t n : {1u, 2u, 5u, 300u, 1000u}) {
    const std::vector<RBoundsTree::RBox> a = draw(n, 0), b = draw(n / 2 + 1, 10);
    std::vector<std::uint32_t> idsA(a.size()), idsB(b.size());
    for (std::size_t k = 0; k < idsA.size(); ++k) idsA[k] = static_cast<std::uint32_t>(k);
    for (std::size_t k = 0; k < idsB.size(); ++k) idsB[k] = static_cast<std::uint32_t>(100000 + k);
    RBoundsTree ta, tb;
    ta.Build(a.data(), idsA.data(), a.size());
    tb.Build(b.data(), idsB.data(), b.size());
    std::vector<std::uint64_t> self, cross;
    for (std::size_t i = 0; i < a.size(); ++i) {
      for (std::size_t j = i + 1; j < a.size(); ++j) {
        if (overlap(a[i], a[j])) self.push_back((std::uint64_t(i) << 32) | j);
      }
      for (std::size_t j = 0; j < b.size(); ++j) {
        if (overlap(a[i], b[j])) cross.push_back((std::uint64_t(i) << 32) | idsB[j]);
      }
    }
    for (std::size_t want : {1u, 7u, 64u}) {
      std::vector<RBoundsTree::RNodePair> seeds, scratch, stack;
      for (int mode = 0; mode < 2; ++mode) {
        const RBoundsTree& other = mode == 0 ? ta : tb;
        ta.PairSeeds(other, want, seeds, scratch);
        std::vector<std::uint64_t> found;
        for (const RBoundsTree::RNodePair& s : seeds) {
          ta.Pairs(other, s, stack, [&](std::uint32_t x, std::uint32_t y) {
            const std::uint32_t lo = mode == 0 ? std::min(x, y) : x, hi = mode == 0 ? std::max(x, y) : y;
            found.push_back((std::uint64_t(lo) << 32) | hi);
          });
        }
        std::sort(found.begin(), found.end());
        EXPECT_EQ(found, mode == 0 ? self : cross) << n << " boxes, " << want << " starts, mode " << mode;
      }
    }
    // Queries.
    for (std::size_t i = 0; i < a.size(); i += 7) {
      std::vector<std::uint32_t> hits, expected, queryStack;
      ta.Query(a[i], hits, queryStack);
      std::sort(hits.begin(), hits.end());
      for (std::size_t j = 0; j < a.size(); ++j) {
        if (overlap(a[i], a[j])) expected.push_back(static_cast<std::uint32_t>(j));
      }
      EXPECT_EQ(hits, expected) << n << " boxes, query " << i;
    }
    // A refit to moved boxes finds what a fresh build finds.
    std::vector<RBoundsTree::RBox> moved = draw(n, 3);
    ta.Refit(moved.data());
    std::vector<std::uint64_t> refitted, expected;
    std::vector<RBoundsTree::RNodePair> seeds, scratch, stack;
    ta.PairSeeds(ta, 5, seeds, scratch);
    for (const RBoundsTree::RNodePair& s : seeds) {
      ta.Pairs(ta, s, stack, [&](std::uint32_t x, std::uint32_t y) {
        refitted.push_back((std::uint64_t(std::min(x, y)) << 32) | std::max(x, y));
      });
    }
    std::sort(refitted.begin(), refitted.end());
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = i + 1; j < n; ++j) {
        if (overlap(moved[i], moved[j])) expected.push_back((std::uint64_t(i) << 32) | j);
      }
    }
    EXPECT_EQ(refitted, expected) << n << " boxes, refitted";
  }
}

// A body whose reach overflows (1.5e308 m/s over a step of 1 s) meets every other in the
// all-pairs loop (its sphere test gives infinity); the broad phase's boxes are infinite
// then, not empty, and find the same pairs.
TEST(BroadPhase, ARunawayBodyMeetsEveryBodyAsInTheLoop) {
  std::vector<RBodyDef> defs;
  for (int i = 0; i < 10; ++i) defs.push_back(SphereDef(0.5).At(RVec3(3.0 * i, 0, 0)).Mass(1).Named("s" + std::to_string(i)));
  BodyDef fast = SphereDef(0.5).At(RVec3(0, 5, 0)).Mass(1).Named("fast");
  fast.velocity_W = RVec3(0, 0, 1.5e308);
  defs.push_back(fast);
  std::uint64_t narrow[2] = {0, 0};
  for (int bp = 0; bp < 2; ++bp) {
    RWorldSettings s;
    s.shortcuts.broadPhase = s.shortcuts.broadPhaseAlways = bp == 1;
    RIntegrator integrator(s);
    std::vector<RRigidBody> bodies;
    for (const RBodyDef& d : defs) bodies.emplace_back(d);
    integrator.Update(bodies, 1.0);
    narrow[bp] = integrator.PairStats().narrowPhase;
  }
  EXPECT_EQ(narrow[0], 10u) << "the loop pairs the runaway with every sphere";
  EXPECT_EQ(narrow[1], narrow[0]);
}

// A refit of a few moved items (RefitItems, the broad phase's each step) against brute force
// and against refitting every node (Refit): the queries find exactly the boxes that overlap
// at their new places, and the two refits leave the same tree to the bit (the same inner
// areas, the same answers in the same order).
TEST(BoundsTree, RefitOfMovedItemsIsTheFullRefit) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<RScalar> coordinate(-50, 50), size(0.1, 3);
  for (std::size_t n : {1u, 3u, 17u, 2000u}) {
    std::vector<RBoundsTree::RBox> boxes(n);
    auto place = [&](RBoundsTree::RBox& b) {
      for (int a = 0; a < 3; ++a) b.lo[a] = coordinate(rng), b.hi[a] = b.lo[a] + size(rng);
    };
    for (RBoundsTree::RBox& b : boxes) place(b);
    std::vector<std::uint32_t> ids(n);
    for (std::size_t k = 0; k < n; ++k) ids[k] = static_cast<std::uint32_t>(k);
    RBoundsTree some, all;
    some.Build(boxes.data(), ids.data(), n);
    all.Build(boxes.data(), ids.data(), n);
    for (int round = 0; round < 5; ++round) {
      // A tenth of the items (at least one) move anywhere, each listed once.
      std::vector<std::uint32_t> moved;
      for (std::uint32_t k = 0; k < n; ++k) {
        if (rng() % 10 == 0 || (moved.empty() && k + 1 == n)) moved.push_back(k), place(boxes[k]);
      }
      some.RefitItems(boxes.data(), moved.data(), moved.size());
      all.Refit(boxes.data());
      EXPECT_EQ(some.InnerArea(), all.InnerArea()) << n << " boxes, round " << round;
      for (std::size_t q = 0; q < std::min<std::size_t>(n, 200); ++q) {
        RBoundsTree::RBox probe;
        place(probe);
        std::vector<std::uint32_t> hitsSome, hitsAll, expected, stack;
        some.Query(probe, hitsSome, stack);
        all.Query(probe, hitsAll, stack);
        EXPECT_EQ(hitsSome, hitsAll);
        for (std::uint32_t k = 0; k < n; ++k) {
          bool overlap = true;
          for (int a = 0; a < 3; ++a) overlap = overlap && boxes[k].lo[a] <= probe.hi[a] && probe.lo[a] <= boxes[k].hi[a];
          if (overlap) expected.push_back(k);
        }
        std::sort(hitsSome.begin(), hitsSome.end());
        EXPECT_EQ(hitsSome, expected) << n << " boxes, round " << round;
      }
    }
  }
}
