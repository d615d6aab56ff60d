#include "Docking.h"

#include <REngineMath/RQuaternion.h>

#include <limits>

namespace spacegame {
using namespace REngine;

Docking::Docking(SpaceWorld& world, const DockTuning& tuning) : m_world(world), m_tuning(tuning) {
  // Port 0: on the hub's top, the ship standing on its tail above the axis, nose down into
  // the hub (on the axis, the port turns without moving). Ports 1 and 2: lying on the
  // ring's top face at opposite sides, nose along the ring's direction of travel, carried
  // round at ring speed.
  DockPort hub;
  hub.p_SP = RVec3(0, GameShapes::kStationHubHalfHeight + GameShapes::kShipNose + 0.2, 0);
  hub.q_SP = RQuat::FromTwoVectors(RVec3::UnitZ(), -RVec3::UnitY());
  m_ports.push_back(hub);
  const double R = GameShapes::kStationRingRadius;
  const double y = GameShapes::kStationRingHalfAxial + GameShapes::kShipHalfHeight + 0.1;
  for (int side = 0; side < 2; ++side) {
    const double a = side * kPi;
    const RQuat around = REngine::QuatAxisAngle(RVec3::UnitY(), -a);
    DockPort ring;
    ring.p_SP = around * RVec3(R, y, 0);
    // At +x the ring moves towards -z for a spin about +y: the ship's nose (+z) along that.
    ring.q_SP = around * REngine::QuatAxisAngle(RVec3::UnitY(), kPi);
    m_ports.push_back(ring);
  }
}

RVec3 Docking::PortPosition_W(int port) const {
  const RRigidBody& st = m_world.Bodies()[m_world.Station()];
  return st.ShapePosition_W() + st.ShapeOrientation_WS() * m_ports[port].p_SP;
}

RQuat Docking::PortOrientation_W(int port) const {
  const RRigidBody& st = m_world.Bodies()[m_world.Station()];
  return st.ShapeOrientation_WS() * m_ports[port].q_SP;
}

RVec3 Docking::PortVelocity_W(int port) const {
  const RRigidBody& st = m_world.Bodies()[m_world.Station()];
  return st.Velocity_W() + st.AngularVelocity_W().cross(PortPosition_W(port) - st.Position_W());
}

double Docking::NearestPort(int& port) const {
  const RVec3 x = m_world.Bodies()[m_world.Ship()].ShapePosition_W();
  double best = std::numeric_limits<double>::infinity();
  port = -1;
  for (int k = 0; k < int(m_ports.size()); ++k) {
    const double d = (PortPosition_W(k) - x).norm();
    if (d < best) best = d, port = k;
  }
  return best;
}

bool Docking::TryDock() {
  if (IsDocked()) return false;
  int port = -1;
  if (NearestPort(port) > m_tuning.captureDistance) return false;
  const RRigidBody& ship = m_world.Bodies()[m_world.Ship()];
  if ((ship.Velocity_W() - PortVelocity_W(port)).norm() > m_tuning.captureSpeed) return false;
  DockAt(port);
  return true;
}

void Docking::DockAt(int port) {
  if (IsDocked()) Undock();
  RBodies& bodies = m_world.Bodies();
  RRigidBody& ship = bodies[m_world.Ship()];
  const RRigidBody& st = bodies[m_world.Station()];
  m_world.NoteDespawn(ship);  // the clamp's pull is the game's doing, not the solver's
  ship.SetShapePose(PortPosition_W(port), PortOrientation_W(port));
  // Moving with the port: the velocity of the station's point under the ship's centre of
  // mass and the station's spin, so the weld starts satisfied at the velocity level too.
  ship.SetVelocity_W(st.Velocity_W() +
                     st.AngularVelocity_W().cross(ship.Position_W() - st.Position_W()));
  ship.SetAngularVelocity_W(st.AngularVelocity_W());
  m_world.NoteSpawn(ship);
  RJointDef weld;
  weld.type = RJointType::kFixed;
  weld.a = m_world.Ship();
  weld.b = m_world.Station();
  weld.anchor_W = ship.Position_W();
  m_joint = bodies.AddJoint(weld);
  m_port = port;
}

void Docking::Undock() {
  if (!IsDocked()) return;
  RBodies& bodies = m_world.Bodies();
  bodies.RemoveJoint(m_joint);
  m_joint = {};
  // Push off along the ports' outward direction, the station's axis (+y of its frame).
  RRigidBody& ship = bodies[m_world.Ship()];
  const RVec3 out = bodies[m_world.Station()].ShapeOrientation_WS() * RVec3::UnitY();
  const RVec3 j = ship.Mass() * m_tuning.undockSpeed * out;
  ship.AddImpulse_W(j);
  m_world.AddExternalImpulse(j, ship.Position_W());
  m_port = -1;
}

}  // namespace spacegame
