#include "Missiles.h"

#include <REngineMath/RFunctions.h>
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RContactEvents.h>

#include <algorithm>
#include <cmath>

namespace spacegame {
using namespace REngine;

Missiles::Missiles(SpaceWorld& world, int missiles, int debris, const MissileTuning& tuning)
    : m_world(world), m_tuning(tuning) {
  RBodies& bodies = world.Bodies();
  // Parked far below the scene: a disabled body touches nothing, but where it waits is
  // where a query would meet it if it were enabled by mistake.
  const RVec3 park = world.Config().origin_W + RVec3(0, -5000, 0);
  for (int k = 0; k < missiles; ++k) {
    RBodyDef d;
    d.prepared = world.Shapes().missile;
    d.mass = 200;
    d.position_W = park + RVec3(10.0 * k, 0, 0);
    d.responds = false;
    d.gravityScale = 0;
    d.category = category::kMissile;
    d.userData = PackUserData(Role::kMissile);
    Slot s;
    s.body = bodies.Add(d);
    bodies.Disable(s.body);
    m_slots.push_back(s);
  }
  for (int k = 0; k < debris; ++k) {
    RBodyDef d;
    d.prepared = world.Shapes().debris;
    d.mass = 30;
    d.position_W = park + RVec3(10.0 * k, 20, 0);
    d.restitution = 0.2;
    d.friction = 0.8;
    d.gravityScale = 0;
    d.category = category::kDebris;
    d.userData = PackUserData(Role::kDebris);
    const RBodyHandle h = bodies.Add(d);
    bodies.Disable(h);
    m_debris.push_back(h);
  }
  m_found.reserve(64);
  m_lastExplosions.reserve(8);
}

bool Missiles::IsMissile(RBodyHandle h) const {
  return std::any_of(m_slots.begin(), m_slots.end(), [h](const Slot& s) { return s.body == h; });
}

int Missiles::InFlight() const {
  return int(std::count_if(m_slots.begin(), m_slots.end(), [](const Slot& s) { return s.live; }));
}

RBodyHandle Missiles::Fire(RBodyHandle launcher, const RVec3& position_W, const RVec3& direction_W,
                           RBodyHandle target) {
  auto free = std::find_if(m_slots.begin(), m_slots.end(), [](const Slot& s) { return !s.live; });
  if (free == m_slots.end()) return {};
  RBodies& bodies = m_world.Bodies();
  // Read before Enable, which may move bodies in the container's storage.
  const RVec3 launcherVelocity = bodies[launcher].Velocity_W();
  const RVec3 dir = direction_W.normalized();
  bodies.Enable(free->body);
  RRigidBody& m = bodies[free->body];
  // The pool keeps its bodies, so the ignore list only grows; the same launcher again adds
  // nothing (the engine keeps the list sorted and unique).
  bodies.IgnoreCollisions(free->body, launcher);
  // The capsule's axis is its S frame's y: turn y onto the flight direction.
  m.SetShapePose(position_W, RQuat::FromTwoVectors(RVec3::UnitY(), dir));
  m.SetVelocity_W(launcherVelocity + m_tuning.launchSpeed * dir);
  m.SetAngularVelocity_W(RVec3::Zero());
  m_world.NoteSpawn(m);
  free->launcher = launcher;
  free->target = target;
  free->age = 0;
  free->live = true;
  return free->body;
}

void Missiles::BeforeStep() {
  RBodies& bodies = m_world.Bodies();
  for (Slot& s : m_slots) {
    if (!s.live || s.age >= m_tuning.burnTime) continue;
    RRigidBody& m = bodies[s.body];
    const RVec3 axis = m.ShapeOrientation_WS() * RVec3::UnitY();
    RVec3 f = m_tuning.motorForce * axis;
    if (const RRigidBody* t = bodies.Find(s.target); t && bodies.IsEnabled(s.target)) {
      const RVec3 v = m.Velocity_W();
      const RVec3 want = std::max(v.norm(), m_tuning.launchSpeed) *
                         (t->Position_W() - m.Position_W()).normalized();
      RVec3 push = m.Mass() * (want - v) / m_tuning.homingTime;
      push += m_tuning.motorForce * want.normalized();  // and keep accelerating along it
      if (push.norm() > m_tuning.motorForce) push *= m_tuning.motorForce / push.norm();
      f = push;
      // Nose along the velocity: a spin about axis x v at the rate that turns it in a step.
      const RVec3 turn = axis.cross(v.normalized());
      m_world.NoteDespawn(m);  // the ledger takes the spin the game sets
      m.SetAngularVelocity_W(REngine::Asin(std::min(1.0, turn.norm())) / m_world.StepDt() *
                             (turn.norm() > 1e-9 ? RVec3(turn.normalized()) : RVec3::Zero()));
      m_world.NoteSpawn(m);
    }
    m_world.AddExternalForce(s.body, f, m.Position_W());
  }
}

void Missiles::AfterStep() {
  m_lastExplosions.clear();
  RBodies& bodies = m_world.Bodies();
  // Events are sorted by handle, so the first begin a missile meets is the same on every
  // run and every thread count.
  for (const RContactEvent& e : m_world.Integrator().Events()) {
    if (e.type != RContactEventType::kBegin) continue;
    for (Slot& s : m_slots) {
      if (!s.live || (e.handleA != s.body && e.handleB != s.body)) continue;
      const bool missileIsA = e.handleA == s.body;
      const RBodyHandle other = missileIsA ? e.handleB : e.handleA;
      // The normal runs from A to B: outward from what was hit is towards the missile.
      Explode(s, e.point_W, missileIsA ? RVec3(-e.normal_W) : e.normal_W, other);
    }
  }
  for (Slot& s : m_slots) {
    if (!s.live) continue;
    s.age += m_world.StepDt();
    if (s.age >= m_tuning.lifetime) {
      const RRigidBody& m = bodies[s.body];
      Explode(s, m.Position_W(), -(m.ShapeOrientation_WS() * RVec3::UnitY()), {});
    }
  }
}

void Missiles::Explode(Slot& s, const RVec3& point_W, const RVec3& outward_W, RBodyHandle hit) {
  RBodies& bodies = m_world.Bodies();
  const RRigidBody& m = bodies[s.body];
  const RVec3 missileVelocity = m.Velocity_W();
  m_world.NoteDespawn(m);
  bodies.Disable(s.body);
  s.live = false;

  // The blast: an impulse on every dynamic body within the radius, away from the point,
  // through its centre of mass, capped so that light debris is not flung off at km/s.
  m_world.Queries().OverlapSphere(bodies, point_W, m_tuning.blastRadius, m_found);
  for (const RBodyHandle h : m_found) {
    RRigidBody& b = bodies[h];
    if (b.Kind() != RBodyKind::kDynamic) continue;
    const RVec3 r = b.Position_W() - point_W;
    const double d = r.norm();
    const double falloff = std::max(0.0, 1 - d / m_tuning.blastRadius);
    const double j = std::min(m_tuning.blastImpulse * falloff, b.Mass() * m_tuning.maxBlastSpeed);
    if (j <= 0 || d == 0) continue;
    const RVec3 impulse = (j / d) * r;
    b.AddImpulse_W(impulse);
    m_world.AddExternalImpulse(impulse, b.Position_W());
  }
  const RRigidBody* target = bodies.Find(hit);
  const RVec3 base =
      target && target->Kind() == RBodyKind::kDynamic ? target->Velocity_W() : RVec3::Zero();
  SpawnDebris(point_W + 2.0 * outward_W.normalized(), base + 0.2 * missileVelocity,
              outward_W.normalized());
  m_lastExplosions.push_back({point_W, s.body, hit, m_world.Integrator().StepCount()});
  ++m_explosionCount;
}

void Missiles::SpawnDebris(const RVec3& at_W, const RVec3& velocity_W, const RVec3& outward_W) {
  if (m_debris.empty()) return;
  RBodies& bodies = m_world.Bodies();
  RVec3 u, v;
  REngine::OrthonormalBasis(outward_W, u, v);
  for (int k = 0; k < m_tuning.debrisPerBlast; ++k) {
    // A fan about the outward normal, one piece every 2 pi / n, each a metre apart.
    const double a = 2 * kPi * k / m_tuning.debrisPerBlast;
    const RVec3 spread = REngine::Cos(a) * u + REngine::Sin(a) * v;
    const RVec3 dir = (outward_W + 0.8 * spread).normalized();
    const RBodyHandle h = m_debris[m_nextDebris];
    m_nextDebris = (m_nextDebris + 1) % m_debris.size();  // the oldest piece is reused
    if (bodies.IsEnabled(h)) {
      m_world.NoteDespawn(bodies[h]);
    } else {
      bodies.Enable(h);
    }
    RRigidBody& d = bodies[h];
    const RVec3 p = at_W + 1.2 * spread;
    d.SetShapePose(p, REngine::QuatAxisAngle(dir, a));
    d.SetVelocity_W(velocity_W + m_tuning.debrisSpeed * dir);
    d.SetAngularVelocity_W(2.0 * spread.cross(dir));
    d.SetGravityScale(m_world.InBay(p) ? 1 : 0);
    m_world.NoteSpawn(d);
  }
}

}  // namespace spacegame
