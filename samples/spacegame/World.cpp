#include "World.h"

#include <REngineMath/RQuaternion.h>

#include <cmath>

namespace spacegame {
using namespace REngine;

namespace {
RWorldSettings Settings(const WorldConfig& c) {
  RWorldSettings s;
  // The bay's gravity, felt only by bodies whose gravityScale is 1 (see UpdateBayGravity).
  s.gravity_W = RVec3(0, -c.bayGravity, 0);
  s.threads = c.threads;
  return s;
}
}  // namespace

SpaceWorld::SpaceWorld(const WorldConfig& config)
    : m_config(config), m_shapes(MakeGameShapes(config.seed)), m_integrator(Settings(config)) {
  BuildScene();
}

RBodyHandle SpaceWorld::AddAsteroid(int sizeClass, int variant, const RVec3& position_W,
                                    const RQuat& q_WS, const RVec3& velocity_W,
                                    const RVec3& angularVelocity_W) {
  RBodyDef d;
  d.prepared = m_shapes.rocks[sizeClass][variant];
  d.density = 2500;
  d.position_W = position_W;
  d.q_WS = q_WS;
  d.velocity_W = velocity_W;
  d.angularVelocity_W = angularVelocity_W;
  d.restitution = 0.3;
  d.friction = 0.6;
  d.gravityScale = 0;
  d.category = category::kAsteroid;
  d.userData = PackUserData(Role::kAsteroid, sizeClass);
  const RBodyHandle h = m_bodies.Add(d);
  NoteSpawn(m_bodies[h]);
  return h;
}

void SpaceWorld::BuildScene() {
  const RVec3 O = m_config.origin_W;
  m_bodies.Reserve(512);
  m_forces.reserve(64);

  RBodyDef station;
  station.prepared = m_shapes.station;
  station.kind = RBodyKind::kKinematic;
  station.position_W = O;
  station.angularVelocity_W = RVec3(0, m_config.stationSpin, 0);
  station.restitution = 0.5;  // the station's hull and bay give back half an approach speed
  station.category = category::kStation;
  station.userData = PackUserData(Role::kStation);
  m_station = m_bodies.Add(station);

  RBodyDef bay;
  bay.prepared = m_shapes.bay;
  bay.kind = RBodyKind::kStatic;
  bay.position_W = O + RVec3(0, GameShapes::kBayY, 0);
  bay.restitution = 0.5;
  bay.category = category::kStation;
  bay.userData = PackUserData(Role::kBay);
  m_bay = m_bodies.Add(bay);

  // Crates resting on the bay floor, a little apart: they fall asleep within a second.
  for (int k = 0; k < 4; ++k) {
    RBodyDef crate;
    crate.prepared = m_shapes.crate;
    crate.mass = 400;
    crate.position_W = O + RVec3(-6 + 4.0 * k, GameShapes::kBayY + 1.0, -4 + 2.0 * (k % 2));
    crate.restitution = 0.1;
    crate.category = category::kCrate;
    crate.userData = PackUserData(Role::kCrate);
    m_bodies.Add(crate);
  }

  RBodyDef ship;
  ship.prepared = m_shapes.ship;
  ship.mass = 20000;
  ship.position_W = O + RVec3(70, 15, 40);
  ship.q_WS = REngine::QuatAxisAngle(RVec3::UnitY(), 0.35);
  ship.restitution = 0.2;
  ship.gravityScale = 0;
  ship.category = category::kShip;
  ship.userData = PackUserData(Role::kShip);
  m_ship = m_bodies.Add(ship);

  // The asteroid field: a slab ahead of the ship, rocks drifting and tumbling slowly.
  Rng rng(m_config.seed * 7919 + 1);
  const RVec3 field = O + RVec3(110, 0, 230);
  // A point in the box of half-extents h about the origin, x drawn first: one statement
  // each, as the order a constructor's arguments are evaluated in is the compiler's choice
  // (gcc goes right to left, clang left to right) and the field must be the same for both.
  auto inBox = [&rng](double hx, double hy, double hz) {
    const double x = rng.Uniform(-hx, hx);
    const double y = rng.Uniform(-hy, hy);
    const double z = rng.Uniform(-hz, hz);
    return RVec3(x, y, z);
  };
  for (int k = 0; k < m_config.asteroids; ++k) {
    const int size = k % 7 == 0 ? 2 : k % 3 == 0 ? 1 : 0;
    const RVec3 p = field + inBox(130, 45, 90);
    const RVec3 axis = inBox(1, 1, 1).normalized();
    const RQuat q = REngine::QuatAxisAngle(axis, rng.Uniform(0, 2 * kPi));
    const RVec3 v = inBox(1, 0.5, 1);
    const RVec3 w = rng.Uniform(0.05, 0.4) * axis.cross(RVec3(0.3, 1, 0.2)).normalized();
    AddAsteroid(size, int(rng.Next() % kRockVariants), p, q, v, w);
  }
  UpdateBayGravity();
  m_external = {};  // the ledger counts from the scene as built
}

bool SpaceWorld::InBay(const RVec3& p_W) const {
  const RVec3 r = p_W - m_config.origin_W;
  const double w = GameShapes::kBayHalfWidth;
  // The bay's gravity plating reaches 20 m up, short of the hub (22 m above the floor).
  return std::abs(r.x()) < w && std::abs(r.z()) < w && r.y() > GameShapes::kBayY - 1 &&
         r.y() < GameShapes::kBayY + 20;
}

void SpaceWorld::UpdateBayGravity() {
  for (RRigidBody& b : m_bodies) {
    if (b.Kind() != RBodyKind::kDynamic || RoleOf(b) == Role::kShip) continue;
    const double want = InBay(b.Position_W()) ? 1 : 0;
    if (b.GravityScale() != want) b.SetGravityScale(want);
  }
}

void SpaceWorld::AddExternalImpulse(const RVec3& j_W, const RVec3& at_W) {
  m_external.momentum_W += j_W;
  m_external.angularMomentum_W += (at_W - m_config.origin_W).cross(j_W);
}

void SpaceWorld::AddExternalForce(RBodyHandle body, const RVec3& f_W, const RVec3& at_W) {
  RRigidBody& b = m_bodies[body];
  b.AddForceAtPoint_W(f_W, at_W);
  m_forces.push_back({body, f_W, at_W - b.Position_W(), b.Position_W()});
}

void SpaceWorld::Step() {
  m_integrator.Update(m_bodies, m_config.dt);
  const double dt = m_config.dt;
  for (const PendingForce& f : m_forces) {
    const RRigidBody* b = m_bodies.Find(f.body);
    const RVec3 x1 = b ? b->Position_W() : f.x0_W;
    m_external.momentum_W += f.f_W * dt;
    m_external.angularMomentum_W +=
        (0.5 * (f.x0_W + x1) - m_config.origin_W).cross(f.f_W * dt) + f.arm_W.cross(f.f_W * dt);
  }
  m_forces.clear();
}

void SpaceWorld::NoteBody(const RRigidBody& b, double sign) {
  if (b.Kind() != RBodyKind::kDynamic) return;
  AddExternalImpulse(sign * b.Mass() * b.Velocity_W(), b.Position_W());
  m_external.angularMomentum_W += sign * b.AngularMomentum_W();
}

Conservation SpaceWorld::Measure() const {
  Conservation c;
  for (const RRigidBody& b : m_bodies) {
    if (b.Kind() != RBodyKind::kDynamic) continue;
    const RVec3 p = b.Mass() * b.Velocity_W();
    c.momentum_W += p;
    c.angularMomentum_W += (b.Position_W() - m_config.origin_W).cross(p) + b.AngularMomentum_W();
    c.kineticEnergy += b.LinearKineticEnergy() + b.RotationalKineticEnergy();
  }
  return c;
}

}  // namespace spacegame
