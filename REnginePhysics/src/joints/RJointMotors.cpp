// A hinge motor turning a body about a fixed axis, in the Newton rounds (the joint solver's,
// RJointSolver.h; the rounds are RContactSolver::JointRounds).
//
// Why. A motor at its force is a constant torque: tau dt / 2 of impulse at each end of the
// step, as gravity is, which is exact for a body turning about a hinge through its centre of
// mass. With the centre at a distance d from the hinge's axis it is not. The step moves the
// centre along the chord of its arc, whose moment about the axis, m d^2 sin(phi) / dt for a
// turn phi, falls short of the arc's m d^2 phi / dt, and the hinge's impulses, acting on the
// axis, change nothing about it; so the turn that the motor's half impulse buys solves
// I_c phi + m d^2 sin(phi) = I_n omega_mid dt instead of I_n phi = I_n omega_mid dt
// (I_n = I_c + m d^2): the body turns too far by m d^2 (phi - sin phi) / I_n, about
// phi^3 / 6 of it each step (a 4 kg box 0.4 m off its hinge, to 10 rad/s at 60 Hz: 3.7e-2
// rad after 316 steps). Held at its speed, the motor had to give back that shortfall at the
// end of each step, which took more than its half impulse: the speed fell 1.2e-2 rad/s
// short. Where the axis is not a principal axis of the body, the free flow between the
// kicks is not a turn about it either. The spin at the end of each step was right (the
// step's impulse about the axis is tau dt); the turn was not.
//
// How. About a fixed axis a body's moment I_n is constant and nothing that acts through the
// axis turns it, so its turn is what the velocity level gives, as the motor itself is
// decided: the velocities' moment about the anchor, taken along the axis, over I_n (the rate
// of their projection on the hinge's velocity constraint, the contacts' impulses as they
// are), with the motor's impulse taken out and put back as its velocity row would give it
// (towards its speed, within its half impulse); that rate times dt is the turn. In the
// rounds that follow the motor's row is an equality on that turn (a Newton target from the
// predicted end poses, as the other rows' are), in the block with the joints' rows, within
// the step's whole impulse tau dt; the end of the step has what the start left of it. The
// body then turns by alpha t^2 / 2 to rounding, and keeps its speed.
//
// Only there: between bodies that both move (a turret on a ship, an arm's elbow), the
// joint's moment of inertia changes as it turns and the outer bodies' centripetal pulls turn
// the inner joints, forces of the velocities squared that the position level (RATTLE)
// carries and the velocity level does not: held to the velocity level's turn, a 4-link arm's
// motors were asked for more than their force. There a motor stays the velocity row it
// starts as.
//
// The rounds of an island with such a motor go on to rounding (FineTolerance) while each at
// least halves what is left: a motor's angle has nothing that pulls it back, unlike a joint's
// rows, so what a step leaves adds up; and a hinge's anchor left 1e-10 m off its pivot (the
// joints' tolerance) moved the spin by its impulses' moment about the pivot, 2e-9 rad/s over
// 316 steps.
#include "joints/RJointSolver.h"

#include "joints/RJointRows.h"
#include "joints/RJointSystem.h"
#include "world/RStepBodies.h"

#include <algorithm>
#include <cmath>

namespace REngine {

using namespace joints;

namespace {

// Rounding (m or rad) near world point x, for a step of dt: what an island with motors is
// solved to. The passes leave a row's velocity kAtTarget off its target, kAtTarget dt over
// the step; far from the origin, a few ulps of x.
RScalar FineTolerance(const RVec3& x, RScalar dt) {
  return std::max(kAtTarget * dt, RScalar(1e-15) * x.cwiseAbs().maxCoeff());
}

// How far what a motor drives is off, a hinge's angle taken modulo a turn.
RScalar MotorOffset(const RJoint& J, RScalar off) {
  return J.def.type == RJointType::kHinge ? std::remainder(off, 2 * kPi) : off;
}

}  // namespace

RScalar RJointSolver::MotorRound(const RJointIslandView& v, RIslandScratch& sc) {
  if (!sc.jointMotors || sc.stiffened) return 0;
  const RStepBodies& bodies = v.bodies;
  const RScalar dt = v.dt;
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  const RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  RScalar worst = 0;
  for (std::uint32_t p = j0; p < j1; ++p) {
    const RStepJoint& sj = m_stepJoints[m_islandJoints[p]];
    const RJointPoseIn pa = JointPose(v, sj.a, true), pb = JointPose(v, sj.b, true);
    const RScalar tolerance = FineTolerance(pa.x, dt);
    // The rows' errors (PredictJoints has just predicted them) beyond rounding.
    const std::size_t at = std::size_t(p - j0) * kRows;
    for (int k = 0; k < kRows; ++k) {
      const RJointRow& r = rows[at + k];
      if (r.kind != Kind::kEquality && r.kind != Kind::kLimit) continue;
      const RScalar C = sc.jointC[at + k];
      const RScalar off = r.kind == Kind::kEquality || r.lambda > 0 ? std::abs(C) : std::max(RScalar(0), -C);
      if (off > tolerance) worst = std::max(worst, off);
    }
    RMotorTurn& t = m_motorTurns[p];
    t.measured = false;
    // (A hinge at its limit turns no further: a motor pushing it there has no turn of its
    // own. A body an impact hit this step moves on a path of two pieces: left as it is.)
    const bool aMoves = v.solverBodies[sj.a].invM != 0;
    const std::uint32_t i = aMoves ? sj.a : sj.b;
    const RSolverBody& s = v.solverBodies[i];
    if (!t.fixedAxis || sc.jointActive[at + 5] || sc.jointActive[at + 6] || !s.deferV.isZero(0)) continue;
    // The body's velocity-level turn about the axis n through its anchor (arm r from its
    // centre): the velocities' moment about the anchor, L = I w + m c x v (c = -r), taken
    // along n, over the moment of inertia about the axis, I_n = n . I n + m |n x c|^2 (both
    // in the row's sense: b's relative to a); without the motor's impulse, then the motor
    // towards its speed within its half impulse. Plus what position correction's turn adds.
    const RBodyCore& B = bodies[i];
    const RJoint& J = bodies.joints[sj.joint];
    const RJointRow& row = rows[at + kMotorRow];
    const RScalar sense = aMoves ? -1 : 1;
    const RVec3& n = row.dir.rBxd;
    const RVec3 r = B.m_q_WB * (aMoves ? J.anchorA_B : J.anchorB_B);
    const RMat3 R = B.m_q_WB.toRotationMatrix();
    const RMat3 I = R * B.m_I_B.asDiagonal() * R.transpose();
    const RScalar m = 1 / s.invM;
    const RVec3 L = I * s.w - m * r.cross(s.v);
    const RScalar In = n.dot(I * n) + m * n.cross(r).squaredNorm();
    const RScalar free = (sense * n.dot(L) - row.lambda) / In;
    const RScalar push = std::clamp((J.def.motor.speed - free) * In, -t.nominal, t.nominal);
    t.end = t.start + (free + push / In + sense * n.dot(s.wp)) * dt;
    t.error = MotorOffset(J, JointMotorPosition(J, pa, pb) - t.end);
    t.measured = true;
    if (std::abs(t.error) > tolerance) worst = std::max(worst, std::abs(t.error));
  }
  return worst;
}

// Each measured motor's row holds its turn: an equality (in the block) whose target takes the
// predicted error out, within the step's whole impulse. One that has no turn of its own now
// (a limit reached holds its axis) is a velocity row again.
void RJointSolver::SetMotorTargets(const RJointIslandView& v, RIslandScratch& sc) {
  if (!sc.jointMotors || sc.stiffened) return;
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  for (std::uint32_t p = j0; p < j1; ++p) {
    RMotorTurn& t = m_motorTurns[p];
    if (!t.measured) {
      if (t.on) ResetMotor(v, sc, p);
      continue;
    }
    const std::size_t i = std::size_t(p - j0) * kRows + kMotorRow;
    RJointRow& r = rows[i];
    if (!t.on) {
      t.on = true;
      r.lo = -2 * t.nominal, r.hi = 2 * t.nominal;
      sc.jointActive[i] = 1, sc.blockStale = true;
    }
    r.target = RowSpeed(r, v.solverBodies.data()) - t.error / v.dt;
  }
}

// The motors' velocity rows again: half the step's impulse at most, towards their speed.
void RJointSolver::ResetMotors(const RJointIslandView& v, RIslandScratch& sc) {
  if (!sc.jointMotors) return;
  for (std::uint32_t p = m_islandJointStart[v.island]; p < m_islandJointStart[v.island + 1]; ++p) {
    m_motorTurns[p].measured = false;
    if (m_motorTurns[p].on) ResetMotor(v, sc, p);
  }
}

void RJointSolver::ResetMotor(const RJointIslandView& v, RIslandScratch& sc, std::uint32_t p) {
  RMotorTurn& t = m_motorTurns[p];
  t.on = false;
  const std::uint32_t j0 = m_islandJointStart[v.island];
  const std::size_t i = std::size_t(p - j0) * kRows + kMotorRow;
  RJointRow& r = m_jointRows[std::size_t(j0) * kRows + i];
  r.lo = -t.nominal, r.hi = t.nominal;
  r.target = v.bodies.joints[m_stepJoints[m_islandJoints[p]].joint].def.motor.speed;
  const RScalar clamped = std::clamp(r.lambda, r.lo, r.hi);
  if (clamped != r.lambda) RowPush(r, clamped - r.lambda, v.solverBodies.data());
  r.lambda = clamped;
  sc.jointActive[i] = r.lambda > r.lo && r.lambda < r.hi;
  sc.blockStale = true;
}

RScalar RJointSolver::MotorError(const RJointIslandView& v, std::uint32_t p) const {
  const RStepJoint& sj = m_stepJoints[m_islandJoints[p]];
  const RJoint& J = v.bodies.joints[sj.joint];
  return MotorOffset(J, JointMotorPosition(J, JointPose(v, sj.a, true), JointPose(v, sj.b, true)) - m_motorTurns[p].end);
}

void RJointSolver::EndMotorBounds(std::uint32_t p, const RJointRow& mid, RJointRow& end) const {
  const RMotorTurn& t = m_motorTurns[p];
  if (!t.on || end.kind != Kind::kMotor) return;
  end.lo = -2 * t.nominal - mid.lambda, end.hi = 2 * t.nominal - mid.lambda;
}

}  // namespace REngine
