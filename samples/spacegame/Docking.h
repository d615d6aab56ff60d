// Docking: a clamp on the station holds the ship with a weld (RBodies::AddJoint, kFixed)
// to the spinning kinematic station, so the ship is carried round with it and nothing the
// ship does can push the station (a kinematic body is infinitely heavy to the solver).
//
// A port is the pose the ship's shape frame S takes in the station's shape frame when it
// is docked there. Docking is allowed within a capture distance and below a closing speed;
// the clamp then draws the ship onto the port (sets its pose and velocity to the port's:
// the clamp's arms are not simulated) and welds it. Joined bodies do not collide
// (RJointDef::collideConnected is false), so the ship may sit snug against the hull.
#pragma once

#include <REnginePhysics/RJoint.h>

#include <vector>

#include "World.h"

namespace spacegame {

struct DockPort {
  RVec3 p_SP = RVec3::Zero();      // ship's origin in the station's frame, m
  RQuat q_SP = RQuat::Identity();  // ship's orientation in the station's frame
};

struct DockTuning {
  double captureDistance = 25;  // m, ship origin to the port
  double captureSpeed = 6;      // m/s, relative to the port's own motion
  double undockSpeed = 2;       // m/s, the push off the port along its outward direction
};

class Docking {
 public:
  explicit Docking(SpaceWorld& world, const DockTuning& tuning = {});

  // Docks the ship at the nearest port within reach (true), or does nothing (false).
  bool TryDock();
  // Docks at a port whatever the distance (the clamp pulls the ship in).
  void DockAt(int port);
  void Undock();
  // Dock when free, undock when docked.
  void Toggle() { IsDocked() ? Undock() : void(TryDock()); }
  bool IsDocked() const { return m_joint.IsValid(); }
  int DockedPort() const { return m_port; }

  const std::vector<DockPort>& Ports() const { return m_ports; }
  // Where port k is now (world pose of the ship's frame when docked there).
  RVec3 PortPosition_W(int port) const;
  RQuat PortOrientation_W(int port) const;
  // The port's velocity at its point (the station's spin), m/s.
  RVec3 PortVelocity_W(int port) const;
  // Distance from the nearest port, m, and which one.
  double NearestPort(int& port) const;
  REngine::RJointHandle Joint() const { return m_joint; }

 private:
  SpaceWorld& m_world;
  DockTuning m_tuning;
  std::vector<DockPort> m_ports;
  REngine::RJointHandle m_joint;
  int m_port = -1;
};

}  // namespace spacegame
