// Sleeping islands (RWorldSettings::RShortcuts::sleeping): waking before the step, putting to
// sleep after it; see RIntegrator.h.
#include <REnginePhysics/RIntegrator.h>

#include "RSolverRows.h"

#include <algorithm>
#include <limits>

namespace REngine {

using namespace solver;

void RIntegrator::KeepSleepingWarmStarts(const std::vector<RRigidBody>& bodies) {
  auto passive = [&bodies](std::uint32_t i) {
    return bodies[i].m_sleeping || bodies[i].m_isStatic;
  };
  for (const RWarmStart& w : m_warm) {
    const std::uint32_t a = static_cast<std::uint32_t>(w.pair >> 32);
    const std::uint32_t b = static_cast<std::uint32_t>(w.pair & 0xffffffffu);
    if (passive(a) && passive(b)) m_warmNext.push_back(w);
  }
}

void RIntegrator::WakeIslands(std::vector<RRigidBody>& bodies) {
  const std::size_t n = bodies.size();
  m_wakeMark.assign(n, 0);  // keeps its capacity: no allocation once the world's size is set
  // Island ids are body indices: when bodies were added or removed they mean nothing, and a
  // removed body may have held a sleeping stack up. A sleeping body ignores gravity, so a
  // change of gravity wakes everything too; and so does static geometry that the game moved,
  // which may have held sleeping bodies where it was (their contacts are not kept while they
  // sleep, so which ones is not known).
  // Any body not where this integrator left it (see RRigidBody::m_slot) wakes everything:
  // a removal and an addition in one frame keep the count and may still remove a support.
  bool moved = m_wakeAll;
  for (std::size_t i = 0; i < n && !moved; ++i) {
    const RRigidBody& b = bodies[i];
    moved = b.m_staticMoved || b.m_slot != i || b.m_slotWorld != m_worldId.value;
  }
  m_wakeAll = false;
  if (!m_settings.shortcuts.sleeping || n != m_sleepBodyCount || moved ||
      m_settings.gravity_W != m_sleepGravity_W) {
    m_sleepBodyCount = n;
    m_sleepGravity_W = m_settings.gravity_W;
    for (RRigidBody& b : bodies) {
      if (b.m_sleeping || b.m_sleepIsland != RRigidBody::kNoIsland) {
        b.m_sleeping = false, b.m_restTime = 0, b.m_sleepIsland = RRigidBody::kNoIsland;
      }
    }
    return;
  }
  // A body the game woke (RRigidBody::Wake) still names the island it slept with.
  bool any = false;
  for (const RRigidBody& b : bodies) {
    if (!b.m_sleeping && b.m_sleepIsland != RRigidBody::kNoIsland) {
      m_wakeMark[b.m_sleepIsland] = 1, any = true;
    }
  }
  if (any) WakeMarked(bodies);
}

void RIntegrator::WakeMarked(std::vector<RRigidBody>& bodies) {
  for (RRigidBody& b : bodies) {
    if (b.m_sleepIsland != RRigidBody::kNoIsland && m_wakeMark[b.m_sleepIsland]) {
      b.m_sleeping = false, b.m_restTime = 0, b.m_sleepIsland = RRigidBody::kNoIsland;
    }
  }
  std::fill(m_wakeMark.begin(), m_wakeMark.end(), 0);
}

// Islands are the bodies linked by this step's resolved contacts between two dynamic
// bodies. An island sleeps when every body in it has been slower than the sleep speed for
// the sleep time and either static geometry holds it (a static body pushed one of its
// bodies this step) or it is exactly still: a drifting body in space is never stopped.
void RIntegrator::SleepIslands(std::vector<RRigidBody>& bodies) {
  const std::size_t n = bodies.size();
  bool anyRested = false;
  std::uint64_t asleep = 0;
  for (std::size_t i = 0; i < n; ++i) {
    RRigidBody& b = bodies[i];
    b.m_staticMoved = false, b.m_slot = static_cast<std::uint32_t>(i), b.m_slotWorld = m_worldId.value;
    anyRested = anyRested || (!b.m_isStatic && !b.m_sleeping && b.m_restTime >= m_settings.sleepTime);
    asleep += b.m_sleeping;
  }
  m_pairStats.sleepingBodies = asleep;
  // Islands are built only in a step where some body has rested long enough.
  if (!m_settings.shortcuts.sleeping || !anyRested) return;
  m_sleepParent.resize(n);
  m_sleepRest.assign(n, std::numeric_limits<RScalar>::infinity());
  m_sleepSupported.assign(n, 0);
  m_sleepStill.assign(n, 1);
  for (std::size_t i = 0; i < n; ++i) m_sleepParent[i] = static_cast<std::uint32_t>(i);
  auto find = [this](std::uint32_t i) {
    while (m_sleepParent[i] != i) i = m_sleepParent[i] = m_sleepParent[m_sleepParent[i]];
    return i;
  };
  for (const RContact& c : m_contacts) {
    if (!c.resolved) continue;
    const bool staticA = bodies[c.a].m_isStatic, staticB = bodies[c.b].m_isStatic;
    if (staticA || staticB) {
      // Held: the static body pushed this step (a speculative contact, or a body sliding
      // along a floor in space, is not held).
      RScalar pushed = 0;
      for (int k = 0; k < c.manifold.pointCount; ++k) pushed += c.normalImpulse[k];
      if (pushed > 0) m_sleepSupported[staticA ? c.b : c.a] = 1;
      continue;
    }
    const std::uint32_t ra = find(c.a), rb = find(c.b);
    // The smaller index as the root: island ids do not depend on the order of contacts.
    if (ra != rb) m_sleepParent[std::max(ra, rb)] = std::min(ra, rb);
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const RRigidBody& b = bodies[i];
    if (b.m_isStatic || b.m_sleeping) continue;
    const std::uint32_t r = find(i);
    m_sleepRest[r] = std::min(m_sleepRest[r], b.m_restTime);
    if (m_sleepSupported[i]) m_sleepSupported[r] = 1;
    if (!(b.m_v_W.isZero(0) && b.m_w_B.isZero(0))) m_sleepStill[r] = 0;
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    RRigidBody& b = bodies[i];
    if (b.m_isStatic || b.m_sleeping) continue;
    const std::uint32_t r = find(i);
    if (m_sleepRest[r] >= m_settings.sleepTime && (m_sleepSupported[r] || m_sleepStill[r])) {
      b.m_sleeping = true;
      b.m_sleepIsland = r;
      b.m_v_W.setZero(), b.m_w_B.setZero();
      ++m_pairStats.sleepingBodies;
    }
  }
}

}  // namespace REngine
