// Game: the game loop of the REngine design, without a display. Each frame adds its elapsed
// time to an accumulator and steps the world at the fixed dt while a whole step is owed; the
// remainder, as a fraction of dt, is how far the drawing sits between the last two steps
// (DrawPose interpolates each body's pose between them). The fixed step keeps the physics
// the same whatever the frame rate, and the interpolation keeps the motion smooth when the
// frame rate and the step rate differ.
//
// Per step: the ship's thrusters (held input), the one-shot buttons of the frame (a missile,
// the dock clamp), the laser, the missiles' motors; the step; explosions from the step's
// contact events; the bay's gravity.
#pragma once

#include <cstdint>
#include <vector>

#include "Crew.h"
#include "Docking.h"
#include "Lasers.h"
#include "Missiles.h"
#include "Ship.h"
#include "World.h"

namespace spacegame {

// What the HUD shows about the run's steps.
struct StepTiming {
  std::uint64_t steps = 0;
  double totalMs = 0;  // wall-clock time inside RIntegrator::Update, summed
  double MsPerStep() const { return steps ? totalMs / double(steps) : 0; }
};

class Game {
 public:
  explicit Game(const WorldConfig& config = {});

  // Adds frameSeconds to the accumulator (at most kMaxFrame: a stall does not make the
  // game step for seconds to catch up) and takes the steps owed. Button edges in `input`
  // are taken by the first of them (or kept for the next frame if none is owed).
  void Frame(double frameSeconds, const ShipInput& input);
  // One fixed step with this input, whatever the accumulator (tests).
  void Step(const ShipInput& input);

  // Fraction of a step the drawing is past the last step, [0, 1).
  double Alpha() const { return m_accumulator / m_world.StepDt(); }
  // Body at dense index i, posed for drawing: its shape frame between the last two steps.
  void DrawPose(std::size_t dense, RVec3& position_W, RQuat& q_WS) const;

  SpaceWorld& World() { return m_world; }
  const SpaceWorld& World() const { return m_world; }
  Missiles& MissileSystem() { return m_missiles; }
  const Missiles& MissileSystem() const { return m_missiles; }
  Lasers& LaserSystem() { return m_lasers; }
  const Lasers& LaserSystem() const { return m_lasers; }
  const Crew& CrewMember() const { return m_crew; }
  Docking& DockingClamp() { return m_docking; }
  const Docking& DockingClamp() const { return m_docking; }
  const StepTiming& Timing() const { return m_timing; }
  bool LaserOn() const { return m_laserOn; }
  // Conservation at the start, and the change since, less what the game put in or took out.
  const Conservation& Initial() const { return m_initial; }
  Conservation Residual() const;

  static constexpr double kMaxFrame = 0.25;  // s

 private:
  struct Pose {
    RVec3 p = RVec3::Zero();
    RQuat q = RQuat::Identity();
    std::uint32_t generation = ~0u;  // the handle generation it belongs to
  };
  void SavePoses();

  SpaceWorld m_world;
  Missiles m_missiles;
  Lasers m_lasers;
  Docking m_docking;
  Crew m_crew;
  double m_accumulator = 0;
  bool m_pendingMissile = false, m_pendingDock = false, m_laserOn = false;
  std::vector<Pose> m_previous;  // by slot index: the pose before the last step
  StepTiming m_timing;
  Conservation m_initial;
};

}  // namespace spacegame
