// The broad phase (RShortcuts::broadPhase): bounding-volume trees over the pair sweep's
// grown spheres (RBoundsTree), and the pairs whose boxes overlap, found without visiting
// every pair and handed to the pair sweep in its all-pairs order (see DetectPairs).
#include "RWorldStep.h"

#include <algorithm>
#include <cmath>

namespace REngine {

RBoundsTree::RBox RWorldStep::SweepBox(std::size_t i) const {
  // The grown sphere's box, widened by a millionth of the reach and by a few units in the
  // last place of the coordinates: the all-pairs loop's sphere test, with its own
  // rounding, passes no pair whose boxes are apart.
  const RScalar c[3] = {m_cx[i], m_cy[i], m_cz[i]};
  const RScalar reach = m_reach[i];
  RBoundsTree::RBox box;
  for (int a = 0; a < 3; ++a) {
    const RScalar half = reach * (1 + 1e-6) + 4e-15 * (std::abs(c[a]) + reach);
    box.lo[a] = c[a] - half, box.hi[a] = c[a] + half;
  }
  return box;
}

void RWorldStep::BuildBroadPhase(const RStepBodies& bodies) {
  // A box with a NaN (a body with a non-finite reach) would pass no sphere test: such a
  // body is left out of the trees, as the all-pairs loop pairs it with nothing.
  auto finite = [](const RBoundsTree::RBox& b) {
    return !(std::isnan(b.lo[0]) || std::isnan(b.lo[1]) || std::isnan(b.lo[2]) ||
             std::isnan(b.hi[0]) || std::isnan(b.hi[1]) || std::isnan(b.hi[2]));
  };
  const std::size_t n = bodies.size();
  m_sweepBoxes.resize(n);
  ParallelRanges(m_jobs, n, m_tasks, 512, [&](std::size_t i0, std::size_t i1, std::size_t) {
    for (std::size_t i = i0; i < i1; ++i) m_sweepBoxes[i] = SweepBox(i);
  });
  // The active tree: refitted to this step's boxes while it holds the same bodies (O(n)),
  // rebuilt when they change and every kRefits steps, since a refitted tree loosens as
  // its bodies move apart. Its shape changes how fast queries are, never what they find.
  m_treeIds.clear();
  for (std::uint32_t i : m_active) {
    if (finite(m_sweepBoxes[i])) m_treeIds.push_back(i);
  }
  constexpr int kRefits = 8;
  if (m_treeIds == m_activeIds && m_activeRefits < kRefits) {
    m_activeTree.Refit(m_sweepBoxes.data());
    ++m_activeRefits;
  } else {
    std::swap(m_treeIds, m_activeIds);
    m_treeBoxes.clear();
    for (std::uint32_t i : m_activeIds) m_treeBoxes.push_back(m_sweepBoxes[i]);
    m_activeTree.Build(m_treeBoxes.data(), m_activeIds.data(), m_activeIds.size());
    m_activeRefits = 0;
  }
  // The passive bodies (asleep, or static, and responding): their boxes change only when
  // the game moves or replaces one, or the step's size or gravity changes their reach.
  m_treeBoxes.clear(), m_treeIds.clear();
  std::size_t next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (next < m_active.size() && m_active[next] == i) {
      ++next;
      continue;
    }
    const RBoundsTree::RBox& box = m_sweepBoxes[i];
    if (finite(box)) m_treeBoxes.push_back(box), m_treeIds.push_back(static_cast<std::uint32_t>(i));
  }
  const bool same = m_treeIds == m_passiveIds && m_treeBoxes.size() == m_passiveBoxes.size() &&
                    std::equal(m_treeBoxes.begin(), m_treeBoxes.end(), m_passiveBoxes.begin(),
                               [](const RBoundsTree::RBox& x, const RBoundsTree::RBox& y) {
                                 return std::equal(x.lo, x.lo + 3, y.lo) &&
                                        std::equal(x.hi, x.hi + 3, y.hi);
                               });
  if (!same) {
    std::swap(m_treeIds, m_passiveIds), std::swap(m_treeBoxes, m_passiveBoxes);
    m_passiveTree.Build(m_passiveBoxes.data(), m_passiveIds.data(), m_passiveIds.size());
  }
}

// Stage 1 of the pair sweep with the broad phase: the pairs of overlapping boxes in the
// active tree and between it and the passive one, each through the all-pairs loop's
// sphere test (the same operands in the same order, so the same answer to the bit), then
// sorted into the loop's (i, then j) order. The search is split into independent starts
// (PairSeeds), taken by the tasks; the sort makes the result independent of the split.
void RWorldStep::TreePairs(RScalar grow) {
  const std::size_t tasks = m_tasks;
  m_activeTree.PairSeeds(m_activeTree, 8 * tasks, m_seeds, m_seedScratch);
  const std::size_t selfSeeds = m_seeds.size();
  m_activeTree.PairSeeds(m_passiveTree, 8 * tasks, m_seedScratch2, m_seedScratch);
  m_seeds.insert(m_seeds.end(), m_seedScratch2.begin(), m_seedScratch2.end());
  // Trees of a few hundred bodies are searched on one thread.
  const std::size_t grain = m_activeIds.size() < 256 ? m_seeds.size() : 1;
  const std::size_t used = ParallelRanges(m_jobs, m_seeds.size(), tasks, grain, [&](std::size_t k0, std::size_t k1, std::size_t task) {
    RSweepTask& st = m_sweepTasks[task];
    st.pairs.clear();
    st.sphereTests = 0;
    auto found = [&](std::uint32_t x, std::uint32_t y) {
      ++st.sphereTests;
      const std::uint32_t i = std::min(x, y), j = std::max(x, y);
      const RScalar dx = m_cx[j] - m_cx[i], dy = m_cy[j] - m_cy[i], dz = m_cz[j] - m_cz[i];
      const RScalar lim = (m_reach[i] + m_reach[j]) * grow;
      if (lim * lim - (dx * dx + dy * dy + dz * dz) >= 0) st.pairs.emplace_back(i, j);
    };
    for (std::size_t k = k0; k < k1; ++k) {
      const RBoundsTree& other = k < selfSeeds ? m_activeTree : m_passiveTree;
      m_activeTree.Pairs(other, m_seeds[k], st.nodeStack, found);
    }
  });
  // Into (i, then j) order: a counting sort by i (O(pairs + bodies)) of the tasks' lists,
  // then each body's few partners by insertion.
  const std::size_t n = m_cx.size();
  m_pairStart.assign(n + 1, 0);
  std::size_t total = 0;
  for (std::size_t t = 0; t < used; ++t) {
    for (const auto& [i, j] : m_sweepTasks[t].pairs) ++m_pairStart[i + 1];
    total += m_sweepTasks[t].pairs.size();
    m_pairStats.sphereTests += m_sweepTasks[t].sphereTests;
  }
  for (std::size_t i = 0; i < n; ++i) m_pairStart[i + 1] += m_pairStart[i];
  m_pairs.resize(total);
  for (std::size_t t = 0; t < used; ++t) {
    for (const auto& pair : m_sweepTasks[t].pairs) m_pairs[m_pairStart[pair.first]++] = pair;
  }
  for (std::size_t first = 0, i = 0; i < n; first = m_pairStart[i++]) {
    const std::size_t last = m_pairStart[i];
    for (std::size_t k = first + 1; k < last; ++k) {
      const auto pair = m_pairs[k];
      std::size_t at = k;
      for (; at > first && m_pairs[at - 1].second > pair.second; --at) m_pairs[at] = m_pairs[at - 1];
      m_pairs[at] = pair;
    }
  }
}

}  // namespace REngine
