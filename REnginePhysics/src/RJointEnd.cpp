// The joints at the end of the step (RWorldStep's joints, RJoints.cpp): the projection of
// the position error the Newton rounds leave, and the end's velocity projection (the
// second half of RATTLE), both on rows built at the predicted end poses.
#include "RWorldStep.h"

#include "RJointRows.h"
#include "RJointSystem.h"

#include <REngineMath/RQuaternion.h>

#include <algorithm>
#include <cmath>

namespace REngine {

using namespace joints;

void RWorldStep::BuildEndRows(const RStepBodies& bodies, std::size_t island, RScalar dt, RIslandScratch& sc,
                              bool atEnd) {
  const std::uint32_t j0 = m_islandJointStart[island], j1 = m_islandJointStart[island + 1];
  const int nj = static_cast<int>(j1 - j0);
  const std::uint32_t world = static_cast<std::uint32_t>(bodies.size());
  const RScalar halfDt = RScalar(0.5) * dt;
  sc.endRows.resize(std::size_t(nj) * kRows);
  sc.jointC.resize(std::size_t(nj) * kRows);
  sc.endBodies.clear();
  using REndBody = RIslandScratch::REndBody;
  auto endBody = [&](std::uint32_t i) -> std::uint32_t {
    if (i != world && m_solverBodies[i].invM != 0) {
      if (sc.mark[i] != kNone) return sc.mark[i];
      const RRigidBody& b = bodies[i];
      const RSolverBody& s = m_solverBodies[i];
      const RJointPose& p = m_jointPoses[i];
      REndBody e;
      const RMat3 R = p.q.toRotationMatrix();
      e.invI = b.m_angularLocked ? InvInertia_W(b, R) : RMat3(R * b.m_invI_B.asDiagonal() * R.transpose());
      e.invM = s.invM, e.linMask = s.linMask, e.linLocked = s.linLocked;
      e.v.setZero(), e.w.setZero();
      if (atEnd) {
        // As the motion will leave them before these impulses: the second half-kick, the
        // impacts' deferred change and the contacts' end impulses (their moments about the
        // centre where the step ends), the end of the free flow.
        e.v = p.vMid + Acceleration(b, m_settings.gravity_W) * halfDt + LinearKick(b, s.deferredImpulse + s.endLinear);
        const RVec3 h = s.endAngular - (p.x - b.m_x_W).cross(s.endLinear);
        e.w = p.wEnd_W + e.invI * (EndAngularKick_W(b, halfDt) + h);
      }
      sc.mark[i] = static_cast<std::uint32_t>(sc.endBodies.size());
      sc.endBodies.push_back(e);
      return sc.mark[i];
    }
    REndBody e;
    e.invI.setZero(), e.invM = 0, e.linMask = RVec3::Ones(), e.linLocked = false;
    e.v.setZero(), e.w.setZero();
    if (atEnd && i != world && bodies[i].IsKinematic()) e.v = bodies[i].m_v_W, e.w = bodies[i].m_w_W;
    sc.endBodies.push_back(e);
    return static_cast<std::uint32_t>(sc.endBodies.size() - 1);
  };
  for (int t = 0; t < nj; ++t) {
    const RStepJoint& sj = m_stepJoints[m_islandJoints[j0 + t]];
    const std::uint32_t a = endBody(sj.a), b = endBody(sj.b);
    BuildJointRows(bodies.joints[sj.joint], JointPose(bodies, sj.a, dt, true), JointPose(bodies, sj.b, dt, true),
                   sc.endBodies[a], sc.endBodies[b], a, b, dt, sc.endRows.data() + std::size_t(t) * kRows,
                   sc.jointC.data() + std::size_t(t) * kRows);
  }
  if (sc.endMark.size() < sc.endBodies.size()) sc.endMark.resize(sc.endBodies.size(), kNone);
}

void RWorldStep::ClearJointMarks(RIslandScratch& sc) {
  for (std::uint32_t i : sc.jointBodies) sc.mark[i] = kNone;
}

// What error the Newton rounds leave, taken out of the predicted end poses alone (a
// displacement without velocity, as the contacts' position correction: the motion applies
// it as the bodies' pseudo-velocities): the rows built at the corrected poses each time,
// so that a joint whose arm the step turned far still converges.
void RWorldStep::ProjectJoints(const RStepBodies& bodies, std::size_t island, RScalar dt, RIslandScratch& sc) {
  const std::uint32_t j0 = m_islandJointStart[island], j1 = m_islandJointStart[island + 1];
  const int nj = static_cast<int>(j1 - j0);
  const std::uint32_t world = static_cast<std::uint32_t>(bodies.size());
  const int iterations = std::max(1, m_settings.solverIterations);
  constexpr int kProjections = 8;
  bool moved = false;
  for (int projection = 0; projection < kProjections; ++projection) {
    BuildEndRows(bodies, island, dt, sc, false);
    bool any = false;
    for (int t = 0; t < nj; ++t) {
      const RStepJoint& sj = m_stepJoints[m_islandJoints[j0 + t]];
      const RScalar tolerance = JointTolerance(JointPose(bodies, sj.a, dt, true).x);
      for (int k = 0; k < kRows; ++k) {
        RJointRow& r = sc.endRows[std::size_t(t) * kRows + k];
        const RScalar C = sc.jointC[std::size_t(t) * kRows + k];
        if (r.kind == Kind::kMotor || (r.kind == Kind::kLimit && C >= 0)) r.kind = Kind::kOff;
        if (r.kind == Kind::kOff) continue;
        r.target = -C / dt;
        any = any || std::abs(C) > tolerance;
      }
    }
    if (!any) {
      ClearJointMarks(sc);
      break;
    }
    BeginJointBlocks(sc.endRows.data(), nj, sc);
    for (int it = 0; it < iterations; ++it) {
      if (!(JointPass(sc.endRows.data(), nj, sc.endBodies.data(), sc, sc.endMark, kJointBlockRows) > kAtTarget)) break;
    }
    for (std::uint32_t i : sc.jointBodies) {
      const RIslandScratch::REndBody& e = sc.endBodies[sc.mark[i]];
      RJointPose& p = m_jointPoses[i];
      p.x += e.v * dt;
      if (!e.w.isZero(0)) {
        const RQuat turn = QuatExp(e.w * dt);
        p.q = turn * p.q, p.q.normalize();
        if (!bodies[i].m_angularLocked) p.wEnd_W = turn * p.wEnd_W;
      }
    }
    ClearJointMarks(sc);
    moved = true;
  }
  if (!moved) return;
  // The displacement to the motion, as pseudo-velocities on top of the flow.
  for (std::uint32_t i : sc.jointBodies) {
    RSolverBody& s = m_solverBodies[i];
    const RJointPose& p = m_jointPoses[i];
    s.vp = (p.x - bodies[i].m_x_W) / dt - p.vMid;
    s.wp = QuatLog(p.q * p.qFlow.conjugate()) / dt;
  }
  (void)world;
}

// The second half of RATTLE: at the end poses, the end velocities (what the motion will
// leave, contacts' end impulses included) projected onto the joints' rows, equality rows to
// no relative velocity and limits that are reached to none into them; the impulses go to
// the motion as end-of-step impulses. Then each joint remembers its impulses (next step's
// warm start) and reports what it did.
void RWorldStep::SolveJointsAtEnd(const RStepBodies& bodies, std::size_t island, RScalar dt, RIslandScratch& sc) {
  const std::uint32_t j0 = m_islandJointStart[island], j1 = m_islandJointStart[island + 1];
  const int nj = static_cast<int>(j1 - j0);
  const std::uint32_t world = static_cast<std::uint32_t>(bodies.size());
  const RJointRow* midRows = m_jointRows.data() + std::size_t(j0) * kRows;
  BuildEndRows(bodies, island, dt, sc, true);
  for (int t = 0; t < nj; ++t) {
    const RStepJoint& sj = m_stepJoints[m_islandJoints[j0 + t]];
    const RJoint& J = bodies.joints[sj.joint];
    const RScalar tolerance = JointTolerance(JointPose(bodies, sj.a, dt, true).x);
    for (int k = 0; k < kRows; ++k) {
      RJointRow& r = sc.endRows[std::size_t(t) * kRows + k];
      // A limit holds at the end only where it is reached; a motor drives at both ends.
      if (r.kind == Kind::kLimit && sc.jointC[std::size_t(t) * kRows + k] > tolerance) r.kind = Kind::kOff;
      if (r.kind != Kind::kMotor) r.target = 0;
      if (r.kind == Kind::kOff || !std::isfinite(J.lambdaEnd[k])) continue;
      r.lambda = std::clamp(J.lambdaEnd[k], r.lo, r.hi);
      if (r.lambda != 0) RowPush(r, r.lambda, sc.endBodies.data());
    }
  }
  BeginJointBlocks(sc.endRows.data(), nj, sc);
  const int iterations = std::max(1, m_settings.solverIterations);
  for (int it = 0; it < iterations; ++it) {
    if (!(JointPass(sc.endRows.data(), nj, sc.endBodies.data(), sc, sc.endMark, kJointBlockRows) > kAtTarget)) break;
  }
  ClearJointMarks(sc);
  // The end impulses to the motion, about the centres where the step starts (Integrate
  // moves their moments to where the centres end); what each joint did.
  for (int t = 0; t < nj; ++t) {
    const RStepJoint& sj = m_stepJoints[m_islandJoints[j0 + t]];
    RJoint& J = bodies.joints[sj.joint];
    RVec3 linear = RVec3::Zero(), angular = RVec3::Zero();
    for (int k = 0; k < kRows; ++k) {
      const RJointRow& mid = midRows[std::size_t(t) * kRows + k];
      const RJointRow& end = sc.endRows[std::size_t(t) * kRows + k];
      J.lambda[k] = mid.kind == Kind::kOff ? 0 : mid.lambda;
      J.lambdaEnd[k] = end.kind == Kind::kOff ? 0 : end.lambda;
      if (mid.kind != Kind::kOff) {
        linear += mid.lambda * mid.dir.d;
        if (mid.dir.d.isZero(0)) angular += mid.lambda * mid.dir.rBxd;
      }
      if (end.kind == Kind::kOff || end.lambda == 0) continue;
      linear += end.lambda * end.dir.d;
      if (end.dir.d.isZero(0)) angular += end.lambda * end.dir.rBxd;
      const RVec3 Jl = end.lambda * end.dir.d;
      for (const bool isB : {false, true}) {
        const std::uint32_t i = isB ? sj.b : sj.a;
        if (i == world || m_solverBodies[i].invM == 0) continue;
        RSolverBody& s = m_solverBodies[i];
        const RVec3 shift = m_jointPoses[i].x - bodies[i].m_x_W;
        const RScalar sign = isB ? 1 : -1;
        s.endLinear += sign * Jl;
        s.endAngular += sign * (end.lambda * (isB ? end.dir.rBxd : end.dir.rAxd) + shift.cross(Jl));
      }
    }
    J.impulse_W = linear, J.angularImpulse_W = angular;
  }
}

}  // namespace REngine
