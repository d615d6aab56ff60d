#include "Ship.h"

#include <algorithm>

namespace spacegame {
using namespace REngine;

namespace {
double Clamp1(double x) { return std::clamp(x, -1.0, 1.0); }
}  // namespace

RVec3 ShipForward_W(const SpaceWorld& world) {
  return world.Bodies()[world.Ship()].ShapeOrientation_WS() * RVec3::UnitZ();
}

RVec3 ShipNose_W(const SpaceWorld& world) {
  const RRigidBody& s = world.Bodies()[world.Ship()];
  return s.ShapePosition_W() + s.ShapeOrientation_WS() * RVec3(0, 0, GameShapes::kShipNose);
}

void ApplyShipControl(SpaceWorld& world, const ShipInput& in, const ShipTuning& t) {
  const RRigidBody& ship = world.Bodies()[world.Ship()];
  const RQuat q = ship.ShapeOrientation_WS();
  const RVec3 c = ship.Position_W();  // centre of mass: translation thrusters act through it
  const RVec3 x = q * RVec3::UnitX(), y = q * RVec3::UnitY(), z = q * RVec3::UnitZ();
  auto fire = [&](const RVec3& f, const RVec3& at) {
    if (!f.isZero(0)) world.AddExternalForce(world.Ship(), f, at);
  };
  const double thrust = Clamp1(in.thrust);
  fire((thrust > 0 ? t.mainThrust : t.retroThrust) * thrust * z, c);
  fire(t.rcsThrust * Clamp1(in.strafe) * x, c);
  fire(t.rcsThrust * Clamp1(in.lift) * y, c);
  // Attitude: opposite thrusters at the nose and the tail, a pure couple.
  const RVec3 nose = c + t.rcsArm * z, tail = c - t.rcsArm * z;
  const RVec3 pitchF = t.rcsThrust * Clamp1(in.pitch) * y;  // nose up
  fire(pitchF, nose), fire(-pitchF, tail);
  const RVec3 yawF = t.rcsThrust * Clamp1(in.yaw) * x;  // nose towards +x (left)
  fire(yawF, nose), fire(-yawF, tail);
  const RVec3 left = c + t.rcsArm * x, right = c - t.rcsArm * x;
  const RVec3 rollF = t.rcsThrust * Clamp1(in.roll) * y;  // +x wing up, -x wing down
  fire(rollF, left), fire(-rollF, right);
}

}  // namespace spacegame
