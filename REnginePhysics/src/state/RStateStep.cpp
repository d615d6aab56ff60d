// The integrator's records of a state (RStateAccess, RStateAccess.h): its settings, its
// memory of contacts (warm starts, manifolds, touching pairs) and sleeping's bookkeeping,
// each written as a record of fixed fields and read back field for field into temporaries
// that RWorldState.cpp checks whole before the world is touched.
#include "state/RStateAccess.h"

#include <REnginePhysics/RLimits.h>

#include <cmath>
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
  // Bounded as Update bounds it: a step of 2^31 passes would never end.
  s.solverIterations = r.I32("iterations");
  if (s.solverIterations < 1 || s.solverIterations > RWorldSettings::kMaxSolverIterations) {
    r.Fail("iterations", "must be 1 to " + std::to_string(RWorldSettings::kMaxSolverIterations) + " (got " +
                             std::to_string(s.solverIterations) + ")");
  }
  // Speeds, lengths, fractions and times: a negative one means nothing.
  s.restitutionThreshold = r.NonNegative("restitution_threshold");
  s.penetrationSlop = r.NonNegative("penetration_slop");
  s.positionCorrection = r.NonNegative("position_correction");
  s.maxPositionCorrection = r.NonNegative("max_position_correction");
  RWorldSettings::RShortcuts& c = s.shortcuts;
  c.sleeping = r.Bool("sleeping"), c.boundsRejection = r.Bool("bounds_rejection");
  c.broadPhase = r.Bool("broad_phase"), c.broadPhaseAlways = r.Bool("broad_phase_always");
  c.staticForms = r.Bool("static_forms"), c.contactReuse = r.Bool("contact_reuse");
  s.sleepSpeed = r.NonNegative("sleep_speed");
  s.sleepTime = r.NonNegative("sleep_time");
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
  if (!AllFinite(m.normal)) r.Fail("manifold.normal", "must be finite");
  m.pointCount = r.I32("manifold.point_count");
  if (m.pointCount < 0 || m.pointCount > 4) {
    r.Fail("manifold.point_count", "must be 0 to 4 (got " + std::to_string(m.pointCount) + ")");
  }
  // The points in use are a contact's (in A's frame); the rest are never read.
  for (int k = 0; k < 4; ++k) {
    RContactPoint& p = m.points[k];
    p.position = r.Vec3("manifold.points.position");
    p.separation = r.F64("manifold.points.separation");
    p.featureId = r.U32("manifold.points.feature");
    if (k < m.pointCount && !(AllFinite(p.position) && p.position.cwiseAbs().maxCoeff() <= kMaxSpan)) {
      r.Fail("manifold.points.position", "must be finite and within " + RReader::Number(kMaxSpan));
    }
    if (k < m.pointCount && !std::isfinite(p.separation)) r.Fail("manifold.points.separation", "must be finite");
  }
  return m;
}

// serialOwned(handle, serial): whether that body is in the container with that serial.
void RStateAccess::WriteStep(RWriter& w, const RWorldStep& s, const RSerialOwned& serialOwned) {
  WriteSettings(w, s.m_settings);
  w.U64(s.m_stepCount);
  const RSleeping::RSaved sleep = s.m_sleep.Saved();
  w.U64(s.m_solver.WarmBodyCount()), w.U64(sleep.bodyCount);
  w.Bool(sleep.wakeAll);
  w.Vec3(sleep.gravity_W);
  w.Bool(s.m_motion.NonFinite().has_value());
  if (s.m_motion.NonFinite()) {
    const RNonFiniteBody& nf = *s.m_motion.NonFinite();
    w.U64(nf.bodyIndex), w.U32(nf.handle.index), w.U32(nf.handle.generation);
    w.String(nf.bodyName);
    w.U64(nf.step);
  }
  w.U64(s.m_solver.WarmStarts().size());
  for (const RWarmStart& ws : s.m_solver.WarmStarts()) {
    w.U64(ws.pair), w.U32(ws.genA), w.U32(ws.genB), w.U32(ws.feature);
    w.Vec3(ws.point_A);
    w.F64(ws.lambdaN), w.F64(ws.lambdaE);
    for (int k = 0; k < 2; ++k) w.Vec3(ws.tangentImpulse[k]), w.F64(ws.twistImpulse[k]);
  }
  w.U64(s.m_sweep.Manifolds().size());
  for (const RManifoldMemory& m : s.m_sweep.Manifolds()) {
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
  w.U64(s.m_eventLog.Touching().size());
  for (const RContactEventLog::RTouchingPair& t : s.m_eventLog.Touching()) {
    w.U32(t.a.index), w.U32(t.a.generation), w.U32(t.b.index), w.U32(t.b.generation);
    w.Vec3(t.point_W), w.Vec3(t.normal_W);
  }
  // The contact materials kept while pairs stay in contact (one-way bodies, the callback's).
  w.U64(s.m_materials.Memory().size());
  for (const RContactMaterials::RRemembered& m : s.m_materials.Memory()) {
    w.U32(m.a.index), w.U32(m.a.generation), w.U32(m.b.index), w.U32(m.b.generation);
    w.F64(m.settings.friction), w.F64(m.settings.restitution);
    w.Vec3(m.settings.relativeSurfaceVelocity_W), w.Bool(m.settings.enabled);
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
    if (nf.step > s.stepCount) r.Fail("non_finite.step", "is after the state's step count");
    s.nonFinite = std::move(nf);
  }
  // Warm starts: finite (a non-finite impulse is never remembered) and in the order the
  // solver's lookups need, by pair, then feature.
  s.warm.resize(r.Count("warm_starts", 124));
  for (std::size_t k = 0; k < s.warm.size(); ++k) {
    r.SetRecord(Indexed("warm_starts", k));
    RWarmStart& ws = s.warm[k];
    ws.pair = r.U64("pair");
    // A pair of two slots, the lower first (as the sweep orders a pair's bodies).
    if (!(ws.pair >> 32 < (ws.pair & 0xffffffffu))) r.Fail("pair", "must name two slots, the lower first");
    ws.genA = r.U32("generation_a"), ws.genB = r.U32("generation_b");
    ws.feature = r.U32("feature");
    ws.point_A = r.WithinVec3("point", kMaxSpan);
    ws.lambdaN = r.Within("normal_impulse", kMaxImpulse);
    ws.lambdaE = r.Within("end_impulse", kMaxImpulse);
    for (int p = 0; p < 2; ++p) {
      ws.tangentImpulse[p] = r.WithinVec3("tangent_impulse", kMaxImpulse);
      ws.twistImpulse[p] = r.Within("twist_impulse", kMaxImpulse);
    }
    if (k > 0) {
      const RWarmStart& prev = s.warm[k - 1];
      if (!(prev.pair < ws.pair || (prev.pair == ws.pair && prev.feature <= ws.feature))) {
        r.Fail("pair", "is out of order (warm starts are sorted by pair, then feature)");
      }
    }
  }
  s.manifolds.resize(r.Count("manifolds", 399));
  s.manifoldSerials.resize(s.manifolds.size());
  for (std::size_t k = 0; k < s.manifolds.size(); ++k) {
    r.SetRecord(Indexed("manifolds", k));
    RManifoldMemory& m = s.manifolds[k];
    m.i = r.U32("i"), m.j = r.U32("j");
    if (m.i >= m.j) r.Fail("j", "must be above i (a pair i < j)");
    if (k > 0) {
      const RManifoldMemory& prev = s.manifolds[k - 1];
      if (!(prev.i < m.i || (prev.i == m.i && prev.j <= m.j))) {
        r.Fail("i", "is out of order (manifolds are sorted by i, then j)");
      }
    }
    m.handleA = ReadHandle(r, "handle_a"), m.handleB = ReadHandle(r, "handle_b");
    s.manifoldSerials[k] = r.U8("serials");
    if (s.manifoldSerials[k] > 3) r.Fail("serials", "must be 0 to 3");
    // A pose between two bodies, finite: kept only while it is (a reused manifold moves with it).
    m.X.R_AB = r.Matrix<3, 3>("relative_rotation");
    if (!AllFinite(m.X.R_AB) || m.X.R_AB.cwiseAbs().maxCoeff() > 1 + 1e-6) {
      r.Fail("relative_rotation", "must be a finite rotation");
    }
    m.X.t_AB = r.WithinVec3("relative_position", kMaxSpan);
    m.manifold_A = ReadManifold(r);
    // keptMax: the kept points' largest separation (remembered only when finite);
    // droppedMin: the dropped points' smallest (+infinity when none was dropped).
    m.keptMax = r.Finite("kept_max"), m.droppedMin = r.F64("dropped_min");
    if (std::isnan(m.droppedMin)) r.Fail("dropped_min", "must not be NaN");
    m.hasInverse = r.Bool("has_inverse");
    if (m.hasInverse) {
      m.K = r.Matrix<4, 4>("block");
      m.pinv = r.Matrix<4, 4>("block_inverse");
      if (!AllFinite(m.K)) r.Fail("block", "must be finite");
      if (!AllFinite(m.pinv)) r.Fail("block_inverse", "must be finite");
    }
  }
  s.touching.resize(r.Count("touching", 64));
  for (std::size_t k = 0; k < s.touching.size(); ++k) {
    r.SetRecord(Indexed("touching", k));
    RContactEventLog::RTouchingPair& t = s.touching[k];
    t.a = ReadHandle(r, "handle_a"), t.b = ReadHandle(r, "handle_b");
    // Two bodies, the lower slot first (as the sweep orders a pair's bodies).
    if (!(t.a.index < t.b.index)) r.Fail("handle_b", "must name another body than handle_a, at a higher slot");
    t.point_W = r.FiniteVec3("point"), t.normal_W = r.FiniteVec3("normal");
    if (k > 0) {
      const RContactEventLog::RTouchingPair& prev = s.touching[k - 1];
      if (!(prev.a < t.a || (prev.a == t.a && !(t.b < prev.b)))) {
        r.Fail("handle_a", "is out of order (touching pairs are sorted by handles)");
      }
    }
  }
  s.materials.resize(r.Count("materials", 16 + 8 * 5 + 1));
  for (std::size_t k = 0; k < s.materials.size(); ++k) {
    r.SetRecord(Indexed("materials", k));
    RContactMaterials::RRemembered& m = s.materials[k];
    m.a = ReadHandle(r, "handle_a"), m.b = ReadHandle(r, "handle_b");
    if (!(m.a.index < m.b.index)) r.Fail("handle_b", "must name another body than handle_a, at a higher slot");
    if (k > 0 && !(s.materials[k - 1].a < m.a || (s.materials[k - 1].a == m.a && s.materials[k - 1].b < m.b))) {
      r.Fail("handle_a", "is out of order (materials are sorted by handles)");
    }
    m.settings.friction = r.Finite("friction");
    m.settings.restitution = r.Finite("restitution");
    m.settings.relativeSurfaceVelocity_W = r.FiniteVec3("relative_surface_velocity");
    m.settings.enabled = r.Bool("enabled");
    if (m.settings.friction < 0) r.Fail("friction", "must be >= 0");
    if (m.settings.restitution < 0 || m.settings.restitution > 1) r.Fail("restitution", "must be in [0, 1]");
  }
  r.SetRecord("");
  return s;
}
}  // namespace REngine
