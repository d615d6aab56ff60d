// An independent reference for rigid-body rotation: classical RK4 on Euler's equations and
// the quaternion kinematics, nothing shared with the engine's closed-form solution. Its
// global error is O(h^4); tests run it at a step small enough that this error is far below
// the tolerance being checked, and say so.
#pragma once

#include <REngineMath/RMath.h>

namespace REngine::test {

struct RotState {
  RVec3 w_B;   // body-frame angular velocity, rad/s
  RQuat q_WB;  // orientation
};

// Time derivative of (w_B, q_WB) for principal moments I_B and a body-frame torque.
inline void RotDerivative(const RVec3& I_B, const RotState& s, const RVec3& torque_B,
                          RVec3& dw, RVec4& dq) {
  const RVec3 L = I_B.cwiseProduct(s.w_B);
  dw = (L.cross(s.w_B) + torque_B).cwiseQuotient(I_B);
  const RQuat wq(0, s.w_B.x(), s.w_B.y(), s.w_B.z());
  const RQuat qd = s.q_WB * wq;
  dq = 0.5 * RVec4(qd.w(), qd.x(), qd.y(), qd.z());
}

inline RotState RK4Step(const RVec3& I_B, const RotState& s, RScalar h,
                        const RVec3& torque_B = RVec3::Zero()) {
  auto add = [](const RotState& a, const RVec3& dw, const RVec4& dq, RScalar f) {
    RotState r;
    r.w_B = a.w_B + f * dw;
    r.q_WB = RQuat(a.q_WB.w() + f * dq[0], a.q_WB.x() + f * dq[1], a.q_WB.y() + f * dq[2],
                   a.q_WB.z() + f * dq[3]);
    return r;
  };
  RVec3 k1w, k2w, k3w, k4w;
  RVec4 k1q, k2q, k3q, k4q;
  RotDerivative(I_B, s, torque_B, k1w, k1q);
  RotDerivative(I_B, add(s, k1w, k1q, h / 2), torque_B, k2w, k2q);
  RotDerivative(I_B, add(s, k2w, k2q, h / 2), torque_B, k3w, k3q);
  RotDerivative(I_B, add(s, k3w, k3q, h), torque_B, k4w, k4q);
  RotState r = add(s, k1w + 2 * k2w + 2 * k3w + k4w, k1q + 2 * k2q + 2 * k3q + k4q, h / 6);
  r.q_WB.normalize();
  return r;
}

}  // namespace REngine::test
