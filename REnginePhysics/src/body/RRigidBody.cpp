#include <REnginePhysics/RRigidBody.h>
#include <REngineMath/RFunctions.h>
#include <REnginePhysics/RLimits.h>

#include <REngineMath/RQuaternion.h>

#include "shape/RCompound.h"
#include "collision/RMesh.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace REngine {

namespace {
void Require(bool ok, const char* field, const char* what) {
  if (!ok) throw RBodyError(field, what);
}
bool PositiveFinite(RScalar x) { return std::isfinite(x) && x > 0; }
// BodyEditCount's counter (relaxed: it orders nothing, it only has to change).
std::atomic<std::uint64_t> s_bodyEdits{0};
void CountEdit() { s_bodyEdits.fetch_add(1, std::memory_order_relaxed); }
constexpr RScalar kMaxInertiaRatio = 1e9;
constexpr RScalar kMaxSize = 1e12;       // m
constexpr RScalar kMinThickness = 1e-4;  // of the largest size
constexpr const char* kPositionRange = "must be finite and within 1e15 m of the origin";
// (AllFinite first: Eigen's maxCoeff passes over a NaN.)
bool InRange(const RVec3& p) { return AllFinite(p) && p.cwiseAbs().maxCoeff() <= kMaxPosition; }
// A field the shape's kind does not read must be as RShape leaves it (0, empty): a value
// there was meant for another kind, and ignoring it would hide the mistake.
void RefuseFieldsNotRead(const RShape& s) {
  const RShapeType t = s.type;
  const bool round = t == RShapeType::kSphere || t == RShapeType::kCapsule || t == RShapeType::kCylinder;
  const char* unused = "does not apply to this shape's type (RShape's factories set only what a type reads)";
  Require(round || s.radius == 0, "shape.radius", unused);
  Require(t == RShapeType::kCapsule || t == RShapeType::kCylinder || s.halfHeight == 0, "shape.half_height", unused);
  Require(t == RShapeType::kBox || s.halfExtents == RVec3::Zero(), "shape.half_extents", unused);
  Require(t == RShapeType::kHull || t == RShapeType::kMesh || s.points.empty(), "shape.points", unused);
  Require(t == RShapeType::kMesh || s.triangles.empty(), "shape.triangles", unused);
  Require(t == RShapeType::kCompound || s.children.empty(), "shape.children", unused);
}
}  // namespace

std::uint64_t BodyEditCount() { return s_bodyEdits.load(std::memory_order_relaxed); }

namespace {
std::atomic<std::uint64_t> s_serials{0};
}  // namespace

RBodyCore::RSerial::RSerial() : value(s_serials.fetch_add(1, std::memory_order_relaxed) + 1) {}

namespace {
std::atomic<std::uint64_t> s_definitions{0};
}  // namespace

RBodyCore::RDefinitionStamp::RDefinitionStamp() : value(s_definitions.fetch_add(1, std::memory_order_relaxed) + 1) {}
void RBodyCore::RDefinitionStamp::Bump() { value = s_definitions.fetch_add(1, std::memory_order_relaxed) + 1; }

RBodyCore::RSerial& RBodyCore::RSerial::operator=(const RSerial& other) {
  value = other.value;
  CountEdit();
  return *this;
}

std::shared_ptr<const RPreparedShape> PrepareShape(const RShape& shape) {
  // A type from a cast or a newer header would fall through every case below.
  Require(shape.type == RShapeType::kSphere || shape.type == RShapeType::kBox || shape.type == RShapeType::kHull ||
              shape.type == RShapeType::kCapsule || shape.type == RShapeType::kCylinder ||
              shape.type == RShapeType::kCompound || shape.type == RShapeType::kMesh,
          "shape.type", "must be sphere, box, hull, capsule, cylinder, compound or mesh");
  RefuseFieldsNotRead(shape);
  auto prepared = std::make_shared<RPreparedShape>();
  RPreparedShape& p = *prepared;
  p.shape = shape;
  switch (shape.type) {
    // Sizes within 1e12 m, as hull points are (RConvexPolyhedron::Hull), and a box no
    // thinner than 1e-4 of its size, as a hull: a box 1e134 m wide and 1e-237 m thick had a
    // finite mass and a sane inertia ratio, and overflowed the narrow phase's squares (found
    // by fuzz_narrowphase).
    case RShapeType::kSphere:
      Require(PositiveFinite(shape.radius) && shape.radius <= kMaxSize, "shape.radius",
              "must be finite, > 0 and at most 1e12 m");
      break;
    case RShapeType::kBox: {
      const RVec3& e = shape.halfExtents;
      Require(AllFinite(e) && (e.array() > 0).all() && e.maxCoeff() <= kMaxSize,
              "shape.half_extents", "must be finite, > 0 and at most 1e12 m");
      Require(e.minCoeff() >= kMinThickness * e.maxCoeff(), "shape.half_extents",
              "is too thin: its smallest half extent is below 1e-4 of its largest");
      break;
    }
    case RShapeType::kCapsule:
    case RShapeType::kCylinder:
      Require(PositiveFinite(shape.radius) && shape.radius <= kMaxSize, "shape.radius",
              "must be finite, > 0 and at most 1e12 m");
      Require(PositiveFinite(shape.halfHeight) && shape.halfHeight <= kMaxSize, "shape.half_height",
              "must be finite, > 0 and at most 1e12 m");
      // As a box: a capsule or cylinder 1e-4 as thick as it is long is as thin as the narrow
      // phase takes, and so is a cylinder 1e-4 as tall as it is wide.
      Require(shape.radius >= kMinThickness * shape.halfHeight, "shape.radius",
              "is too thin: below 1e-4 of half_height");
      Require(shape.type == RShapeType::kCapsule || shape.halfHeight >= kMinThickness * shape.radius,
              "shape.half_height", "is too thin: below 1e-4 of radius");
      break;
    case RShapeType::kHull:
    case RShapeType::kCompound:
    case RShapeType::kMesh:
      break;
  }
  if (shape.type == RShapeType::kCompound) {
    PrepareCompound(shape, p);
    return prepared;
  }
  if (shape.type == RShapeType::kMesh) {
    PrepareMesh(shape, p);
    return prepared;
  }
  if (shape.type == RShapeType::kHull) {
    RConvexPolyhedron hull_S;
    try {
      hull_S = RConvexPolyhedron::Hull(shape.points);
    } catch (const RHullError& e) {
      throw RBodyError("shape.points", e.what());
    }
    p.unitMass = ComputeMassProperties(hull_S);
    p.q_BS = p.unitMass.q_SB.conjugate();
    p.p_BS = -(p.q_BS * p.unitMass.com_S);
    p.polyhedron_B = std::make_shared<const RConvexPolyhedron>(
        hull_S.Transformed(p.q_BS.toRotationMatrix(), p.p_BS));
  } else {
    p.unitMass = ComputeMassProperties(shape);
    p.q_BS = p.unitMass.q_SB.conjugate();
    p.p_BS = -(p.q_BS * p.unitMass.com_S);
    if (shape.type == RShapeType::kBox) {
      p.polyhedron_B = std::make_shared<const RConvexPolyhedron>(
          RConvexPolyhedron::Box(shape.halfExtents));
    }
  }
  p.boundingRadius = p.polyhedron_B ? p.polyhedron_B->MaxRadius()
                     : shape.type == RShapeType::kCapsule  ? shape.halfHeight + shape.radius
                     : shape.type == RShapeType::kCylinder ? Hypot(shape.halfHeight, shape.radius)
                                                           : shape.radius;
  return prepared;
}

RRigidBody::RRigidBody(const RBodyDef& def) {
  m_responds = def.responds;
  m_oneWay = def.oneWay;
  m_category = def.category, m_mask = def.mask;
  m_restitution = def.restitution, m_friction = def.friction;
  m_name = def.name;
  m_id = def.id.value_or(kNoId);
  m_ignore = def.ignore;
  m_userData = def.userData;
  Require(!def.id || *def.id != kNoId, "id", "must be 0 to 2^32 - 2");
  for (std::uint32_t other : m_ignore) Require(other != kNoId, "ignore", "ids must be 0 to 2^32 - 2");
  std::sort(m_ignore.begin(), m_ignore.end());
  m_ignore.erase(std::unique(m_ignore.begin(), m_ignore.end()), m_ignore.end());
  m_ignores = !m_ignore.empty();
  Require(std::isfinite(def.restitution) && def.restitution >= 0, "restitution",
          "must be a finite number >= 0");
  Require(std::isfinite(def.friction) && def.friction >= 0, "friction",
          "must be a finite number >= 0");
  RBodyKind kind = def.kind;
  Require(kind == RBodyKind::kDynamic || kind == RBodyKind::kStatic || kind == RBodyKind::kKinematic,
          "kind", "must be dynamic, static or kinematic");
  Require(std::isfinite(def.linearDamping) && def.linearDamping >= 0, "linear_damping",
          "must be a finite number >= 0");
  Require(std::isfinite(def.angularDamping) && def.angularDamping >= 0, "angular_damping",
          "must be a finite number >= 0");
  Require(std::isfinite(def.gravityScale), "gravity_scale", "must be a finite number");
  m_linearDamping = def.linearDamping, m_angularDamping = def.angularDamping;
  m_gravityScale = def.gravityScale;
  m_locks = def.locks;
  for (int a = 0; a < 3; ++a) {
    m_linearMask[a] = def.locks.linear[a] ? 0 : 1;
    m_angularMask[a] = def.locks.angular[a] ? 0 : 1;
  }
  // A static body never moves: its locks mean nothing. A dynamic body locked on all six axes
  // can move neither way, and is infinitely heavy along every one: kinematic, at rest.
  if (kind == RBodyKind::kStatic) m_linearMask.setOnes(), m_angularMask.setOnes();
  m_linearLocked = m_linearMask != RVec3::Ones();
  m_angularLocked = m_angularMask != RVec3::Ones();
  if (kind == RBodyKind::kDynamic && m_linearMask.isZero(0) && m_angularMask.isZero(0)) {
    kind = RBodyKind::kKinematic;
  }
  m_isStatic = kind == RBodyKind::kStatic;
  m_isKinematic = kind == RBodyKind::kKinematic;
  m_worldSpin = m_isKinematic || m_angularLocked;
  // Shape checks first, as a scene lists them (a hull is built after the pose checks).
  if (!def.prepared && def.shape.type != RShapeType::kHull) m_prepared = PrepareShape(def.shape);
  Require(InRange(def.position_W), "position", kPositionRange);
  Require(AllFinite(def.velocity_W), "velocity", "must be finite");
  Require(AllFinite(def.angularVelocity_W), "angular_velocity", "must be finite");
  const std::optional<RQuat> q_WS = QuatNormalized(def.q_WS);
  Require(q_WS.has_value(), "orientation", "must be a finite quaternion of non-zero length");
  if (def.prepared) {
    m_prepared = def.prepared;
  } else if (!m_prepared) {
    m_prepared = PrepareShape(def.shape);
  }
  const RPreparedShape& shape = *m_prepared;
  const RMassProperties& mp = shape.unitMass;
  m_q_BS = shape.q_BS;
  m_p_BS = shape.p_BS;
  m_polyhedron_B = shape.polyhedron_B.get();
  m_boundingRadius = shape.boundingRadius;
  if (m_polyhedron_B) {
    RVec3 lo = RVec3::Constant(std::numeric_limits<RScalar>::infinity()), hi = -lo;
    for (const RVec3& v : m_polyhedron_B->Vertices()) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    m_boxCenter_B = RScalar(0.5) * (lo + hi), m_boxHalf_B = RScalar(0.5) * (hi - lo);
  } else if (shape.shape.type == RShapeType::kCapsule) {
    m_coreHalfHeight = shape.shape.halfHeight, m_coreRadius = shape.shape.radius;
    m_boxHalf_B = RVec3(m_coreRadius, m_coreHalfHeight + m_coreRadius, m_coreRadius);
  } else if (!shape.children.empty()) {
    m_children = shape.children.data(), m_childCount = static_cast<std::uint32_t>(shape.children.size());
    m_boxCenter_B = shape.boxCenter_B, m_boxHalf_B = shape.boxHalf_B;
  } else if (shape.mesh_B) {
    m_mesh = shape.mesh_B.get();
    m_boxCenter_B = shape.boxCenter_B, m_boxHalf_B = shape.boxHalf_B;
  } else if (shape.shape.type == RShapeType::kCylinder) {
    m_coreHalfHeight = shape.shape.halfHeight, m_cylinderRadius = shape.shape.radius;
    m_boxHalf_B = RVec3(m_cylinderRadius, m_coreHalfHeight, m_cylinderRadius);
  } else {
    m_coreRadius = m_boundingRadius;
    m_boxHalf_B = RVec3::Constant(m_boundingRadius);
  }
  // Triangles enclose no volume, so a mesh has no mass to move with: terrain and stations
  // are static, moving platforms kinematic.
  Require(!m_mesh || kind != RBodyKind::kDynamic, "kind",
          "must be static or kinematic for a mesh (a mesh has no volume, so no mass)");
  if (kind == RBodyKind::kDynamic) {
    if (def.mass) {
      Require(PositiveFinite(*def.mass), "mass", "must be finite and > 0");
      m_mass = *def.mass;
    } else {
      Require(PositiveFinite(def.density), "density", "must be finite and > 0");
      m_mass = def.density * mp.volume;
    }
    const char* massField = def.mass ? "mass" : "density";
    Require(PositiveFinite(m_mass), massField, "density * volume is not a positive finite mass");
    m_invMass = 1 / m_mass;
    m_I_B = mp.principalMoments * (m_mass / mp.volume);
    // A mass of 1e-310 is positive and finite, but its inverse is not, and a tiny body's
    // moments underflow to 0: refuse it here rather than let the first step produce
    // infinities (and invert only what is invertible).
    Require(std::isfinite(m_invMass) && AllFinite(m_I_B) && (m_I_B.array() > 0).all(),
            massField, "gives a mass or inertia too small or too large to invert");
    m_invI_B = m_I_B.cwiseInverse();
    Require(AllFinite(m_invI_B), massField,
            "gives a mass or inertia too small or too large to invert");
    // A needle's inertia about its long axis is tiny against the others: an off-centre
    // touch spins it up without limit (a box 1e-9 m thick and 10 m long). 1e9 is the
    // largest ratio of effective masses the contact solver holds (README, stability
    // envelope); a hull at the thinnest RConvexPolyhedron::Hull accepts stays below it.
    const char* shapeField = shape.shape.type == RShapeType::kHull       ? "shape.points"
                             : shape.shape.type == RShapeType::kBox      ? "shape.half_extents"
                             : shape.shape.type == RShapeType::kCompound ? "shape.children"
                                                                        : "shape.radius";  // (a capsule: its radius is what makes it thin)
    Require(m_I_B.maxCoeff() <= kMaxInertiaRatio * m_I_B.minCoeff(), shapeField,
            "is too thin: its largest principal moment exceeds 1e9 times its smallest");
    m_rotation.SetInertia(m_I_B);
  }
  SetShapePose(def.position_W, *q_WS);
  SetVelocity_W(def.velocity_W);
  SetAngularVelocity_W(def.angularVelocity_W);
}

void RBodyCore::WorldBox(RVec3& min_W, RVec3& max_W) const {
  const RMat3 R = m_q_WB.toRotationMatrix();
  const RVec3 centre = m_x_W + R * m_boxCenter_B;
  const RVec3 half = R.cwiseAbs() * m_boxHalf_B;
  min_W = centre - half, max_W = centre + half;
}

void RBodyCore::NoteImmovableEdit() {
  if (!Immovable()) return;
  m_definition.Bump();
  // Where it was at the last step: the poses it is given between two steps held nothing.
  if (m_slotWorld != 0 && !m_wakeFromSet) {
    WorldBox(m_wakeFromMin_W, m_wakeFromMax_W);
    m_wakeFromSet = true;
  }
  m_staticMoved = true;
}

void RRigidBody::SetShapePose(const RVec3& position_W, const RQuat& q) {
  Require(InRange(position_W), "position", kPositionRange);
  const std::optional<RQuat> q_WS = QuatNormalized(q);
  Require(q_WS.has_value(), "orientation", "must be a finite quaternion of non-zero length");
  // A static or kinematic body set to a pose jumps there: the sleepers that rested on it
  // where it was lose their support, and those it lands on are pushed (WakeIslands).
  NoteImmovableEdit();
  m_q_WB = *q_WS * m_q_BS.conjugate();
  m_q_WB.normalize();
  m_x_W = position_W - m_q_WB * m_p_BS;
  m_worldForm.stamp = 0;  // moved outside a step: the cached world form is stale
  if (m_worldSpin) m_w_B = m_q_WB.conjugate() * m_w_W;
  CountEdit();
  Wake();
}

void RBodyCore::ComputeWorldForm(std::uint64_t stamp) const {
  RWorldForm& wf = m_worldForm;
  wf.stamp = stamp;
  ++m_worldFormComputations;
  wf.sphereCenter_W = m_x_W;
  wf.sphereRadius = m_boundingRadius;
  if (m_childCount > 0 || m_mesh) {  // a compound or mesh: its body-frame box turned with it
    const RMat3 R = m_q_WB.toRotationMatrix();
    const RVec3 centre = m_x_W + R * m_boxCenter_B, half = R.cwiseAbs() * m_boxHalf_B;
    wf.aabbMin_W = centre - half;
    wf.aabbMax_W = centre + half;
    return;
  }
  if (m_cylinderRadius > 0) {
    // A cylinder: along world axis k, its axis a reaches h |a_k| and its end discs
    // r sqrt(1 - a_k^2).
    const RVec3 a_W = m_q_WB * RVec3::UnitY();
    const RVec3 e = (m_coreHalfHeight * a_W.cwiseAbs()).array() +
                    m_cylinderRadius * (RVec3::Ones() - a_W.cwiseAbs2()).cwiseMax(RVec3::Zero()).cwiseSqrt().array();
    wf.aabbMin_W = m_x_W - e;
    wf.aabbMax_W = m_x_W + e;
    return;
  }
  if (!m_polyhedron_B && m_coreHalfHeight > 0) {  // a capsule: its core's ends, grown by its radius
    const RVec3 axis_W = m_q_WB * RVec3(0, m_coreHalfHeight, 0);
    wf.aabbMin_W = m_x_W.cwiseMin(m_x_W + axis_W).cwiseMin(m_x_W - axis_W).array() - m_coreRadius;
    wf.aabbMax_W = m_x_W.cwiseMax(m_x_W + axis_W).cwiseMax(m_x_W - axis_W).array() + m_coreRadius;
    return;
  }
  if (!m_polyhedron_B) {
    wf.aabbMin_W = m_x_W.array() - m_boundingRadius;
    wf.aabbMax_W = m_x_W.array() + m_boundingRadius;
    return;
  }
  // Rotate about the centre of mass, then translate: the body-frame vertices are small
  // numbers, so a body 1e7 m out loses nothing but the final addition's rounding.
  const RMat3 R = m_q_WB.toRotationMatrix();
  const std::vector<RVec3>& v_B = m_polyhedron_B->Vertices();
  RVec3 lo = RVec3::Constant(std::numeric_limits<RScalar>::infinity());
  RVec3 hi = -lo;
  for (std::size_t i = 0; i < v_B.size(); ++i) {
    const RVec3 v = R * v_B[i] + m_x_W;
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  wf.aabbMin_W = lo;
  wf.aabbMax_W = hi;
}

bool RRigidBody::ShouldCheckCollision(const RRigidBody& other) const {
  return (m_category & other.m_mask) != 0 && (other.m_category & m_mask) != 0 &&
         !(m_ignores && std::binary_search(m_ignore.begin(), m_ignore.end(), other.m_id)) &&
         !(other.m_ignores && std::binary_search(other.m_ignore.begin(), other.m_ignore.end(), m_id));
}

void RRigidBody::IgnoreCollisionsWith(std::uint32_t otherId) {
  Require(otherId != kNoId, "ignore", "ids must be 0 to 2^32 - 2");
  const auto it = std::lower_bound(m_ignore.begin(), m_ignore.end(), otherId);
  if (it == m_ignore.end() || *it != otherId) m_ignore.insert(it, otherId);
  m_ignores = true;
  m_definition.Bump();
  // A sleeping pair is not looked at: it would never learn to ignore. A static body cannot
  // sleep: the sleepers about it wake, as if it had moved.
  Wake();
  NoteImmovableEdit();
}

void RRigidBody::SetCollisionFilter(std::uint32_t category, std::uint32_t mask) {
  if (category == m_category && mask == m_mask) return;
  m_category = category, m_mask = mask;
  m_definition.Bump();
  CountEdit();  // queries cache the category beside the bounds
  Wake();
  NoteImmovableEdit();
}

void RRigidBody::SetVelocity_W(const RVec3& v_W) {
  Require(AllFinite(v_W), "velocity", "must be finite");
  if (!m_isStatic) m_v_W = m_linearLocked ? RVec3(v_W.cwiseProduct(m_linearMask)) : v_W;
  Wake();
}

void RRigidBody::SetAngularVelocity_W(const RVec3& w_W) {
  Require(AllFinite(w_W), "angular_velocity", "must be finite");
  const RVec3 w = m_angularLocked ? RVec3(w_W.cwiseProduct(m_angularMask)) : w_W;
  // Rotating 1e308 rad/s into the body frame overflows to NaN (found by fuzz_world).
  const RVec3 w_B = m_q_WB.conjugate() * w;
  Require(AllFinite(w_B), "angular_velocity", "is too large to turn into the body frame");
  if (!m_isStatic) m_w_B = w_B, m_w_W = w;
  Wake();
}

void RRigidBody::SetLinearDamping(RScalar c) {
  Require(std::isfinite(c) && c >= 0, "linear_damping", "must be a finite number >= 0");
  m_linearDamping = c;
  m_definition.Bump();
  Wake();
}

void RRigidBody::SetAngularDamping(RScalar c) {
  Require(std::isfinite(c) && c >= 0, "angular_damping", "must be a finite number >= 0");
  m_angularDamping = c;
  m_definition.Bump();
  Wake();
}

void RRigidBody::SetGravityScale(RScalar s) {
  Require(std::isfinite(s), "gravity_scale", "must be a finite number");
  m_gravityScale = s;
  m_definition.Bump();
  Wake();
}

namespace {
// acc + x, refused when x or the sum is not finite: one overflowing force would otherwise
// turn every body it touches non-finite in the next step.
RVec3 FiniteSum(const RVec3& acc, const RVec3& x, const char* field) {
  const RVec3 sum = acc + x;
  Require(AllFinite(x), field, "must be finite");
  Require(AllFinite(sum), field, "makes the accumulated sum overflow");
  return sum;
}
// An impulse the game gives: finite, and each component within kMaxImpulse (RLimits.h).
void CheckImpulse(const RVec3& j, const char* field) {
  Require(AllFinite(j), field, "must be finite");
  Require(j.cwiseAbs().maxCoeff() <= kMaxImpulse, field, "must be within 1e30 (N s or N m s) in each component");
}
}  // namespace

void RRigidBody::AddForce_W(const RVec3& f_W) {
  m_force_W = FiniteSum(m_force_W, f_W, "force");
  WakeIfNonZero(f_W);
}

void RRigidBody::AddTorque_W(const RVec3& t_W) {
  m_torque_W = FiniteSum(m_torque_W, t_W, "torque");
  WakeIfNonZero(t_W);
}

void RRigidBody::AddImpulse_W(const RVec3& j_W) {
  CheckImpulse(j_W, "impulse");
  m_linearImpulse_W = FiniteSum(m_linearImpulse_W, j_W, "impulse");
  WakeIfNonZero(j_W);
}

void RRigidBody::AddAngularImpulse_W(const RVec3& h_W) {
  CheckImpulse(h_W, "angular_impulse");
  m_angularImpulse_W = FiniteSum(m_angularImpulse_W, h_W, "angular_impulse");
  WakeIfNonZero(h_W);
}

namespace {
// x acting at world point p on a body whose centre of mass is at com: x added to `linear`,
// its moment to `angular`; neither changes unless both sums are finite.
void AddAtPoint(RVec3& linear, RVec3& angular, const RVec3& x, const RVec3& p_W,
                const RVec3& com_W, const char* field) {
  Require(AllFinite(p_W), "point", "must be finite");
  const RVec3 sum = FiniteSum(linear, x, field);
  angular = FiniteSum(angular, (p_W - com_W).cross(x), field);
  linear = sum;
}
}  // namespace

void RRigidBody::AddForceAtPoint_W(const RVec3& f_W, const RVec3& p_W) {
  AddAtPoint(m_force_W, m_torque_W, f_W, p_W, m_x_W, "force");
  WakeIfNonZero(f_W);
}

void RRigidBody::AddImpulseAtPoint_W(const RVec3& j_W, const RVec3& p_W) {
  CheckImpulse(j_W, "impulse");
  AddAtPoint(m_linearImpulse_W, m_angularImpulse_W, j_W, p_W, m_x_W, "impulse");
  WakeIfNonZero(j_W);
}

}  // namespace REngine
