// Private to REnginePhysics: the broad phase (RShortcuts::broadPhase), the pair sweep's
// stage 1 when a tree costs less than the all-pairs loop. It owns each body's sweep box
// (where the all-pairs loop can pair it this sweep) and fat box (a sweep box grown by a
// margin, which the body may move inside without a new search), the tree of the fat boxes
// (RBoundsTree) and the sorted list of the pairs whose fat boxes overlap, kept between
// steps while the broad phase is in use, and the scratch that keeps them up to date. What
// it shares with the all-pairs loop stays the pair sweep's (DetectPairs) and is lent to it
// for the call: the bodies' centres, reaches and passive flags (RSweep), the sweep's
// per-task scratch and its pair list. Every vector keeps its capacity between steps.
#pragma once

#include <REngineMath/RMath.h>

#include "pairs/RBoundsTree.h"
#include "pairs/RSweepTask.h"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace REngine {

class RJobSystem;
struct RBodyCore;
struct RPairStats;
struct RStepBodies;

class RBroadPhase {
 public:
  // Two bodies' dense indices, i < j.
  using RPair = std::pair<std::uint32_t, std::uint32_t>;

  // What the broad phase reads of the pair sweep's set-up pass (SweepMotion), per body by
  // dense index, this sweep: its centre of mass (world, m), its reach (its bounding radius
  // grown by the step's motion and the allowance, m), and whether it is passive (cannot
  // start a contact: RPairSweep::Passive). And the step's job system (null: one thread)
  // with how many tasks a parallel stage is cut into.
  struct RSweep {
    const std::vector<RScalar>& cx;
    const std::vector<RScalar>& cy;
    const std::vector<RScalar>& cz;
    const std::vector<RScalar>& reach;
    const std::vector<char>& passive;
    RJobSystem* jobs;
    std::size_t tasks;
  };

  // The sweep boxes of this sweep's n bodies, made by MakeSweepBox in the pair sweep's
  // set-up pass while each body's lines are in the cache (threads make different bodies'
  // boxes side by side).
  void ResizeSweepBoxes(std::size_t n) { m_sweepBoxes.resize(n); }
  // Body i's sweep box, from its centre of mass (world, m) and reach (m) this sweep.
  void MakeSweepBox(std::size_t i, const RBodyCore& b, RScalar cx, RScalar cy, RScalar cz, RScalar reach) {
    m_sweepBoxes[i] = SweepBox(b, cx, cy, cz, reach);
  }

  // The fat boxes, their tree and their pair list brought up to this sweep's boxes: the
  // bodies that left their fat boxes get new ones and new pairs, or everything is built
  // anew (the list was not kept, the bodies changed, many moved, or the tree has been
  // refitted kFatRefits times).
  // tasks: the pair sweep's per-task scratch, whose pairs, query, queryStack and nodeStack
  // are written here, at least sweep.tasks of them.
  void UpdateBroadPhase(const RStepBodies& bodies, const RSweep& sweep, std::vector<RSweepTask>& tasks);
  // Stage 1 of the pair sweep with the broad phase, after UpdateBroadPhase: into `pairs`
  // (cleared first), in (i, then j) order, the listed pairs that can start a contact and
  // whose grown spheres touch (the all-pairs loop's test with the same factor `grow`);
  // counts the sphere tests into stats.sphereTests. Uses the tasks' pairs and sphereTests.
  void TreePairs(RScalar grow, const RSweep& sweep, std::vector<RSweepTask>& tasks,
                 std::vector<RPair>& pairs, RPairStats& stats);

  // Whether the pair list is kept up to date with the fat boxes (the last sweep used the
  // broad phase), and how many pairs it holds: the pair sweep's estimate of its cost.
  bool ListValid() const { return m_fatValid; }
  std::size_t ListedPairs() const { return m_fatPairs.size(); }
  // Forgets the list: the next UpdateBroadPhase builds the tree and the list anew. For a
  // sweep that used the all-pairs loop, which does not keep the list, and for a load,
  // after which the bodies are others.
  void Invalidate() { m_fatValid = false, m_fatRefits = 0; }

 private:
  static RBoundsTree::RBox SweepBox(const RBodyCore& b, RScalar cx, RScalar cy, RScalar cz, RScalar reach);
  // Body i's fat box around its sweep box; reach is its reach this sweep (m).
  RBoundsTree::RBox FatBox(const RBodyCore& b, std::size_t i, RScalar reach) const;
  void RebuildFatPairs(const RStepBodies& bodies, const RSweep& sweep, std::vector<RSweepTask>& tasks);
  void MergeFresh(const RSweep& sweep);

  std::vector<RBoundsTree::RBox> m_sweepBoxes;  // per body, this sweep
  std::vector<RBoundsTree::RBox> m_fatBoxes;    // per body
  RBoundsTree m_fatTree;
  std::vector<RPair> m_fatPairs, m_fatScratch, m_fatMerged;  // (i < j), sorted
  std::vector<std::uint32_t> m_treeIds, m_moved;
  std::vector<char> m_movedMark;  // per body
  bool m_fatValid = false;  // the list matches the fat boxes (false after a sweep without it)
  int m_fatRefits = 0;      // steps since the tree was built: it is rebuilt every kFatRefits
  static constexpr int kFatRefits = 64;
  std::vector<RBoundsTree::RNodePair> m_seeds, m_seedScratch;  // RebuildFatPairs
  std::vector<std::uint32_t> m_pairStart;  // RebuildFatPairs: counting sort by i
  std::vector<std::uint32_t> m_rangeStart;  // MergeFresh: each range's first body, pair and new pair
  std::vector<std::size_t> m_rangeCount;    // MergeFresh: where each range's merge goes
};

}  // namespace REngine
