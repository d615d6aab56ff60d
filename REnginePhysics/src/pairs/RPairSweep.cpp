// The pair sweep (RPairSweep::DetectPairs): every pair, bounding spheres and boxes grown by
// the step's motion (SweepMotion; stage 1: AllPairs here, TreePairs in RBroadPhase.cpp), the
// filters, then CheckCollision (stage 2, RPairNarrow.cpp), the tasks' results joined
// (JoinSweep); see RIntegrator.h.
#include "pairs/RPairSweep.h"

#include "shape/RCompound.h"
#include "world/RStepBodies.h"

#include "solver/RSolverRows.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace solver;


// Stage 1 of the pair sweep without the broad phase: the all-pairs loop, the reference.
// Each task takes a contiguous range of i and lists its pairs; the lists, joined in task
// order, are the loop's order whatever the number of tasks or threads.
void RPairSweep::AllPairs(const RStepBodies& bodies, RScalar grow, const RStepInputs& in) {
  const std::size_t n = bodies.size();
  const bool bounds = in.settings.shortcuts.boundsRejection;
  const RScalar kGrow = grow;
  const std::size_t used = ParallelRanges(in.jobs, n, in.tasks, 64, [&](std::size_t i0, std::size_t i1, std::size_t task) {
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

// The sweep's set-up pass: each body's centre, the motion it will have this step (moveV,
// moveW) and its reach (its bounding sphere grown by that motion and the allowance), its
// flags, and its broad-phase box when the tree may be used.
void RPairSweep::SweepMotion(const RStepBodies& bodies, RScalar dt, RScalar allowance, bool sweepBoxes,
                             const RStepInputs& in, RBroadPhase& broad) {
  const std::size_t n = bodies.size();
  const RWorldSettings& settings = in.settings;
  const RWorldSettings::RShortcuts& shortcuts = settings.shortcuts;
  const RScalar halfDt = RScalar(0.5) * dt;
  ParallelRanges(in.jobs, n, in.tasks, 128, [&](std::size_t i0, std::size_t i1, std::size_t) {
    for (std::size_t i = i0; i < i1; ++i) {
      if (i + 6 < i1) PrefetchBody(bodies[i + 6], 7 * 64);  // flags, state, accumulators, masks, box
      RBodyCore& b = bodies[i];
      const RScalar r = b.m_boundingRadius;
      m_cx[i] = b.m_x_W.x(), m_cy[i] = b.m_x_W.y(), m_cz[i] = b.m_x_W.z();
      if (b.m_sleeping) {
        // Reach and margin as if it were awake and resting (half a step of gravity), so
        // that the margin between a sleeper and a resting neighbour is the one two awake
        // bodies have: a neighbour beyond it while both were awake does not wake it.
        m_moveV[i] = RMotion::Gravity(b, settings.gravity_W) * halfDt, m_moveW[i] = 0;
      } else if (b.m_isStatic) {
        m_moveV[i].setZero(), m_moveW[i] = 0;
        // Without the shortcut a static body's world form is recomputed every step, as a
        // moving body's is.
        if (!shortcuts.staticForms) b.m_worldForm.stamp = 0;
      } else if (b.m_isKinematic) {
        m_moveV[i] = b.m_v_W, m_moveW[i] = b.m_w_W.norm();
      } else if (b.m_angularLocked || b.m_angularDamping != 0) {
        m_moveV[i] = RMotion::MidStepVelocity(b, settings.gravity_W, halfDt);
        const RMat3 R = b.m_q_WB.toRotationMatrix();
        m_moveW[i] = RMotion::MidStepSpin_W(b, R, RMotion::InvInertia_W(b, R), halfDt).norm();
      } else {
        m_moveV[i] = RMotion::MidStepVelocity(b, settings.gravity_W, halfDt);
        // Most bodies have no angular kick (debris): turning a zero into the body frame
        // and adding it would give w_B to the bit.
        const RVec3 kick_W = RMotion::StartAngularKick_W(b, halfDt);
        m_moveW[i] = kick_W.isZero(0) ? b.m_w_B.norm()
                                      : (b.m_w_B + b.m_invI_B.cwiseProduct(b.m_q_WB.conjugate() * kick_W)).norm();
      }
      m_reach[i] = r + (m_moveV[i].norm() + m_moveW[i] * r) * dt + allowance;
      m_passive[i] = Passive(b);
      m_bodyFlags[i] = static_cast<std::uint8_t>((b.Immovable() ? kFlagImmovable : 0) | (b.m_responds ? kFlagResponds : 0));
      if (sweepBoxes) broad.MakeSweepBox(i, b, m_cx[i], m_cy[i], m_cz[i], m_reach[i]);
    }
  });
}

// The tasks' contacts, wake marks, counts, manifold memory and contact memory joined in task
// order (the pairs' order). Returns whether a sleeping island was touched.
bool RPairSweep::JoinSweep(std::size_t pairTasks, const RStepInputs& in, RSleeping& sleep) {
  bool woke = false;
  // The tasks' contacts joined in task order: with one task its list is swapped in; with
  // several each task copies its own to its place (a contact is about 400 bytes).
  if (pairTasks == 0) {
    m_contacts.clear();
  } else if (pairTasks == 1) {
    std::swap(m_contacts, m_sweepTasks[0].contacts);
    m_sweepTasks[0].contactsAt = 0;
  } else {
    std::size_t total = 0;
    for (std::size_t t = 0; t < pairTasks; ++t) m_sweepTasks[t].contactsAt = total, total += m_sweepTasks[t].contacts.size();
    m_contacts.resize(total);
    ParallelRanges(in.jobs, pairTasks, pairTasks, 1, [&](std::size_t t0, std::size_t t1, std::size_t) {
      for (std::size_t t = t0; t < t1; ++t) {
        const RSweepTask& st = m_sweepTasks[t];
        std::copy(st.contacts.begin(), st.contacts.end(), m_contacts.begin() + static_cast<std::ptrdiff_t>(st.contactsAt));
      }
    });
  }
  for (std::size_t t = 0; t < pairTasks; ++t) {
    RSweepTask& st = m_sweepTasks[t];
    for (std::uint32_t island : st.wake) sleep.Mark(island), woke = true;
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
    ParallelRanges(in.jobs, pairTasks, pairTasks, 1, [&](std::size_t t0, std::size_t t1, std::size_t) {
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
    ParallelRanges(in.jobs, pairTasks, pairTasks, 1, [&](std::size_t t0, std::size_t t1, std::size_t) {
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
  return woke;
}

bool RPairSweep::DetectPairs(const RStepBodies& bodies, RScalar dt, const RStepInputs& in, RBroadPhase& broad,
                             RSleeping& sleep) {
  // (m_contacts is replaced at the end of the sweep: not cleared here, so that joining
  // several tasks' contacts resizes it without constructing 4 MB of contacts again.)
  m_pairStats = RPairStats{};
  const std::size_t n = bodies.size();
  const RWorldSettings& settings = in.settings;
  const RWorldSettings::RShortcuts& shortcuts = settings.shortcuts;
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
  const RScalar gravity = settings.gravity_W.norm();
  const RScalar allowance =
      gravity * (gravity != 0 ? RMotion::GravitySpread(bodies) : 1) * dt * dt + settings.penetrationSlop;
  m_cx.resize(n), m_cy.resize(n), m_cz.resize(n), m_reach.resize(n);
  m_moveV.resize(n), m_moveW.resize(n);
  m_passive.resize(n), m_bodyFlags.resize(n);
  // The broad phase's boxes (SweepBox) are made here too, while the body's lines are in
  // the cache: a pass of their own waited for every body again (30000 bodies: 2 ms a
  // step). A world small enough for the all-pairs loop makes them unread, for little.
  const bool sweepBoxes = shortcuts.boundsRejection && shortcuts.broadPhase;
  if (sweepBoxes) broad.ResizeSweepBoxes(n);
  SweepMotion(bodies, dt, allowance, sweepBoxes, in, broad);
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
  const double listed = broad.ListValid() ? static_cast<double>(broad.ListedPairs()) : 4.0 * static_cast<double>(m_lastPairCount);
  const double treeWork = (64.0 * static_cast<double>(n) + 8.0 * listed) * (broad.ListValid() ? 0.5 : 1.0);
  const bool tree = bounds && shortcuts.broadPhase && (shortcuts.broadPhaseAlways || loopWork > treeWork);
  m_pairStats.broadPhase = tree;

  // Stage 1: the pairs whose grown spheres touch, in (i, then j) order.
  const std::size_t tasks = in.tasks;
  if (m_sweepTasks.size() < tasks) m_sweepTasks.resize(tasks);
  if (tree) {
    const RBroadPhase::RSweep sweep{m_cx, m_cy, m_cz, m_reach, m_passive, in.jobs, in.tasks};
    broad.UpdateBroadPhase(bodies, sweep, m_sweepTasks);
    broad.TreePairs(kGrow, sweep, m_sweepTasks, m_pairs, m_pairStats);
  } else {
    broad.Invalidate();  // the list is not kept up to date by the loop
    AllPairs(bodies, kGrow, in);
  }

  m_lastPairCount = m_pairs.size();

  // The world forms those pairs read, each computed once: on several threads they are
  // computed here, before the pairs are shared out, since a lazily computed form would be
  // written by whichever threads asked at once.
  if (in.jobs && RangeCount(m_pairs.size(), tasks, kSweepPairGrain) > 1) {
    m_formNeeded.assign(n, 0);
    for (const auto& [i, j] : m_pairs) m_formNeeded[i] = m_formNeeded[j] = 1;
    ParallelRanges(in.jobs, n, tasks, 512, [&](std::size_t i0, std::size_t i1, std::size_t) {
      for (std::size_t i = i0; i < i1; ++i) {
        if (m_formNeeded[i]) Body(bodies[i]).WorldForm(in.cacheStamp);
      }
    });
  }

  const std::size_t pairTasks = NarrowPairs(bodies, dt, allowance, kGrow, in);
  const bool woke = JoinSweep(pairTasks, in, sleep);
  // (A sweep that woke islands runs again: its contacts are not the step's.)
  if (!woke) CoveredFeatures(bodies, dt, allowance, pairTasks, in);
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
