// Missiles and the debris they leave. A missile is a capsule that does not respond
// (RBodyDef::responds = false: its contacts are reported, not resolved), ignores the body
// that launched it (RBodies::IgnoreCollisions, by handle, so it can leave from inside the hull),
// burns its motor for a few seconds, and explodes on the first contact event with anything
// else: it is parked, the bodies within the blast radius get an impulse away from it, and
// pieces of debris fly out.
//
// Missiles and debris are pools of bodies made once and parked (RBodies::Disable): firing
// and exploding enable, place and disable them, and allocate nothing.
#pragma once

#include <vector>

#include "World.h"

namespace spacegame {

struct MissileTuning {
  double launchSpeed = 40;      // m/s, added to the launcher's velocity
  double motorForce = 3.0e4;    // N along the missile's axis while it burns
  double homingTime = 0.25;     // s: how fast a homing missile turns its velocity onto the target
  double burnTime = 4.0;        // s
  double lifetime = 8.0;        // s, then it explodes where it is
  double blastRadius = 20;      // m
  double blastImpulse = 4.0e5;  // N s at the centre, falling linearly to 0 at the radius
  double maxBlastSpeed = 25;    // m/s: the most a blast changes a body's speed by
  int debrisPerBlast = 8;
  double debrisSpeed = 9;  // m/s, outward
};

struct Explosion {
  RVec3 point_W = RVec3::Zero();
  RBodyHandle missile;
  RBodyHandle hit;         // what it touched (invalid: its lifetime ran out)
  std::uint64_t step = 0;  // the integrator's step count when it went off
};

class Missiles {
 public:
  Missiles(SpaceWorld& world, int missiles = 8, int debris = 64, const MissileTuning& tuning = {});

  // Launches a missile from `launcher` at position_W along direction_W (any length), with the
  // launcher's velocity plus the launch speed. Invalid handle: every missile is in flight.
  // With a target, it homes on it while the target lives (see BeforeStep).
  RBodyHandle Fire(RBodyHandle launcher, const RVec3& position_W, const RVec3& direction_W,
                   RBodyHandle target = {});
  // Motors, before each step. A homing missile's motor pushes along the velocity it wants
  // (straight at the target, at least its present speed), within the motor's force, and its
  // nose is turned onto its velocity: a game's guidance, not a flight model.
  void BeforeStep();
  // After each step: the step's begin events set missiles off; so does old age.
  void AfterStep();

  // This step's explosions (cleared by AfterStep), and the run's count.
  const std::vector<Explosion>& LastExplosions() const { return m_lastExplosions; }
  std::uint64_t ExplosionCount() const { return m_explosionCount; }
  int InFlight() const;
  bool IsMissile(RBodyHandle h) const;
  const MissileTuning& Tuning() const { return m_tuning; }

 private:
  struct Slot {
    RBodyHandle body;
    RBodyHandle launcher;
    RBodyHandle target;
    double age = 0;
    bool live = false;
  };
  void Explode(Slot& slot, const RVec3& point_W, const RVec3& outward_W, RBodyHandle hit);
  void SpawnDebris(const RVec3& at_W, const RVec3& velocity_W, const RVec3& outward_W);

  SpaceWorld& m_world;
  MissileTuning m_tuning;
  std::vector<Slot> m_slots;
  std::vector<RBodyHandle> m_debris;
  std::size_t m_nextDebris = 0;
  std::vector<RBodyHandle> m_found;  // blast overlap scratch
  std::vector<Explosion> m_lastExplosions;
  std::uint64_t m_explosionCount = 0;
};

}  // namespace spacegame
