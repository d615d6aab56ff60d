// What the game looks like: its bodies as drawn between steps (Game::DrawPose), coloured by
// role, sleeping ones tinted; the laser's beam; explosion flashes; the debug lines (contact
// points with their normals, bounding boxes, joints); and where the camera looks from.
#pragma once

#include <cstdint>
#include <vector>

#include "Camera.h"
#include "Game.h"
#include "Renderer.h"

namespace spacegame {

struct DebugDraw {
  bool contacts = false;  // manifold points and their normals
  bool bounds = false;    // world bounding boxes
  bool sleeping = true;   // sleeping bodies tinted blue
  bool joints = true;     // joints as lines between the anchor and the bodies' centres
};

enum class CameraMode { kChase, kWide, kCrew };

class GameView {
 public:
  GameView() { m_flashes.reserve(16); }
  // Fills `out` (cleared first) with this frame of the game.
  void Build(const Game& game, const DebugDraw& debug, DrawList& out);
  // Chase: behind and above the ship, looking past it. Wide: over the station's rim, at a
  // point between the station and the ship, so both and the rocks beyond share the frame.
  static void Aim(Camera& camera, CameraMode mode, const Game& game);

 private:
  struct Flash {
    RVec3 point_W;
    double age = 0;  // s
  };
  std::vector<Flash> m_flashes;
  std::uint64_t m_lastStep = 0;
};

}  // namespace spacegame
