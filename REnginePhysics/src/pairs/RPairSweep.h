// Private to REnginePhysics: the pair sweep, the step's collision detection (see
// RIntegrator.h). A sweep (DetectPairs) sets up every body's centre, step motion, reach and
// flags (SweepMotion); finds the pairs whose bounding spheres, grown by the step's motion,
// touch (stage 1: the all-pairs loop, AllPairs, or the broad phase's tree, RBroadPhase);
// takes each through the bounding boxes, the filters and the narrow phase, or keeps last
// step's manifold (stage 2, NarrowPairs in RPairNarrow.cpp); and joins the tasks' results
// (JoinSweep); then rewrites or drops the contacts on features that flush immovable bodies
// cover, which are no surface of the world (CoveredFeatures, RPairCovered.cpp). It owns the
// step's contacts (its output, which the contact solver, the events, sleeping and save/load
// read), the manifold memory carried from step to step with each contact's entry in it, the
// set-up pass's per-body arrays (centres, reaches, motion, passive and body flags), the pair
// list, the per-task scratch (RSweepTask), the covered-feature rule's scratch, the game's
// pair filter and the step's pair counters. The broad phase, sleeping (which a sweep marks
// the sleeping islands it touched in), the settings and the job system come in as
// parameters. Every vector keeps its capacity between steps.
#pragma once

#include "state/RLoadKey.h"

#include <REngineMath/RMath.h>
#include <REnginePhysics/RIntegrator.h>

#include "collision/RCoveredFeatures.h"
#include "pairs/RSweepTask.h"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace REngine {

class RBroadPhase;
class RJobSystem;
class RSleeping;
struct RStepBodies;

class RPairSweep {
 public:
  // What a sweep reads of the step, this step.
  struct RStepInputs {
    const RWorldSettings& settings;
    RJobSystem* jobs;           // null: one thread
    std::size_t tasks;          // how many tasks a parallel stage is cut into
    std::uint64_t cacheStamp;   // the step's stamp of the bodies' world forms
  };

  // One sweep over the pairs, filling Contacts(). Returns true when it found a sleeping
  // island touched (marked in sleep): the islands are woken and the sweep runs again. The
  // broad phase is its stage 1 when the tree costs less than the all-pairs loop.
  bool DetectPairs(const RStepBodies& bodies, RScalar dt, const RStepInputs& in, RBroadPhase& broad,
                   RSleeping& sleep);

  // The game's veto on pairs (RIntegrator::SetPairFilter; null: none).
  void SetPairFilter(RPairFilter filter, void* user) { m_filter = filter, m_filterUser = user; }
  // Forgets the manifold memory: the next sweep computes every manifold anew
  // (RIntegrator::ForgetContacts).
  void ForgetManifolds() { m_manifolds.clear(); }

  // The step's contacts, in the pairs' (i, then j) order, manifolds in world space (m,
  // normal from a to b): the sweep's output, read by the contact solver, the events and
  // sleeping, and by the game through RIntegrator::Contacts.
  const std::vector<RContact>& Contacts() const { return m_contacts; }
  // The contact solver's writes to contact c: whether it is resolved, and the impulses it
  // reports on it (N s).
  RContact& SolverContact(std::size_t c) { return m_contacts[c]; }
  // The contact solver's cache: contact c's entry in the manifold memory, where the solver
  // keeps its block matrix and inverse (hasInverse, K, pinv: BlockInverse) for as long as
  // the manifold is kept; null when the contact has none (a compound's child contact, or
  // contact reuse off). The solver writes nothing else of it.
  RManifoldMemory* MemoryOf(std::size_t c) {
    const std::uint32_t memory = m_contactMemory.empty() ? kNoMemory : m_contactMemory[c];
    return memory == kNoMemory ? nullptr : &m_manifolds[memory];
  }

  // The velocity body i (dense index) moves with this step, world, m/s: its mid-step
  // velocity (a sleeper's: half a step of gravity), which its reach was grown by and the
  // contact solver starts its solver body from.
  const RVec3& MoveV(std::size_t i) const { return m_moveV[i]; }
  // Per body, this step (DetectPairs' set-up pass): whether it is static or kinematic and
  // whether it responds, a byte each beside the others, for the contact phase's passes
  // over contacts and bodies, which would otherwise wait for each body's first line.
  static constexpr std::uint8_t kFlagImmovable = 1, kFlagResponds = 2;
  const std::vector<std::uint8_t>& BodyFlags() const { return m_bodyFlags; }
  bool ImmovableAt(std::size_t i) const { return m_bodyFlags[i] & kFlagImmovable; }
  bool RespondsAt(std::size_t i) const { return m_bodyFlags[i] & kFlagResponds; }
  // Per body, this sweep: Passive (below), as the contact events read it.
  const std::vector<char>& PassiveFlags() const { return m_passive; }

  // Bodies that cannot start a contact: asleep, static, or kinematic and still, and
  // responding (a sensor keeps reporting what sleeps on it). A pair of two of them is
  // skipped; a sleeping body touched by any other (in the speculative margin) wakes with its
  // island: a kinematic body that moves wakes what it touches and nothing else.
  static bool StillKinematic(const RBodyCore& b) {
    return b.m_isKinematic && b.m_v_W.isZero(0) && b.m_w_W.isZero(0);
  }
  static bool Passive(const RBodyCore& b) {
    return (b.m_sleeping || b.m_isStatic || StillKinematic(b)) && b.m_responds;
  }

  // The counts of the step's pair loop (RIntegrator::PairStats): each sweep starts them
  // anew; the contact solver (contact points, warm starts, block inverses) and the step
  // (wake runs, sleeping bodies) write theirs through MutableStats.
  const RPairStats& Stats() const { return m_pairStats; }
  RPairStats& MutableStats() { return m_pairStats; }

  // Save/load's (state/RStateStep.cpp, RWorldState.cpp): the manifold memory, sorted by
  // (i, then j), is what carries to the next step; a load restores it and drops the last
  // step's contacts, their memory entries, the counts and the pair count (the broad
  // phase's cost estimate), which are not saved.
  const std::vector<RManifoldMemory>& Manifolds() const { return m_manifolds; }
  void RestoreForLoad(RLoadKey key, std::vector<RManifoldMemory> manifolds) {
    m_manifolds = std::move(manifolds);
    ForgetLastStep(key);
  }
  // A rollback snapshot's (RSnapshot.h): copied into the memory's capacity, no allocation.
  void RestoreForSnapshot(RLoadKey key, const std::vector<RManifoldMemory>& manifolds) {
    m_manifolds = manifolds;
    ForgetLastStep(key);
  }
  void ForgetLastStep(RLoadKey) {
    m_contacts.clear(), m_contactMemory.clear();
    m_pairStats = RPairStats{};
    m_lastPairCount = 0;
  }

 private:
  // A sweep's parts: the set-up pass over the bodies (centres, step motion, reach, flags,
  // the broad phase's sweep boxes); stage 1 without the broad phase; stage 2
  // (RPairNarrow.cpp), returning its task count; the tasks' results joined (returns whether
  // a sleeping island was touched).
  void SweepMotion(const RStepBodies& bodies, RScalar dt, RScalar allowance, bool sweepBoxes,
                   const RStepInputs& in, RBroadPhase& broad);
  void AllPairs(const RStepBodies& bodies, RScalar grow, const RStepInputs& in);
  std::size_t NarrowPairs(const RStepBodies& bodies, RScalar dt, RScalar allowance, RScalar grow,
                          const RStepInputs& in);
  bool JoinSweep(std::size_t pairTasks, const RStepInputs& in, RSleeping& sleep);
  // The covered-feature rule (collision/RCoveredFeatures.h) over the joined contacts
  // (RPairCovered.cpp): each moving body that touches several immovable bodies, its contacts
  // with each against the others; a contact on a covered feature is rewritten along the
  // surface or dropped (the contacts and their memory entries closed up). One thread, in
  // the contacts' order.
  void CoveredFeatures(const RStepBodies& bodies, RScalar dt, RScalar allowance, std::size_t pairTasks,
                       const RStepInputs& in);
  // The rule for one moving body's contacts m_coverContacts[first, last): false when
  // none was dropped.
  bool CoverBody(const RStepBodies& bodies, RScalar dt, RScalar allowance, RScalar slop, std::size_t first,
                 std::size_t last, std::uint64_t cacheStamp);

  // Stage 2, pair by pair (RPairNarrow.cpp). A task's place in last step's manifold memory:
  // the next entry to look at, the end of its part, and whether this step's entries still
  // go over last step's in place.
  struct RMemoryCursor {
    std::size_t memory, memoryEnd;
    bool inPlace;
  };
  // Whether pair (i, j) passes its grown bounding boxes (else counted in st.rejectedBoxes)
  // and the filters (else in st.rejectedFilter).
  bool PairPasses(const RStepBodies& bodies, std::size_t i, std::size_t j, RScalar grow, bool bounds,
                  std::uint64_t cacheStamp, RSweepTask& st) const;
  // A pair that passed them, through the narrow phase: its contacts (a compound's, child by
  // child), or the sleeping island it wakes, into the task.
  void NarrowPair(const RStepBodies& bodies, const std::pair<std::uint32_t, std::uint32_t>& pair, RScalar dt,
                  RScalar allowance, bool reuse, RSweepTask& st, RMemoryCursor& cursor);
  // A pair in the narrow phase: (i, j) in the sweep's order, the same bodies (ia, ib) in slot
  // order (A the lower slot), their shapes, B's pose in A's frame and the margin.
  struct RNarrowPair {
    std::pair<std::uint32_t, std::uint32_t> pair;
    std::size_t i, j, ia, ib;
    RConvexShape shapeA, shapeB;
    RRelativePose X;
    RMargin margin;
  };
  // A pair with a compound or a mesh: one contact per touching child pair.
  void ChildContacts(const RStepBodies& bodies, const RNarrowPair& p, RScalar dt, RSweepTask& st) const;
  // Last step's manifold of the pair when it may be kept (else null); sets unread to the
  // first of last step's entries still to be read.
  const RManifoldMemory* KeptManifold(const RStepBodies& bodies, const RNarrowPair& p, RMemoryCursor& cursor,
                                      std::size_t& unread) const;
  // The narrow phase's manifold of the pair (in A's frame), remembered for the next step
  // when reuse; returns whether the bodies touch.
  bool NewManifold(const RStepBodies& bodies, const RNarrowPair& p, bool reuse, std::size_t unread,
                   RContactManifold& manifold, RSweepTask& st, RMemoryCursor& cursor);
  // Where this task's next entry of the manifold memory goes (in place while it stays
  // behind last step's entries still to be read, from `unread` on; else in st.manifolds).
  RManifoldMemory* Remember(RSweepTask& st, RMemoryCursor& cursor, std::size_t unread);
  // The speculative margin of pair (i, j) (m): how far its bodies can approach within the
  // step, from their step motion, plus the allowance.
  RScalar PairMargin(const RStepBodies& bodies, std::size_t i, std::size_t j, RScalar dt, RScalar allowance) const;
  // When within the step the manifold's deepest point closes, moving with the bodies' step
  // velocities: 0 when it is closed already, infinity when it does not close this step.
  static RScalar TimeOfImpact(const RBodyCore& a, const RBodyCore& b, const RVec3& va, const RVec3& vb,
                              const RContactManifold& m, RScalar dt);
  // A body's hull (its polyhedron's vertex array, up to 4 lines), read by its world form
  // and the narrow phase: asked for once the body's own lines have arrived (PrefetchBody a
  // few pairs earlier), since the pointer to it is in them.
  static void PrefetchHull(const RBodyCore& b);

  static constexpr std::size_t kSweepPairGrain = 32;  // pairs per stage-2 task, at least
  std::vector<RContact> m_contacts;  // capacity kept between steps: no per-step allocation
  std::vector<RScalar> m_cx, m_cy, m_cz, m_reach;  // centres and grown radii
  std::vector<std::uint32_t> m_active;  // bodies that can start a contact (not Passive)
  std::vector<RVec3> m_moveV;    // velocity each body moves with this step, world, m/s
  std::vector<RScalar> m_moveW;  // its angular speed this step, rad/s
  std::vector<char> m_passive;  // per body, this sweep: Passive
  std::vector<std::uint8_t> m_bodyFlags;  // per body, this step: kFlagImmovable, kFlagResponds
  // The manifold memory (RManifoldMemory), in the sweep's (i, then j) order.
  std::vector<RManifoldMemory> m_manifolds;
  std::vector<RManifoldMemory> m_manifoldsGather;  // JoinSweep's when it cannot keep them in place
  std::vector<std::size_t> m_memoryFrom;  // NarrowPairs: each pair range's first entry of m_manifolds
  std::vector<std::uint32_t> m_contactMemory;  // per contact: its m_manifolds entry, or kNoMemory
  static constexpr std::uint32_t kNoMemory = 0xffffffffu;
  std::vector<RSweepTask> m_sweepTasks;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_pairs;  // (i < j), the loop's order
  std::size_t m_lastPairCount = 0;  // pairs the last sweep found (the trees' cost estimate)
  std::vector<char> m_formNeeded;  // bodies whose world form a pair reads (threads only)
  // The covered-feature rule's scratch (CoveredFeatures): per body, its first contact with
  // an immovable body this step (kNoCover: none; kSeveralCovers set: it has more), every
  // entry kNoCover between steps; the (moving body, contact) pairs of the bodies with
  // several, sorted; one body's immovable surfaces; the contacts dropped.
  static constexpr std::uint32_t kNoCover = 0xffffffffu, kSeveralCovers = 0x80000000u;
  std::vector<std::uint32_t> m_coverFirst;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_coverContacts;
  std::vector<RCoverSurface> m_coverSurfaces;
  std::vector<std::uint32_t> m_coverDropped;
  RPairStats m_pairStats;
  RPairFilter m_filter = nullptr;
  void* m_filterUser = nullptr;
};

}  // namespace REngine
