// RCharacter (RCharacter.h): the definition's checks, the commands and one Update, whose
// moves are RCharacterMove.cpp's.
#include <REnginePhysics/RCharacter.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RLimits.h>

#include <REngineMath/RQuaternion.h>

#include "character/RCharacterMove.h"

#include <algorithm>
#include <cmath>

namespace REngine {

namespace {

constexpr RScalar kHalfPi = RScalar(1.5707963267948966);
constexpr std::uint32_t kNoId = 0xFFFFFFFFu;

void RequireCharacter(bool ok, const char* field, const char* problem) {
  if (!ok) throw RCharacterError(field, problem);
}


// The rotation of q about up (its twist): what a turning platform turns the character by.
RQuat TwistAbout(const RQuat& q, const RVec3& up) {
  const RVec3 axis = up * q.vec().dot(up);
  RQuat t(q.w(), axis.x(), axis.y(), axis.z());
  const RScalar n = t.norm();
  if (!(n > RScalar(1e-12))) return RQuat::Identity();  // half a turn about a level axis
  t.coeffs() /= n;
  return t;
}

}  // namespace

RCharacter::RCharacter(const RCharacterDef& def) : m_def(def) {
  if (def.prepared) {
    m_shape = def.prepared;
  } else {
    try {
      m_shape = PrepareShape(def.shape);
    } catch (const RBodyError& e) {
      throw RCharacterError(e.Field(), e.Problem());
    }
  }
  const RShapeType type = m_shape->shape.type;
  RequireCharacter(type != RShapeType::kCompound && type != RShapeType::kMesh, "shape",
          "must be convex: a sphere, box, capsule, cylinder or hull");
  RequireCharacter(AllFinite(def.position_W) && def.position_W.cwiseAbs().maxCoeff() <= kMaxPosition, "position",
          "must be finite and within 1e15 m of the origin");
  const std::optional<RQuat> q = QuatNormalized(def.q_WS);
  RequireCharacter(q.has_value(), "orientation", "must be a finite quaternion of non-zero length");
  RequireCharacter(AllFinite(def.up_W), "up", "must be finite");
  if (def.up_W != RVec3::Zero()) {
    const RScalar n = def.up_W.norm();
    RequireCharacter(std::abs(n - 1) <= RScalar(1e-3), "up", "must be a unit vector (or zero: opposite gravity)");
    m_def.up_W = def.up_W / n;
    m_up = m_def.up_W;
  }
  RequireCharacter(std::isfinite(def.mass) && def.mass > 0 && def.mass <= RScalar(1e30), "mass",
          "must be finite and > 0 (kg)");
  RequireCharacter(std::isfinite(def.maxSlope) && def.maxSlope >= 0 && def.maxSlope < kHalfPi, "max_slope",
          "must be at least 0 and below 90 degrees");
  RequireCharacter(std::isfinite(def.stepHeight) && def.stepHeight >= 0 && def.stepHeight <= RScalar(1e12), "step_height",
          "must be finite and >= 0 (m)");
  RequireCharacter(std::isfinite(def.maxPushForce) && def.maxPushForce >= 0 && def.maxPushForce <= RScalar(1e30),
          "max_push_force", "must be finite and >= 0 (N)");
  RequireCharacter(std::isfinite(def.contactOffset) && def.contactOffset > 0 &&
              def.contactOffset <= RScalar(0.1) * m_shape->boundingRadius,
          "contact_offset", "must be > 0 and at most a tenth of the shape's bounding radius (m)");
  RequireCharacter(!def.id || *def.id != kNoId, "id", "must be 0 to 2^32 - 2");
  for (std::uint32_t id : def.ignore) RequireCharacter(id != kNoId, "ignore", "ids must be 0 to 2^32 - 2");
  std::sort(m_def.ignore.begin(), m_def.ignore.end());
  m_def.ignore.erase(std::unique(m_def.ignore.begin(), m_def.ignore.end()), m_def.ignore.end());
  m_def.prepared = m_shape;
  m_def.q_WS = *q;
  m_cosSlope = std::cos(def.maxSlope);
  m_position = def.position_W;
  m_q = *q;
}

void RCharacter::SetDesiredVelocity(const RVec3& v_W) {
  RequireCharacter(AllFinite(v_W) && v_W.cwiseAbs().maxCoeff() <= RScalar(1e15), "velocity", "must be finite (m/s)");
  m_desired = v_W;
}

void RCharacter::Jump(RScalar speed) {
  RequireCharacter(std::isfinite(speed) && speed > 0 && speed <= RScalar(1e15), "jump", "must be finite and > 0 (m/s)");
  m_jump = speed;
}

void RCharacter::SetPosition(const RVec3& p) {
  RequireCharacter(AllFinite(p) && p.cwiseAbs().maxCoeff() <= kMaxPosition, "position",
          "must be finite and within 1e15 m of the origin");
  m_position = p;
  m_ground = RCharacterGround{};
  m_contacts.clear();
}

void RCharacter::SetVelocity(const RVec3& v) {
  RequireCharacter(AllFinite(v) && v.cwiseAbs().maxCoeff() <= RScalar(1e15), "velocity", "must be finite (m/s)");
  m_velocity = v;
  m_airCarry = RVec3::Zero();
  if (v.dot(m_up) > 0) m_ground.state = RGroundState::kInAir;
}

void RCharacter::Update(RBodies& bodies, RQueries& queries, RScalar dt, const RVec3& gravity_W) {
  RequireCharacter(std::isfinite(dt) && dt > 0 && dt <= RIntegrator::kMaxDt, "dt", "must be finite, > 0 and at most 1 s");
  RequireCharacter(AllFinite(gravity_W), "gravity", "must be finite");
  if (m_def.up_W == RVec3::Zero()) {
    const RScalar g = gravity_W.norm();
    RequireCharacter(g > 0, "up", "is opposite gravity by default: with zero gravity give RCharacterDef::up_W");
    const RVec3 up = -gravity_W / g;
    // Up turned (a station's spin gravity, seen from a point that moves round): the shape
    // turns with it, by the least rotation, so that it keeps standing along up.
    if (m_updates > 0 && up != m_up) {
      m_q = (RQuat::FromTwoVectors(m_up, up) * m_q).normalized();
    }
    m_up = up;
  }
  RCharacterMover mv{*this, bodies, queries, dt, gravity_W, RBodyHandle{}, nullptr, m_scratch};
  const RScalar offset = m_def.contactOffset;
  const RVec3 start = m_position;
  const RScalar gUp = gravity_W.dot(m_up);
  m_passed.clear();
  m_pushed.clear();

  // 1. Carried by what it stands on: to where its place on that body went.
  RVec3 groundVelocity = RVec3::Zero();
  RBodyHandle carrier;
  if (m_ground.state != RGroundState::kInAir) {
    const RRigidBody* g = bodies.Find(m_ground.contact.body);
    if (!g || !bodies.IsEnabled(m_ground.contact.body)) {
      m_ground = RCharacterGround{};
    } else if (!g->IsStatic()) {
      carrier = m_ground.contact.body;
      const RVec3 target = g->Position_W() + g->Orientation_WB() * m_groundLocal;
      mv.skip = carrier;
      mv.carrier = g;
      mv.Slide(target - m_position, false, RVec3::Zero(), false);
      mv.carrier = nullptr;
      mv.skip = RBodyHandle{};
      m_q = (TwistAbout(g->Orientation_WB() * m_groundQ.conjugate(), m_up) * m_q).normalized();
      groundVelocity = SurfaceVelocity(*g, m_position);
    }
  }
  // 2. Pushed by the kinematic bodies it touched, by their surfaces' speed into it; then out
  // of whatever it overlaps.
  for (const RCharacterContact& k : m_contacts) {
    if (k.body == carrier || !bodies.Contains(k.body) || !bodies.IsEnabled(k.body)) continue;
    const RRigidBody& b = bodies[k.body];
    if (!b.IsKinematic()) continue;
    // Relative to what carries it: a wall moving with the deck has carried it already.
    const RRigidBody* g = carrier.IsValid() ? &bodies[carrier] : nullptr;
    const RVec3 carried = g ? SurfaceVelocity(*g, k.point_W) : RVec3::Zero();
    const RScalar in = (SurfaceVelocity(b, k.point_W) - carried).dot(k.normal_W);
    if (in > 0) {
      mv.skip = k.body;
      mv.Slide(k.normal_W * (in * dt), false, RVec3::Zero(), false);
      mv.skip = RBodyHandle{};
    }
  }
  mv.Depenetrate();

  // 3. The motion: along the ground, or in the air under gravity along up.
  const RVec3 across = AcrossUp(m_desired, m_up);
  bool walking = m_ground.state == RGroundState::kOnGround;
  const bool startedOnGround = m_ground.state != RGroundState::kInAir;
  const bool jumped = m_jump > 0 && m_ground.state == RGroundState::kOnGround;
  if (jumped) {
    m_airCarry = AcrossUp(groundVelocity, m_up);
    m_velocity = across + m_airCarry + m_up * (m_jump + groundVelocity.dot(m_up));
    m_ground.state = RGroundState::kInAir;
    walking = false;
  }
  m_jump = 0;
  RVec3 d;
  if (walking) {
    // The horizontal part kept exactly, the vertical part along the ground's slope.
    const RVec3& n = m_ground.surfaceNormal_W;
    d = (across - m_up * (across.dot(n) / n.dot(m_up))) * dt;
    m_velocity = across;
  } else {
    const RScalar vz = m_velocity.dot(m_up);
    const RVec3 level = across + m_airCarry;
    d = level * dt + m_up * (vz * dt + RScalar(0.5) * gUp * dt * dt);
    m_velocity = level + m_up * (vz + gUp * dt);
  }

  // 4. Collide and slide; a wall met walking is tried as a step.
  const RVec3 before = m_position;
  bool steep = false;
  mv.Slide(d, walking, d / dt, true, &steep);
  if (walking && steep) mv.TryStep(before, d, m_position);

  // 5. The ground: kept under it walking down slopes and stairs.
  mv.Collect(2 * offset, m_contacts);
  const auto best = [&]() -> const RCharacterContact* {
    const RCharacterContact* b = nullptr;
    for (const RCharacterContact& k : m_contacts) {
      const RScalar rise = k.normal_W.dot(m_up);
      if (rise > RScalar(1e-6) && (!b || rise > b->normal_W.dot(m_up))) b = &k;
    }
    return b;
  };
  const RCharacterContact* ground = best();
  RVec3 surface = ground ? mv.SurfaceNormal(ground->body, ground->point_W, ground->normal_W) : m_up;
  if (walking && !jumped && (!ground || !mv.Walkable(surface))) {
    const RScalar reach = m_def.stepHeight + 2 * offset;
    const std::optional<RShapeCastHit> hit = mv.Cast(-m_up * reach);
    if (hit && hit->normal_W.dot(m_up) > 0 && mv.Walkable(mv.SurfaceNormal(hit->body, hit->point_W, hit->normal_W))) {
      const RScalar fall = hit->fraction * reach - offset / hit->normal_W.dot(m_up);
      if (fall > 0) m_position -= m_up * fall;
      mv.Collect(2 * offset, m_contacts);
      ground = best();
      surface = ground ? mv.SurfaceNormal(ground->body, ground->point_W, ground->normal_W) : m_up;
    }
  }
  // On walkable ground, at contactOffset above it: a step's landing or a nosing rolled over
  // leaves it a little higher.
  if (ground && !jumped && mv.Walkable(surface) && ground->normal_W.dot(m_up) > 0 &&
      std::abs(ground->distance - offset) > RScalar(1e-3) * offset) {
    const RScalar s = (ground->distance - offset) / ground->normal_W.dot(m_up);
    if (s > 0) mv.Slide(-m_up * s, false, RVec3::Zero(), false);
    else m_position -= m_up * s;
    mv.Collect(2 * offset, m_contacts);
    ground = best();
    surface = ground ? mv.SurfaceNormal(ground->body, ground->point_W, ground->normal_W) : m_up;
  }
  const RGroundState was = m_ground.state;
  m_ground = RCharacterGround{};
  if (ground) {
    // Leaving it (a jump, or still rising in the air): not standing on it. Walking, the
    // character's vertical motion is the ground's (a descending lift included).
    const RScalar rising = jumped || !startedOnGround
                               ? m_velocity.dot(m_up) - ground->surfaceVelocity_W.dot(m_up) : 0;
    if (!(rising > RScalar(1e-6))) {
      m_ground.contact = *ground;
      m_ground.surfaceNormal_W = surface;
      m_ground.state = mv.Walkable(surface) ? RGroundState::kOnGround : RGroundState::kOnSteepGround;
    }
  }
  if (m_ground.state == RGroundState::kOnGround) {
    m_velocity = across;
    m_airCarry = RVec3::Zero();
    RRigidBody& g = bodies[m_ground.contact.body];
    // Its weight on a dynamic body it stands on.
    if (g.Kind() == RBodyKind::kDynamic && gUp < 0) {
      g.AddImpulseAtPoint_W(m_up * (m_def.mass * gUp * dt), m_ground.contact.point_W);
    }
  } else if (m_ground.state == RGroundState::kOnSteepGround) {
    // Sliding down: the vertical speed it moved with, not what gravity would have given.
    m_velocity = AcrossUp(m_velocity, m_up) + m_up * std::min(RScalar(0), (m_position - before).dot(m_up) / dt);
  } else if (was != RGroundState::kInAir && !jumped) {
    // Walked off an edge: it leaves with the ground's velocity.
    m_airCarry = AcrossUp(groundVelocity, m_up);
    m_velocity = across + m_airCarry + m_up * groundVelocity.dot(m_up);
  }
  if (m_ground.state != RGroundState::kInAir) {
    const RRigidBody& g = bodies[m_ground.contact.body];
    m_groundLocal = g.Orientation_WB().conjugate() * (m_position - g.Position_W());
    m_groundQ = g.Orientation_WB();
  }
  // Never past the world's edge (1e15 m), never NaN: back where it was, at rest.
  if (!(AllFinite(m_position) && m_position.cwiseAbs().maxCoeff() <= kMaxPosition)) {
    m_position = start;
    m_velocity = m_airCarry = RVec3::Zero();
    m_ground = RCharacterGround{};
    m_contacts.clear();
  }
  m_moved = (m_position - start) / dt;
  ++m_updates;
}

RCharacter::RState RCharacter::State() const {
  RState s;
  s.position = m_position, s.q = m_q;
  s.velocity = m_velocity, s.desired = m_desired, s.moved = m_moved, s.up = m_up;
  s.jump = m_jump, s.airCarry = m_airCarry, s.ground = m_ground;
  s.groundLocal = m_groundLocal, s.groundQ = m_groundQ, s.updates = m_updates;
  s.contacts = m_contacts;
  return s;
}

void RCharacter::Restore(const RState& s) {
  const auto finite = [](const RVec3& v) { return AllFinite(v) && v.cwiseAbs().maxCoeff() <= kMaxPosition; };
  RequireCharacter(finite(s.position), "position", "must be finite and within 1e15 m of the origin");
  RequireCharacter(AllFinite(s.q) && std::abs(s.q.norm() - 1) <= RScalar(1e-6), "orientation", "must be a unit quaternion");
  RequireCharacter(finite(s.velocity) && finite(s.desired) && finite(s.moved) && finite(s.airCarry), "velocity",
          "must be finite (m/s)");
  RequireCharacter(AllFinite(s.up) && std::abs(s.up.norm() - 1) <= RScalar(1e-6), "up", "must be a unit vector");
  RequireCharacter(std::isfinite(s.jump) && s.jump >= 0, "jump", "must be finite and >= 0 (m/s)");
  RequireCharacter(static_cast<int>(s.ground.state) <= 2, "ground.state", "must be 0, 1 or 2");
  RequireCharacter(finite(s.groundLocal) && AllFinite(s.groundQ) && std::abs(s.groundQ.norm() - 1) <= RScalar(1e-6),
          "ground", "must be finite, its orientation a unit quaternion");
  m_position = s.position, m_q = s.q;
  m_velocity = s.velocity, m_desired = s.desired, m_moved = s.moved, m_up = s.up;
  m_jump = s.jump, m_airCarry = s.airCarry, m_ground = s.ground;
  m_groundLocal = s.groundLocal, m_groundQ = s.groundQ, m_updates = s.updates;
  m_contacts = s.contacts;
}

}  // namespace REngine
