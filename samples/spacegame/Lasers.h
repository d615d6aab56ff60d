// The ship's laser: a ray cast (RQueries::CastRay) from the nose along the ship's axis, every
// step the trigger is held. What it hits gets the beam's impulse at the hit point
// (RRigidBody::AddImpulseAtPoint_W), so an off-centre hit also spins a rock; a rock that has
// taken enough of it splits into two of the next size down.
#pragma once

#include <optional>
#include <vector>

#include "World.h"

namespace spacegame {

struct LaserTuning {
  double range = 1500;          // m
  double force = 2.0e5;         // N while it plays on a body: its impulse is force * dt a step
  double splitImpulse = 1.5e5;  // N s a rock takes before it splits
  double splitSpeed = 2.5;      // m/s the halves part at, across the beam
};

struct LaserHit {
  RBodyHandle body;
  RVec3 point_W = RVec3::Zero();
  RVec3 impulse_W = RVec3::Zero();  // what the body was given, N s
  bool split = false;               // the rock broke (body is then removed)
};

class Lasers {
 public:
  explicit Lasers(SpaceWorld& world, const LaserTuning& tuning = {});

  // Casts the beam from origin_W along direction_W (any length) and pushes what it hits, the
  // ship and missiles excluded (their categories are not in the beam's mask). Call between
  // steps; the impulse acts at the start of the next.
  std::optional<LaserHit> Fire(const RVec3& origin_W, const RVec3& direction_W);
  // From the ship's nose along its axis.
  std::optional<LaserHit> FireFromShip();
  // What the beam would hit from the ship's nose, without firing (a missile's target).
  RBodyHandle AimFromShip();

  // The beam of the last Fire, for drawing: from, to (the hit or the range's end).
  const RVec3& BeamFrom() const { return m_from; }
  const RVec3& BeamTo() const { return m_to; }
  std::uint64_t Splits() const { return m_splits; }
  const LaserTuning& Tuning() const { return m_tuning; }

 private:
  void Split(RBodyHandle rock, const RVec3& beam_W);
  std::optional<REngine::RRayHit> Cast(const RVec3& origin_W, const RVec3& dir_W);

  SpaceWorld& m_world;
  LaserTuning m_tuning;
  // Beam impulse each asteroid has taken, by slot index (a slot's new body starts at 0:
  // the generation is kept beside it).
  std::vector<double> m_heat;
  std::vector<std::uint32_t> m_heatGeneration;
  RVec3 m_from = RVec3::Zero(), m_to = RVec3::Zero();
  std::uint64_t m_splits = 0;
};

}  // namespace spacegame
