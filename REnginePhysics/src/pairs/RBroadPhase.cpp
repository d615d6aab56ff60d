// The broad phase (RShortcuts::broadPhase): the pairs whose sweep boxes overlap, found
// without visiting every pair and handed to the pair sweep in its all-pairs order (see
// DetectPairs).
//
// Each body has a fat box, its sweep box grown by a margin, kept while the sweep box stays
// inside it; a bounding-volume tree holds the fat boxes (RBoundsTree) and a sorted list
// holds every pair of overlapping fat boxes. A step then only asks the tree about the
// bodies that left their fat boxes (in a resting pile, none; in a debris cloud, about one
// in ten), replaces their pairs in the list, and tests the list's pairs against this
// step's sweep boxes. Since a sweep box lies inside its fat box, two sweep boxes that
// overlap belong to a listed pair: the pairs found are exactly the all-pairs loop's
// (Box2D's and Bullet's dynamic trees keep fat boxes and a pair list the same way).
#include "pairs/RBroadPhase.h"

#include "world/RStepBodies.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace REngine {

RBoundsTree::RBox RBroadPhase::SweepBox(const RBodyCore& b, RScalar cx, RScalar cy, RScalar cz, RScalar reach) {
  // Where the all-pairs loop can pass a pair: its grown spheres touch and its world boxes,
  // grown by the same motion (DetectPairs' stage 2), overlap. So a body's box here is the
  // part of its grown sphere's box that its grown world box can reach, the world box
  // bounded without visiting vertices: the body-frame box turned, |R| h about R c.
  // Both are widened by a millionth of the growth and by a few units in the last place of
  // every term, so that no pair the loop passes, with its own rounding, has boxes apart
  // here. (A non-finite orientation leaves the sphere's box alone.)
  const RScalar c[3] = {cx, cy, cz};
  const RScalar grow = (reach - b.m_boundingRadius) * (1 + 1e-6);
  const RMat3 R = b.m_q_WB.toRotationMatrix();
  const RVec3 centre = R * b.m_boxCenter_B;
  const RVec3 half = R.cwiseAbs() * b.m_boxHalf_B;
  RBoundsTree::RBox box;
  for (int a = 0; a < 3; ++a) {
    const RScalar sphereHalf = reach * (1 + 1e-6) + 4e-15 * (std::abs(c[a]) + reach);
    box.lo[a] = c[a] - sphereHalf, box.hi[a] = c[a] + sphereHalf;
    const RScalar boxHalf = half[a] + grow + 1e-14 * (std::abs(c[a]) + std::abs(centre[a]) + half[a] + reach);
    const RScalar lo = c[a] + centre[a] - boxHalf, hi = c[a] + centre[a] + boxHalf;
    if (std::isfinite(lo) && std::isfinite(hi)) box.lo[a] = std::max(box.lo[a], lo), box.hi[a] = std::min(box.hi[a], hi);
  }
  return box;
}

namespace {

// Whether a box is a box: infinite bounds are (a body whose reach overflowed meets every
// other, as in the all-pairs loop, whose sphere test then passes every pair), NaN is not.
bool Valid(const RBoundsTree::RBox& b) {
  return !(std::isnan(b.lo[0]) || std::isnan(b.lo[1]) || std::isnan(b.lo[2]) ||
           std::isnan(b.hi[0]) || std::isnan(b.hi[1]) || std::isnan(b.hi[2]));
}

bool Contains(const RBoundsTree::RBox& outer, const RBoundsTree::RBox& inner) {
  return outer.lo[0] <= inner.lo[0] && outer.lo[1] <= inner.lo[1] && outer.lo[2] <= inner.lo[2] &&
         inner.hi[0] <= outer.hi[0] && inner.hi[1] <= outer.hi[1] && inner.hi[2] <= outer.hi[2];
}

// A box that overlaps nothing: the fat box of a body whose sweep box is not a number (game
// code set a NaN), which the all-pairs loop pairs with nothing.
constexpr RBoundsTree::RBox kEmpty = {
    {std::numeric_limits<RScalar>::infinity(), std::numeric_limits<RScalar>::infinity(),
     std::numeric_limits<RScalar>::infinity()},
    {-std::numeric_limits<RScalar>::infinity(), -std::numeric_limits<RScalar>::infinity(),
     -std::numeric_limits<RScalar>::infinity()}};

bool IsEmpty(const RBoundsTree::RBox& b) { return std::memcmp(&b, &kEmpty, sizeof b) == 0; }

}  // namespace

RBoundsTree::RBox RBroadPhase::FatBox(const RBodyCore& b, std::size_t i, RScalar reach) const {
  const RBoundsTree::RBox& box = m_sweepBoxes[i];
  if (!Valid(box)) return kEmpty;
  // A quarter of the reach, plus four steps of its motion: a resting body never leaves
  // its fat box, a fast one leaves it every few steps rather than every step. Only the
  // speed of the search depends on it.
  const RScalar motion = reach - b.m_boundingRadius;
  const RScalar margin = RScalar(0.25) * reach + 4 * motion;
  RBoundsTree::RBox fat = box;
  for (int a = 0; a < 3; ++a) fat.lo[a] -= margin, fat.hi[a] += margin;
  // Infinite sums stay infinite (a finite bound and an infinite margin give an infinite
  // bound, never a NaN: a bound is never infinite the other way).
  return Valid(fat) ? fat : box;
}

// The sweep boxes are this step's (DetectPairs made them with the reaches).
void RBroadPhase::UpdateBroadPhase(const RStepBodies& bodies, const RSweep& sweep, std::vector<RSweepTask>& tasks) {
  const std::size_t n = bodies.size();
  // The bodies that left their fat boxes (or whose box stopped or started being a number).
  m_moved.clear();
  const bool rebuild = !m_fatValid || m_fatBoxes.size() != n || m_fatRefits >= kFatRefits;
  if (!rebuild) {
    // Ranges of bodies, their lists joined in order: index order.
    const std::size_t used = ParallelRanges(sweep.jobs, n, sweep.tasks, 512, [&](std::size_t i0, std::size_t i1, std::size_t task) {
      std::vector<std::uint32_t>& moved = tasks[task].moved;
      moved.clear();
      for (std::size_t i = i0; i < i1; ++i) {
        const RBoundsTree::RBox& box = m_sweepBoxes[i];
        const RBoundsTree::RBox& fat = m_fatBoxes[i];
        if (Valid(box) ? !Contains(fat, box) : !IsEmpty(fat)) moved.push_back(static_cast<std::uint32_t>(i));
      }
    });
    for (std::size_t t = 0; t < used; ++t) m_moved.insert(m_moved.end(), tasks[t].moved.begin(), tasks[t].moved.end());
  }
  // Many moved (bodies added or removed shift the indices): a new tree and list, O(n log n
  // + pairs); otherwise the moved bodies' pairs are replaced, O(moved log n + pairs).
  if (rebuild || 4 * m_moved.size() > n) {
    RebuildFatPairs(bodies, sweep, tasks);
    return;
  }
  ++m_fatRefits;
  if (m_moved.empty()) return;
  m_movedMark.resize(n, 0);  // all 0 between steps: cleared below after use
  for (std::uint32_t i : m_moved) m_fatBoxes[i] = FatBox(bodies[i], i, sweep.reach[i]), m_movedMark[i] = 1;
  m_fatTree.RefitItems(m_fatBoxes.data(), m_moved.data(), m_moved.size());
  // Each moved body's new partners, from the tree; a pair of two moved bodies is taken by
  // the first of them.
  const std::size_t used = ParallelRanges(sweep.jobs, m_moved.size(), sweep.tasks, 64, [&](std::size_t k0, std::size_t k1, std::size_t task) {
    RSweepTask& st = tasks[task];
    st.pairs.clear();
    for (std::size_t k = k0; k < k1; ++k) {
      const std::uint32_t i = m_moved[k];
      st.query.clear();
      m_fatTree.Query(m_fatBoxes[i], st.query, st.queryStack);
      for (std::uint32_t j : st.query) {
        if (j == i || (m_movedMark[j] && j < i)) continue;
        st.pairs.emplace_back(std::min(i, j), std::max(i, j));
      }
    }
  });
  m_fatScratch.clear();
  for (std::size_t t = 0; t < used; ++t) {
    m_fatScratch.insert(m_fatScratch.end(), tasks[t].pairs.begin(), tasks[t].pairs.end());
  }
  std::sort(m_fatScratch.begin(), m_fatScratch.end());
  MergeFresh(sweep);
  for (std::uint32_t i : m_moved) m_movedMark[i] = 0;
}

// The list's pairs of unmoved bodies, kept in order, merged with the new ones (sorted, in
// m_fatScratch) into the next list. Cut by the first body's index into ranges, whose pairs
// and new pairs are both contiguous: each range counts what it keeps, then writes its merge
// at its place.
void RBroadPhase::MergeFresh(const RSweep& sweep) {
  const std::size_t listed = m_fatPairs.size();
  const std::size_t ranges = RangeCount(listed, sweep.tasks, 1024);
  if (ranges == 0) {  // nothing listed: the new pairs are the list
    m_fatPairs.assign(m_fatScratch.begin(), m_fatScratch.end());
    return;
  }
  const auto kept = [this](const RPair& pair) { return !m_movedMark[pair.first] && !m_movedMark[pair.second]; };
  // Range t covers the pairs whose first body is in [bodyStart[t], bodyStart[t + 1]).
  m_rangeStart.resize(3 * (ranges + 1));
  std::uint32_t* bodyStart = m_rangeStart.data();
  std::uint32_t* listStart = bodyStart + ranges + 1;
  std::uint32_t* freshStart = listStart + ranges + 1;
  const auto byFirst = [](const RPair& pair, std::uint32_t i) { return pair.first < i; };
  for (std::size_t t = 0; t <= ranges; ++t) {
    const std::size_t at = listed * t / ranges;
    bodyStart[t] = t == 0 ? 0 : t == ranges ? std::numeric_limits<std::uint32_t>::max() : m_fatPairs[at].first;
    listStart[t] = static_cast<std::uint32_t>(
        std::lower_bound(m_fatPairs.begin(), m_fatPairs.end(), bodyStart[t], byFirst) - m_fatPairs.begin());
    freshStart[t] = static_cast<std::uint32_t>(
        std::lower_bound(m_fatScratch.begin(), m_fatScratch.end(), bodyStart[t], byFirst) - m_fatScratch.begin());
  }
  m_rangeCount.assign(ranges + 1, 0);
  ParallelRanges(sweep.jobs, ranges, ranges, 1, [&](std::size_t t0, std::size_t t1, std::size_t) {
    for (std::size_t t = t0; t < t1; ++t) {
      m_rangeCount[t + 1] = static_cast<std::size_t>(std::count_if(m_fatPairs.begin() + listStart[t], m_fatPairs.begin() + listStart[t + 1], kept)) +
                            (freshStart[t + 1] - freshStart[t]);
    }
  });
  for (std::size_t t = 0; t < ranges; ++t) m_rangeCount[t + 1] += m_rangeCount[t];
  m_fatMerged.resize(m_rangeCount[ranges]);
  ParallelRanges(sweep.jobs, ranges, ranges, 1, [&](std::size_t t0, std::size_t t1, std::size_t) {
    for (std::size_t t = t0; t < t1; ++t) {
      // std::merge of the kept pairs and the new ones (the kept first of equals: none are).
      const RPair* a = m_fatPairs.data() + listStart[t];
      const RPair* aEnd = m_fatPairs.data() + listStart[t + 1];
      const RPair* b = m_fatScratch.data() + freshStart[t];
      const RPair* bEnd = m_fatScratch.data() + freshStart[t + 1];
      RPair* out = m_fatMerged.data() + m_rangeCount[t];
      for (;;) {
        while (a != aEnd && !kept(*a)) ++a;
        if (a == aEnd) {
          out = std::copy(b, bEnd, out);
          break;
        }
        if (b != bEnd && *b < *a) {
          *out++ = *b++;
        } else {
          *out++ = *a++;
        }
      }
    }
  });
  std::swap(m_fatPairs, m_fatMerged);
}

// Every body's fat box anew, its tree built, and every pair of overlapping fat boxes
// found by the tree's pair search (split into tasks), then sorted by (i, then j).
void RBroadPhase::RebuildFatPairs(const RStepBodies& bodies, const RSweep& sweep, std::vector<RSweepTask>& tasks) {
  const std::size_t n = bodies.size();
  m_fatBoxes.resize(n);
  m_treeIds.resize(n);
  ParallelRanges(sweep.jobs, n, sweep.tasks, 512, [&](std::size_t i0, std::size_t i1, std::size_t) {
    for (std::size_t i = i0; i < i1; ++i) m_fatBoxes[i] = FatBox(bodies[i], i, sweep.reach[i]), m_treeIds[i] = static_cast<std::uint32_t>(i);
  });
  m_fatTree.Build(m_fatBoxes.data(), m_treeIds.data(), n);
  m_fatValid = true;
  m_fatRefits = 0;
  const std::size_t taskCount = sweep.tasks;
  m_fatTree.PairSeeds(m_fatTree, 8 * taskCount, m_seeds, m_seedScratch);
  // Trees of a few hundred bodies are searched on one thread.
  const std::size_t grain = n < 256 ? m_seeds.size() : 1;
  const std::size_t used = ParallelRanges(sweep.jobs, m_seeds.size(), taskCount, grain, [&](std::size_t k0, std::size_t k1, std::size_t task) {
    RSweepTask& st = tasks[task];
    st.pairs.clear();
    auto found = [&st](std::uint32_t x, std::uint32_t y) { st.pairs.emplace_back(std::min(x, y), std::max(x, y)); };
    for (std::size_t k = k0; k < k1; ++k) m_fatTree.Pairs(m_fatTree, m_seeds[k], st.nodeStack, found);
  });
  // Into (i, then j) order: a counting sort by i (O(pairs + bodies)) of the tasks' lists,
  // then each body's partners (few, but the ground under a pile has hundreds).
  m_pairStart.assign(n + 1, 0);
  std::size_t total = 0;
  for (std::size_t t = 0; t < used; ++t) {
    for (const auto& [i, j] : tasks[t].pairs) ++m_pairStart[i + 1];
    total += tasks[t].pairs.size();
  }
  for (std::size_t i = 0; i < n; ++i) m_pairStart[i + 1] += m_pairStart[i];
  m_fatPairs.resize(total);
  for (std::size_t t = 0; t < used; ++t) {
    for (const auto& pair : tasks[t].pairs) m_fatPairs[m_pairStart[pair.first]++] = pair;
  }
  for (std::size_t first = 0, i = 0; i < n; first = m_pairStart[i++]) {
    std::sort(m_fatPairs.begin() + static_cast<std::ptrdiff_t>(first),
              m_fatPairs.begin() + static_cast<std::ptrdiff_t>(m_pairStart[i]));
  }
}

// Stage 1 of the pair sweep with the broad phase: the listed pairs that can start a
// contact (not both passive) and whose sweep boxes overlap, each through the all-pairs
// loop's sphere test (the same operands in the same order, so the same answer to the bit).
// The list is in (i, then j) order, and so are the tasks' ranges of it, joined in order.
void RBroadPhase::TreePairs(RScalar grow, const RSweep& sweep, std::vector<RSweepTask>& tasks,
                            std::vector<RPair>& pairs, RPairStats& stats) {
  constexpr std::size_t kBoxAhead = 16;
  const std::vector<char>& passive = sweep.passive;
  const std::vector<RScalar>& cx = sweep.cx;
  const std::vector<RScalar>& cy = sweep.cy;
  const std::vector<RScalar>& cz = sweep.cz;
  const std::vector<RScalar>& reach = sweep.reach;
  const std::size_t used = ParallelRanges(sweep.jobs, m_fatPairs.size(), sweep.tasks, 1024, [&](std::size_t k0, std::size_t k1, std::size_t task) {
    RSweepTask& st = tasks[task];
    st.pairs.clear();
    st.sphereTests = 0;
    for (std::size_t k = k0; k < k1; ++k) {
      // The second body's box is anywhere in a 1.4 MB array (30000 bodies): asked for a
      // few pairs ahead, it is there when the pair is tested.
      if (k + kBoxAhead < k1) {
        const std::uint32_t ahead = m_fatPairs[k + kBoxAhead].second;
        PrefetchBytes(&m_sweepBoxes[ahead], sizeof(RBoundsTree::RBox));
        __builtin_prefetch(&passive[ahead]);
      }
      const auto [i, j] = m_fatPairs[k];
      // Without branches until the one that rejects most pairs (about 7 in 8 of a debris
      // cloud's listed pairs): short-circuit tests mispredict often.
      const bool overlap = RBoundsTree::Overlap(m_sweepBoxes[i], m_sweepBoxes[j]);
      if ((!overlap) | ((passive[i] != 0) & (passive[j] != 0))) continue;
      ++st.sphereTests;
      const RScalar dx = cx[j] - cx[i], dy = cy[j] - cy[i], dz = cz[j] - cz[i];
      const RScalar lim = (reach[i] + reach[j]) * grow;
      if (lim * lim - (dx * dx + dy * dy + dz * dz) >= 0) st.pairs.emplace_back(i, j);
    }
  });
  pairs.clear();
  for (std::size_t t = 0; t < used; ++t) {
    pairs.insert(pairs.end(), tasks[t].pairs.begin(), tasks[t].pairs.end());
    stats.sphereTests += tasks[t].sphereTests;
  }
}

}  // namespace REngine
