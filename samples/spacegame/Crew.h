// Crew: a crew member walking inside the station's ring, an RCharacter with the station's
// spin as its gravity. The ring turns at w about its axis: standing on its inner floor, at
// distance r from the axis, the crew member is pressed outwards at w^2 r (0.42 m/s^2 at the
// ring's 41.6 m with the station's 0.1 rad/s), so its up points at the axis and turns with it.
// Carried by the turning ring (the character keeps its place on what it stands on, exactly),
// it walks round at the speed the game commands, along the floor's flat segments and over
// the creases where they meet.
//
// Not modelled: the Coriolis force on a walker (2 w v, 0.3 m/s^2 at 1.5 m/s), which a
// kinematic controller that walks at the commanded speed leaves out by design, and a jump's
// flight, whose straight line in the world the spin gravity only approximates.
#pragma once

#include <REnginePhysics/RCharacter.h>

#include "World.h"

namespace spacegame {

class Crew {
 public:
  // The crew member on the ring's floor, at the middle of the segment on the station's +x
  // (as the game starts), 2.5 m off the ring's middle plane (clear of the spokes).
  explicit Crew(SpaceWorld& world);
  // After each step of the world: walks round the ring at `walk` m/s (positive: the way the
  // station turns) under the spin gravity where it stands.
  void Step(double walk);
  // The station's spin gravity at a world point, m/s^2: w^2 times the point's distance from
  // the axis, outwards.
  RVec3 SpinGravity_W(const RVec3& p_W) const;
  const REngine::RCharacter& Character() const { return m_character; }
  // Where it is in the station's frame (m), the frame its walk is measured in.
  RVec3 InStation() const;

 private:
  SpaceWorld& m_world;
  REngine::RCharacter m_character;
};

}  // namespace spacegame
