#include "Game.h"

#include <algorithm>
#include <chrono>

namespace spacegame {
using namespace REngine;

Game::Game(const WorldConfig& config)
    : m_world(config), m_missiles(m_world), m_lasers(m_world), m_docking(m_world), m_crew(m_world) {
  m_previous.resize(m_world.Bodies().Size() + 64);
  SavePoses();
  m_initial = m_world.Measure();
}

void Game::Frame(double frameSeconds, const ShipInput& input) {
  m_pendingMissile |= input.fireMissile;
  m_pendingDock |= input.dockToggle;
  m_accumulator += std::clamp(frameSeconds, 0.0, kMaxFrame);
  // A step is owed once the accumulator holds a whole one (less rounding: 1/60 added to
  // itself sixty times is not exactly 1).
  const double dt = m_world.StepDt();
  while (m_accumulator >= dt * (1 - 1e-9)) {
    Step(input);
    m_accumulator = std::max(0.0, m_accumulator - dt);
  }
}

void Game::Step(const ShipInput& input) {
  const bool missile = m_pendingMissile || input.fireMissile;
  const bool dock = m_pendingDock || input.dockToggle;
  m_pendingMissile = m_pendingDock = false;

  SavePoses();
  if (dock) m_docking.Toggle();
  if (!m_docking.IsDocked()) ApplyShipControl(m_world, input);
  if (missile) {
    // Launched from inside the hull, two metres behind the nose: the missile ignores its
    // launcher, so it leaves through the hull as through a launch tube. It homes on what
    // the nose points at, if that is a rock or a crate.
    const RVec3 fwd = ShipForward_W(m_world);
    RBodyHandle target = m_lasers.AimFromShip();
    if (target.IsValid()) {
      const Role role = RoleOf(m_world.Bodies()[target]);
      if (role != Role::kAsteroid && role != Role::kCrate) target = {};
    }
    m_missiles.Fire(m_world.Ship(), ShipNose_W(m_world) - 2.0 * fwd, fwd, target);
  }
  m_laserOn = input.laser;
  if (m_laserOn) m_lasers.FireFromShip();
  m_missiles.BeforeStep();

  const auto t0 = std::chrono::steady_clock::now();
  m_world.Step();
  const auto t1 = std::chrono::steady_clock::now();
  m_timing.totalMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
  ++m_timing.steps;

  m_missiles.AfterStep();
  m_world.UpdateBayGravity();
  m_crew.Step(input.crewWalk);
}

void Game::SavePoses() {
  const RBodies& bodies = m_world.Bodies();
  for (std::size_t i = 0; i < bodies.EnabledCount(); ++i) {
    const RBodyHandle h = bodies.HandleAt(i);
    if (h.index >= m_previous.size()) m_previous.resize(h.index + 64);  // rare: new slots only
    const RRigidBody& b = bodies.At(i);
    m_previous[h.index] = {b.ShapePosition_W(), b.ShapeOrientation_WS(), h.generation};
  }
}

void Game::DrawPose(std::size_t dense, RVec3& position_W, RQuat& q_WS) const {
  const RBodies& bodies = m_world.Bodies();
  const RRigidBody& b = bodies.At(dense);
  const RBodyHandle h = bodies.HandleAt(dense);
  position_W = b.ShapePosition_W();
  q_WS = b.ShapeOrientation_WS();
  if (h.index >= m_previous.size()) return;
  const Pose& prev = m_previous[h.index];
  // A body new since the last step, or one the game moved far (a pooled piece of debris
  // thrown in again), is drawn where it is: interpolating would streak it across the sky.
  if (prev.generation != h.generation || (prev.p - position_W).squaredNorm() > 50.0 * 50.0) return;
  const double a = Alpha();
  // Between the last two steps: the step just taken ends at the current pose, so the
  // drawing lags by up to one step, which is what keeps it smooth.
  position_W = prev.p + a * (position_W - prev.p);
  q_WS = prev.q.slerp(a, q_WS);
}

Conservation Game::Residual() const {
  const Conservation now = m_world.Measure();
  const Conservation& ext = m_world.External();
  Conservation r;
  r.momentum_W = now.momentum_W - m_initial.momentum_W - ext.momentum_W;
  r.angularMomentum_W = now.angularMomentum_W - m_initial.angularMomentum_W - ext.angularMomentum_W;
  r.kineticEnergy = now.kineticEnergy - m_initial.kineticEnergy;
  return r;
}

}  // namespace spacegame
