// The camera: where the eye is (double, world: it lives 1e6 m out like everything else) and
// how it is turned. Drawing is relative to the eye (Renderer.cpp), so the view matrix is a
// rotation only and every float the GPU sees is a distance from the eye, never 1e6 m.
#pragma once

#include <REngineMath/RMath.h>

#include <Eigen/Geometry>

namespace spacegame {

struct Camera {
  REngine::RVec3 eye_W = REngine::RVec3::Zero();
  REngine::RQuat q_WC = REngine::RQuat::Identity();  // camera frame: -z looks, +y up
  float fovY = 1.0f;                                 // rad
  float nearPlane = 0.5f, farPlane = 20000.0f;       // m

  // At `eye`, looking at `target`, turned so that `up` is as near its +y as it goes (world).
  void LookAt(const REngine::RVec3& eye, const REngine::RVec3& target, const REngine::RVec3& up);
  Eigen::Matrix4f View() const;  // rotation only
  Eigen::Matrix4f Projection(float aspect) const;
};

}  // namespace spacegame
