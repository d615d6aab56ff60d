// Rollback snapshots (RSnapshot.h): the restore, and the ring of frames. Checks come first
// (nothing is touched before the snapshot is known to apply); then the layout is put back
// only where the container's version numbers say it differs, and the frame records are
// written over the bodies.
#include "state/RSnapshotData.h"

#include "body/RBodyAccess.h"

#include <REngineMath/RQuaternion.h>

#include <algorithm>
#include <string>

namespace REngine {

namespace {

RVec3 Get3(const double* v) { return RVec3(v[0], v[1], v[2]); }

void Apply(RBodyCore& b, const RBodyFrame& f, std::size_t d, std::uint64_t worldId) {
  b.m_x_W = Get3(f.x);
  b.m_q_WB = RQuat(f.q[0], f.q[1], f.q[2], f.q[3]);
  b.m_v_W = Get3(f.v);
  b.m_w_B = Get3(f.w);
  b.m_restTime = f.restTime;
  b.m_sleepIsland = f.sleepIsland;
  b.m_sleeping = (f.flags & kFrameSleeping) != 0;
  b.m_staticMoved = (f.flags & kFrameStaticMoved) != 0;
  b.m_wakeFromSet = (f.flags & kFrameWakeFromSet) != 0;
  if (!(f.flags & kFrameExtra)) {
    b.m_slot = (f.flags & kFrameSlotDense) ? static_cast<std::uint32_t>(d) : RBodyCore::kNoIsland;
    b.m_slotWorld = (f.flags & kFrameOwnWorld) ? worldId : 0;
    b.m_force_W.setZero(), b.m_torque_W.setZero();
    b.m_linearImpulse_W.setZero(), b.m_angularImpulse_W.setZero();
  }
  // The exact rotation's cache: invalid unless a rotation record restores it (below).
  Core(b.m_rotation).m_cacheValid = false;
}

void ApplyExtra(RBodyCore& b, const RBodyExtra& e) {
  b.m_slot = e.slot, b.m_slotWorld = e.slotWorld;
  b.m_w_W = Get3(e.w_W);
  b.m_force_W = Get3(e.force), b.m_torque_W = Get3(e.torque);
  b.m_linearImpulse_W = Get3(e.linearImpulse), b.m_angularImpulse_W = Get3(e.angularImpulse);
}

[[noreturn]] void Refuse(const char* field, const std::string& problem) { throw RStateError(field, problem); }

}  // namespace

void RSnapshotAccess::Restore(RIntegrator& integrator, RBodies& bodies, const RSnapshot& snapshot,
                              std::uint64_t worldTag) {
  if (!snapshot.m_data || !snapshot.m_data->saved) Refuse("snapshot", "is empty (never saved)");
  const RSnapshotData& s = Data(snapshot);
  RWorldStep& w = *Core(integrator).m_w;
  RBodiesCore& c = Core(bodies);
  if (s.worldTag != worldTag) {
    Refuse("snapshot.world_tag", "is " + std::to_string(s.worldTag) + ", the restoring world's " +
                                     std::to_string(worldTag) + ": a snapshot of another world");
  }
  if (s.worldId != w.m_sleep.WorldId()) {
    Refuse("snapshot.integrator", "was saved by another RIntegrator: its contact memory and sleeping "
                                  "name that integrator's bodies (save and load a state to move a world)");
  }
  const RSnapshotLayout& layout = *s.layout;
  const std::size_t n = layout.slots.items.size();
  if (s.base ? s.base->size() != n || s.frames->size() != s.deltaBodies.size() : s.frames->size() != n) {
    Refuse("snapshot.frames", "do not match its layout (a delta whose key frame changed)");
  }

  // The layout: in place when the container is the snapshot's (its version numbers), body
  // by body where only some bodies' definitions were edited, else copied whole.
  const bool sameContainer = c.m_definitionStamp.Value() == layout.containerStamp && c.m_slots.items.size() == n;
  if (sameContainer) {
    for (std::size_t d = 0; d < n; ++d) {
      if (Core(c.m_slots.items[d]).m_definition.value != layout.definitions[d]) {
        c.m_slots.items[d] = layout.slots.items[d];
      }
    }
  } else {
    c.m_slots = layout.slots;
    c.m_enabled = layout.enabled;
    c.m_jointSlots = layout.jointSlots;
    c.m_noCollide = layout.noCollide;
    c.LayoutChanged();  // queries' trees are rebuilt
    c.m_definitionStamp.Adopt(layout.containerStamp);
    w.m_broad.Invalidate();
  }

  // Frame records.
  const std::uint64_t worldId = w.m_sleep.WorldId();
  if (s.base) {
    const std::vector<RBodyFrame>& key = *s.base;
    std::size_t k = 0;
    for (std::size_t d = 0; d < n; ++d) {
      const bool changed = k < s.deltaBodies.size() && s.deltaBodies[k] == d;
      Apply(Core(c.m_slots.items[d]), changed ? (*s.frames)[k++] : key[d], d, worldId);
    }
  } else {
    const std::vector<RBodyFrame>& frames = *s.frames;
    for (std::size_t d = 0; d < n; ++d) Apply(Core(c.m_slots.items[d]), frames[d], d, worldId);
  }
  for (const RBodyExtra& e : s.extras) ApplyExtra(Core(c.m_slots.items[e.body]), e);
  std::size_t extra = 0;
  for (const RRotationFrame& r : s.rotations) {
    RBodyCore& b = Core(c.m_slots.items[r.body]);
    RFreeRotationCore& f = Core(b.m_rotation);
    f = (*s.rotationTable)[r.body]->core;
    f.m_phase.sn = r.sn, f.m_phase.cn = r.cn, f.m_phase.dn = r.dn;
    // The cache's key is the spin the last flow produced: the body's, unless an impulse
    // changed it after the flow (then its extra holds the key).
    while (extra < s.extras.size() && s.extras[extra].body < r.body) ++extra;
    const bool keyed = extra < s.extras.size() && s.extras[extra].body == r.body;
    f.m_cacheW_B = keyed ? Get3(s.extras[extra].cacheW_B) : b.m_w_B;
    // As RFreeRotation::Advance leaves it: the minimal rotation taking l = I w / |L| to the
    // pole axis, of the same operands, so the same bits.
    RVec3 e = RVec3::Zero();
    e[f.m_c] = f.m_signC;
    f.m_align0 = QuatFromTo(f.m_I_B.cwiseProduct(f.m_cacheW_B) * f.m_invM, e);
    f.m_cacheValid = true;
  }
  c.m_wakeIslands = s.wakeIslands;
  c.m_wakeAll = s.wakeAll;
  c.m_wakeBoxes = s.wakeBoxes;
  c.m_jointSlots.items = s.joints;
  c.m_poseStamp.Bump();

  // The integrator: its settings (but its own threads), memory and step count; a new cache
  // stamp, since every world form is to be recomputed.
  const int threads = w.m_settings.threads;
  w.m_settings = s.settings;
  w.m_settings.threads = threads;
  w.m_stepCount = s.stepCount;
  w.m_sleep.RestoreForSnapshot(RLoadKey{}, s.sleep);
  w.m_motion.RestoreForSnapshot(RLoadKey{}, s.nonFinite);
  w.m_solver.RestoreForSnapshot(RLoadKey{}, s.warm, static_cast<std::size_t>(s.warmBodyCount));
  w.m_sweep.RestoreForSnapshot(RLoadKey{}, s.manifolds);
  w.m_eventLog.RestoreForSnapshot(RLoadKey{}, s.touching);
  w.m_materials.Restore(s.materials);
  w.m_cacheStamp = NextCacheStamp();
  w.m_profile = RStepProfile{};
}

void RestoreSnapshot(RIntegrator& integrator, RBodies& bodies, const RSnapshot& snapshot, std::uint64_t worldTag) {
  RSnapshotAccess::Restore(integrator, bodies, snapshot, worldTag);
}

// ---- the ring ---------------------------------------------------------------------------

RSnapshotRing::RSnapshotRing(std::size_t frames, std::size_t keyInterval, std::uint64_t worldTag)
    : m_slots(frames), m_frame(frames, 0), m_held(frames, false), m_keyInterval(keyInterval), m_worldTag(worldTag) {
  if (frames == 0) throw RStateError("frames", "must be at least 1");
  if (keyInterval == 0) throw RStateError("key_interval", "must be at least 1");
}

void RSnapshotRing::Save(const RIntegrator& integrator, const RBodies& bodies) {
  const std::uint64_t frame = integrator.StepCount();
  const std::size_t slot = static_cast<std::size_t>(frame % m_slots.size());
  RSnapshotOptions options;
  options.worldTag = m_worldTag;
  if (m_any && m_last != slot && m_held[m_last]) options.shareWith = &m_slots[m_last];
  if (m_keyInterval > 1 && frame % m_keyInterval != 0) {
    // The key frame of this interval, when the ring still holds it.
    const std::uint64_t key = frame - frame % m_keyInterval;
    if (Has(key) && m_frame[key % m_slots.size()] == key && key % m_slots.size() != slot) {
      options.deltaFrom = &m_slots[key % m_slots.size()];
    }
  }
  SaveSnapshot(integrator, bodies, m_slots[slot], options);
  m_frame[slot] = frame, m_held[slot] = true;
  m_last = slot, m_any = true;
}

bool RSnapshotRing::Has(std::uint64_t frame) const {
  const std::size_t slot = static_cast<std::size_t>(frame % m_slots.size());
  return m_held[slot] && m_frame[slot] == frame;
}

const RSnapshot& RSnapshotRing::At(std::uint64_t frame) const {
  if (!Has(frame)) {
    throw RStateError("frame", "frame " + std::to_string(frame) + " is not among the last " +
                                   std::to_string(m_slots.size()) + " saved");
  }
  return m_slots[frame % m_slots.size()];
}

void RSnapshotRing::Restore(RIntegrator& integrator, RBodies& bodies, std::uint64_t frame) {
  RestoreSnapshot(integrator, bodies, At(frame), m_worldTag);
  for (std::size_t k = 0; k < m_slots.size(); ++k) {
    if (m_held[k] && m_frame[k] > frame) m_held[k] = false;
  }
  m_last = static_cast<std::size_t>(frame % m_slots.size());
}

std::size_t RSnapshotRing::TotalBytes() const {
  std::size_t bytes = 0;
  std::vector<const void*> seen;
  for (std::size_t k = 0; k < m_slots.size(); ++k) {
    if (!m_held[k]) continue;
    const RSnapshotData& s = RSnapshotAccess::Data(m_slots[k]);
    bytes += s.FrameBytes();
    if (std::find(seen.begin(), seen.end(), s.layout.get()) == seen.end()) {
      seen.push_back(s.layout.get());
      bytes += s.layout->Bytes();
    }
    if (s.rotationTable && std::find(seen.begin(), seen.end(), s.rotationTable.get()) == seen.end()) {
      seen.push_back(s.rotationTable.get());
      bytes += s.rotationTable->size() * sizeof(std::shared_ptr<const RRotationConstants>);
      for (const auto& r : *s.rotationTable) bytes += r ? sizeof(RRotationConstants) : 0;
    }
  }
  return bytes;
}

}  // namespace REngine
