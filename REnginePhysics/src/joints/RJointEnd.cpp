// The joints at the end of the step (the joint solver's, RJointSolver.h and RJoints.cpp): the
// projection of the position error the Newton rounds leave, and the end's velocity
// projection (the second half of RATTLE), both on rows built at the predicted end poses.
#include "joints/RJointSolver.h"
#include <REngineMath/RFunctions.h>

#include <REnginePhysics/RIntegrator.h>

#include "joints/RJointRows.h"
#include "joints/RJointSystem.h"
#include "joints/RWeldGroups.h"
#include "motion/RMotion.h"
#include "pairs/RPairSweep.h"
#include "solver/RSolverRows.h"
#include "world/RStepBodies.h"

#include <REngineMath/RQuaternion.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace joints;

void RJointSolver::BuildEndRows(const RJointIslandView& v, RIslandScratch& sc, bool atEnd) {
  const RStepBodies& bodies = v.bodies;
  const RScalar dt = v.dt;
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  const int nj = static_cast<int>(j1 - j0);
  const std::uint32_t world = static_cast<std::uint32_t>(bodies.size());
  const RScalar halfDt = RScalar(0.5) * dt;
  sc.endRows.resize(std::size_t(nj) * kRows);
  sc.jointC.resize(std::size_t(nj) * kRows);
  sc.endBodies.clear();
  auto endBody = [&](std::uint32_t i) -> std::uint32_t {
    if (i != world && v.solverBodies[i].invM != 0) {
      if (sc.mark[i] != kNone) return sc.mark[i];
      const RBodyCore& b = bodies[i];
      const RSolverBody& s = v.solverBodies[i];
      const RJointPose& p = m_jointPoses[i];
      RJointEndBody e;
      const RMat3 R = p.q.toRotationMatrix();
      e.invI = b.m_angularLocked ? RMotion::InvInertia_W(b, R) : RMat3(R * b.m_invI_B.asDiagonal() * R.transpose());
      // (Stiffened: as the rounds solved it, RJointStiffness.cpp.)
      if (sc.stiffened && sc.stiffness[i] > 0) e.invI = Stiffened(e.invI, sc.stiffness[i]);
      e.invM = s.invM, e.linMask = s.linMask, e.linLocked = s.linLocked;
      e.v.setZero(), e.w.setZero();
      if (atEnd) {
        // As the motion will leave them before these impulses: the second half-kick, the
        // contacts' end impulses (their moments about the centre where the step ends), the
        // end of the free flow.
        // (An impact's deferred change is in vMid: the body moves with vMid - deferV and
        // gets deferV back at the end.)
        e.v = p.vMid + RMotion::Acceleration(b, v.settings.gravity_W) * halfDt + RMotion::LinearKick(b, s.endLinear);
        const RVec3 h = s.endAngular - (p.x - b.m_x_W).cross(s.endLinear);
        e.w = p.wEnd_W + e.invI * (RMotion::EndAngularKick_W(b, halfDt) + h);
      }
      sc.mark[i] = static_cast<std::uint32_t>(sc.endBodies.size());
      sc.endBodies.push_back(e);
      return sc.mark[i];
    }
    RJointEndBody e;
    e.invI.setZero(), e.invM = 0, e.linMask = RVec3::Ones(), e.linLocked = false;
    e.v.setZero(), e.w.setZero();
    if (atEnd && i != world && bodies[i].m_isKinematic) e.v = bodies[i].m_v_W, e.w = bodies[i].m_w_W;
    sc.endBodies.push_back(e);
    return static_cast<std::uint32_t>(sc.endBodies.size() - 1);
  };
  for (int t = 0; t < nj; ++t) {
    const RStepJoint& sj = m_stepJoints[m_islandJoints[j0 + t]];
    const std::uint32_t a = endBody(sj.a), b = endBody(sj.b);
    BuildJointRows(bodies.joints[sj.joint], JointPose(v, sj.a, true), JointPose(v, sj.b, true), sc.endBodies[a],
                   sc.endBodies[b], a, b, dt, sc.endRows.data() + std::size_t(t) * kRows,
                   sc.jointC.data() + std::size_t(t) * kRows);
  }
  if (sc.endMark.size() < sc.endBodies.size()) sc.endMark.resize(sc.endBodies.size(), kNone);
}

void RJointSolver::ClearJointMarks(RIslandScratch& sc) {
  for (std::uint32_t i : sc.jointBodies) sc.mark[i] = kNone;
}

// What error the Newton rounds leave, taken out of the predicted end poses alone (a
// displacement without velocity, as the contacts' position correction: the motion applies
// it as the bodies' pseudo-velocities): the rows built at the corrected poses each time,
// so that a joint whose arm the step turned far still converges.
void RJointSolver::ProjectJoints(const RJointIslandView& v, RIslandScratch& sc) {
  const RStepBodies& bodies = v.bodies;
  const RScalar dt = v.dt;
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  const int nj = static_cast<int>(j1 - j0);
  const int iterations = std::max(1, v.settings.solverIterations);
  constexpr int kProjections = 8;
  bool moved = false;
  for (int projection = 0; projection < kProjections; ++projection) {
    BuildEndRows(v, sc, false);
    bool any = false;
    for (int t = 0; t < nj; ++t) {
      const RStepJoint& sj = m_stepJoints[m_islandJoints[j0 + t]];
      const RScalar tolerance = JointTolerance(JointPose(v, sj.a, true).x);
      for (int k = 0; k < kRows; ++k) {
        RJointRow& r = sc.endRows[std::size_t(t) * kRows + k];
        RScalar C = sc.jointC[std::size_t(t) * kRows + k];
        // A motor whose row held its turn in the rounds keeps it (RJointMotors.cpp).
        if (r.kind == Kind::kMotor && MotorTurning(j0 + t)) {
          r.kind = Kind::kEquality, r.lo = -kInf, r.hi = kInf;
          C = MotorError(v, j0 + t);
        }
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
    BeginJointBlocks(sc.endRows.data(), sc.endRows.size(), sc);
    for (int it = 0; it < iterations; ++it) {
      if (!(JointPass(sc.endRows.data(), sc.endRows.size(), sc.endBodies.data(), sc, sc.endMark, kJointBlockRows) >
            kAtTarget)) {
        break;
      }
    }
    for (std::uint32_t i : sc.jointBodies) {
      const RJointEndBody& e = sc.endBodies[sc.mark[i]];
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
    RSolverBody& s = v.solverBodies[i];
    const RJointPose& p = m_jointPoses[i];
    if (v.welds.Welded(i)) {
      // A weld's member does not move with its own velocity (its group turns it about the
      // group's centre): the correction alone, on top of the pseudo-velocities predicted.
      s.vp += (p.x - p.xPredicted) / dt;
      s.wp += QuatLog(p.q * p.qPredicted.conjugate()) / dt;
      continue;
    }
    s.vp = (p.x - bodies[i].m_x_W) / dt - (p.vMid - s.deferV);
    s.wp = QuatLog(p.q * p.qFlow.conjugate()) / dt;
  }
}

// The second half of RATTLE: at the end poses, the end velocities (what the motion will
// leave, contacts' end impulses included) projected onto the joints' rows, equality rows to
// no relative velocity and limits that are reached to none into them; the impulses go to
// the motion as end-of-step impulses. Then each joint remembers its impulses (next step's
// warm start) and reports what it did.
void RJointSolver::SolveJointsAtEnd(const RJointIslandView& v, RIslandScratch& sc) {
  const RStepBodies& bodies = v.bodies;
  const RScalar dt = v.dt;
  std::vector<RSolverBody>& solverBodies = v.solverBodies;
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  const int nj = static_cast<int>(j1 - j0);
  const std::uint32_t world = static_cast<std::uint32_t>(bodies.size());
  const RJointRow* midRows = m_jointRows.data() + std::size_t(j0) * kRows;
  BuildEndRows(v, sc, true);
  // (Stiffened: each joint body's spin before the projection, in keptW, which the rounds are
  // done with.)
  if (sc.stiffened) {
    for (std::size_t k = 0; k < sc.jointBodies.size(); ++k) sc.keptW[k] = sc.endBodies[sc.mark[sc.jointBodies[k]]].w;
  }
  // What ProjectJoints' displacement, which moves no body's momentum, added to a free
  // island's angular momentum (the end's projection keeps it, at the corrected poses): each
  // centre's shift across its momentum, each body's own spin turned with it. EndStiffness
  // takes it back.
  RVec3 projected = RVec3::Zero();
  if (FreeJointIsland(v, sc)) {
    for (std::uint32_t i : sc.jointBodies) {
      const RJointPose& p = m_jointPoses[i];
      if (p.x == p.xPredicted && p.q.coeffs() == p.qPredicted.coeffs()) continue;
      const RJointEndBody& e = sc.endBodies[sc.mark[i]];
      const RMat3 R = p.q.toRotationMatrix();
      const RVec3 spin = R * bodies[i].m_invI_B.cwiseInverse().cwiseProduct(R.transpose() * e.w);
      projected += (p.x - p.xPredicted).cross(RVec3(e.v / e.invM)) + spin - (p.qPredicted * p.q.conjugate()) * spin;
    }
  }
  for (int t = 0; t < nj; ++t) {
    const RStepJoint& sj = m_stepJoints[m_islandJoints[j0 + t]];
    const RJoint& J = bodies.joints[sj.joint];
    const RScalar tolerance = JointTolerance(JointPose(v, sj.a, true).x);
    for (int k = 0; k < kRows; ++k) {
      RJointRow& r = sc.endRows[std::size_t(t) * kRows + k];
      // A limit holds at the end only where it is reached; a motor drives at both ends.
      if (r.kind == Kind::kLimit && sc.jointC[std::size_t(t) * kRows + k] > tolerance) r.kind = Kind::kOff;
      if (r.kind != Kind::kMotor) r.target = 0;
      if (r.kind == Kind::kMotor) EndMotorBounds(j0 + t, midRows[std::size_t(t) * kRows + k], r);
      if (r.kind == Kind::kOff || !std::isfinite(J.lambdaEnd[k])) continue;
      r.lambda = std::clamp(J.lambdaEnd[k], r.lo, r.hi);
      if (r.lambda != 0) RowPush(r, r.lambda, sc.endBodies.data());
    }
  }
  // The island's contacts closed at the end of the step between its joint bodies and static
  // or kinematic ones (a chain lying on the ground), solved with the joints: projected alone,
  // the joints' end velocities pushed the links into the ground (6 cm/s a step, and the chain
  // never slept). Each may give back its own end impulse, never pull: lo = -lambdaE.
  sc.endContacts.clear();
  for (std::uint32_t i = v.rowsFirst; i < v.rowsLast; ++i) {
    const RContactRow& c = v.rows[i];
    if (c.endTarget == solver::kNever || !(c.n.k > 0)) continue;
    auto endIndex = [&](std::uint32_t body) -> std::uint32_t {
      if (solverBodies[body].invM != 0) return sc.mark[body];  // kNone: not a joint body
      RJointEndBody e;
      e.invI.setZero(), e.invM = 0, e.linMask = RVec3::Ones(), e.linLocked = false;
      e.v = bodies[body].m_isKinematic ? bodies[body].m_v_W : RVec3::Zero();
      e.w = bodies[body].m_isKinematic ? bodies[body].m_w_W : RVec3::Zero();
      sc.endBodies.push_back(e);
      return static_cast<std::uint32_t>(sc.endBodies.size() - 1);
    };
    if ((solverBodies[c.a].invM != 0 && sc.mark[c.a] == kNone) || (solverBodies[c.b].invM != 0 && sc.mark[c.b] == kNone)) {
      continue;
    }
    RJointRow r;
    r.a = endIndex(c.a), r.b = endIndex(c.b);
    r.dir = c.n;
    const RJointEndBody& ea = sc.endBodies[r.a];
    const RJointEndBody& eb = sc.endBodies[r.b];
    r.dir.iA = ea.invI * r.dir.rAxd, r.dir.iB = eb.invI * r.dir.rBxd;
    r.dir.k = solver::LinearCoupling(ea, r.dir.d, r.dir.d, 1) + solver::LinearCoupling(eb, r.dir.d, r.dir.d, 1) +
              r.dir.rAxd.dot(r.dir.iA) + r.dir.rBxd.dot(r.dir.iB);
    r.kind = Kind::kLimit, r.target = 0, r.lo = -c.lambdaE, r.hi = std::numeric_limits<RScalar>::infinity();
    r.lambda = 0;
    sc.endRows.push_back(r);
    sc.endContacts.push_back(i);
  }
  // Their manifolds' friction, at the patch (the manifold's centroid, its tangents): what
  // the normal impulses of the step leave of the friction cone, each way. Without it the
  // joints' projection slid a chain lying on the ground by 1 cm/s at the end of every step,
  // and it never slept.
  const std::size_t normalRows = sc.endRows.size();
  sc.endPatches.clear();
  for (std::size_t e = 0; e < sc.endContacts.size(); ++e) {
    const RContactRow& c = v.rows[sc.endContacts[e]];
    if (!sc.endPatches.empty() && sc.endPatches.back() == c.block) continue;
    const RBlock& blk = v.blocks[c.block];
    if (!(blk.friction > 0)) continue;
    RScalar normal = 0;
    for (int k = 0; k < blk.count; ++k) normal += v.rows[blk.first + k].lambdaN + v.rows[blk.first + k].lambdaE;
    const RScalar used = Hypot(blk.lambdaT1[0] + blk.lambdaT1[1], blk.lambdaT2[0] + blk.lambdaT2[1]);
    const RScalar left = blk.friction * normal - used;
    if (!(left > 0)) continue;
    // (The contact row's end bodies by value: the pushes below may move the rows.)
    const std::uint32_t endA = sc.endRows[std::size_t(nj) * kRows + e].a, endB = sc.endRows[std::size_t(nj) * kRows + e].b;
    for (int t = 0; t < 2; ++t) {
      RJointRow r;
      r.a = endA, r.b = endB;
      r.dir = blk.t[t];
      const RJointEndBody& ea = sc.endBodies[r.a];
      const RJointEndBody& eb = sc.endBodies[r.b];
      r.dir.iA = ea.invI * r.dir.rAxd, r.dir.iB = eb.invI * r.dir.rBxd;
      r.dir.k = solver::LinearCoupling(ea, r.dir.d, r.dir.d, 1) + solver::LinearCoupling(eb, r.dir.d, r.dir.d, 1) +
                r.dir.rAxd.dot(r.dir.iA) + r.dir.rBxd.dot(r.dir.iB);
      // (A motor's kind: bounded both ways, in the exact block while within its bounds.)
      r.kind = Kind::kMotor, r.target = blk.targetT[1][t], r.lo = -left, r.hi = left, r.lambda = 0;
      sc.endRows.push_back(r);
    }
    sc.endPatches.push_back(c.block);
  }
  if (sc.endMark.size() < sc.endBodies.size()) sc.endMark.resize(sc.endBodies.size(), kNone);
  BeginJointBlocks(sc.endRows.data(), sc.endRows.size(), sc);
  const int iterations = std::max(1, v.settings.solverIterations);
  for (int it = 0; it < iterations; ++it) {
    if (!(JointPass(sc.endRows.data(), sc.endRows.size(), sc.endBodies.data(), sc, sc.endMark, kJointBlockRows) >
          kAtTarget)) {
      break;
    }
  }
  if (sc.stiffened || !projected.isZero(0)) EndStiffness(v, sc, sc.keptW.data(), projected);
  ClearJointMarks(sc);
  // The patches' friction, as the manifolds' end friction (at the centroid, moved with the
  // lighter body as ReportIsland moves a contact's end impulse), and in their report.
  for (std::size_t p = 0; p < sc.endPatches.size(); ++p) {
    const RBlock& blk = v.blocks[sc.endPatches[p]];
    const RContactRow& c = v.rows[blk.first];
    RVec3 J = RVec3::Zero();
    for (int t = 0; t < 2; ++t) J += sc.endRows[normalRows + 2 * p + t].lambda * blk.t[t].d;
    if (J.isZero(0)) continue;
    RSolverBody& sa = solverBodies[c.a];
    RSolverBody& sb = solverBodies[c.b];
    const RVec3 moveA = (sa.vMid + sa.vp) * dt, moveB = (sb.vMid + sb.vp) * dt;
    const RVec3 shift = (sa.invM * moveA + sb.invM * moveB) / (sa.invM + sb.invM);
    if (!bodies[c.a].Immovable()) sa.endLinear -= J, sa.endAngular -= (blk.rA + shift).cross(J);
    if (!bodies[c.b].Immovable()) sb.endLinear += J, sb.endAngular += (blk.rB + shift).cross(J);
    v.sweep.SolverContact(c.contact).frictionImpulse_W += J;
  }
  // What the contacts gave back or added, as their end impulses (at the point ReportIsland
  // puts a contact's end impulse: moved with the lighter body), and in their report.
  for (std::size_t k = 0; k < sc.endContacts.size(); ++k) {
    const RJointRow& r = sc.endRows[std::size_t(nj) * kRows + k];
    if (r.lambda == 0) continue;
    const RContactRow& c = v.rows[sc.endContacts[k]];
    RSolverBody& sa = solverBodies[c.a];
    RSolverBody& sb = solverBodies[c.b];
    const RVec3 J = r.lambda * c.n.d;
    const RVec3 moveA = (sa.vMid + sa.vp) * dt, moveB = (sb.vMid + sb.vp) * dt;
    const RVec3 shift = (sa.invM * moveA + sb.invM * moveB) / (sa.invM + sb.invM);
    if (!bodies[c.a].Immovable()) sa.endLinear -= J, sa.endAngular -= (c.rA + shift).cross(J);
    if (!bodies[c.b].Immovable()) sb.endLinear += J, sb.endAngular += (c.rB + shift).cross(J);
    v.sweep.SolverContact(c.contact).normalImpulse[c.point] += r.lambda;
  }
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
        if (i == world || solverBodies[i].invM == 0) continue;
        RSolverBody& s = solverBodies[i];
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
