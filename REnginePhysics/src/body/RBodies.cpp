// The body container: a slot map over dense storage (see RBodies.h).
#include <REnginePhysics/RBodies.h>

#include "body/RBodyAccess.h"

#include <REnginePhysics/RIntegrator.h>  // NextCacheStamp

#include <algorithm>
#include <string>
#include <utility>

namespace REngine {

RBodiesStamp::RBodiesStamp() : m_value(NextCacheStamp()) {}
RBodiesStamp::RBodiesStamp(const RBodiesStamp&) : m_value(NextCacheStamp()) {}
RBodiesStamp& RBodiesStamp::operator=(const RBodiesStamp&) {
  m_value = NextCacheStamp();
  return *this;
}
void RBodiesStamp::Bump() { m_value = NextCacheStamp(); }

std::uint32_t RBodies::DenseIndex(RBodyHandle h) const {
  if (!Contains(h)) {
    throw RHandleError("RBodies: handle (index " + std::to_string(h.index) + ", generation " +
                       std::to_string(h.generation) + ") names no body: " +
                       (h.IsValid() ? "it was removed" : "it was never issued"));
  }
  return m_slots.denseOfSlot[h.index];
}

RBodyHandle RBodies::Add(const RBodyDef& def) { return Add(RRigidBody(def)); }

RBodyHandle RBodies::Add(RRigidBody body) {
  if (m_slots.items.size() >= kMaxBodies) {
    throw RError("bodies", "hold their maximum of 2^31", "RBodies::Add: the container holds its maximum of 2^31 bodies");
  }
  // A new body sleeps with no island and has not been stepped yet; a static one appearing
  // beside a sleeper must wake it (a sleeping body is not paired with static geometry),
  // which is what a moved static body does.
  RBodyCore& c = Core(body);
  c.m_sleeping = false, c.m_restTime = 0;
  c.m_sleepIsland = RBodyCore::kNoIsland;
  c.m_slot = RBodyCore::kNoIsland, c.m_slotWorld = 0;
  if (c.Immovable()) c.m_staticMoved = true;
  const std::uint32_t dense = static_cast<std::uint32_t>(m_slots.items.size());
  const RBodyHandle h = m_slots.Insert(std::move(body));
  // Enabled: swap it from the end of the disabled range to the end of the enabled one.
  m_slots.SwapDense(dense, static_cast<std::uint32_t>(m_enabled));
  ++m_enabled;
  LayoutChanged();
  return h;
}

void RBodies::WakeForDeparture(RRigidBody& body) {
  RBodyCore& b = Core(body);
  if (b.Immovable()) {
    if (b.m_slotWorld != 0) {  // stepped: sleepers may rest on it
      RVec3 lo, hi;
      b.WorldBox(lo, hi);
      m_wakeBoxes.push_back(lo), m_wakeBoxes.push_back(hi);
    }
    // Moved since the last step, then taken away: where it was is where sleepers rest.
    if (b.m_wakeFromSet) m_wakeBoxes.push_back(b.m_wakeFromMin_W), m_wakeBoxes.push_back(b.m_wakeFromMax_W);
    b.m_wakeFromSet = false, b.m_staticMoved = false;
  } else if (b.m_sleepIsland != RBodyCore::kNoIsland) {
    // Asleep, or woken by the game since the last step: its island still has the id.
    m_wakeIslands.push_back(b.m_sleepIsland);
  }
  b.m_sleeping = false, b.m_restTime = 0;
  b.m_sleepIsland = RBodyCore::kNoIsland;
  b.m_slot = RBodyCore::kNoIsland, b.m_slotWorld = 0;
}

void RBodies::Remove(RBodyHandle h) {
  std::uint32_t dense = DenseIndex(h);
  if (!m_jointSlots.items.empty()) RemoveJointsOf(h), dense = DenseIndex(h);
  if (dense < m_enabled) {
    WakeForDeparture(m_slots.items[dense]);
    // To the end of the enabled range (its last body takes the removed one's place), then
    // to the end of the storage (the last disabled body takes that place).
    m_slots.SwapDense(dense, static_cast<std::uint32_t>(m_enabled - 1));
    dense = static_cast<std::uint32_t>(--m_enabled);
  }
  m_slots.SwapDense(dense, static_cast<std::uint32_t>(m_slots.items.size() - 1));
  m_slots.PopBack();
  LayoutChanged();
}

void RBodies::Disable(RBodyHandle h) {
  const std::uint32_t dense = DenseIndex(h);
  if (dense >= m_enabled) return;
  WakeForDeparture(m_slots.items[dense]);
  WakeJointPartners(h);
  m_slots.SwapDense(dense, static_cast<std::uint32_t>(m_enabled - 1));
  --m_enabled;
  LayoutChanged();
}

void RBodies::Enable(RBodyHandle h) {
  const std::uint32_t dense = DenseIndex(h);
  if (dense < m_enabled) return;
  RBodyCore& b = Core(m_slots.items[dense]);
  if (b.Immovable()) b.m_staticMoved = true;
  WakeJointPartners(h);
  m_slots.SwapDense(dense, static_cast<std::uint32_t>(m_enabled));
  ++m_enabled;
  LayoutChanged();
}

void RBodies::Reserve(std::size_t n) { m_slots.Reserve(n); }

void RBodies::IgnoreCollisions(RBodyHandle a, RBodyHandle b) {
  RRigidBody& bodyA = m_slots.items[DenseIndex(a)];
  RRigidBody& bodyB = m_slots.items[DenseIndex(b)];
  if (a == b) throw RBodyError("ignore", "a body cannot ignore itself");
  for (RRigidBody* body : {&bodyA, &bodyB}) {
    if (Core(*body).m_id != RBodyCore::kNoId) continue;
    // The least id no body here holds: ids stay small, and a game's own ids are left alone.
    std::vector<std::uint32_t> taken;
    taken.reserve(m_slots.items.size());
    for (const RRigidBody& other : m_slots.items) {
      if (Core(other).m_id != RBodyCore::kNoId) taken.push_back(Core(other).m_id);
    }
    std::sort(taken.begin(), taken.end());
    std::uint32_t id = 0;
    for (std::uint32_t t : taken) {
      if (t > id) break;
      if (t == id) ++id;
    }
    if (id == RBodyCore::kNoId) throw RError("id", "every id is taken");
    Core(*body).m_id = id;
    Core(*body).m_definition.Bump();
  }
  // Waking a (IgnoreCollisionsWith) is enough: a sleeping pair that touches is one island.
  bodyA.IgnoreCollisionsWith(Core(bodyB).m_id);
}

void RBodies::Clear() {
  while (!m_slots.items.empty()) Remove(m_slots.handles.back());
}

}  // namespace REngine
