// The state's records (RStateAccess, RStateAccess.h): each part of a world written as a
// record of fixed fields, and read back field for field in the same order into temporaries
// that RWorldState.cpp checks whole before the world is touched.
#include "RStateAccess.h"

#include <algorithm>
#include <utility>

namespace REngine {

using namespace state;

void RStateAccess::WriteSettings(RWriter& w, const RWorldSettings& s) {
  w.Vec3(s.gravity_W);
  w.U8(static_cast<std::uint8_t>(s.restitutionCombine));
  w.U8(static_cast<std::uint8_t>(s.frictionCombine));
  w.I32(s.solverIterations);
  w.F64(s.restitutionThreshold), w.F64(s.penetrationSlop);
  w.F64(s.positionCorrection), w.F64(s.maxPositionCorrection);
  const RWorldSettings::RShortcuts& c = s.shortcuts;
  w.Bool(c.sleeping), w.Bool(c.boundsRejection), w.Bool(c.broadPhase);
  w.Bool(c.broadPhaseAlways), w.Bool(c.staticForms), w.Bool(c.contactReuse);
  w.F64(s.sleepSpeed), w.F64(s.sleepTime);
  w.Bool(s.contactEvents);
}

RWorldSettings RStateAccess::ReadSettings(RReader& r) {
  r.SetRecord("settings");
  RWorldSettings s;
  s.gravity_W = r.FiniteVec3("gravity");
  const auto combine = [&r](const char* field) {
    const std::uint8_t v = r.U8(field);
    if (v > static_cast<std::uint8_t>(RCombineMode::kGeometric)) {
      r.Fail(field, "is not a combine mode (got " + std::to_string(v) + ")");
    }
    return static_cast<RCombineMode>(v);
  };
  s.restitutionCombine = combine("restitution_combine");
  s.frictionCombine = combine("friction_combine");
  s.solverIterations = r.I32("iterations");
  s.restitutionThreshold = r.Finite("restitution_threshold");
  s.penetrationSlop = r.Finite("penetration_slop");
  s.positionCorrection = r.Finite("position_correction");
  s.maxPositionCorrection = r.Finite("max_position_correction");
  RWorldSettings::RShortcuts& c = s.shortcuts;
  c.sleeping = r.Bool("sleeping"), c.boundsRejection = r.Bool("bounds_rejection");
  c.broadPhase = r.Bool("broad_phase"), c.broadPhaseAlways = r.Bool("broad_phase_always");
  c.staticForms = r.Bool("static_forms"), c.contactReuse = r.Bool("contact_reuse");
  s.sleepSpeed = r.Finite("sleep_speed");
  s.sleepTime = r.Finite("sleep_time");
  s.contactEvents = r.Bool("contact_events");
  return s;
}

void RStateAccess::WriteManifold(RWriter& w, const RContactManifold& m) {
  w.U8(static_cast<std::uint8_t>(m.query.status));
  w.F64(m.query.separation);
  w.Vec3(m.query.normal), w.Vec3(m.query.witnessA), w.Vec3(m.query.witnessB);
  w.I32(m.query.gjkIterations), w.I32(m.query.epaIterations);
  w.Vec3(m.normal);
  w.I32(m.pointCount);
  for (const RContactPoint& p : m.points) w.Vec3(p.position), w.F64(p.separation), w.U32(p.featureId);
}

RContactManifold RStateAccess::ReadManifold(RReader& r) {
  RContactManifold m;
  const std::uint8_t status = r.U8("manifold.status");
  if (status > static_cast<std::uint8_t>(RCollisionStatus::kIterationCap)) {
    r.Fail("manifold.status", "is not a collision status (got " + std::to_string(status) + ")");
  }
  m.query.status = static_cast<RCollisionStatus>(status);
  m.query.separation = r.F64("manifold.separation");
  m.query.normal = r.Vec3("manifold.query_normal");
  m.query.witnessA = r.Vec3("manifold.witness_a");
  m.query.witnessB = r.Vec3("manifold.witness_b");
  m.query.gjkIterations = r.I32("manifold.gjk_iterations");
  m.query.epaIterations = r.I32("manifold.epa_iterations");
  m.normal = r.Vec3("manifold.normal");
  m.pointCount = r.I32("manifold.point_count");
  if (m.pointCount < 0 || m.pointCount > 4) {
    r.Fail("manifold.point_count", "must be 0 to 4 (got " + std::to_string(m.pointCount) + ")");
  }
  for (RContactPoint& p : m.points) {
    p.position = r.Vec3("manifold.points.position");
    p.separation = r.F64("manifold.points.separation");
    p.featureId = r.U32("manifold.points.feature");
  }
  return m;
}

// serialOwned(handle, serial): whether that body is in the container with that serial.
void RStateAccess::WriteStep(RWriter& w, const RWorldStep& s, const RSerialOwned& serialOwned) {
  WriteSettings(w, s.m_settings);
  w.U64(s.m_stepCount);
  w.U64(s.m_warmBodyCount), w.U64(s.m_sleepBodyCount);
  w.Bool(s.m_wakeAll);
  w.Vec3(s.m_sleepGravity_W);
  w.Bool(s.m_nonFinite.has_value());
  if (s.m_nonFinite) {
    const RNonFiniteBody& nf = *s.m_nonFinite;
    w.U64(nf.bodyIndex), w.U32(nf.handle.index), w.U32(nf.handle.generation);
    w.String(nf.bodyName);
    w.U64(nf.step);
  }
  w.U64(s.m_warm.size());
  for (const RWorldStep::RWarmStart& ws : s.m_warm) {
    w.U64(ws.pair), w.U32(ws.genA), w.U32(ws.genB), w.U32(ws.feature);
    w.Vec3(ws.point_A);
    w.F64(ws.lambdaN), w.F64(ws.lambdaE);
    for (int k = 0; k < 2; ++k) w.Vec3(ws.tangentImpulse[k]), w.F64(ws.twistImpulse[k]);
  }
  w.U64(s.m_manifolds.size());
  for (const RWorldStep::RManifoldMemory& m : s.m_manifolds) {
    w.U32(m.i), w.U32(m.j);
    w.U32(m.handleA.index), w.U32(m.handleA.generation);
    w.U32(m.handleB.index), w.U32(m.handleB.generation);
    // Serials are process-wide: saved as whether they were the bodies' (a load gives the
    // rebuilt bodies' own), never as numbers.
    w.U8(static_cast<std::uint8_t>((serialOwned(m.handleA, m.serialA) ? 1 : 0) |
                                   (serialOwned(m.handleB, m.serialB) ? 2 : 0)));
    w.Matrix(m.X.R_AB), w.Vec3(m.X.t_AB);
    WriteManifold(w, m.manifold_A);
    w.F64(m.keptMax), w.F64(m.droppedMin);
    // The block and its inverse are read only while hasInverse holds.
    w.Bool(m.hasInverse);
    if (m.hasInverse) w.Matrix(m.K), w.Matrix(m.pinv);
  }
  w.U64(s.m_touching.size());
  for (const RWorldStep::RTouchingPair& t : s.m_touching) {
    w.U32(t.a.index), w.U32(t.a.generation), w.U32(t.b.index), w.U32(t.b.generation);
    w.Vec3(t.point_W), w.Vec3(t.normal_W);
  }
}

RBodyHandle RStateAccess::ReadHandle(RReader& r, const char* field) {
  RBodyHandle h;
  h.index = r.U32(field);
  h.generation = r.U32(field);
  return h;
}

RStateAccess::RSavedStep RStateAccess::ReadStep(RReader& r) {
  RSavedStep s;
  s.settings = ReadSettings(r);
  r.SetRecord("integrator");
  s.stepCount = r.U64("step_count");
  s.warmBodyCount = r.U64("warm_body_count");
  s.sleepBodyCount = r.U64("sleep_body_count");
  s.wakeAll = r.Bool("wake_all");
  s.sleepGravity_W = r.FiniteVec3("sleep_gravity");
  if (r.Bool("has_non_finite")) {
    RNonFiniteBody nf;
    nf.bodyIndex = static_cast<std::size_t>(r.U64("non_finite.body_index"));
    nf.handle = ReadHandle(r, "non_finite.handle");
    nf.bodyName = r.String("non_finite.name");
    nf.step = r.U64("non_finite.step");
    s.nonFinite = std::move(nf);
  }
  // Warm starts: finite (a non-finite impulse is never remembered) and in the order the
  // solver's lookups need, by pair, then feature.
  s.warm.resize(r.Count("warm_starts", 124));
  for (std::size_t k = 0; k < s.warm.size(); ++k) {
    r.SetRecord(Indexed("warm_starts", k));
    RWorldStep::RWarmStart& ws = s.warm[k];
    ws.pair = r.U64("pair");
    ws.genA = r.U32("generation_a"), ws.genB = r.U32("generation_b");
    ws.feature = r.U32("feature");
    ws.point_A = r.FiniteVec3("point");
    ws.lambdaN = r.Finite("normal_impulse");
    ws.lambdaE = r.Finite("end_impulse");
    for (int p = 0; p < 2; ++p) {
      ws.tangentImpulse[p] = r.FiniteVec3("tangent_impulse");
      ws.twistImpulse[p] = r.Finite("twist_impulse");
    }
    if (k > 0) {
      const RWorldStep::RWarmStart& prev = s.warm[k - 1];
      if (!(prev.pair < ws.pair || (prev.pair == ws.pair && prev.feature <= ws.feature))) {
        r.Fail("pair", "is out of order (warm starts are sorted by pair, then feature)");
      }
    }
  }
  s.manifolds.resize(r.Count("manifolds", 399));
  s.manifoldSerials.resize(s.manifolds.size());
  for (std::size_t k = 0; k < s.manifolds.size(); ++k) {
    r.SetRecord(Indexed("manifolds", k));
    RWorldStep::RManifoldMemory& m = s.manifolds[k];
    m.i = r.U32("i"), m.j = r.U32("j");
    if (m.i >= m.j) r.Fail("j", "must be above i (a pair i < j)");
    if (k > 0) {
      const RWorldStep::RManifoldMemory& prev = s.manifolds[k - 1];
      if (!(prev.i < m.i || (prev.i == m.i && prev.j <= m.j))) {
        r.Fail("i", "is out of order (manifolds are sorted by i, then j)");
      }
    }
    m.handleA = ReadHandle(r, "handle_a"), m.handleB = ReadHandle(r, "handle_b");
    s.manifoldSerials[k] = r.U8("serials");
    if (s.manifoldSerials[k] > 3) r.Fail("serials", "must be 0 to 3");
    m.X.R_AB = r.Matrix<3, 3>("relative_rotation");
    m.X.t_AB = r.Vec3("relative_position");
    m.manifold_A = ReadManifold(r);
    m.keptMax = r.F64("kept_max"), m.droppedMin = r.F64("dropped_min");
    m.hasInverse = r.Bool("has_inverse");
    if (m.hasInverse) {
      m.K = r.Matrix<4, 4>("block");
      m.pinv = r.Matrix<4, 4>("block_inverse");
    }
  }
  s.touching.resize(r.Count("touching", 64));
  for (std::size_t k = 0; k < s.touching.size(); ++k) {
    r.SetRecord(Indexed("touching", k));
    RWorldStep::RTouchingPair& t = s.touching[k];
    t.a = ReadHandle(r, "handle_a"), t.b = ReadHandle(r, "handle_b");
    t.point_W = r.Vec3("point"), t.normal_W = r.Vec3("normal");
    if (k > 0) {
      const RWorldStep::RTouchingPair& prev = s.touching[k - 1];
      if (!(prev.a < t.a || (prev.a == t.a && !(t.b < prev.b)))) {
        r.Fail("handle_a", "is out of order (touching pairs are sorted by handles)");
      }
    }
  }
  r.SetRecord("");
  return s;
}


void RStateAccess::WriteJacobi(RWriter& w, const RJacobiSnCnDn& j) { w.F64(j.sn), w.F64(j.cn), w.F64(j.dn); }

RJacobiSnCnDn RStateAccess::ReadJacobi(RReader& r, const char* field) {
  RJacobiSnCnDn j;
  j.sn = r.F64(field), j.cn = r.F64(field), j.dn = r.F64(field);
  return j;
}

// The exact rotation's cache, as it is: the next step reuses it, and what it would compute
// afresh differs in the last bits (its phase is the last step's output, stepped on). Only
// a body of three distinct moments has one: the others' closed forms never touch it.
void RStateAccess::WriteRotation(RWriter& w, const RFreeRotation& f) {
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

void RStateAccess::ReadRotation(RReader& r, RFreeRotation& f) {
  const bool general = r.Bool("rotation.general");
  if (general != (f.m_symmetry == RInertiaSymmetry::kGeneral)) {
    r.Fail("rotation.general", "contradicts the symmetry of the body's moments of inertia");
  }
  if (!general) return;
  f.m_cacheValid = r.Bool("rotation.cache_valid");
  f.m_cacheH = r.F64("rotation.step");
  f.m_cacheW_B = r.Vec3("rotation.angular_velocity");
  int* axes[3] = {&f.m_a, &f.m_b, &f.m_c};
  for (int* axis : axes) {
    *axis = r.U8("rotation.axes");
    if (*axis > 2) r.Fail("rotation.axes", "must be 0, 1 or 2 (got " + std::to_string(*axis) + ")");
  }
  f.m_signC = r.F64("rotation.sign");
  f.m_invM = r.F64("rotation.inverse_momentum");
  f.m_align0 = r.Quat("rotation.align");
  for (RScalar& a : f.m_amp) a = r.F64("rotation.amplitudes");
  f.m_m = r.F64("rotation.parameter"), f.m_mc = r.F64("rotation.complement");
  f.m_lambda = r.F64("rotation.phase_rate");
  // Loop counts: bounded as the step bounds them (kMaxPanels, RFreeRotation.cpp).
  f.m_panels = r.I32("rotation.panels");
  if (f.m_panels < 1 || f.m_panels > 4096) r.Fail("rotation.panels", "must be 1 to 4096");
  f.m_phase = ReadJacobi(r, "rotation.phase");
  for (RJacobiSnCnDn& j : f.m_node) j = ReadJacobi(r, "rotation.nodes");
  f.m_panelStep = ReadJacobi(r, "rotation.panel_step");
  f.m_end = ReadJacobi(r, "rotation.end");
  f.m_periods = r.F64("rotation.periods");
  f.m_psiPeriod = r.F64("rotation.period_precession");
  f.m_hRest = r.F64("rotation.rest");
  f.m_periodPanels = r.I32("rotation.period_panels");
  if (f.m_periodPanels < 0 || f.m_periodPanels > 4096) r.Fail("rotation.period_panels", "must be 0 to 4096");
}

// Where a body was last stepped (RRigidBody::m_slotWorld), as the state writes it: not yet
// (0), by this integrator (1), by another (2). Ids are process-wide, so never stored.
std::uint8_t RStateAccess::WorldOf(const RRigidBody& b, const RWorldStep& s) {
  return b.m_slotWorld == 0 ? 0 : s.m_worldId.Owns(b.m_slotWorld) ? 1 : 2;
}

void RStateAccess::WriteBody(RWriter& w, const RRigidBody& b, std::uint64_t shapeKey, std::uint8_t world) {
  // What the body was made as (RBodyDef), then what game code may change.
  w.String(b.m_name);
  w.U64(shapeKey);
  w.U8(b.m_isStatic ? kStatic : b.m_isKinematic ? kKinematic : kDynamic);
  w.Bool(b.m_responds);
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
  const std::uint8_t locks = r.U8("locks");
  if (locks > 63) r.Fail("locks", "must be 6 bits");
  for (int a = 0; a < 3; ++a) def.locks.linear[a] = (locks >> a) & 1, def.locks.angular[a] = (locks >> (3 + a)) & 1;
  const RScalar mass = r.F64("mass");
  if (kind == kDynamic) def.mass = mass;
  const RVec3 inertia = r.Vec3("inertia");
  def.restitution = r.F64("restitution");
  def.friction = r.F64("friction");
  def.id = r.U32("id");
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
  RRigidBody& b = *made;
  const auto same = [](const RVec3& x, const RVec3& y) {
    return std::memcmp(x.data(), y.data(), sizeof(RScalar) * 3) == 0;
  };
  if (std::memcmp(&b.m_mass, &mass, sizeof mass) != 0 || !same(b.m_I_B, inertia)) {
    r.Fail("inertia", "this build computes other mass properties from the body's shape and mass "
                      "(a state from another build or platform)");
  }
  b.m_x_W = r.FiniteVec3("position");
  b.m_q_WB = r.Quat("orientation");
  if (!AllFinite(b.m_q_WB) || !(std::abs(b.m_q_WB.norm() - 1) <= 1e-6)) {
    r.Fail("orientation", "must be a finite unit quaternion");
  }
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
  return std::move(b);
}

void RStateAccess::WriteBodies(RWriter& w, const RWorldStep& s, const std::vector<RRigidBody>& bodies) {
  RShapeKeys keys;
  for (const RRigidBody& b : bodies) WriteBody(w, b, keys.Of(b.m_prepared), WorldOf(b, s));
}

void RStateAccess::WriteContainer(RWriter& w, const RWorldStep& s, const RBodies& c) {
  w.U8(0);  // an RBodies
  w.U64(c.m_generation.size());
  for (std::uint32_t g : c.m_generation) w.U32(g);
  w.U64(c.m_free.size());
  for (std::uint32_t slot : c.m_free) w.U32(slot);
  w.U64(c.m_enabled);
  w.U64(c.m_bodies.size());
  for (RBodyHandle h : c.m_handles) w.U32(h.index), w.U32(h.generation);
  w.U64(c.m_wakeIslands.size());
  for (std::uint32_t island : c.m_wakeIslands) w.U32(island);
  w.Bool(c.m_wakeAll);
  w.U64(c.m_wakeBoxes.size());
  for (const RVec3& corner : c.m_wakeBoxes) w.Vec3(corner);
  WriteBodies(w, s, c.m_bodies);
  WriteJoints(w, c);
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
    const std::uint32_t kFree = RBodies::kFree;
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
