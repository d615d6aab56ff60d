// The bodies' records of a state (RStateAccess, RStateAccess.h): each body, its exact
// rotation's cache and the container's tables, written as records of fixed fields and read
// back field for field in the same order into temporaries that RWorldState.cpp checks whole before the world is touched.
#include "state/RStateAccess.h"

#include <REnginePhysics/RLimits.h>
#include "body/RBodyAccess.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace REngine {

using namespace state;

void RStateAccess::WriteJacobi(RWriter& w, const RJacobiSnCnDn& j) { w.F64(j.sn), w.F64(j.cn), w.F64(j.dn); }

// Jacobi's sn and cn lie in [-1, 1] and dn in [0, 1] (for a parameter in [0, 1]); rounding
// may carry them a few ulps past.
RJacobiSnCnDn RStateAccess::ReadJacobi(RReader& r, const char* field, bool check) {
  RJacobiSnCnDn j;
  j.sn = r.F64(field), j.cn = r.F64(field), j.dn = r.F64(field);
  constexpr RScalar kOne = 1 + 1e-9;
  if (check && !(std::abs(j.sn) <= kOne && std::abs(j.cn) <= kOne && j.dn >= -1e-9 && j.dn <= kOne)) {
    r.Fail(field, "must be Jacobi values: sn and cn within [-1, 1], dn within [0, 1]");
  }
  return j;
}

// The exact rotation's cache, as it is: the next step reuses it, and what it would compute
// afresh differs in the last bits (its phase is the last step's output, stepped on). Only
// a body of three distinct moments has one: the others' closed forms never touch it.
void RStateAccess::WriteRotation(RWriter& w, const RFreeRotation& rotation) {
  const RFreeRotationCore& f = Core(rotation);
  w.Bool(f.m_symmetry == RInertiaSymmetry::kGeneral);
  if (f.m_symmetry != RInertiaSymmetry::kGeneral) return;
  w.Bool(f.m_cacheValid);
  w.F64(f.m_cacheH);
  w.Vec3(f.m_cacheW_B);
  for (int axis : {f.m_a, f.m_b, f.m_c}) w.U8(static_cast<std::uint8_t>(axis));
  w.F64(f.m_signC), w.F64(f.m_invM);
  w.Quat(f.m_align0);
  for (RScalar a : f.m_amp) w.F64(a);
  w.F64(f.m_m), w.F64(f.m_mc), w.F64(f.m_lambda);
  w.I32(f.m_panels);
  WriteJacobi(w, f.m_phase);
  for (const RJacobiSnCnDn& j : f.m_node) WriteJacobi(w, j);
  WriteJacobi(w, f.m_panelStep);
  WriteJacobi(w, f.m_end);
  w.F64(f.m_periods), w.F64(f.m_psiPeriod), w.F64(f.m_hRest);
  w.I32(f.m_periodPanels);
}

void RStateAccess::ReadRotation(RReader& r, RFreeRotation& rotation) {
  RFreeRotationCore& f = Core(rotation);
  const bool general = r.Bool("rotation.general");
  if (general != (f.m_symmetry == RInertiaSymmetry::kGeneral)) {
    r.Fail("rotation.general", "contradicts the symmetry of the body's moments of inertia");
  }
  if (!general) return;
  // The cache is read by the next step only while it is valid: then every value is one a
  // step computed (finite, in its range); an invalid one is recomputed before use.
  f.m_cacheValid = r.Bool("rotation.cache_valid");
  const bool valid = f.m_cacheValid;
  const auto finite = [&r, valid](const char* field, RScalar v) {
    if (valid && !std::isfinite(v)) r.Fail(field, "must be finite (got " + RReader::Number(v) + ")");
    return v;
  };
  f.m_cacheH = finite("rotation.step", r.F64("rotation.step"));
  f.m_cacheW_B = r.Vec3("rotation.angular_velocity");
  if (valid && !AllFinite(f.m_cacheW_B)) r.Fail("rotation.angular_velocity", "must be finite");
  int* axes[3] = {&f.m_a, &f.m_b, &f.m_c};
  for (int* axis : axes) {
    *axis = r.U8("rotation.axes");
    if (*axis > 2) r.Fail("rotation.axes", "must be 0, 1 or 2 (got " + std::to_string(*axis) + ")");
  }
  if (f.m_a == f.m_b || f.m_b == f.m_c || f.m_a == f.m_c) r.Fail("rotation.axes", "must be three different axes");
  f.m_signC = r.F64("rotation.sign");
  if (valid && f.m_signC != 1 && f.m_signC != -1) r.Fail("rotation.sign", "must be 1 or -1");
  f.m_invM = finite("rotation.inverse_momentum", r.F64("rotation.inverse_momentum"));
  f.m_align0 = r.Quat("rotation.align");
  if (valid && !(AllFinite(f.m_align0) && std::abs(f.m_align0.norm() - 1) <= 1e-6)) {
    r.Fail("rotation.align", "must be a finite unit quaternion");
  }
  for (RScalar& a : f.m_amp) a = finite("rotation.amplitudes", r.F64("rotation.amplitudes"));
  f.m_m = r.F64("rotation.parameter"), f.m_mc = r.F64("rotation.complement");
  if (valid && !(f.m_m >= 0 && f.m_m <= 1 && f.m_mc >= 0 && f.m_mc <= 1)) {
    r.Fail("rotation.parameter", "must be an elliptic parameter and its complement, both within [0, 1]");
  }
  f.m_lambda = finite("rotation.phase_rate", r.F64("rotation.phase_rate"));
  // Loop counts: bounded as the step bounds them (kMaxPanels, RFreeRotation.cpp).
  f.m_panels = r.I32("rotation.panels");
  if (f.m_panels < 1 || f.m_panels > 4096) r.Fail("rotation.panels", "must be 1 to 4096");
  f.m_phase = ReadJacobi(r, "rotation.phase", valid);
  for (RJacobiSnCnDn& j : f.m_node) j = ReadJacobi(r, "rotation.nodes", valid);
  f.m_panelStep = ReadJacobi(r, "rotation.panel_step", valid);
  f.m_end = ReadJacobi(r, "rotation.end", valid);
  f.m_periods = finite("rotation.periods", r.F64("rotation.periods"));
  f.m_psiPeriod = finite("rotation.period_precession", r.F64("rotation.period_precession"));
  f.m_hRest = finite("rotation.rest", r.F64("rotation.rest"));
  f.m_periodPanels = r.I32("rotation.period_panels");
  if (f.m_periodPanels < 0 || f.m_periodPanels > 4096) r.Fail("rotation.period_panels", "must be 0 to 4096");
}

// Where a body was last stepped (RBodyCore::m_slotWorld), as the state writes it: not yet
// (0), by this integrator (1), by another (2). Ids are process-wide, so never stored.
std::uint8_t RStateAccess::WorldOf(const RRigidBody& body, const RWorldStep& s) {
  const RBodyCore& b = Core(body);
  return b.m_slotWorld == 0 ? 0 : s.m_sleep.OwnsBody(b.m_slotWorld) ? 1 : 2;
}

void RStateAccess::WriteBody(RWriter& w, const RRigidBody& body, std::uint64_t shapeKey, std::uint8_t world) {
  const RBodyCore& b = Core(body);
  // What the body was made as (RBodyDef), then what game code may change.
  w.String(b.m_name);
  w.U64(shapeKey);
  w.U8(b.m_isStatic ? kStatic : b.m_isKinematic ? kKinematic : kDynamic);
  w.Bool(b.m_responds);
  w.Bool(b.m_oneWay);
  std::uint8_t locks = 0;
  for (int a = 0; a < 3; ++a) locks |= static_cast<std::uint8_t>((b.m_locks.linear[a] ? 1 : 0) << a);
  for (int a = 0; a < 3; ++a) locks |= static_cast<std::uint8_t>((b.m_locks.angular[a] ? 1 : 0) << (3 + a));
  w.U8(locks);
  w.F64(b.m_mass);
  w.Vec3(b.m_I_B);
  w.F64(b.m_restitution), w.F64(b.m_friction);
  w.U32(b.m_id);
  w.U64(b.m_ignore.size());
  for (std::uint32_t id : b.m_ignore) w.U32(id);
  w.U32(b.m_category), w.U32(b.m_mask);
  w.U64(static_cast<std::uint64_t>(b.m_userData));
  w.F64(b.m_linearDamping), w.F64(b.m_angularDamping), w.F64(b.m_gravityScale);
  // The state.
  w.Vec3(b.m_x_W), w.Quat(b.m_q_WB);
  w.Vec3(b.m_v_W), w.Vec3(b.m_w_B), w.Vec3(b.m_w_W);
  w.Vec3(b.m_force_W), w.Vec3(b.m_torque_W);
  w.Vec3(b.m_linearImpulse_W), w.Vec3(b.m_angularImpulse_W);
  w.Bool(b.m_sleeping), w.Bool(b.m_staticMoved);
  w.Bool(b.m_wakeFromSet), w.Vec3(b.m_wakeFromMin_W), w.Vec3(b.m_wakeFromMax_W);
  w.F64(b.m_restTime);
  w.U32(b.m_sleepIsland), w.U32(b.m_slot);
  w.U8(world);
  WriteRotation(w, b.m_rotation);
}

// A body read back: rebuilt from its definition and shape (its mass properties checked
// against the saved ones), then given its state. `worldId`: the loading integrator's id,
// `foreignId`: one no integrator has.
RRigidBody RStateAccess::ReadBody(RReader& r, const RShapeCatalog& shapes, std::uint64_t& shapeKey,
                           std::uint64_t worldId, std::uint64_t foreignId) {
  RBodyDef def;
  def.name = r.String("name");
  shapeKey = r.U64("shape");
  const auto shape = shapes.find(shapeKey);
  if (shape == shapes.end()) {
    r.Fail("shape", "no body of the loading container and no shape of RLoadOptions::shapes has "
                    "this body's shape (key " + Hex(shapeKey) + "): a state of another world, or "
                    "a body removed since whose shape the game must pass");
  }
  def.prepared = shape->second;
  const std::uint8_t kind = r.U8("kind");
  if (kind > kKinematic) r.Fail("kind", "must be 0 (dynamic), 1 (static) or 2 (kinematic)");
  def.kind = kind == kStatic ? RBodyKind::kStatic : kind == kKinematic ? RBodyKind::kKinematic : RBodyKind::kDynamic;
  def.responds = r.Bool("responds");
  def.oneWay = r.Bool("one_way");
  const std::uint8_t locks = r.U8("locks");
  if (locks > 63) r.Fail("locks", "must be 6 bits");
  for (int a = 0; a < 3; ++a) def.locks.linear[a] = (locks >> a) & 1, def.locks.angular[a] = (locks >> (3 + a)) & 1;
  const RScalar mass = r.F64("mass");
  if (kind == kDynamic) def.mass = mass;
  const RVec3 inertia = r.Vec3("inertia");
  def.restitution = r.F64("restitution");
  def.friction = r.F64("friction");
  const std::uint32_t id = r.U32("id");
  if (id != 0xFFFFFFFFu) def.id = id;  // 2^32 - 1: the body has no id
  def.ignore.resize(r.Count("ignore", 4));
  for (std::size_t k = 0; k < def.ignore.size(); ++k) {
    def.ignore[k] = r.U32("ignore");
    if (k > 0 && def.ignore[k - 1] >= def.ignore[k]) r.Fail("ignore", "must be sorted and unique");
  }
  def.category = r.U32("category"), def.mask = r.U32("mask");
  def.userData = static_cast<std::uintptr_t>(r.U64("user_data"));
  def.linearDamping = r.F64("linear_damping");
  def.angularDamping = r.F64("angular_damping");
  def.gravityScale = r.F64("gravity_scale");
  // RRigidBody's own checks (mass, inertia, drag, ...): a state holds what a body can be.
  std::optional<RRigidBody> made;
  try {
    made.emplace(def);
  } catch (const RBodyError& e) {
    r.Fail(e.Field(), e.Problem());
  }
  RBodyCore& b = Core(*made);
  const auto same = [](const RVec3& x, const RVec3& y) {
    return std::memcmp(x.data(), y.data(), sizeof(RScalar) * 3) == 0;
  };
  if (std::memcmp(&b.m_mass, &mass, sizeof mass) != 0 || !same(b.m_I_B, inertia)) {
    r.Fail("inertia", "this build computes other mass properties from the body's shape and mass "
                      "(a state from another build or platform)");
  }
  // Where the API and the scene loader let a body be (RRigidBody::SetShapePose).
  b.m_x_W = r.WithinVec3("position", kMaxPosition);
  b.m_q_WB = r.UnitQuat("orientation");
  b.m_v_W = r.FiniteVec3("velocity");
  b.m_w_B = r.FiniteVec3("angular_velocity_body");
  b.m_w_W = r.FiniteVec3("angular_velocity_world");
  b.m_force_W = r.FiniteVec3("force");
  b.m_torque_W = r.FiniteVec3("torque");
  b.m_linearImpulse_W = r.FiniteVec3("impulse");
  b.m_angularImpulse_W = r.FiniteVec3("angular_impulse");
  b.m_sleeping = r.Bool("sleeping");
  b.m_staticMoved = r.Bool("static_moved");
  b.m_wakeFromSet = r.Bool("wake_from_set");
  b.m_wakeFromMin_W = r.FiniteVec3("wake_from_min");
  b.m_wakeFromMax_W = r.FiniteVec3("wake_from_max");
  b.m_restTime = r.Finite("rest_time");
  if (b.m_restTime < 0) r.Fail("rest_time", "must be >= 0");
  b.m_sleepIsland = r.U32("island");
  b.m_slot = r.U32("slot");
  const std::uint8_t world = r.U8("stepped_by");
  if (world > 2) r.Fail("stepped_by", "must be 0, 1 or 2");
  b.m_slotWorld = world == 0 ? 0 : world == 1 ? worldId : foreignId;
  ReadRotation(r, b.m_rotation);
  b.m_worldForm.stamp = 0;  // recomputed from the pose, to the same bits
  return std::move(*made);
}

void RStateAccess::WriteBodies(RWriter& w, const RWorldStep& s, const std::vector<RRigidBody>& bodies) {
  RShapeKeys keys;
  for (const RRigidBody& b : bodies) WriteBody(w, b, keys.Of(Core(b).m_prepared), WorldOf(b, s));
}

void RStateAccess::WriteContainer(RWriter& w, const RWorldStep& s, const RBodies& bodies) {
  const RBodiesCore& c = Core(bodies);
  w.U8(0);  // an RBodies
  w.U64(c.m_slots.generation.size());
  for (std::uint32_t g : c.m_slots.generation) w.U32(g);
  w.U64(c.m_slots.free.size());
  for (std::uint32_t slot : c.m_slots.free) w.U32(slot);
  w.U64(c.m_enabled);
  w.U64(c.m_slots.items.size());
  for (RBodyHandle h : c.m_slots.handles) w.U32(h.index), w.U32(h.generation);
  w.U64(c.m_wakeIslands.size());
  for (std::uint32_t island : c.m_wakeIslands) w.U32(island);
  w.Bool(c.m_wakeAll);
  w.U64(c.m_wakeBoxes.size());
  for (const RVec3& corner : c.m_wakeBoxes) w.Vec3(corner);
  WriteBodies(w, s, c.m_slots.items);
  WriteJoints(w, bodies);
}

void RStateAccess::WriteContainer(RWriter& w, const RWorldStep& s, const std::vector<RRigidBody>& c) {
  w.U8(1);  // a plain vector
  w.U64(c.size());
  WriteBodies(w, s, c);
}

// Reads the container's tables and bodies; checks that the tables describe a container
// RBodies could have made (every handle's slot live once, at its generation; free slots not
// live, each once).
RStateAccess::RSavedBodies RStateAccess::ReadContainer(RReader& r, const RShapeCatalog& shapes, std::uint64_t worldId,
                                  std::uint64_t foreignId) {
  RSavedBodies out;
  r.SetRecord("container");
  const std::uint8_t kind = r.U8("kind");
  if (kind > 1) r.Fail("kind", "must be 0 (RBodies) or 1 (a plain vector)");
  out.plainVector = kind == 1;
  std::size_t count = 0;
  if (out.plainVector) {
    count = r.Count("bodies", 360);
    out.enabled = count;
  } else {
    out.generation.resize(r.Count("slots", 4));
    for (std::uint32_t& g : out.generation) g = r.U32("generations");
    out.free.resize(r.Count("free", 4));
    for (std::uint32_t& slot : out.free) slot = r.U32("free");
    const std::uint64_t enabled = r.U64("enabled");
    count = r.Count("bodies", 8 + 360);
    if (enabled > count) r.Fail("enabled", "is more than the bodies (" + std::to_string(count) + ")");
    out.enabled = static_cast<std::size_t>(enabled);
    const std::uint32_t kFree = RBodiesCore::kFree;
    out.denseOfSlot.assign(out.generation.size(), kFree);
    out.handles.resize(count);
    for (std::size_t d = 0; d < count; ++d) {
      const RBodyHandle h = ReadHandle(r, "handles");
      if (h.index >= out.generation.size() || out.generation[h.index] != h.generation ||
          out.denseOfSlot[h.index] != kFree) {
        r.Fail(Indexed("handles", d),
               "handle " + HandleText(h) + " is not a live slot of the table, or is named twice");
      }
      out.handles[d] = h;
      out.denseOfSlot[h.index] = static_cast<std::uint32_t>(d);
    }
    std::vector<char> freed(out.generation.size(), 0);
    for (std::uint32_t slot : out.free) {
      if (slot >= out.generation.size() || out.denseOfSlot[slot] != kFree || freed[slot]) {
        r.Fail("free", "slot " + std::to_string(slot) + " is beyond the table, live, or free twice");
      }
      freed[slot] = 1;
    }
    out.wakeIslands.resize(r.Count("wake_islands", 4));
    for (std::uint32_t& island : out.wakeIslands) island = r.U32("wake_islands");
    out.wakeAll = r.Bool("wake_all");
    out.wakeBoxes.resize(r.Count("wake_boxes", 24));
    if (out.wakeBoxes.size() % 2 != 0) r.Fail("wake_boxes", "must hold pairs of corners");
    for (RVec3& corner : out.wakeBoxes) corner = r.FiniteVec3("wake_boxes");
  }
  out.bodies.reserve(count);
  out.shapeKeys.resize(count);
  for (std::size_t d = 0; d < count; ++d) {
    r.SetRecord(Indexed("bodies", d));
    out.bodies.push_back(ReadBody(r, shapes, out.shapeKeys[d], worldId, foreignId));
  }
  if (!out.plainVector) ReadJoints(r, out);
  r.SetRecord("");
  return out;
}

}  // namespace REngine
