#include "Camera.h"

#include <cmath>

namespace spacegame {
using namespace REngine;

void Camera::LookAt(const RVec3& eye, const RVec3& target, const RVec3& up) {
  eye_W = eye;
  const RVec3 back = (eye - target).normalized();  // the camera's +z
  const RVec3 right = up.cross(back).normalized();
  RMat3 R;
  R.col(0) = right, R.col(1) = back.cross(right), R.col(2) = back;
  q_WC = RQuat(R);
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
