// Flying the ship: thrusters are forces at points of the hull (RRigidBody::AddForceAtPoint_W),
// so turning comes from pairs of thrusters whose forces cancel and whose torques add, as on
// a real ship, and an off-centre thruster also turns it. Nothing here sets a velocity.
#pragma once

#include "World.h"

namespace spacegame {

// What the pilot asks for this frame. Axes in [-1, 1], in the ship frame (+z forward, +y up,
// +x the left wing, right-handed); buttons are edges, each taken once.
struct ShipInput {
  double thrust = 0;   // main engine forward (+) or retro (-)
  double strafe = 0;   // sideways, +x of the ship
  double lift = 0;     // along +y of the ship
  double pitch = 0;    // nose up (+)
  double yaw = 0;      // nose left (+)
  double roll = 0;     // right wing down (+)
  bool laser = false;  // the laser fires every step it is held
  bool fireMissile = false;
  bool dockToggle = false;
  double crewWalk = 0;  // m/s round the station's ring, the crew member's (Crew.h)
};

struct ShipTuning {
  double mainThrust = 4.0e5;   // N
  double retroThrust = 2.0e5;  // N
  double rcsThrust = 6.0e4;    // N, each attitude thruster
  double rcsArm = 6.0;         // m: thrusters at the nose and tail, this far from the centre
};

// Adds the thrusters' forces for the next step. Call before every step the input holds for.
void ApplyShipControl(SpaceWorld& world, const ShipInput& input, const ShipTuning& tuning = {});

// Where the ship's nose is and where it points (world, m; unit), for weapons.
RVec3 ShipNose_W(const SpaceWorld& world);
RVec3 ShipForward_W(const SpaceWorld& world);

}  // namespace spacegame
