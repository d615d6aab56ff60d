// Sleeping islands (RWorldSettings::RShortcuts::sleeping): waking before the step, putting to
// sleep after it (RSleeping, sleep/RSleeping.h); see RIntegrator.h.
#include "sleep/RSleeping.h"

#include "pairs/RPairSweep.h"

#include "world/RStepBodies.h"

#include "solver/RSolverRows.h"

#include <algorithm>
#include <limits>

namespace REngine {

using namespace solver;

void RSleeping::WakeIslands(const RStepBodies& bodies, const RWorldSettings& settings) {
  const std::size_t n = bodies.size();
  // Island ids are slots (a plain vector's: indices).
  m_wakeMark.assign(bodies.slotCount, 0);  // keeps its capacity: no allocation once sized
  // A plain vector's bodies are known by index: when bodies were added or removed the ids
  // mean nothing, and a removed body may have held a sleeping stack up. An RBodies reports
  // its departures instead (RBodies::Remove, Disable): only their islands wake.
  // A sleeping body ignores gravity, so a change of gravity wakes everything.
  // Any body not where this integrator left it (see RBodyCore::m_slot) wakes everything:
  // in a plain vector a removal and an addition in one frame keep the count and may still
  // remove a support; a body that was stepped by another integrator brings island ids
  // that mean nothing here (a copy of this integrator's, before its first step, is this
  // world: RWorldId). (A body an RBodies has just added has not been stepped.)
  // Static and kinematic bodies that the game moved, added or removed may hold or have held
  // sleeping bodies (their contacts are not kept while they sleep): the sleepers whose
  // boxes touch where such a body was or is wake, with their islands (below): a moving
  // platform whose pose the game sets wakes what is about it, not the world.
  bool moved = m_wakeAll || (bodies.wakeAll && *bodies.wakeAll);
  m_wakeBoxes.clear();
  if (bodies.wakeBoxes) m_wakeBoxes.swap(*bodies.wakeBoxes), bodies.wakeBoxes->clear();
  for (std::size_t i = 0; i < n && !moved; ++i) {
    RBodyCore& b = bodies[i];
    const bool fresh = !bodies.byIndex && b.m_slotWorld == 0;
    moved = !fresh && (b.m_slot != bodies.Slot(i) || !m_worldId.Owns(b.m_slotWorld));
    if (!b.m_staticMoved) continue;
    RVec3 lo, hi;
    b.WorldBox(lo, hi);
    m_wakeBoxes.push_back(lo), m_wakeBoxes.push_back(hi);
    if (b.m_wakeFromSet) m_wakeBoxes.push_back(b.m_wakeFromMin_W), m_wakeBoxes.push_back(b.m_wakeFromMax_W);
    b.m_wakeFromSet = false;
  }
  // From this step on the bodies carry this integrator's own id (SleepIslands).
  m_worldId.inherited = 0;
  // Past a few hundred edits a frame, a sweep of every box against every sleeper would
  // cost more than the wake it saves.
  constexpr std::size_t kMostWakeBoxes = 256;
  moved = moved || m_wakeBoxes.size() > 2 * kMostWakeBoxes;
  m_wakeAll = false;
  if (bodies.wakeAll) *bodies.wakeAll = false;
  const bool countChanged = bodies.byIndex && n != m_sleepBodyCount;
  if (!settings.shortcuts.sleeping || countChanged || moved || settings.gravity_W != m_sleepGravity_W) {
    m_sleepBodyCount = n;
    m_sleepGravity_W = settings.gravity_W;
    if (bodies.wakeIslands) bodies.wakeIslands->clear();
    for (RBodyCore& b : bodies) {
      if (b.m_sleeping || b.m_sleepIsland != RBodyCore::kNoIsland) {
        b.m_sleeping = false, b.m_restTime = 0, b.m_sleepIsland = RBodyCore::kNoIsland;
      }
    }
    return;
  }
  m_sleepBodyCount = n;
  bool any = false;
  // Islands a removed or disabled body belonged to.
  if (bodies.wakeIslands) {
    for (std::uint32_t island : *bodies.wakeIslands) {
      if (island < m_wakeMark.size()) m_wakeMark[island] = 1, any = true;
    }
    bodies.wakeIslands->clear();
  }
  // A body the game woke (RRigidBody::Wake) still names the island it slept with; a
  // sleeper whose box touches one of the moved static and kinematic bodies' boxes wakes its
  // island (boxes grown by twice the slop and a hundredth of the sleeper's size: a resting
  // contact overlaps by at most the slop).
  for (const RBodyCore& b : bodies) {
    if (!b.m_sleeping && b.m_sleepIsland < m_wakeMark.size()) {
      m_wakeMark[b.m_sleepIsland] = 1, any = true;
    }
    if (!b.m_sleeping || m_wakeBoxes.empty() || !(b.m_sleepIsland < m_wakeMark.size())) continue;
    RVec3 lo, hi;
    b.WorldBox(lo, hi);
    const RScalar grow = 2 * settings.penetrationSlop + RScalar(0.01) * b.m_boundingRadius;
    lo.array() -= grow, hi.array() += grow;
    for (std::size_t k = 0; k < m_wakeBoxes.size(); k += 2) {
      if ((lo.array() <= m_wakeBoxes[k + 1].array()).all() && (m_wakeBoxes[k].array() <= hi.array()).all()) {
        m_wakeMark[b.m_sleepIsland] = 1, any = true;
        break;
      }
    }
  }
  // A sleeper joined to something that moves wakes with its island: to an awake body (a
  // joint the game added, a body enabled again), to a kinematic body its velocities move or a
  // static or kinematic body the game moved or enabled (the sleeper may hang far from it,
  // where no box sweep finds it). (A body disabled or enabled wakes its joints' partners
  // itself: RBodies::Disable.)
  // (The world: not an index, where a disabled body's dense index may be n itself.)
  constexpr std::uint32_t world = 0xffffffffu;
  auto moves = [&](std::uint32_t i) {
    if (i == world || i >= n) return false;  // the world; a disabled body
    const RBodyCore& b = bodies[i];
    if (b.Immovable()) return b.m_staticMoved || (b.m_isKinematic && !RPairSweep::StillKinematic(b));
    return !b.m_sleeping;
  };
  for (std::size_t k = 0; k < bodies.jointCount; ++k) {
    const RJointDef& def = bodies.joints[k].def;
    const std::uint32_t a = bodies.denseOfSlot[def.a.index];
    const std::uint32_t b = def.b.IsValid() ? bodies.denseOfSlot[def.b.index] : world;
    for (const auto& [sleeper, other] : {std::pair{a, b}, std::pair{b, a}}) {
      if (sleeper >= n || !bodies[sleeper].m_sleeping || !moves(other)) continue;
      const RBodyCore& s = bodies[sleeper];
      if (s.m_sleepIsland < m_wakeMark.size()) m_wakeMark[s.m_sleepIsland] = 1, any = true;
    }
  }
  if (any) WakeMarked(bodies);
}

void RSleeping::WakeMarked(const RStepBodies& bodies) {
  for (RBodyCore& b : bodies) {
    if (b.m_sleepIsland < m_wakeMark.size() && m_wakeMark[b.m_sleepIsland]) {
      b.m_sleeping = false, b.m_restTime = 0, b.m_sleepIsland = RBodyCore::kNoIsland;
    }
  }
  std::fill(m_wakeMark.begin(), m_wakeMark.end(), 0);
}

// Islands are the bodies linked by this step's resolved contacts between two dynamic
// bodies. An island sleeps when every body in it has been slower than the sleep speed for
// the sleep time and either static geometry holds it (a static body pushed one of its
// bodies this step) or it is exactly still: a drifting body in space is never stopped.
std::uint64_t RSleeping::SleepIslands(const RStepBodies& bodies, const RWorldSettings& settings,
                                      const std::vector<RContact>& contacts,
                                      const std::vector<std::uint8_t>& bodyFlags,
                                      const std::vector<RStepJoint>& joints) {
  const std::size_t n = bodies.size();
  bool anyRested = false;
  std::uint64_t asleep = 0;
  for (std::size_t i = 0; i < n; ++i) {
    RBodyCore& b = bodies[i];
    b.m_staticMoved = false, b.m_wakeFromSet = false, b.m_slot = bodies.Slot(i), b.m_slotWorld = m_worldId.value;
    anyRested = anyRested || (!b.Immovable() && !b.m_sleeping && b.m_restTime >= settings.sleepTime);
    asleep += b.m_sleeping;
  }
  // Islands are built only in a step where some body has rested long enough.
  if (!settings.shortcuts.sleeping || !anyRested) return asleep;
  m_sleepSets.Reset(n);
  m_sleepRest.assign(n, std::numeric_limits<RScalar>::infinity());
  m_sleepSupported.assign(n, 0);
  m_sleepStill.assign(n, 1);
  auto find = [this](std::uint32_t i) { return m_sleepSets.Find(i); };
  for (const RContact& c : contacts) {
    if (!c.resolved) continue;
    // A kinematic body holds as static geometry does, and joins no island: the islands on a
    // platform sleep and wake apart (its motion wakes what it touches, SetShapePose the sleepers about where it was and is).
    const bool staticA = bodyFlags[c.a] & RPairSweep::kFlagImmovable;
    const bool staticB = bodyFlags[c.b] & RPairSweep::kFlagImmovable;
    if (staticA || staticB) {
      // Held: the static body pushed this step (a speculative contact, or a body sliding
      // along a floor in space, is not held).
      RScalar pushed = 0;
      for (int k = 0; k < c.manifold.pointCount; ++k) pushed += c.normalImpulse[k];
      if (pushed > 0) m_sleepSupported[staticA ? c.b : c.a] = 1;
      continue;
    }
    m_sleepSets.Union(c.a, c.b);
  }
  // Joints bind islands as contacts do (they sleep and wake as one); a joint to the world or
  // to static geometry that held its body this step supports it.
  const std::uint32_t world = static_cast<std::uint32_t>(n);
  for (const RStepJoint& j : joints) {
    const bool immovableA = bodies[j.a].Immovable(), immovableB = j.b == world || bodies[j.b].Immovable();
    if (!immovableA && !immovableB) {
      m_sleepSets.Union(j.a, j.b);
      continue;
    }
    const RJoint& J = bodies.joints[j.joint];
    if (!(J.impulse_W.isZero(0) && J.angularImpulse_W.isZero(0))) m_sleepSupported[immovableA ? j.b : j.a] = 1;
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const RBodyCore& b = bodies[i];
    if (b.Immovable() || b.m_sleeping) continue;
    const std::uint32_t r = find(i);
    m_sleepRest[r] = std::min(m_sleepRest[r], b.m_restTime);
    if (m_sleepSupported[i]) m_sleepSupported[r] = 1;
    if (!(b.m_v_W.isZero(0) && b.m_w_B.isZero(0))) m_sleepStill[r] = 0;
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    RBodyCore& b = bodies[i];
    if (b.Immovable() || b.m_sleeping) continue;
    const std::uint32_t r = find(i);
    if (m_sleepRest[r] >= settings.sleepTime && (m_sleepSupported[r] || m_sleepStill[r])) {
      b.m_sleeping = true;
      b.m_sleepIsland = bodies.Slot(r);  // the id: its root's slot
      b.m_v_W.setZero(), b.m_w_B.setZero(), b.m_w_W.setZero();
      ++asleep;
    }
  }
  return asleep;
}

}  // namespace REngine
