#include "Lasers.h"

#include "Ship.h"

namespace spacegame {
using namespace REngine;

Lasers::Lasers(SpaceWorld& world, const LaserTuning& tuning) : m_world(world), m_tuning(tuning) {}

std::optional<LaserHit> Lasers::FireFromShip() {
  return Fire(ShipNose_W(m_world), ShipForward_W(m_world));
}

std::optional<RRayHit> Lasers::Cast(const RVec3& origin_W, const RVec3& dir_W) {
  RQueryFilter filter;
  // Not the ship that fires it, nor its own missiles flying down the beam.
  filter.mask = ~(category::kShip | category::kMissile);
  return m_world.Queries().CastRay(m_world.Bodies(), {origin_W, dir_W, m_tuning.range}, filter);
}

RBodyHandle Lasers::AimFromShip() {
  const std::optional<RRayHit> ray = Cast(ShipNose_W(m_world), ShipForward_W(m_world));
  return ray ? ray->body : RBodyHandle{};
}

std::optional<LaserHit> Lasers::Fire(const RVec3& origin_W, const RVec3& direction_W) {
  RBodies& bodies = m_world.Bodies();
  const RVec3 dir = direction_W.normalized();
  m_from = origin_W;
  m_to = origin_W + m_tuning.range * dir;
  const std::optional<RRayHit> ray = Cast(origin_W, dir);
  if (!ray) return std::nullopt;
  m_to = ray->point_W;
  LaserHit hit;
  hit.body = ray->body;
  hit.point_W = ray->point_W;
  RRigidBody& b = bodies[ray->body];
  if (b.Kind() != RBodyKind::kDynamic) return hit;  // the station takes it without moving

  hit.impulse_W = m_tuning.force * m_world.StepDt() * dir;
  b.AddImpulseAtPoint_W(hit.impulse_W, hit.point_W);
  m_world.AddExternalImpulse(hit.impulse_W, hit.point_W);

  if (RoleOf(b) != Role::kAsteroid || SizeClassOf(b) == 0) return hit;
  const std::uint32_t slot = ray->body.index;
  if (slot >= m_heat.size()) m_heat.resize(slot + 1, 0), m_heatGeneration.resize(slot + 1, 0);
  if (m_heatGeneration[slot] != ray->body.generation) {
    m_heatGeneration[slot] = ray->body.generation;
    m_heat[slot] = 0;
  }
  // The beam's dose, force dt a step: as a number, not the norm of the impulse along the
  // beam, whose last bits follow the beam's direction (the split would then come a step
  // early or late as the rock's 45th dose lands a rounding under or over splitImpulse).
  m_heat[slot] += m_tuning.force * m_world.StepDt();
  if (m_heat[slot] >= m_tuning.splitImpulse) {
    Split(ray->body, dir);
    hit.split = true;
  }
  return hit;
}

// The rock is replaced by two of the next size down, side by side across the beam, parting
// at splitSpeed, each with the rock's velocity and spin: a game's split, not a fracture
// model. The impulse just given is lost with the rock (it never reached a step).
void Lasers::Split(RBodyHandle rock, const RVec3& beam_W) {
  RBodies& bodies = m_world.Bodies();
  const RRigidBody& b = bodies[rock];
  const int size = SizeClassOf(b) - 1;
  const RVec3 x = b.Position_W(), v = b.Velocity_W(), w = b.AngularVelocity_W();
  const RQuat q = b.ShapeOrientation_WS();
  // Take the rock's momentum out of the ledger, and the beam's impulse it never felt.
  m_world.NoteDespawn(b);
  m_world.AddExternalImpulse(-m_tuning.force * m_world.StepDt() * beam_W, x);
  const int variant = int(rock.index % kRockVariants);
  bodies.Remove(rock);
  RVec3 across, other;
  OrthonormalBasis(beam_W, across, other);
  const double gap = kRockRadius[size] * 1.05;
  for (int side = -1; side <= 1; side += 2) {
    m_world.AddAsteroid(size, (variant + side + kRockVariants) % kRockVariants,
                        x + side * gap * across, q, v + side * m_tuning.splitSpeed * across, w);
  }
  ++m_splits;
}

}  // namespace spacegame
