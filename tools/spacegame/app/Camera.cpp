#include "Camera.h"

#include <algorithm>
#include <cmath>

#include "Game.h"

namespace spacegame {
using namespace REngine;

namespace {
// The camera turned to look from eye towards target with `up` as near its +y as it goes.
RQuat LookAt(const RVec3& eye, const RVec3& target, const RVec3& up) {
  const RVec3 back = (eye - target).normalized();  // the camera's +z
  const RVec3 right = up.cross(back).normalized();
  RMat3 R;
  R.col(0) = right, R.col(1) = back.cross(right), R.col(2) = back;
  return RQuat(R);
}
}  // namespace

void Camera::Follow(CameraMode mode, const Game& game, const RVec3& shipPosition_W,
                    const RQuat& shipQ_WS) {
  if (mode == CameraMode::kChase) {
    const RVec3 up = shipQ_WS * RVec3::UnitY(), fwd = shipQ_WS * RVec3::UnitZ();
    eye_W = shipPosition_W - 32.0 * fwd + 11.0 * up + 6.0 * (shipQ_WS * RVec3::UnitX());
    q_WC = LookAt(eye_W, shipPosition_W + 40.0 * fwd, up);
    return;
  }
  // Wide: from above and behind the station's rim, looking at a point between the station
  // and the ship, so the station, the ship and the rocks beyond share the frame; the eye
  // comes in as the ship does, so the ship never shrinks to a dot.
  const RVec3 O = game.World().Config().origin_W;
  const RVec3 target = 0.5 * (O + shipPosition_W);
  const double reach = std::clamp((shipPosition_W - O).norm() / 100, 0.8, 1.6);
  eye_W = O + reach * RVec3(-60, 55, -95);
  q_WC = LookAt(eye_W, target, RVec3::UnitY());
}

Eigen::Matrix4f Camera::View() const {
  Eigen::Matrix4f V = Eigen::Matrix4f::Identity();
  V.topLeftCorner<3, 3>() = q_WC.conjugate().toRotationMatrix().cast<float>();
  return V;
}

Eigen::Matrix4f Camera::Projection(float aspect) const {
  const float f = 1.0f / std::tan(0.5f * fovY);
  Eigen::Matrix4f P = Eigen::Matrix4f::Zero();
  P(0, 0) = f / aspect;
  P(1, 1) = f;
  P(2, 2) = (farPlane + nearPlane) / (nearPlane - farPlane);
  P(2, 3) = 2 * farPlane * nearPlane / (nearPlane - farPlane);
  P(3, 2) = -1;
  return P;
}

}  // namespace spacegame
