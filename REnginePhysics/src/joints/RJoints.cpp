// The joint solver (RJointSolver.h), the joints' part of the contact solver's island solve
// (RContactSolver::FindImpulses), island by island.
//
// Method: RATTLE (Andersen 1983), the constrained form of the kick-drift-kick the bodies
// move with, in impulses. At the start of the step each joint's rows (RJointRows.cpp) get
// the impulse that makes the constraint hold at the END of the step, at the poses the
// motion will then give the bodies: the position error the motion would leave is
// predicted from the solver's velocities (the exact free flow included, as the motion runs
// it), and the rows' targets are the velocities that remove it; a few Newton rounds, each
// a prediction and the passes again (RContactSolver::JointRounds, solver/RContactPasses.cpp:
// the rounds drive the contact solver's passes, which solve the joints with the contacts).
// At the end of the step the rows are built again at the end poses and the end velocities
// projected onto them (the second half of RATTLE).
// No position correction is needed beyond that (no drift to correct: each step ends on
// the constraint to the Newton tolerance), and both impulses are real ones acting at the
// anchors, so momentum and angular momentum are conserved as in a collision.
//
// The Newton rounds use the rows of the start of the step, so a joint's pull acts along its
// arm as it was: a light link between two heavily loaded joints turns under any imbalance of
// their pulls by a mode faster than the step, which the rounds amplify. Where an arm's mode
// is faster than the step follows, or the rounds stop converging, the island is solved
// stiffened (RJointStiffness.cpp: each pull added to its body's inertia, the implicit
// treatment of the arm's turn). Where even those rounds stop converging, the plain velocity
// constraint takes over, and the error is taken out of the positions alone (ProjectJoints,
// RJointEnd.cpp: projections with the rows built again at each corrected pose, as Jolt's and
// Box2D's position passes do).
//
// The equality rows of an island are solved exactly together, as one block (a skyline
// Cholesky of their matrix, a chain's banded), inside each pass of the sequential-impulse
// passes that the contacts run: a 10-link chain holding a weight 100 times its links'
// does not stretch, which iterative solvers (Bullet's, Jolt's) let it do; past
// kJointBlockRows rows, as one sparse system with the bodies as unknowns (RJointSparse.h).
// Limits and motors join the block while they push or hold within their force (an active
// set, RJointSystem.h).
#include "joints/RJointSolver.h"

#include "joints/RJointRows.h"
#include "joints/RJointSystem.h"
#include "joints/RWeldGroups.h"
#include "world/RStepBodies.h"
#include "world/RUnionFind.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace joints;

bool RStepBodies::JointedNoCollide(std::size_t i, std::size_t j) const {
  const std::uint32_t si = Slot(i), sj = Slot(j);
  const std::uint64_t key = si < sj ? (std::uint64_t(si) << 32) | sj : (std::uint64_t(sj) << 32) | si;
  return std::binary_search(noCollidePairs, noCollidePairs + noCollideCount, key);
}

// The step's joints: both bodies stepped (a joint of a disabled body waits), one at least
// movable and awake (an island sleeps as one: a sleeping joint's bodies both sleep).
void RJointSolver::GatherJoints(const RStepBodies& bodies) {
  m_stepJoints.clear();
  const std::uint32_t world = static_cast<std::uint32_t>(bodies.size());
  for (std::size_t k = 0; k < bodies.jointCount; ++k) {
    const RJointDef& def = bodies.joints[k].def;
    const std::uint32_t a = bodies.denseOfSlot[def.a.index];
    if (a >= bodies.size()) continue;
    // (A disabled body's dense index may be bodies.size() itself, the world's solver body.)
    std::uint32_t b = world;
    if (def.b.IsValid()) {
      b = bodies.denseOfSlot[def.b.index];
      if (b >= bodies.size()) continue;
    }
    const RBodyCore& A = bodies[a];
    const bool movesA = !A.Immovable() && !A.m_sleeping;
    const bool movesB = b != world && !bodies[b].Immovable() && !bodies[b].m_sleeping;
    if (!movesA && !movesB) continue;
    m_stepJoints.push_back(RStepJoint{static_cast<std::uint32_t>(k), a, b});
  }
}

// Each joint counted at the root of its island (the representative of its movable body).
void RJointSolver::CountIslandJoints(const RStepBodies& bodies, RUnionFind& sets) {
  if (m_stepJoints.empty()) return;
  m_jointRootCount.assign(bodies.size(), 0);
  for (const RStepJoint& j : m_stepJoints) {
    ++m_jointRootCount[sets.Find(bodies[j.a].Immovable() ? j.b : j.a)];
  }
}

// Each island's joints in the step's order: its count (at its root) to starts, then the
// joints placed. A root with joints is an island (JointsAtRoot); islands of contacts alone
// have none.
void RJointSolver::LayOutIslandJoints(const RStepBodies& bodies, RUnionFind& sets,
                                      const std::vector<std::uint32_t>& islandOfRoot, std::size_t islands) {
  m_islandJointStart.clear();
  if (m_stepJoints.empty()) return;
  m_islandJointStart.assign(islands + 1, 0);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (m_jointRootCount[i] > 0) m_islandJointStart[islandOfRoot[i] + 1] = m_jointRootCount[i];
  }
  for (std::size_t k = 0; k < islands; ++k) m_islandJointStart[k + 1] += m_islandJointStart[k];
  m_islandJoints.resize(m_islandJointStart[islands]);
  m_islandJointFill.assign(m_islandJointStart.begin(), m_islandJointStart.end() - 1);
  for (std::uint32_t k = 0; k < m_stepJoints.size(); ++k) {
    const RStepJoint& j = m_stepJoints[k];
    const std::uint32_t root = sets.Find(bodies[j.a].Immovable() ? j.b : j.a);
    m_islandJoints[m_islandJointFill[islandOfRoot[root]]++] = k;
  }
}

RJointPoseIn RJointSolver::JointPose(const RJointIslandView& v, std::uint32_t i, bool end) const {
  const RStepBodies& bodies = v.bodies;
  if (i == bodies.size()) return RJointPoseIn{RVec3::Zero(), RQuat::Identity()};
  if (!end) return RJointPoseIn{bodies[i].m_x_W, bodies[i].m_q_WB};
  if (v.solverBodies[i].invM != 0) return RJointPoseIn{m_jointPoses[i].x, m_jointPoses[i].q};
  return ImmovablePose(bodies[i], v.dt, true);
}

// The island's joints at the start of the step: their rows at the start poses, last step's
// impulses applied (warm start), the equality blocks factored and the first targets.
void RJointSolver::BuildIslandJoints(const RJointIslandView& v, RIslandScratch& sc) {
  const RStepBodies& bodies = v.bodies;
  const std::size_t island = v.island;
  const RScalar dt = v.dt;
  const std::uint32_t j0 = m_islandJointStart[island], j1 = m_islandJointStart[island + 1];
  RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  RScalar C[kRows];
  sc.startC.resize(std::size_t(j1 - j0) * kRows);
  for (std::uint32_t p = j0; p < j1; ++p) {
    const RStepJoint& sj = m_stepJoints[m_islandJoints[p]];
    const RJoint& J = bodies.joints[sj.joint];
    RJointRow* jr = rows + std::size_t(p - j0) * kRows;
    BuildJointRows(J, JointPose(v, sj.a, false), JointPose(v, sj.b, false), v.solverBodies[sj.a],
                   v.solverBodies[sj.b], sj.a, sj.b, dt, jr, C);
    std::copy(C, C + kRows, sc.startC.begin() + std::size_t(p - j0) * kRows);
    // A motor starts the step as a velocity row (RJointMotors.cpp).
    RMotorTurn& turn = m_motorTurns[p];
    turn.measured = turn.on = turn.fixedAxis = false;
    turn.nominal = jr[kMotorRow].kind == Kind::kMotor ? jr[kMotorRow].hi : 0;
    for (int k = 0; k < kRows; ++k) {
      RJointRow& r = jr[k];
      if (r.kind == Kind::kOff || !std::isfinite(J.lambda[k])) continue;
      r.lambda = std::clamp(J.lambda[k], r.lo, r.hi);
      if (r.lambda != 0) RowPush(r, r.lambda, v.solverBodies.data());
    }
  }
  // The island's movable joint bodies, each once (their end poses are predicted per round),
  // with how many joints each has (in mark).
  sc.jointBodies.clear();
  if (sc.mark.size() < v.solverBodies.size()) sc.mark.resize(v.solverBodies.size(), kNone);
  for (std::uint32_t p = j0; p < j1; ++p) {
    const RStepJoint& sj = m_stepJoints[m_islandJoints[p]];
    for (std::uint32_t i : {sj.a, sj.b}) {
      if (v.solverBodies[i].invM == 0) continue;
      if (sc.mark[i] == kNone) sc.mark[i] = 0, sc.jointBodies.push_back(i);
      ++sc.mark[i];
    }
  }
  // A hinge motor whose body turns about a fixed axis: the body's one joint, to the world or
  // a static body, the body in no weld and without locks. Its turn is held in the rounds
  // (RJointMotors.cpp says why there alone).
  sc.jointMotors = false;
  for (std::uint32_t p = j0; p < j1; ++p) {
    const RStepJoint& sj = m_stepJoints[m_islandJoints[p]];
    const RJoint& J = bodies.joints[sj.joint];
    if (J.def.type != RJointType::kHinge || !(m_motorTurns[p].nominal > 0)) continue;
    const bool aMoves = v.solverBodies[sj.a].invM != 0;
    const std::uint32_t moving = aMoves ? sj.a : sj.b, other = aMoves ? sj.b : sj.a;
    const bool fixed = other == bodies.size() || (v.solverBodies[other].invM == 0 && !bodies[other].m_isKinematic);
    if (!fixed || sc.mark[moving] != 1 || v.welds.Welded(moving) || bodies[moving].m_linearLocked ||
        bodies[moving].m_angularLocked) {
      continue;
    }
    m_motorTurns[p].fixedAxis = sc.jointMotors = true;
    m_motorTurns[p].start = JointMotorPosition(J, JointPose(v, sj.a, false), JointPose(v, sj.b, false));
  }
  for (std::uint32_t i : sc.jointBodies) sc.mark[i] = kNone;
  BeginJointBlocks(rows, std::size_t(j1 - j0) * kRows, sc);
  sc.jointC.resize(std::size_t(j1 - j0) * kRows);
  PredictJoints(v, sc);
  SetJointTargets(v, sc);
}

// The poses the motion will give the island's joint bodies from the solver's velocities
// now (m_jointPoses), and each row's position error there (sc.jointC). Returns how far the
// worst row is off (m or rad: an equality row's error, a limit's overshoot or, pushing, its
// gap) beyond the tolerance, 0 when none is.
RScalar RJointSolver::PredictJoints(const RJointIslandView& v, RIslandScratch& sc) {
  const RStepBodies& bodies = v.bodies;
  const std::size_t island = v.island;
  const RScalar dt = v.dt;
  const std::uint32_t j0 = m_islandJointStart[island], j1 = m_islandJointStart[island + 1];
  const RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  for (std::uint32_t i : sc.jointBodies) {
    // A weld's members move as one body: predicted together, when its first is met.
    if (const std::uint32_t g = v.welds.WeldOf(i); g != RWeldGroups::kNoWeld) {
      if (v.welds.Root(g) == i) v.welds.PredictWeld(bodies, g, dt, v.solverBodies, m_jointPoses);
      continue;
    }
    m_jointPoses[i] = PredictPose(bodies[i], v.solverBodies[i], dt);
  }
  RScalar worst = 0;
  for (std::uint32_t p = j0; p < j1; ++p) {
    const RStepJoint& sj = m_stepJoints[m_islandJoints[p]];
    const RJointPoseIn pa = JointPose(v, sj.a, true), pb = JointPose(v, sj.b, true);
    RScalar* C = sc.jointC.data() + std::size_t(p - j0) * kRows;
    const RJointRow* jr = rows + std::size_t(p - j0) * kRows;
    JointErrors(bodies.joints[sj.joint], pa, pb, jr, C);
    // Rounding far from the origin: a few ulps of the coordinates.
    const RScalar tolerance = JointTolerance(pa.x);
    for (int k = 0; k < kRows; ++k) {
      const RJointRow& r = jr[k];
      if (r.kind != Kind::kEquality && r.kind != Kind::kLimit) continue;
      const RScalar off = r.kind == Kind::kEquality || r.lambda > 0 ? std::abs(C[k]) : std::max(RScalar(0), -C[k]);
      if (off > tolerance) worst = std::max(worst, off);
    }
  }
  return worst;
}

// Each row's target: the relative velocity that takes its predicted error out, to first
// order (the Newton step).
void RJointSolver::SetJointTargets(const RJointIslandView& v, RIslandScratch& sc) {
  const std::size_t island = v.island;
  const RScalar dt = v.dt;
  const std::uint32_t j0 = m_islandJointStart[island], j1 = m_islandJointStart[island + 1];
  RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  for (std::size_t i = 0; i < std::size_t(j1 - j0) * kRows; ++i) {
    RJointRow& r = rows[i];
    if (r.kind != Kind::kEquality && r.kind != Kind::kLimit) continue;
    r.target = RowSpeed(r, v.solverBodies.data()) - sc.jointC[i] / dt;
  }
  // A joint inside a weld: the group moves as one body whatever its members' relative
  // velocities, so its error is 0 at any prediction and the Newton step above says nothing.
  // What its rows must do is make the members answer contacts and other joints as that one
  // body: no relative velocity.
  if (v.welds.GroupCount() == 0) return;
  for (std::uint32_t p = j0; p < j1; ++p) {
    const RStepJoint& sj = m_stepJoints[m_islandJoints[p]];
    const std::uint32_t g = v.welds.WeldOf(sj.a);
    if (g == RWeldGroups::kNoWeld || g != v.welds.WeldOf(sj.b)) continue;
    for (int k = 0; k < kRows; ++k) {
      RJointRow& r = rows[std::size_t(p - j0) * kRows + k];
      if (r.kind == Kind::kEquality || r.kind == Kind::kLimit) r.target = 0;
    }
  }
}

RScalar RJointSolver::SolveJointsPass(const RJointIslandView& v, RIslandScratch& sc) {
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  return JointPass(m_jointRows.data() + std::size_t(j0) * kRows, std::size_t(j1 - j0) * kRows, v.solverBodies.data(),
                   sc, sc.mark, kJointBlockRows);
}

// The equality rows' impulses taken out (with the rows' masses they were given with).
void RJointSolver::ClearEquality(const RJointIslandView& v) {
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  const std::size_t count = std::size_t(j1 - j0) * kRows;
  for (std::size_t i = 0; i < count; ++i) {
    RJointRow& r = rows[i];
    if (r.kind == Kind::kEquality && r.lambda != 0) RowPush(r, -r.lambda, v.solverBodies.data()), r.lambda = 0;
  }
}

// The plain velocity constraint's targets (RContactSolver::JointRounds says when and why).
void RJointSolver::SetPlainTargets(const RJointIslandView& v, const RIslandScratch& sc) {
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  const std::size_t count = std::size_t(j1 - j0) * kRows;
  for (std::size_t i = 0; i < count; ++i) {
    RJointRow& r = rows[i];
    if (r.kind == Kind::kEquality) r.target = 0;
    if (r.kind == Kind::kLimit) r.target = -sc.startC[i] / v.dt;
  }
}

// The joints' impulses at the start of the step, added to the solver bodies' (which the
// report writes to the bodies, and the motion applies).
// (About the body's centre at the start: an arm shifted after an impact (ShiftJointArms) is
// reported without its shift, whose moment ReportIsland adds for all the contact phase did.)
void RJointSolver::ReportJoints(const RJointIslandView& v) {
  const RScalar dt = v.dt;
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  for (std::size_t i = std::size_t(j0) * kRows; i < std::size_t(j1) * kRows; ++i) {
    const RJointRow& r = m_jointRows[i];
    if (r.kind == Kind::kOff || r.lambda == 0) continue;
    RSolverBody& a = v.solverBodies[r.a];
    RSolverBody& b = v.solverBodies[r.b];
    if (a.invM != 0) {
      a.impulse -= r.lambda * r.dir.d;
      a.angularImpulse -= r.lambda * RVec3(r.dir.rAxd - JointArmShift(a, r.dir.d, dt));
    }
    if (b.invM != 0) {
      b.impulse += r.lambda * r.dir.d;
      b.angularImpulse += r.lambda * RVec3(r.dir.rBxd - JointArmShift(b, r.dir.d, dt));
    }
  }
}

}  // namespace REngine
