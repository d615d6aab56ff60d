// The autoplay: scripted input for `rengine-spacegame --autoplay` and the tests. It is a
// function of the frame number and the game's state alone (no clock, no randomness), so
// the same build plays the same game on every run, and the final state's hash repeats.
//
// The script: turn towards a big rock ahead and close in, play the laser on it whenever the
// nose is on it, fire a missile at it once the nose is on it from frame 20 and again from
// frame 150; from frame 240 fly to the hub's port (point the main engine along the
// velocity still to be gained, burn, flip to brake) and dock.
#pragma once

#include "Game.h"

namespace spacegame {

class Autoplay {
 public:
  explicit Autoplay(const Game& game);
  ShipInput Input(int frame, const Game& game);

  static constexpr int kFirstMissile = 20;
  static constexpr int kSecondMissile = 150;
  static constexpr int kHeadHome = 240;
  static constexpr double kCrewWalk = 1.5;  // m/s
  // Autoplay frames are this long (s), whatever the display does, so the run is the same.
  static constexpr double kFrameSeconds = 1.0 / 60;

 private:
  // Turns the nose towards dir_W (and levels the wings' spin), writing pitch, yaw and roll.
  static void Steer(const Game& game, const RVec3& dir_W, ShipInput& in);
  RBodyHandle PickTarget(const Game& game, const RVec3& near_W) const;

  RBodyHandle m_target;
  RVec3 m_lastTargetPosition = RVec3::Zero();
  int m_missilesFired = 0;
};

}  // namespace spacegame
