// The camera: where the eye is (double, world: it lives 1e6 m out like everything else) and
// how it is turned. Drawing is relative to the eye (Renderer.cpp), so the view matrix is a
// rotation only and every float the GPU sees is a distance from the eye, never 1e6 m.
#pragma once

#include <REngineMath/RMath.h>

#include <Eigen/Geometry>

namespace spacegame {

class Game;

enum class CameraMode { kChase, kWide };

struct Camera {
  REngine::RVec3 eye_W = REngine::RVec3::Zero();
  REngine::RQuat q_WC = REngine::RQuat::Identity();  // camera frame: -z looks, +y up
  float fovY = 1.0f;                                 // rad
  float nearPlane = 0.5f, farPlane = 20000.0f;       // m

  // Behind and above the ship, looking past it (chase); or a fixed view over the station,
  // the ship and the field (wide). `shipPosition_W`, `shipQ_WS`: the ship as drawn.
  void Follow(CameraMode mode, const Game& game, const REngine::RVec3& shipPosition_W,
              const REngine::RQuat& shipQ_WS);
  Eigen::Matrix4f View() const;  // rotation only
  Eigen::Matrix4f Projection(float aspect) const;
};

}  // namespace spacegame
