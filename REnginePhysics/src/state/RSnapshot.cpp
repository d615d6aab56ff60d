// Rollback snapshots (RSnapshot.h): the save. One pass over the bodies writes a 120-byte
// record each (plus the few extras and rotation phases); the layout and the rotation
// constants are shared with an earlier snapshot whenever their version numbers say they
// are unchanged, so a frame copies only what its step changed.
#include "state/RSnapshotData.h"

#include "body/RBodyAccess.h"

#include <cstring>

namespace REngine {

namespace {

#define RENGINE_SAME(field) (std::memcmp(&a.field, &b.field, sizeof a.field) == 0)
// Bit for bit, field by field (padding is never compared).
bool SameConstants(const RFreeRotationCore& a, const RFreeRotationCore& b) {
  return RENGINE_SAME(m_I_B) && RENGINE_SAME(m_symmetry) && RENGINE_SAME(m_axisUnique) && RENGINE_SAME(m_sorted) &&
         RENGINE_SAME(m_cacheH) && RENGINE_SAME(m_a) && RENGINE_SAME(m_b) && RENGINE_SAME(m_c) &&
         RENGINE_SAME(m_signC) && RENGINE_SAME(m_invM) && RENGINE_SAME(m_amp) && RENGINE_SAME(m_m) &&
         RENGINE_SAME(m_mc) && RENGINE_SAME(m_lambda) && RENGINE_SAME(m_panels) && RENGINE_SAME(m_node) &&
         RENGINE_SAME(m_panelStep) && RENGINE_SAME(m_end) && RENGINE_SAME(m_periods) &&
         RENGINE_SAME(m_psiPeriod) && RENGINE_SAME(m_hRest) && RENGINE_SAME(m_periodPanels);
}
#undef RENGINE_SAME

void Put3(double* out, const RVec3& v) { out[0] = v.x(), out[1] = v.y(), out[2] = v.z(); }

// Whether `layout` is the container as it stands: the same container version and every
// body's definition version.
bool Current(const RSnapshotLayout* layout, const RBodiesCore& c) {
  if (!layout || layout->containerStamp != c.m_definitionStamp.Value()) return false;
  const std::size_t n = c.m_slots.items.size();
  if (layout->definitions.size() != n) return false;
  for (std::size_t d = 0; d < n; ++d) {
    if (layout->definitions[d] != Core(c.m_slots.items[d]).m_definition.value) return false;
  }
  return true;
}

std::shared_ptr<const RSnapshotLayout> CopyLayout(const RBodiesCore& c) {
  auto layout = std::make_shared<RSnapshotLayout>();
  layout->containerStamp = c.m_definitionStamp.Value();
  layout->slots = c.m_slots;
  layout->enabled = c.m_enabled;
  layout->jointSlots = c.m_jointSlots;
  layout->noCollide = c.m_noCollide;
  layout->definitions.resize(c.m_slots.items.size());
  for (std::size_t d = 0; d < c.m_slots.items.size(); ++d) {
    layout->definitions[d] = Core(c.m_slots.items[d]).m_definition.value;
  }
  return layout;
}

}  // namespace

RRotationConstants RRotationConstants::Of(const RFreeRotationCore& f) {
  RRotationConstants c;
  c.core = f;
  return c;
}
bool RRotationConstants::SameAs(const RFreeRotationCore& f) const { return SameConstants(core, f); }

std::size_t RSnapshotLayout::Bytes() const {
  return sizeof(*this) + definitions.size() * 8 + slots.items.size() * (sizeof(RRigidBody) + sizeof(RBodyHandle)) +
         slots.generation.size() * 8 + slots.free.size() * 4 + jointSlots.items.size() * sizeof(RJoint) +
         noCollide.size() * 8;
}

std::size_t RSnapshotData::FrameBytes() const {
  if (!saved) return 0;
  return (frames ? frames->size() * sizeof(RBodyFrame) : 0) + deltaBodies.size() * 4 +
         extras.size() * sizeof(RBodyExtra) + rotations.size() * sizeof(RRotationFrame) +
         warm.size() * sizeof(RWarmStart) + manifolds.size() * sizeof(RManifoldMemory) +
         touching.size() * sizeof(RContactEventLog::RTouchingPair) +
         materials.size() * sizeof(RContactMaterials::RRemembered) + wakeIslands.size() * 4 +
         wakeBoxes.size() * sizeof(RVec3) + joints.size() * sizeof(RJoint) + sizeof(RSnapshotData);
}

std::size_t RSnapshotData::SharedBytes() const {
  if (!saved) return 0;
  std::size_t bytes = layout ? layout->Bytes() : 0;
  if (rotationTable) {
    bytes += rotationTable->size() * sizeof(std::shared_ptr<const RRotationConstants>);
    for (const auto& c : *rotationTable) bytes += c ? sizeof(RRotationConstants) : 0;
  }
  return bytes;
}

void RSnapshotAccess::Save(const RIntegrator& integrator, const RBodies& bodies, RSnapshot& out,
                           const RSnapshotOptions& options) {
  const RBodiesCore& c = Core(bodies);
  const RWorldStep& w = *Core(integrator).m_w;
  if (!out.m_data) out.m_data = std::make_unique<RSnapshotData>();  // moved from
  RSnapshotData& s = Data(out);
  const RSnapshotData* share = options.shareWith && options.shareWith != &out ? &Data(*options.shareWith) : nullptr;
  const RSnapshotData* delta = options.deltaFrom ? &Data(*options.deltaFrom) : nullptr;
  if (delta && (!delta->saved || delta->base || options.deltaFrom == &out)) {
    throw RStateError("snapshot.delta_from", "must be another, full snapshot (a key frame)");
  }
  const std::size_t n = c.m_slots.items.size();
  const std::uint64_t worldId = w.m_sleep.WorldId();

  // The layout: the shared one's, our own earlier one's, or a new copy.
  if (share && share->saved && Current(share->layout.get(), c)) {
    s.layout = share->layout;
  } else if (!(s.saved && Current(s.layout.get(), c))) {
    s.layout = CopyLayout(c);
  }

  // Frame records. A buffer another snapshot still reads (a delta's base) is left to it.
  if (!s.frames || s.frames.use_count() > 1) s.frames = std::make_shared<std::vector<RBodyFrame>>();
  std::vector<RBodyFrame>& frames = *s.frames;
  frames.resize(n);
  s.extras.clear();
  s.rotations.clear();
  for (std::size_t d = 0; d < n; ++d) {
    const RBodyCore& b = Core(c.m_slots.items[d]);
    RBodyFrame& f = frames[d];
    Put3(f.x, b.m_x_W);
    f.q[0] = b.m_q_WB.w(), f.q[1] = b.m_q_WB.x(), f.q[2] = b.m_q_WB.y(), f.q[3] = b.m_q_WB.z();
    Put3(f.v, b.m_v_W);
    Put3(f.w, b.m_w_B);
    f.restTime = b.m_restTime;
    f.sleepIsland = b.m_sleepIsland;
    std::uint32_t flags = (b.m_sleeping ? kFrameSleeping : 0) | (b.m_staticMoved ? kFrameStaticMoved : 0) |
                          (b.m_wakeFromSet ? kFrameWakeFromSet : 0);
    const bool slotKnown = b.m_slot == d || b.m_slot == RBodyCore::kNoIsland;
    flags |= b.m_slot == d ? kFrameSlotDense : b.m_slot == RBodyCore::kNoIsland ? kFrameSlotNone : 0;
    const bool worldKnown = b.m_slotWorld == worldId || b.m_slotWorld == 0;
    flags |= b.m_slotWorld == worldId ? kFrameOwnWorld : b.m_slotWorld == 0 ? kFrameZeroWorld : 0;
    const RFreeRotationCore& rot = Core(b.m_rotation);
    const bool rotation = rot.m_symmetry == RInertiaSymmetry::kGeneral && rot.m_cacheValid;
    if (rotation) {
      flags |= kFrameRotation;
      s.rotations.push_back({rot.m_phase.sn, rot.m_phase.cn, rot.m_phase.dn, static_cast<std::uint32_t>(d)});
    }
    const bool accumulators = !(b.m_force_W.isZero(0) && b.m_torque_W.isZero(0) && b.m_linearImpulse_W.isZero(0) &&
                                b.m_angularImpulse_W.isZero(0));
    const bool cacheKey = rotation && std::memcmp(rot.m_cacheW_B.data(), b.m_w_B.data(), sizeof(double) * 3) != 0;
    if (!slotKnown || !worldKnown || b.m_worldSpin || accumulators || cacheKey) {
      flags |= kFrameExtra;
      RBodyExtra& e = s.extras.emplace_back();
      e.body = static_cast<std::uint32_t>(d);
      e.slot = b.m_slot, e.slotWorld = b.m_slotWorld;
      Put3(e.w_W, b.m_w_W);
      Put3(e.force, b.m_force_W), Put3(e.torque, b.m_torque_W);
      Put3(e.linearImpulse, b.m_linearImpulse_W), Put3(e.angularImpulse, b.m_angularImpulse_W);
      Put3(e.cacheW_B, rot.m_cacheW_B);
    }
    f.flags = flags;
  }

  // Rotation constants: the shared table where every cached polhode is the one it holds.
  const RRotationTable* prior = share && share->rotationTable ? share->rotationTable.get()
                                : s.rotationTable                ? s.rotationTable.get()
                                                                 : nullptr;
  bool same = prior && prior->size() == n;
  if (same) {
    for (const RRotationFrame& r : s.rotations) {
      const auto& held = (*prior)[r.body];
      if (!held || !held->SameAs(Core(Core(c.m_slots.items[r.body]).m_rotation))) {
        same = false;
        break;
      }
    }
  }
  if (same) {
    if (s.rotationTable.get() != prior) {
      s.rotationTable = share && share->rotationTable.get() == prior ? share->rotationTable : s.rotationTable;
    }
  } else if (s.rotations.empty()) {
    s.rotationTable.reset();
  } else {
    // A new table: unchanged polhodes keep the prior's constants, changed ones get new.
    auto table = std::make_shared<RRotationTable>(n);
    for (const RRotationFrame& r : s.rotations) {
      const RFreeRotationCore& rot = Core(Core(c.m_slots.items[r.body]).m_rotation);
      if (prior && prior->size() == n && (*prior)[r.body] && (*prior)[r.body]->SameAs(rot)) {
        (*table)[r.body] = (*prior)[r.body];
      } else {
        (*table)[r.body] = std::make_shared<const RRotationConstants>(RRotationConstants::Of(rot));
      }
    }
    s.rotationTable = std::move(table);
  }

  // Delta: keep only the records that differ from the key frame's.
  s.deltaBodies.clear();
  s.base.reset();
  if (delta) {
    const std::vector<RBodyFrame>& key = *delta->frames;
    if (key.size() != n || delta->layout != s.layout) {
      // Bodies came or went since the key frame: this frame is stored whole.
    } else {
      std::size_t kept = 0;
      for (std::size_t d = 0; d < n; ++d) {
        if (std::memcmp(&frames[d], &key[d], sizeof(RBodyFrame)) != 0) {
          frames[kept++] = frames[d];
          s.deltaBodies.push_back(static_cast<std::uint32_t>(d));
        }
      }
      frames.resize(kept);
      s.base = delta->frames;
    }
  }

  // The integrator and the container's per-step state.
  s.settings = w.m_settings;
  s.stepCount = w.m_stepCount;
  s.warmBodyCount = w.m_solver.WarmBodyCount();
  s.sleep = w.m_sleep.Saved();
  if (w.m_motion.NonFinite() || s.nonFinite) s.nonFinite = w.m_motion.NonFinite();
  s.warm = w.m_solver.WarmStarts();
  s.manifolds = w.m_sweep.Manifolds();
  s.touching = w.m_eventLog.Touching();
  s.materials = w.m_materials.Memory();
  s.wakeIslands = c.m_wakeIslands;
  s.wakeAll = c.m_wakeAll;
  s.wakeBoxes = c.m_wakeBoxes;
  s.joints = c.m_jointSlots.items;
  s.worldTag = options.worldTag;
  s.worldId = worldId;
  s.saved = true;
}

RSnapshot::RSnapshot() : m_data(std::make_unique<RSnapshotData>()) {}
RSnapshot::~RSnapshot() = default;
RSnapshot::RSnapshot(RSnapshot&&) noexcept = default;
RSnapshot& RSnapshot::operator=(RSnapshot&&) noexcept = default;
bool RSnapshot::Empty() const { return !m_data || !m_data->saved; }
std::uint64_t RSnapshot::StepCount() const { return m_data ? m_data->stepCount : 0; }
std::size_t RSnapshot::FrameBytes() const { return m_data ? m_data->FrameBytes() : 0; }
std::size_t RSnapshot::SharedBytes() const { return m_data ? m_data->SharedBytes() : 0; }
std::size_t RSnapshot::StoredBodies() const {
  return m_data && m_data->frames ? m_data->frames->size() : 0;
}

void SaveSnapshot(const RIntegrator& integrator, const RBodies& bodies, RSnapshot& out,
                  const RSnapshotOptions& options) {
  RSnapshotAccess::Save(integrator, bodies, out, options);
}

}  // namespace REngine
