// The motion of bodies that are not simply free: kinematic bodies, angular locks, the
// inverse inertia the solver sees for them, drag and gravity scales. Integrate
// (RIntegration.cpp) and the solver's set-up (RContactSolver.cpp) call these for the bodies
// that need them; a body without any of it takes the plain free body's path, bit for bit.
#include "motion/RMotion.h"
#include <REngineMath/RFunctions.h>

#include "world/RStepBodies.h"

#include <REngineMath/RQuaternion.h>

#include <algorithm>

namespace REngine {

// With angular locks the body turns only about its free world axes, and the constraint
// torques along the locked ones do no work. Its response to a torque tau (world) is then
// w = (P I_W P)^+ tau, with P the projection on the free axes: the inverse of the inertia
// restricted to them, not the restriction of the inverse (which differ unless the principal
// axes line up with the world's). Only this one is consistent with the kinetic energy
// w . I_W w / 2 of the constrained body, so a collision at restitution 1 conserves it.
// One free axis e: 1 / (e . I_W e) on it; two: the inverse of their 2 x 2 block, whose
// determinant is positive since I_W is (never a NaN, whatever the orientation).
RMat3 RMotion::InvInertia_W(const RBodyCore& b, const RMat3& R_WB) {
  if (b.Immovable()) return RMat3::Zero();
  if (!b.m_angularLocked) return R_WB * b.m_invI_B.asDiagonal() * R_WB.transpose();
  const RMat3 I_W = R_WB * b.m_I_B.asDiagonal() * R_WB.transpose();
  int axes[3];
  int free = 0;
  for (int a = 0; a < 3; ++a) {
    if (b.m_angularMask[a] != 0) axes[free++] = a;
  }
  RMat3 M = RMat3::Zero();
  if (free == 1) {
    M(axes[0], axes[0]) = 1 / I_W(axes[0], axes[0]);
  } else if (free == 2) {
    const int i = axes[0], j = axes[1];
    const RScalar det = I_W(i, i) * I_W(j, j) - I_W(i, j) * I_W(i, j);
    M(i, i) = I_W(j, j) / det;
    M(j, j) = I_W(i, i) / det;
    M(i, j) = M(j, i) = -I_W(i, j) / det;
  }
  return M;
}

// M = -expm1(-x)/x is accurate at every x = c dt > 0. G = (x + expm1(-x))/x^2 loses
// digits to the cancellation in its numerator below x ~ 0.1 (2e-16/x relative), so there it
// is its series, 1/2 - x/6 + x^2/24 - ... = sum (-x)^k/(k+2)!: ten terms leave under
// 0.1^10/12! ~ 2e-19.
RMotion::RDragFlow RMotion::DragFlow(RScalar c, RScalar dt) {
  const RScalar x = c * dt;
  const RScalar em1 = Expm1(-x);
  RScalar G = 0;
  if (x < RScalar(0.1)) {
    // Horner from the highest term: G = 1/2! - x (1/3! - x (1/4! - ...)).
    RScalar inverseFactorial[10];
    RScalar factorial = 2;
    for (int k = 0; k < 10; ++k) inverseFactorial[k] = 1 / factorial, factorial *= k + 3;
    for (int k = 9; k >= 0; --k) G = inverseFactorial[k] - x * G;
  } else {
    G = (x + em1) / (x * x);
  }
  // (x is 0 where c dt underflows: the flow is then the identity, M = 1, not 0/0.)
  return {em1 + 1, x == 0 ? RScalar(1) : -em1 / x, G};
}

RVec3 RMotion::MidStepSpin_W(const RBodyCore& b, const RMat3& R_WB, const RMat3& invI_W,
                             RScalar halfDt) {
  if (b.m_isKinematic) return b.m_w_W;
  RVec3 w = b.m_worldSpin ? b.m_w_W : RVec3(R_WB * b.m_w_B);
  if (b.m_angularDamping != 0) w *= DragFlow(b.m_angularDamping, 2 * halfDt).M;
  const RVec3 kick = StartAngularKick_W(b, halfDt);
  return kick.isZero(0) ? w : RVec3(w + invI_W * kick);
}

// The contact solver's body state (solver/RSolverTypes.h), from the motion's definitions.
void RMotion::InitSolverBody(RSolverBody& s, const RBodyCore& b, const RVec3& vMove, RScalar halfDt,
                             const RVec3& gravity_W) {
  s.invM = b.m_invMass;
  s.accel = b.m_isStatic ? RVec3::Zero() : RMotion::Acceleration(b, gravity_W);
  s.radius = b.m_boundingRadius;
  // A sphere's contact normal passes through its centre: its arm does not turn with it.
  s.armTurns = (b.m_polyhedron_B || b.m_coreHalfHeight > 0 || b.m_childCount > 0 || b.m_mesh) && b.m_invMass != 0;
  s.impulse = b.m_linearImpulse_W, s.angularImpulse = b.m_angularImpulse_W;
  s.linMask = b.m_linearMask, s.linLocked = b.m_linearLocked;
  s.endLinear.setZero(), s.endAngular.setZero(), s.deferredImpulse.setZero();
  s.vp.setZero(), s.wp.setZero(), s.vMid.setZero();
  if (b.m_isStatic) {
    s.v.setZero(), s.w.setZero(), s.invI.setZero();
    return;
  }
  // A kinematic body: its own velocities, the velocity of its surface that the contacts
  // see; infinitely heavy (invM and invI 0, never written by an impulse).
  if (b.m_isKinematic) {
    s.v = b.m_v_W, s.w = b.m_w_W, s.invI.setZero();
    return;
  }
  const RMat3 R = b.m_q_WB.toRotationMatrix();
  s.v = vMove;
  if (b.m_angularLocked || b.m_angularDamping != 0) {
    s.invI = RMotion::InvInertia_W(b, R);
    s.w = RMotion::MidStepSpin_W(b, R, s.invI, halfDt);
    return;
  }
  s.invI = R * b.m_invI_B.asDiagonal() * R.transpose();
  s.w = R * b.m_w_B + s.invI * RMotion::StartAngularKick_W(b, halfDt);
}

// Constant velocities: the centre moves on a line and the body turns about the world axis
// of its spin, q(t) = exp(w t) q(0); one step's rotation exp(w dt) is the same rotation
// every step, so the pose after n steps is the exact one but for rounding.
void RMotion::MoveKinematic(RBodyCore& b, RScalar dt) {
  b.m_x_W += b.m_v_W * dt;
  if (b.m_w_W.isZero(0)) return;
  b.m_q_WB = QuatExp(b.m_w_W * dt) * b.m_q_WB;
  b.m_q_WB.normalize();
  b.m_w_B = b.m_q_WB.conjugate() * b.m_w_W;
}

// A body with angular locks keeps its world spin, which has no component on a locked axis
// (every kick goes through InvInertia_W, zero there). Between the kicks it turns about the
// spin's world axis at a constant rate. With one free axis that is the exact motion: the
// locks' torques keep the spin on that axis, and the inertia about it, e . I_W e, does not
// change as the body turns about e, so the rate is constant. With two free axes it is exact
// when the inertia is the same about every free axis (a sphere, a cube); otherwise it
// leaves out the gyroscopic coupling of the two free axes within a step (first order).
void RMotion::TurnLocked(RBodyCore& b, RScalar dt) {
  const RScalar halfDt = RScalar(0.5) * dt;
  RVec3 w = b.m_w_W;
  if (b.m_angularDamping != 0) w *= DragFlow(b.m_angularDamping, dt).M;
  const RVec3 kick0 = StartAngularKick_W(b, halfDt);
  if (!kick0.isZero(0)) w += InvInertia_W(b, b.m_q_WB.toRotationMatrix()) * kick0;
  if (!w.isZero(0)) {
    b.m_q_WB = QuatExp(w * dt) * b.m_q_WB;
    b.m_q_WB.normalize();
  }
  if (!b.m_torque_W.isZero(0)) {
    w += InvInertia_W(b, b.m_q_WB.toRotationMatrix()) * EndAngularKick_W(b, halfDt);
  }
  b.m_w_W = w;
  b.m_w_B = b.m_q_WB.conjugate() * w;
}

RVec3 RMotion::KinematicDrift_W(const RBodyCore& b, const RVec3& r_W, RScalar dt, bool end) {
  if (!b.m_isKinematic) return RVec3::Zero();
  return SurfaceDrift_W(b.m_w_W, r_W, dt, end);
}

RVec3 RMotion::SurfaceDrift_W(const RVec3& w_W, const RVec3& r_W, RScalar dt, bool end) {
  if (w_W.isZero(0)) return RVec3::Zero();
  const RVec3 chord = QuatExp(w_W * dt) * r_W - r_W;  // the point's displacement, m
  return end ? RVec3(w_W.cross(chord)) : RVec3(chord / dt - w_W.cross(r_W));
}

RScalar RMotion::GravitySpread(const RStepBodies& bodies) {
  RScalar lo = 0, hi = 0;
  for (const RBodyCore& b : bodies) {
    if (b.Immovable()) continue;
    lo = std::min(lo, b.m_gravityScale), hi = std::max(hi, b.m_gravityScale);
  }
  return hi - lo;
}

}  // namespace REngine
