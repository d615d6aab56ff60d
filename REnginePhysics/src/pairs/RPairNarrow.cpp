// Stage 2 of the pair sweep (RPairSweep::NarrowPairs, called by DetectPairs in
// RPairSweep.cpp): each pair the spheres found, through the bounding boxes, the filters
// and the narrow phase, or last step's manifold kept.
#include "pairs/RPairSweep.h"

#include "shape/RCompound.h"
#include "world/RStepBodies.h"

#include "solver/RSolverRows.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace solver;

namespace {

// Whether a pair (its bodies' flags, RPairSweep::BodyFlags) is a moving body's contact with
// an immovable one, both responding: the contacts the covered-feature rule reads.
bool OneImmovable(std::uint8_t fa, std::uint8_t fb) {
  return ((fa ^ fb) & RPairSweep::kFlagImmovable) && (fa & fb & RPairSweep::kFlagResponds);
}

// Whether a memory entry comes before a pair in the sweep's (i, then j) order.
bool Before(const RManifoldMemory& mem, const std::pair<std::uint32_t, std::uint32_t>& p) {
  return mem.i < p.first || (mem.i == p.first && mem.j < p.second);
}

}  // namespace

RScalar RPairSweep::TimeOfImpact(const RBodyCore& a, const RBodyCore& b, const RVec3& va, const RVec3& vb,
                                 const RContactManifold& m, RScalar dt) {
  if (m.pointCount == 0) return m.query.separation <= 0 ? 0 : std::numeric_limits<RScalar>::infinity();
  int deepest = 0;
  for (int k = 1; k < m.pointCount; ++k) {
    if (m.points[k].separation < m.points[deepest].separation) deepest = k;
  }
  const RScalar gap = m.points[deepest].separation;
  if (gap <= 0) return 0;
  const RVec3& p = m.points[deepest].position;
  const RVec3 wa = a.m_isStatic ? RVec3::Zero() : Body(a).AngularVelocity_W();
  const RVec3 wb = b.m_isStatic ? RVec3::Zero() : Body(b).AngularVelocity_W();
  const RScalar vn = m.normal.dot(vb + wb.cross(p - b.m_x_W) - va -
                                        wa.cross(p - a.m_x_W));
  if (vn < 0 && gap <= -vn * dt) return gap / -vn;
  return std::numeric_limits<RScalar>::infinity();
}

RScalar RPairSweep::PairMargin(const RStepBodies& bodies, std::size_t i, std::size_t j, RScalar dt,
                               RScalar allowance) const {
  const RScalar approach = (m_moveV[j] - m_moveV[i]).norm() + m_moveW[i] * bodies[i].m_boundingRadius +
                           m_moveW[j] * bodies[j].m_boundingRadius;
  return approach * dt + allowance;
}

void RPairSweep::PrefetchHull(const RBodyCore& b) {
  if (b.m_polyhedron_B) PrefetchBytes(b.m_polyhedron_B->Vertices().data(), 4 * 64);
}

// Stage 2 of the pair sweep: each pair through the bounding boxes, the filters and the
// narrow phase (CheckCollision, or last step's manifold kept), on the tasks' contiguous
// ranges of the pairs. Returns the number of tasks (their results in m_sweepTasks).
std::size_t RPairSweep::NarrowPairs(const RStepBodies& bodies, RScalar dt, RScalar allowance, RScalar kGrow,
                                    const RStepInputs& in) {
  const RWorldSettings::RShortcuts& shortcuts = in.settings.shortcuts;
  const bool bounds = shortcuts.boundsRejection;
  const std::size_t tasks = in.tasks;
  constexpr std::size_t kPairAhead = 8, kPairLines = 10 * 64;  // see the loop below
  // Tasks take contiguous ranges of the pairs; their contacts, joined in task order, keep
  // the pairs' order.
  const bool reuse = shortcuts.contactReuse;
  // Each range's part of last step's memory (both lists in (i, j) order): from the first
  // entry not before its first pair up to the next range's. A task reads and writes only
  // its own part (see Remember). The ranges are ParallelRanges'.
  const std::size_t ranges = m_pairs.empty() ? 0 : in.jobs ? RangeCount(m_pairs.size(), tasks, kSweepPairGrain) : 1;
  m_memoryFrom.assign(ranges + 1, m_manifolds.size());
  for (std::size_t t = 0; reuse && t < ranges; ++t) {
    m_memoryFrom[t] = static_cast<std::size_t>(
        std::lower_bound(m_manifolds.begin(), m_manifolds.end(), m_pairs[m_pairs.size() * t / ranges], Before) -
        m_manifolds.begin());
  }
  return ParallelRanges(in.jobs, m_pairs.size(), tasks, kSweepPairGrain, [&](std::size_t k0, std::size_t k1, std::size_t task) {
    RSweepTask& st = m_sweepTasks[task];
    st.contacts.clear(), st.wake.clear(), st.manifolds.clear(), st.contactMemory.clear();
    st.immovable.clear();
    st.rejectedFilter = st.rejectedBoxes = st.narrowPhase = st.reused = 0;
    // Last step's manifolds from this range's first pair on.
    RMemoryCursor cursor{m_memoryFrom[task], m_memoryFrom[task + 1], reuse};
    // This step's memory is written over last step's in place, from the range's first entry
    // (st.manifoldsFrom) on, while it stays behind the entries still to be read: a settled
    // pile's memory is then written where it already is, and a kept entry (720 bytes) is not
    // copied at all. The tasks' ranges of last step's entries do not overlap, so a task
    // writes only entries no other task reads. Past the first entry that would overwrite
    // one still to be read, the rest go to st.manifolds (joined after the sweep).
    st.manifoldsFrom = cursor.memory;
    st.inPlace = 0;
    for (std::size_t k = k0; k < k1; ++k) {
      const std::size_t i = m_pairs[k].first, j = m_pairs[k].second;
      // A pair's second body is far from its first in storage (a pile's upper neighbour is
      // a layer of bodies away) and waits for memory: asked for a few pairs ahead, up to
      // its world form (the first lines every pair reads).
      if (k + kPairAhead < k1) {
        PrefetchBody(bodies[m_pairs[k + kPairAhead].first], kPairLines);
        PrefetchBody(bodies[m_pairs[k + kPairAhead].second], kPairLines);
      }
      if (k + kPairAhead / 2 < k1) {
        // Then what the pair reads through the bodies' lines (their hulls) and beside them
        // (reach and motion, in arrays of every body).
        for (const std::uint32_t x : {m_pairs[k + kPairAhead / 2].first, m_pairs[k + kPairAhead / 2].second}) {
          PrefetchHull(bodies[x]);
          __builtin_prefetch(&m_reach[x]), __builtin_prefetch(&m_moveW[x]), __builtin_prefetch(&m_moveV[x]);
        }
      }
      if (!PairPasses(bodies, i, j, kGrow, bounds, in.cacheStamp, st)) continue;
      ++st.narrowPhase;
      NarrowPair(bodies, m_pairs[k], dt, allowance, reuse, st, cursor);
    }
  });
}

bool RPairSweep::PairPasses(const RStepBodies& bodies, std::size_t i, std::size_t j, RScalar kGrow, bool bounds,
                            std::uint64_t cacheStamp, RSweepTask& st) const {
  const RBodyCore& a = bodies[i];
  const RBodyCore& b = bodies[j];
  // Bounding boxes from the stamped world forms, grown the same way: they reject the
  // many pairs whose spheres overlap only because a body is long or flat (the ground).
  // They come before the filters, as a broad phase's proof that a pair is apart does:
  // the broad phase's trees hold these boxes too (SweepBox), and the game's filter
  // sees the same pairs with them or without.
  const RWorldForm& fa = Body(a).WorldForm(cacheStamp);
  const RWorldForm& fb = Body(b).WorldForm(cacheStamp);
  const RScalar grow = (m_reach[i] - fa.sphereRadius + m_reach[j] - fb.sphereRadius) * kGrow;
  if (bounds && (((fa.aabbMin_W.array() - grow) > fb.aabbMax_W.array()).any() ||
                 ((fb.aabbMin_W.array() - grow) > fa.aabbMax_W.array()).any())) {
    ++st.rejectedBoxes;
    return false;
  }
  // Two bodies that nothing moves (static, kinematic) need no response: a kinematic
  // body is tested against another or against static geometry only when one of them
  // does not respond (a kinematic sensor reports what it sweeps through).
  if ((a.m_isStatic && b.m_isStatic) ||
      (a.Immovable() && b.Immovable() && a.m_responds && b.m_responds) ||
      !Body(a).ShouldCheckCollision(Body(b)) || (a.m_jointNoCollide && b.m_jointNoCollide && bodies.JointedNoCollide(i, j)) ||
      (m_filter && !m_filter(Body(a), Body(b), m_filterUser))) {
    ++st.rejectedFilter;
    return false;
  }
  return true;
}

void RPairSweep::NarrowPair(const RStepBodies& bodies, const std::pair<std::uint32_t, std::uint32_t>& pair,
                            RScalar dt, RScalar allowance, bool reuse, RSweepTask& st, RMemoryCursor& cursor) {
  const std::size_t i = pair.first, j = pair.second;
  const RBodyCore& a = bodies[i];
  const RBodyCore& b = bodies[j];
  RContact contact;
  // The pair in slot order, whatever the bodies' places in storage: its manifold, normal
  // and feature ids, and so its warm start, do not change when a removal moves a body.
  const bool flip = bodies.Slot(j) < bodies.Slot(i);
  const std::size_t ia = flip ? j : i, ib = flip ? i : j;
  const RBodyCore& A = bodies[ia];
  const RBodyCore& B = bodies[ib];
  const RNarrowPair p{pair, i, j, ia, ib, ShapeOf(Body(A)), ShapeOf(Body(B)), RelativePose(Body(A), Body(B)),
                      RMargin{PairMargin(bodies, i, j, dt, allowance)}};
  if (HasParts(p.shapeA) || HasParts(p.shapeB)) {
    ChildContacts(bodies, p, dt, st);
    return;
  }
  bool touching = false;
  const std::size_t remembered = st.inPlace + st.manifolds.size();
  // Last step's entries from `unread` on are still to be read (this pair's is read here).
  std::size_t unread = 0;
  const RManifoldMemory* kept = KeptManifold(bodies, p, cursor, unread);
  if (kept) {
    contact.manifold = kept->manifold_A;
    RManifoldMemory* to = Remember(st, cursor, unread);
    if (to != kept) *to = *kept;
    ++st.reused;
    touching = true;
  } else {
    touching = NewManifold(bodies, p, reuse, unread, contact.manifold, st, cursor);
  }
  if (touching) RCollisionSolver::ToWorld(Body(A), contact.manifold);
  if (touching) {
    // A sleeping body touched by one that responds wakes, with its island. A sensor
    // or a laser (does not respond) is reported against it without waking it.
    if ((a.m_sleeping || b.m_sleeping) && a.m_responds && b.m_responds) {
      st.wake.push_back((a.m_sleeping ? a : b).m_sleepIsland);
      return;
    }
    contact.a = static_cast<std::uint32_t>(ia);
    contact.b = static_cast<std::uint32_t>(ib);
    contact.handleA = bodies.handles[ia], contact.handleB = bodies.handles[ib];
    contact.timeOfImpact = TimeOfImpact(A, B, m_moveV[ia], m_moveV[ib], contact.manifold, dt);
    if (OneImmovable(m_bodyFlags[i], m_bodyFlags[j])) {
      st.immovable.push_back(static_cast<std::uint32_t>(st.contacts.size()));
    }
    st.contacts.push_back(contact);
    st.contactMemory.push_back(st.inPlace + st.manifolds.size() > remembered ? static_cast<std::uint32_t>(remembered) : kNoMemory);
  }
}

void RPairSweep::ChildContacts(const RStepBodies& bodies, const RNarrowPair& p, RScalar dt, RSweepTask& st) const {
  const RBodyCore& a = bodies[p.i];
  const RBodyCore& b = bodies[p.j];
  const RBodyCore& A = bodies[p.ia];
  const RBodyCore& B = bodies[p.ib];
  // A compound touches child by child: one contact per touching child pair, each with
  // its own normal (its manifolds are not kept between steps).
  bool woken = false;
  ForEachChildManifold(p.shapeA, p.shapeB, p.X, p.margin.metres, [&](const RContactManifold& m) {
    if (woken) return;
    if ((a.m_sleeping || b.m_sleeping) && a.m_responds && b.m_responds) {
      st.wake.push_back((a.m_sleeping ? a : b).m_sleepIsland);
      woken = true;
      return;
    }
    RContact child;
    child.manifold = m;
    RCollisionSolver::ToWorld(Body(A), child.manifold);
    child.a = static_cast<std::uint32_t>(p.ia), child.b = static_cast<std::uint32_t>(p.ib);
    child.handleA = bodies.handles[p.ia], child.handleB = bodies.handles[p.ib];
    child.timeOfImpact = TimeOfImpact(A, B, m_moveV[p.ia], m_moveV[p.ib], child.manifold, dt);
    if (OneImmovable(m_bodyFlags[p.i], m_bodyFlags[p.j])) {
      st.immovable.push_back(static_cast<std::uint32_t>(st.contacts.size()));
    }
    st.contacts.push_back(child);
    st.contactMemory.push_back(kNoMemory);
  });
}

const RManifoldMemory* RPairSweep::KeptManifold(const RStepBodies& bodies, const RNarrowPair& p,
                                                RMemoryCursor& cursor, std::size_t& unread) const {
  std::size_t& memory = cursor.memory;
  const std::size_t memoryEnd = cursor.memoryEnd;
  while (memory < memoryEnd && Before(m_manifolds[memory], p.pair)) ++memory;
  // Last step's entries are read in order but 720 bytes apart, past the stream
  // prefetch's page: the one two ahead is asked for (a resting pile reads one a pair).
  if (memory + 2 < memoryEnd) PrefetchBytes(&m_manifolds[memory + 2], sizeof(RManifoldMemory));
  unread = memory;
  if (!(memory < memoryEnd && m_manifolds[memory].i == p.i && m_manifolds[memory].j == p.j)) return nullptr;
  unread = memory + 1;
  const RManifoldMemory& mem = m_manifolds[memory];
  const RBodyCore& A = bodies[p.ia];
  const RBodyCore& B = bodies[p.ib];
  // How far any point of B has moved in A's frame since then, and the margin the
  // narrow phase would use now (CheckCollisionInA's): the same points are kept while
  // every kept one stays within it and every dropped one beyond it.
  const RScalar size = A.m_boundingRadius + B.m_boundingRadius;
  const RScalar moved = (p.X.t_AB - mem.X.t_AB).norm() + (p.X.R_AB - mem.X.R_AB).norm() * size;
  const RScalar within = p.margin.metres + RCollisionSolver::kTouchingTolerance * size;
  if (mem.handleA == bodies.handles[p.ia] && mem.handleB == bodies.handles[p.ib] &&
      mem.serialA == A.m_serial.value && mem.serialB == B.m_serial.value &&
      moved <= RCollisionSolver::kTouchingTolerance * size && mem.keptMax + moved <= within &&
      mem.droppedMin - moved > within) {
    return &mem;
  }
  return nullptr;
}

bool RPairSweep::NewManifold(const RStepBodies& bodies, const RNarrowPair& p, bool reuse, std::size_t unread,
                             RContactManifold& manifold, RSweepTask& st, RMemoryCursor& cursor) {
  RScalar droppedMin = 0;
  const bool touching = RCollisionSolver::CheckCollisionInA(p.shapeA, p.shapeB, p.X, p.margin, manifold, &droppedMin);
  RScalar keptMax = manifold.query.separation;
  if (touching && reuse && manifold.pointCount > 0) {
    for (int q = 0; q < manifold.pointCount; ++q) {
      keptMax = std::max(keptMax, manifold.points[q].separation);
    }
  }
  if (touching && reuse && manifold.pointCount > 0 && std::isfinite(keptMax)) {
    const RBodyCore& A = bodies[p.ia];
    const RBodyCore& B = bodies[p.ib];
    RManifoldMemory& mem = *Remember(st, cursor, unread);
    mem.i = static_cast<std::uint32_t>(p.i), mem.j = static_cast<std::uint32_t>(p.j);
    mem.handleA = bodies.handles[p.ia], mem.handleB = bodies.handles[p.ib];
    mem.serialA = A.m_serial.value, mem.serialB = B.m_serial.value;
    mem.X = p.X;
    mem.manifold_A = manifold;
    mem.keptMax = keptMax;
    mem.droppedMin = droppedMin;
    mem.hasInverse = false;
    mem.K.setZero(), mem.pinv.setZero();
  }
  return touching;
}

RManifoldMemory* RPairSweep::Remember(RSweepTask& st, RMemoryCursor& cursor, std::size_t unread) {
  if (cursor.inPlace && st.manifoldsFrom + st.inPlace < unread) return &m_manifolds[st.manifoldsFrom + st.inPlace++];
  cursor.inPlace = false;
  return &st.manifolds.emplace_back();
}

}  // namespace REngine
