#include "Autoplay.h"

#include <REngineMath/RFunctions.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace spacegame {
using namespace REngine;

Autoplay::Autoplay(const Game& game) {
  const RVec3 ahead = ShipNose_W(game.World()) + 150 * ShipForward_W(game.World());
  m_target = PickTarget(game, ahead);
}

// The largest rock nearest to a point (size weighs in as 60 m of distance a class), so
// the laser has something that splits.
RBodyHandle Autoplay::PickTarget(const Game& game, const RVec3& near_W) const {
  const RBodies& bodies = game.World().Bodies();
  RBodyHandle best;
  double bestScore = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < bodies.EnabledCount(); ++i) {
    const RRigidBody& b = bodies.At(i);
    if (RoleOf(b) != Role::kAsteroid) continue;
    const double score = (b.Position_W() - near_W).norm() - 60.0 * SizeClassOf(b);
    if (score < bestScore) bestScore = score, best = bodies.HandleAt(i);
  }
  return best;
}

void Autoplay::Steer(const Game& game, const RVec3& dir_W, ShipInput& in) {
  const RRigidBody& ship = game.World().Bodies()[game.World().Ship()];
  const RQuat q = ship.ShapeOrientation_WS();
  const RVec3 f = q * RVec3::UnitZ();
  const RVec3 d = dir_W.normalized();
  // The turn that takes f onto d, in the ship's frame; aim for an angular velocity along
  // it that slows as the error shrinks, and let the thrusters chase that velocity.
  const RVec3 axis_S = q.conjugate() * f.cross(d);
  const double angle = REngine::Atan2(axis_S.norm(), f.dot(d));
  const RVec3 want_S = axis_S.norm() > 1e-12
                           ? RVec3(std::min(0.8, 1.5 * angle) * axis_S.normalized())
                           : RVec3::Zero();
  const RVec3 w_S = q.conjugate() * ship.AngularVelocity_W();
  const RVec3 e = 3.0 * (want_S - w_S);
  // Ship.cpp: yaw turns about +y, pitch about -x (nose up), roll about +z.
  in.yaw = std::clamp(e.y(), -1.0, 1.0);
  in.pitch = std::clamp(-e.x(), -1.0, 1.0);
  in.roll = std::clamp(-3.0 * w_S.z(), -1.0, 1.0);
}

ShipInput Autoplay::Input(int frame, const Game& game) {
  ShipInput in;
  // Inside the station the crew member walks round the ring the whole time.
  in.crewWalk = kCrewWalk;
  const SpaceWorld& world = game.World();
  const RBodies& bodies = world.Bodies();
  const RRigidBody& ship = bodies[world.Ship()];
  const RQuat q = ship.ShapeOrientation_WS();

  if (frame < kHeadHome) {
    if (!bodies.Contains(m_target)) m_target = PickTarget(game, m_lastTargetPosition);
    if (!m_target.IsValid()) return in;
    const RRigidBody& rock = bodies[m_target];
    m_lastTargetPosition = rock.Position_W();
    const RVec3 to = rock.Position_W() - ShipNose_W(world);
    Steer(game, to, in);
    const double cosAim = std::clamp(to.normalized().dot(q * RVec3::UnitZ()), -1.0, 1.0);
    const double aim = REngine::Atan2(std::sqrt((1 - cosAim) * (1 + cosAim)), cosAim);
    // Close to 80 m at no more than 12 m/s.
    const double closing = ship.Velocity_W().dot(to.normalized());
    const double want = std::clamp(0.1 * (to.norm() - 80), -12.0, 12.0);
    in.thrust = aim < 0.3 ? std::clamp(0.5 * (want - closing), -1.0, 1.0) : 0;
    // The beam holds fire while a missile is on its way: a rock split under it would leave
    // the missile nothing to home on.
    in.laser = frame >= 15 && aim < 0.05 && game.MissileSystem().InFlight() == 0;
    const int nextMissile = m_missilesFired == 0   ? kFirstMissile
                            : m_missilesFired == 1 ? kSecondMissile
                                                   : -1;
    if (nextMissile >= 0 && frame >= nextMissile && aim < 0.05) {
      in.fireMissile = true;
      ++m_missilesFired;
    }
    return in;
  }

  // Home to the hub's port: the velocity wanted is towards the port at the speed from which
  // 2.5 m/s^2 stops the ship there (at most 25 m/s); the nose turns along the velocity still
  // to be gained and the main engine burns when it is on it, so the ship flips to brake.
  const Docking& dock = game.DockingClamp();
  if (dock.IsDocked()) return in;
  const RVec3 to = dock.PortPosition_W(0) - ship.ShapePosition_W();
  const double d = to.norm();
  const RVec3 wantV = dock.PortVelocity_W(0) + std::min(25.0, std::sqrt(2 * 2.5 * d)) * (to / d);
  const RVec3 dv = wantV - ship.Velocity_W();
  if (dv.norm() > 0.3) {
    Steer(game, dv, in);
    const double along = dv.normalized().dot(q * RVec3::UnitZ());
    in.thrust = along > 0.95 ? std::clamp(0.15 * dv.norm(), 0.0, 1.0) : 0;
  }
  const RVec3 dv_S = q.conjugate() * dv;  // the small rest by the side thrusters
  in.strafe = std::clamp(0.8 * dv_S.x(), -1.0, 1.0);
  in.lift = std::clamp(0.8 * dv_S.y(), -1.0, 1.0);
  int nearest = -1;
  in.dockToggle = dock.NearestPort(nearest) < 20 && nearest == 0 &&
                  (ship.Velocity_W() - dock.PortVelocity_W(0)).norm() < 5;
  return in;
}

}  // namespace spacegame
