// The HUD (Dear ImGui): the last step's profile (ms per phase), the run's physics ms per
// step, the body, contact and sleeping counts, what the game is doing (missiles, splits,
// docking), the conservation figures of the run, and the debug-draw switches.
#pragma once

#include "Game.h"
#include "GameView.h"

namespace spacegame {

struct HudState {
  double framesPerSecond = 0;
  std::uint64_t frame = 0;
  bool autoplay = false;
  bool wideCamera = false;
};

void DrawHud(const Game& game, const HudState& state, DebugDraw& debug);

}  // namespace spacegame
