// Stage 2 of the pair sweep (RWorldStep::NarrowPairs, called by DetectPairs in
// RPairSweep.cpp): each pair the spheres found, through the bounding boxes, the filters
// and the narrow phase, or last step's manifold kept.
#include "shape/RCompound.h"
#include "world/RWorldStep.h"

#include "solver/RSolverRows.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace solver;

namespace {

// When within the step the manifold's deepest point closes, moving with the bodies' step
// velocities: 0 when it is closed already, infinity when it does not close this step.
RScalar TimeOfImpact(const RBodyCore& a, const RBodyCore& b, const RVec3& va, const RVec3& vb,
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

}  // namespace

// Stage 2 of the pair sweep: each pair through the bounding boxes, the filters and the
// narrow phase (CheckCollision, or last step's manifold kept), on the tasks' contiguous
// ranges of the pairs. Returns the number of tasks (their results in m_sweepTasks).
std::size_t RWorldStep::NarrowPairs(const RStepBodies& bodies, RScalar dt, RScalar allowance, RScalar kGrow) {
  const RWorldSettings::RShortcuts& shortcuts = m_settings.shortcuts;
  const bool bounds = shortcuts.boundsRejection;
  const std::size_t tasks = m_tasks;
  constexpr std::size_t kPairAhead = 8, kPairLines = 10 * 64;  // see the loop below
  // Tasks take contiguous ranges of the pairs; their contacts, joined in task order, keep
  // the pairs' order.
  const bool reuse = shortcuts.contactReuse;
  auto before = [](const RManifoldMemory& mem, const std::pair<std::uint32_t, std::uint32_t>& p) {
    return mem.i < p.first || (mem.i == p.first && mem.j < p.second);
  };
  // Each range's part of last step's memory (both lists in (i, j) order): from the first
  // entry not before its first pair up to the next range's. A task reads and writes only
  // its own part (see remember below). The ranges are ParallelRanges'.
  const std::size_t ranges = m_pairs.empty() ? 0 : m_jobs ? RangeCount(m_pairs.size(), tasks, kSweepPairGrain) : 1;
  m_memoryFrom.assign(ranges + 1, m_manifolds.size());
  for (std::size_t t = 0; reuse && t < ranges; ++t) {
    m_memoryFrom[t] = static_cast<std::size_t>(
        std::lower_bound(m_manifolds.begin(), m_manifolds.end(), m_pairs[m_pairs.size() * t / ranges], before) -
        m_manifolds.begin());
  }
  return ParallelRanges(m_jobs, m_pairs.size(), tasks, kSweepPairGrain, [&](std::size_t k0, std::size_t k1, std::size_t task) {
    RSweepTask& st = m_sweepTasks[task];
    st.contacts.clear(), st.wake.clear(), st.manifolds.clear(), st.contactMemory.clear();
    st.rejectedFilter = st.rejectedBoxes = st.narrowPhase = st.reused = 0;
    // Last step's manifolds from this range's first pair on.
    std::size_t memory = m_memoryFrom[task];
    const std::size_t memoryEnd = m_memoryFrom[task + 1];
    // This step's memory is written over last step's in place, from the range's first entry
    // (st.manifoldsFrom) on, while it stays behind the entries still to be read: a settled
    // pile's memory is then written where it already is, and a kept entry (720 bytes) is not
    // copied at all. The tasks' ranges of last step's entries do not overlap, so a task
    // writes only entries no other task reads. Past the first entry that would overwrite
    // one still to be read, the rest go to st.manifolds (joined after the sweep).
    st.manifoldsFrom = memory;
    st.inPlace = 0;
    bool inPlace = reuse;
    // Where this task's next entry goes (the count so far: in place, then st.manifolds).
    auto remember = [&](std::size_t unread) -> RManifoldMemory* {
      if (inPlace && st.manifoldsFrom + st.inPlace < unread) return &m_manifolds[st.manifoldsFrom + st.inPlace++];
      inPlace = false;
      return &st.manifolds.emplace_back();
    };
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
      const RBodyCore& a = bodies[i];
      const RBodyCore& b = bodies[j];
      // Bounding boxes from the stamped world forms, grown the same way: they reject the
      // many pairs whose spheres overlap only because a body is long or flat (the ground).
      // They come before the filters, as a broad phase's proof that a pair is apart does:
      // the broad phase's trees hold these boxes too (SweepBox), and the game's filter
      // sees the same pairs with them or without.
      const RWorldForm& fa = Body(a).WorldForm(m_cacheStamp);
      const RWorldForm& fb = Body(b).WorldForm(m_cacheStamp);
      const RScalar grow = (m_reach[i] - fa.sphereRadius + m_reach[j] - fb.sphereRadius) * kGrow;
      if (bounds && (((fa.aabbMin_W.array() - grow) > fb.aabbMax_W.array()).any() ||
                     ((fb.aabbMin_W.array() - grow) > fa.aabbMax_W.array()).any())) {
        ++st.rejectedBoxes;
        continue;
      }
      // Two bodies that nothing moves (static, kinematic) need no response: a kinematic
      // body is tested against another or against static geometry only when one of them
      // does not respond (a kinematic sensor reports what it sweeps through).
      if ((a.m_isStatic && b.m_isStatic) ||
          (a.Immovable() && b.Immovable() && a.m_responds && b.m_responds) ||
          !Body(a).ShouldCheckCollision(Body(b)) || (a.m_jointNoCollide && b.m_jointNoCollide && bodies.JointedNoCollide(i, j)) ||
          (m_filter && !m_filter(Body(a), Body(b), m_filterUser))) {
        ++st.rejectedFilter;
        continue;
      }
      ++st.narrowPhase;
      RContact contact;
      const RScalar approach = (m_moveV[j] - m_moveV[i]).norm() +
                               m_moveW[i] * a.m_boundingRadius + m_moveW[j] * b.m_boundingRadius;
      // The pair in slot order, whatever the bodies' places in storage: its manifold, normal
      // and feature ids, and so its warm start, do not change when a removal moves a body.
      const bool flip = bodies.Slot(j) < bodies.Slot(i);
      const std::size_t ia = flip ? j : i, ib = flip ? i : j;
      const RBodyCore& A = bodies[ia];
      const RBodyCore& B = bodies[ib];
      const RConvexShape shapeA = ShapeOf(Body(A)), shapeB = ShapeOf(Body(B));
      const RRelativePose X = RelativePose(Body(A), Body(B));
      const RMargin margin{approach * dt + allowance};
      if (HasParts(shapeA) || HasParts(shapeB)) {
        // A compound touches child by child: one contact per touching child pair, each with
        // its own normal (its manifolds are not kept between steps).
        bool woken = false;
        ForEachChildManifold(shapeA, shapeB, X, margin.metres, [&](const RContactManifold& m) {
          if (woken) return;
          if ((a.m_sleeping || b.m_sleeping) && a.m_responds && b.m_responds) {
            st.wake.push_back((a.m_sleeping ? a : b).m_sleepIsland);
            woken = true;
            return;
          }
          RContact child;
          child.manifold = m;
          RCollisionSolver::ToWorld(Body(A), child.manifold);
          child.a = static_cast<std::uint32_t>(ia), child.b = static_cast<std::uint32_t>(ib);
          child.handleA = bodies.handles[ia], child.handleB = bodies.handles[ib];
          child.timeOfImpact = TimeOfImpact(A, B, m_moveV[ia], m_moveV[ib], child.manifold, dt);
          st.contacts.push_back(child);
          st.contactMemory.push_back(kNoMemory);
        });
        continue;
      }
      bool touching = false;
      while (memory < memoryEnd && before(m_manifolds[memory], m_pairs[k])) ++memory;
      // Last step's entries are read in order but 720 bytes apart, past the stream
      // prefetch's page: the one two ahead is asked for (a resting pile reads one a pair).
      if (memory + 2 < memoryEnd) PrefetchBytes(&m_manifolds[memory + 2], sizeof(RManifoldMemory));
      const RManifoldMemory* kept = nullptr;
      const std::size_t remembered = st.inPlace + st.manifolds.size();
      // Last step's entries from `unread` on are still to be read (this pair's is read here).
      std::size_t unread = memory;
      if (memory < memoryEnd && m_manifolds[memory].i == i && m_manifolds[memory].j == j) {
        unread = memory + 1;
        const RManifoldMemory& mem = m_manifolds[memory];
        // How far any point of B has moved in A's frame since then, and the margin the
        // narrow phase would use now (CheckCollisionInA's): the same points are kept while
        // every kept one stays within it and every dropped one beyond it.
        const RScalar size = A.m_boundingRadius + B.m_boundingRadius;
        const RScalar moved = (X.t_AB - mem.X.t_AB).norm() + (X.R_AB - mem.X.R_AB).norm() * size;
        const RScalar within = margin.metres + RCollisionSolver::kTouchingTolerance * size;
        if (mem.handleA == bodies.handles[ia] && mem.handleB == bodies.handles[ib] &&
            mem.serialA == A.m_serial.value && mem.serialB == B.m_serial.value &&
            moved <= RCollisionSolver::kTouchingTolerance * size && mem.keptMax + moved <= within &&
            mem.droppedMin - moved > within) {
          kept = &mem;
        }
      }
      if (kept) {
        contact.manifold = kept->manifold_A;
        RManifoldMemory* to = remember(unread);
        if (to != kept) *to = *kept;
        ++st.reused;
        touching = true;
      } else {
        RScalar droppedMin = 0;
        touching = RCollisionSolver::CheckCollisionInA(shapeA, shapeB, X, margin, contact.manifold, &droppedMin);
        RScalar keptMax = contact.manifold.query.separation;
        if (touching && reuse && contact.manifold.pointCount > 0) {
          for (int p = 0; p < contact.manifold.pointCount; ++p) {
            keptMax = std::max(keptMax, contact.manifold.points[p].separation);
          }
        }
        if (touching && reuse && contact.manifold.pointCount > 0 && std::isfinite(keptMax)) {
          RManifoldMemory& mem = *remember(unread);
          mem.i = static_cast<std::uint32_t>(i), mem.j = static_cast<std::uint32_t>(j);
          mem.handleA = bodies.handles[ia], mem.handleB = bodies.handles[ib];
          mem.serialA = A.m_serial.value, mem.serialB = B.m_serial.value;
          mem.X = X;
          mem.manifold_A = contact.manifold;
          mem.keptMax = keptMax;
          mem.droppedMin = droppedMin;
          mem.hasInverse = false;
          mem.K.setZero(), mem.pinv.setZero();
        }
      }
      if (touching) RCollisionSolver::ToWorld(Body(A), contact.manifold);
      if (touching) {
        // A sleeping body touched by one that responds wakes, with its island. A sensor
        // or a laser (does not respond) is reported against it without waking it.
        if ((a.m_sleeping || b.m_sleeping) && a.m_responds && b.m_responds) {
          st.wake.push_back((a.m_sleeping ? a : b).m_sleepIsland);
          continue;
        }
        contact.a = static_cast<std::uint32_t>(ia);
        contact.b = static_cast<std::uint32_t>(ib);
        contact.handleA = bodies.handles[ia], contact.handleB = bodies.handles[ib];
        contact.timeOfImpact = TimeOfImpact(A, B, m_moveV[ia], m_moveV[ib], contact.manifold, dt);
        st.contacts.push_back(contact);
        st.contactMemory.push_back(st.inPlace + st.manifolds.size() > remembered ? static_cast<std::uint32_t>(remembered) : kNoMemory);
      }
    }
  });
}

}  // namespace REngine
