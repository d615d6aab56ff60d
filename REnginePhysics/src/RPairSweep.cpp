// The pair sweep (RWorldStep::DetectPairs): every pair, bounding spheres and boxes grown by
// the step's motion, the filters, then CheckCollision; see RIntegrator.h.
#include "RCompound.h"
#include "RWorldStep.h"

#include "RSolverRows.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace solver;

namespace {

// When within the step the manifold's deepest point closes, moving with the bodies' step
// velocities: 0 when it is closed already, infinity when it does not close this step.
RScalar TimeOfImpact(const RRigidBody& a, const RRigidBody& b, const RVec3& va, const RVec3& vb,
                     const RContactManifold& m, RScalar dt) {
  if (m.pointCount == 0) return m.query.separation <= 0 ? 0 : std::numeric_limits<RScalar>::infinity();
  int deepest = 0;
  for (int k = 1; k < m.pointCount; ++k) {
    if (m.points[k].separation < m.points[deepest].separation) deepest = k;
  }
  const RScalar gap = m.points[deepest].separation;
  if (gap <= 0) return 0;
  const RVec3& p = m.points[deepest].position;
  const RVec3 wa = a.IsStatic() ? RVec3::Zero() : a.AngularVelocity_W();
  const RVec3 wb = b.IsStatic() ? RVec3::Zero() : b.AngularVelocity_W();
  const RScalar vn = m.normal.dot(vb + wb.cross(p - b.Position_W()) - va -
                                        wa.cross(p - a.Position_W()));
  if (vn < 0 && gap <= -vn * dt) return gap / -vn;
  return std::numeric_limits<RScalar>::infinity();
}

}  // namespace

// Stage 1 of the pair sweep without the broad phase: the all-pairs loop, the reference.
// Each task takes a contiguous range of i and lists its pairs; the lists, joined in task
// order, are the loop's order whatever the number of tasks or threads.
void RWorldStep::AllPairs(const RStepBodies& bodies, RScalar grow) {
  const std::size_t n = bodies.size();
  const bool bounds = m_settings.shortcuts.boundsRejection;
  const RScalar kGrow = grow;
  const std::size_t used = ParallelRanges(m_jobs, n, m_tasks, 64, [&](std::size_t i0, std::size_t i1, std::size_t task) {
    RSweepTask& st = m_sweepTasks[task];
    st.pairs.clear();
    st.sphereTests = 0;
    st.near.resize(n), st.candidates.resize(n);
    // The first entry of m_active above i.
    std::size_t nextActive = static_cast<std::size_t>(
        std::lower_bound(m_active.begin(), m_active.end(), static_cast<std::uint32_t>(i0)) -
        m_active.begin());
    for (std::size_t i = i0; i < i1; ++i) {
      const RScalar xi = m_cx[i], yi = m_cy[i], zi = m_cz[i], ri = m_reach[i];
      while (nextActive < m_active.size() && m_active[nextActive] <= i) ++nextActive;
      const bool passiveA = Passive(bodies[i]);
      // The candidates j > i: every later body, or, for a passive body, the later awake
      // ones. First the bounding-sphere test for all of them: lim^2 - d^2, >= 0 when the
      // grown spheres touch, in a branch-free loop over contiguous arrays that the compiler vectorises
      // (the contiguous case; a list of candidates is a gather); then the pairs that passed,
      // in index order. A body with a non-finite position passes no test: UpdateObjects
      // never leaves one so, but game code could set it.
      const std::uint32_t* js = nullptr;  // the candidates, when they are not i + 1 + k
      std::size_t count = 0;
      if (passiveA) {
        js = m_active.data() + nextActive, count = m_active.size() - nextActive;
      } else {
        count = n - i - 1;
      }
      st.sphereTests += count;
      RScalar* near = st.near.data();
      if (!bounds) {
        std::fill(near, near + count, RScalar(0));
      } else if (!js) {
        const RScalar* cx = m_cx.data() + i + 1;
        const RScalar* cy = m_cy.data() + i + 1;
        const RScalar* cz = m_cz.data() + i + 1;
        const RScalar* reach = m_reach.data() + i + 1;
        for (std::size_t k = 0; k < count; ++k) {
          const RScalar dx = cx[k] - xi, dy = cy[k] - yi, dz = cz[k] - zi;
          const RScalar lim = (ri + reach[k]) * kGrow;
          near[k] = lim * lim - (dx * dx + dy * dy + dz * dz);
        }
      } else {
        for (std::size_t k = 0; k < count; ++k) {
          const std::size_t j = js[k];
          const RScalar dx = m_cx[j] - xi, dy = m_cy[j] - yi, dz = m_cz[j] - zi;
          const RScalar lim = (ri + m_reach[j]) * kGrow;
          near[k] = lim * lim - (dx * dx + dy * dy + dz * dz);
        }
      }
      // The few that passed, compacted by a tight loop of its own (kept apart from the
      // pair work, whose register pressure would otherwise put this counter in memory).
      std::uint32_t* candidates = st.candidates.data();
      std::size_t found = 0;
      for (std::size_t k = 0; k < count; ++k) {
        candidates[found] = static_cast<std::uint32_t>(k);
        found += near[k] >= 0;
      }
      for (std::size_t c = 0; c < found; ++c) {
        const std::size_t k = candidates[c];
        const std::size_t j = js ? js[k] : i + 1 + k;
        st.pairs.emplace_back(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j));
      }
    }
  });
  m_pairs.clear();
  for (std::size_t t = 0; t < used; ++t) {
    // One task: its list is the list (swapped, not copied; both keep their capacity).
    if (used == 1) {
      std::swap(m_pairs, m_sweepTasks[t].pairs);
    } else {
      m_pairs.insert(m_pairs.end(), m_sweepTasks[t].pairs.begin(), m_sweepTasks[t].pairs.end());
    }
    m_pairStats.sphereTests += m_sweepTasks[t].sphereTests;
  }
}

bool RWorldStep::DetectPairs(const RStepBodies& bodies, RScalar dt) {
  // (m_contacts is replaced at the end of the sweep: not cleared here, so that joining
  // several tasks' contacts resizes it without constructing 4 MB of contacts again.)
  m_pairStats = RPairStats{};
  const std::size_t n = bodies.size();
  const RWorldSettings::RShortcuts& shortcuts = m_settings.shortcuts;
  // Bounding spheres about the centres of mass, each grown by how far its surface can
  // move within the step (speed plus the farthest point's rotation, times dt): a pair
  // whose grown spheres are apart cannot touch before the next step. Stored as separate
  // arrays so the sweep below is a tight loop over contiguous doubles; the arrays keep
  // their capacity between steps.
  // The velocities are those the body will move with this step: a missile given its
  // launch impulse this step is as fast as one that has flown for a while.
  // Every pair is also looked at within a fixed allowance: two bodies that rest on each
  // other have no relative velocity at the start of a step, yet the lower one is held and
  // the upper one is not, so they close by up to g dt^2 within the step; and a contact
  // that overlaps by less than the slop must not flicker out when it floats up by a
  // rounding error. A contact found early is harmless: its row pushes only if needed.
  // With gravity scales, two bodies separate by at most |g| (max s - min s) dt^2 (a static
  // body's s being 0): GravitySpread is 1 when every scale is 1, and the product unchanged.
  const RScalar gravity = m_settings.gravity_W.norm();
  const RScalar allowance = gravity * (gravity != 0 ? GravitySpread(bodies) : 1) * dt * dt + m_settings.penetrationSlop;
  m_cx.resize(n), m_cy.resize(n), m_cz.resize(n), m_reach.resize(n);
  m_moveV.resize(n), m_moveW.resize(n);
  m_passive.resize(n), m_bodyFlags.resize(n);
  // The broad phase's boxes (SweepBox) are made here too, while the body's lines are in
  // the cache: a pass of their own waited for every body again (30000 bodies: 2 ms a
  // step). A world small enough for the all-pairs loop makes them unread, for little.
  const bool sweepBoxes = shortcuts.boundsRejection && shortcuts.broadPhase;
  if (sweepBoxes) m_sweepBoxes.resize(n);
  const RScalar halfDt = RScalar(0.5) * dt;
  ParallelRanges(m_jobs, n, m_tasks, 512, [&](std::size_t i0, std::size_t i1, std::size_t) {
    for (std::size_t i = i0; i < i1; ++i) {
      if (i + 6 < i1) PrefetchBody(bodies[i + 6], 7 * 64);  // flags, state, accumulators, masks, box
      RRigidBody& b = bodies[i];
      const RScalar r = b.BoundingRadius();
      m_cx[i] = b.m_x_W.x(), m_cy[i] = b.m_x_W.y(), m_cz[i] = b.m_x_W.z();
      if (b.m_sleeping) {
        // Reach and margin as if it were awake and resting (half a step of gravity), so
        // that the margin between a sleeper and a resting neighbour is the one two awake
        // bodies have: a neighbour beyond it while both were awake does not wake it.
        m_moveV[i] = Gravity(b, m_settings.gravity_W) * halfDt, m_moveW[i] = 0;
      } else if (b.m_isStatic) {
        m_moveV[i].setZero(), m_moveW[i] = 0;
        // Without the shortcut a static body's world form is recomputed every step, as a
        // moving body's is.
        if (!shortcuts.staticForms) b.m_worldForm.stamp = 0;
      } else if (b.m_isKinematic) {
        m_moveV[i] = b.m_v_W, m_moveW[i] = b.m_w_W.norm();
      } else if (b.m_angularLocked || b.m_angularDamping != 0) {
        m_moveV[i] = MidStepVelocity(b, m_settings.gravity_W, halfDt);
        const RMat3 R = b.m_q_WB.toRotationMatrix();
        m_moveW[i] = MidStepSpin_W(b, R, InvInertia_W(b, R), halfDt).norm();
      } else {
        m_moveV[i] = MidStepVelocity(b, m_settings.gravity_W, halfDt);
        // Most bodies have no angular kick (debris): turning a zero into the body frame
        // and adding it would give w_B to the bit.
        const RVec3 kick_W = StartAngularKick_W(b, halfDt);
        m_moveW[i] = kick_W.isZero(0) ? b.m_w_B.norm()
                                      : (b.m_w_B + b.m_invI_B.cwiseProduct(b.m_q_WB.conjugate() * kick_W)).norm();
      }
      m_reach[i] = r + (m_moveV[i].norm() + m_moveW[i] * r) * dt + allowance;
      m_passive[i] = Passive(b);
      m_bodyFlags[i] = static_cast<std::uint8_t>((b.Immovable() ? kFlagImmovable : 0) | (b.m_responds ? kFlagResponds : 0));
      if (sweepBoxes) m_sweepBoxes[i] = SweepBox(b, i);
    }
  });
  // The bodies that can start a contact (not Passive), in index order. A passive body is only paired with
  // these, so a world that mostly sleeps costs O(n m) for m awake bodies, not O(n^2); and
  // the pairs are still visited in (i, then j) order.
  m_active.clear();
  std::uint64_t passiveCount = 0, staticCount = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (m_passive[i]) {
      ++passiveCount, staticCount += bodies[i].m_isStatic;
    } else {
      m_active.push_back(static_cast<std::uint32_t>(i));
    }
  }
  // The touching band, and a relative allowance for the rounding of the squares.
  constexpr RScalar kGrow = 1 + 1e-9;
  const bool bounds = shortcuts.boundsRejection;
  // The broad phase (RShortcuts::broadPhase, RBroadPhase.cpp): a tree of boxes that hold
  // the same grown spheres and grown world boxes, with a list of the pairs whose boxes are
  // near, kept from step to step; every listed pair whose boxes overlap then takes the same
  // sphere test as in the all-pairs loop, in the same (i, then j) order: the pairs found
  // are exactly the loop's. The broad phase pays where the loop's work (about half a
  // nanosecond a pair, vectorised) is larger than its own (tens of nanoseconds a body and a
  // few a listed pair): beyond a hundred bodies or so. Once in use it stays unless the
  // loop costs half as much (its list would have to be built again). Either way the pairs
  // and the result are the same.
  const double activeCount = static_cast<double>(m_active.size());
  const double loopWork = activeCount * (0.5 * activeCount + static_cast<double>(passiveCount));
  const double listed = m_fatValid ? static_cast<double>(m_fatPairs.size()) : 4.0 * static_cast<double>(m_lastPairCount);
  const double treeWork = (64.0 * static_cast<double>(n) + 8.0 * listed) * (m_fatValid ? 0.5 : 1.0);
  const bool tree = bounds && shortcuts.broadPhase && (shortcuts.broadPhaseAlways || loopWork > treeWork);
  m_pairStats.broadPhase = tree;

  // Stage 1: the pairs whose grown spheres touch, in (i, then j) order.
  const std::size_t tasks = m_tasks;
  if (m_sweepTasks.size() < tasks) m_sweepTasks.resize(tasks);
  if (tree) {
    UpdateBroadPhase(bodies);
    TreePairs(kGrow);
  } else {
    m_fatValid = false;  // the list is not kept up to date by the loop
    AllPairs(bodies, kGrow);
  }

  m_lastPairCount = m_pairs.size();

  // The world forms those pairs read, each computed once: on several threads they are
  // computed here, before the pairs are shared out, since a lazily computed form would be
  // written by whichever threads asked at once.
  constexpr std::size_t kPairGrain = 32;  // pairs per task, at least
  constexpr std::size_t kPairAhead = 8, kPairLines = 10 * 64;  // see stage 2's loop
  if (m_jobs && RangeCount(m_pairs.size(), tasks, kPairGrain) > 1) {
    m_formNeeded.assign(n, 0);
    for (const auto& [i, j] : m_pairs) m_formNeeded[i] = m_formNeeded[j] = 1;
    ParallelRanges(m_jobs, n, tasks, 512, [&](std::size_t i0, std::size_t i1, std::size_t) {
      for (std::size_t i = i0; i < i1; ++i) {
        if (m_formNeeded[i]) bodies[i].WorldForm(m_cacheStamp);
      }
    });
  }

  // Stage 2: each pair through the filters, the bounding boxes and the narrow phase. Tasks
  // take contiguous ranges of the pairs; their contacts, joined in task order, keep the
  // pairs' order.
  const bool reuse = shortcuts.contactReuse;
  auto before = [](const RManifoldMemory& mem, const std::pair<std::uint32_t, std::uint32_t>& p) {
    return mem.i < p.first || (mem.i == p.first && mem.j < p.second);
  };
  // Each range's part of last step's memory (both lists in (i, j) order): from the first
  // entry not before its first pair up to the next range's. A task reads and writes only
  // its own part (see remember below). The ranges are ParallelRanges'.
  const std::size_t ranges = m_pairs.empty() ? 0 : m_jobs ? RangeCount(m_pairs.size(), tasks, kPairGrain) : 1;
  m_memoryFrom.assign(ranges + 1, m_manifolds.size());
  for (std::size_t t = 0; reuse && t < ranges; ++t) {
    m_memoryFrom[t] = static_cast<std::size_t>(
        std::lower_bound(m_manifolds.begin(), m_manifolds.end(), m_pairs[m_pairs.size() * t / ranges], before) -
        m_manifolds.begin());
  }
  const std::size_t pairTasks = ParallelRanges(m_jobs, m_pairs.size(), tasks, kPairGrain, [&](std::size_t k0, std::size_t k1, std::size_t task) {
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
      const RRigidBody& a = bodies[i];
      const RRigidBody& b = bodies[j];
      // Bounding boxes from the stamped world forms, grown the same way: they reject the
      // many pairs whose spheres overlap only because a body is long or flat (the ground).
      // They come before the filters, as a broad phase's proof that a pair is apart does:
      // the broad phase's trees hold these boxes too (SweepBox), and the game's filter
      // sees the same pairs with them or without.
      const RWorldForm& fa = a.WorldForm(m_cacheStamp);
      const RWorldForm& fb = b.WorldForm(m_cacheStamp);
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
          !a.ShouldCheckCollision(b) || (a.m_jointNoCollide && b.m_jointNoCollide && bodies.JointedNoCollide(i, j)) ||
          (m_filter && !m_filter(a, b, m_filterUser))) {
        ++st.rejectedFilter;
        continue;
      }
      ++st.narrowPhase;
      RContact contact;
      const RScalar approach = (m_moveV[j] - m_moveV[i]).norm() +
                               m_moveW[i] * a.BoundingRadius() + m_moveW[j] * b.BoundingRadius();
      // The pair in slot order, whatever the bodies' places in storage: its manifold, normal
      // and feature ids, and so its warm start, do not change when a removal moves a body.
      const bool flip = bodies.Slot(j) < bodies.Slot(i);
      const std::size_t ia = flip ? j : i, ib = flip ? i : j;
      const RRigidBody& A = bodies[ia];
      const RRigidBody& B = bodies[ib];
      const RConvexShape shapeA = ShapeOf(A), shapeB = ShapeOf(B);
      const RRelativePose X = RelativePose(A, B);
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
          RCollisionSolver::ToWorld(A, child.manifold);
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
        const RScalar size = A.BoundingRadius() + B.BoundingRadius();
        const RScalar moved = (X.t_AB - mem.X.t_AB).norm() + (X.R_AB - mem.X.R_AB).norm() * size;
        const RScalar within = margin.metres + RCollisionSolver::kTouchingTolerance * size;
        if (mem.handleA == bodies.handles[ia] && mem.handleB == bodies.handles[ib] &&
            mem.serialA == A.Serial() && mem.serialB == B.Serial() &&
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
          mem.serialA = A.Serial(), mem.serialB = B.Serial();
          mem.X = X;
          mem.manifold_A = contact.manifold;
          mem.keptMax = keptMax;
          mem.droppedMin = droppedMin;
          mem.hasInverse = false;
          mem.K.setZero(), mem.pinv.setZero();
        }
      }
      if (touching) RCollisionSolver::ToWorld(A, contact.manifold);
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
  bool woke = false;
  // The tasks' contacts joined in task order: with one task its list is swapped in; with
  // several each task copies its own to its place (a contact is about 400 bytes).
  if (pairTasks == 0) {
    m_contacts.clear();
  } else if (pairTasks == 1) {
    std::swap(m_contacts, m_sweepTasks[0].contacts);
  } else {
    std::size_t total = 0;
    for (std::size_t t = 0; t < pairTasks; ++t) m_sweepTasks[t].contactsAt = total, total += m_sweepTasks[t].contacts.size();
    m_contacts.resize(total);
    ParallelRanges(m_jobs, pairTasks, pairTasks, 1, [&](std::size_t t0, std::size_t t1, std::size_t) {
      for (std::size_t t = t0; t < t1; ++t) {
        const RSweepTask& st = m_sweepTasks[t];
        std::copy(st.contacts.begin(), st.contacts.end(), m_contacts.begin() + static_cast<std::ptrdiff_t>(st.contactsAt));
      }
    });
  }
  for (std::size_t t = 0; t < pairTasks; ++t) {
    RSweepTask& st = m_sweepTasks[t];
    for (std::uint32_t island : st.wake) m_wakeMark[island] = 1, woke = true;
    m_pairStats.rejectedFilter += st.rejectedFilter;
    m_pairStats.rejectedBoxes += st.rejectedBoxes;
    m_pairStats.narrowPhase += st.narrowPhase;
    m_pairStats.reusedManifolds += st.reused;
  }
  // This step's manifolds, joined in task order: the (i, j) order for the next step; and
  // each contact's entry among them. Each task's are its entries written in place, from
  // manifoldsFrom on, then its st.manifolds. When the tasks' in-place runs follow one
  // another from the list's start and no task has any aside (a settled pile: every step),
  // the list is cut to its new length; otherwise the entries are gathered into a new list.
  std::size_t manifolds = 0, contacts = 0;
  bool contiguous = true;
  for (std::size_t t = 0; t < pairTasks; ++t) {
    RSweepTask& st = m_sweepTasks[t];
    contiguous = contiguous && st.manifoldsFrom == manifolds && st.manifolds.empty();
    st.manifoldsAt = manifolds, manifolds += st.inPlace + st.manifolds.size();
    contacts += st.contactMemory.size();
  }
  if (contiguous) {
    m_manifolds.resize(manifolds);
  } else {
    m_manifoldsGather.resize(manifolds);
    ParallelRanges(m_jobs, pairTasks, pairTasks, 1, [&](std::size_t t0, std::size_t t1, std::size_t) {
      for (std::size_t t = t0; t < t1; ++t) {
        const RSweepTask& st = m_sweepTasks[t];
        const auto from = m_manifolds.begin() + static_cast<std::ptrdiff_t>(st.manifoldsFrom);
        const auto to = m_manifoldsGather.begin() + static_cast<std::ptrdiff_t>(st.manifoldsAt);
        std::copy(from, from + static_cast<std::ptrdiff_t>(st.inPlace), to);
        std::copy(st.manifolds.begin(), st.manifolds.end(), to + static_cast<std::ptrdiff_t>(st.inPlace));
      }
    });
    std::swap(m_manifolds, m_manifoldsGather);
  }
  if (pairTasks <= 1) {
    m_contactMemory.clear();
    if (pairTasks == 1) std::swap(m_contactMemory, m_sweepTasks[0].contactMemory);
  } else {
    m_contactMemory.resize(contacts);
    ParallelRanges(m_jobs, pairTasks, pairTasks, 1, [&](std::size_t t0, std::size_t t1, std::size_t) {
      for (std::size_t t = t0; t < t1; ++t) {
        const RSweepTask& st = m_sweepTasks[t];
        const auto base = static_cast<std::uint32_t>(st.manifoldsAt);
        for (std::size_t k = 0; k < st.contactMemory.size(); ++k) {
          const std::uint32_t m = st.contactMemory[k];
          m_contactMemory[st.contactsAt + k] = m == kNoMemory ? m : base + m;
        }
      }
    });
  }
  // Pairs never visited: two passive static bodies (counted with the filter's), or two
  // passive bodies of which one at least sleeps. (Counts are those of the last sweep when
  // waking islands made it run again.)
  const std::uint64_t staticPairs = staticCount * (staticCount - (staticCount > 0)) / 2;
  m_pairStats.rejectedFilter += staticPairs;
  m_pairStats.rejectedSleeping = passiveCount * (passiveCount - (passiveCount > 0)) / 2 - staticPairs;
  m_pairStats.pairs = n * (n - (n > 0)) / 2;
  m_pairStats.rejectedBounds = m_pairStats.pairs - m_pairStats.rejectedFilter -
                               m_pairStats.rejectedSleeping - m_pairStats.rejectedBoxes -
                               m_pairStats.narrowPhase;
  m_pairStats.contacts = m_contacts.size();
  return woke;
}

}  // namespace REngine
