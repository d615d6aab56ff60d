// Private to REnginePhysics: the joint solver, the joints' part of the contact solver's
// island solve (RATTLE in impulses: RJoints.cpp says how). It gathers the step's joints
// (both bodies stepped, one at least movable and awake), lays each island's joints out once
// the contact solver has found the islands, and solves them island by island as the contact
// solver drives it: rows built and warm-started at the start of the step, one pass of them
// inside each of the contact solver's passes, the end poses predicted and the rows'
// targets set for each Newton round, geometric stiffness for islands the step cannot
// follow, the position projection, the joints within the impacts, the impulses reported
// and the end's velocity projection. It owns the step's joints, each island's joints, their
// rows and the joint bodies' predicted end poses. What it works on of the contact solver
// (its solver bodies, the island's contact rows and blocks) and of the step (the bodies,
// dt, the settings, the welds, the contacts its end projection reports on) comes in as an
// RJointIslandView the contact solver fills for each island; per-task scratch as an
// RIslandScratch (solver/RIslandScratch.h). Definitions: RJoints.cpp, RJointRows.cpp
// (PredictPose), RJointStiffness.cpp, RJointTurning.cpp, RJointMotors.cpp, RJointEnd.cpp and RJointImpacts.cpp.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RJoint.h>
#include <REnginePhysics/detail/RBodyCore.h>

#include "joints/RJointTypes.h"
#include "solver/RSolverTypes.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace REngine {

class RPairSweep;
class RUnionFind;
class RWeldGroups;
struct RIslandScratch;
struct RStepBodies;
struct RWorldSettings;

// One island of the contact solver's, as the joint solver works on it: the step's inputs,
// the contact solver's state it reads and writes, and the island's range of contact rows.
// Filled by the contact solver for the island it solves; valid while it does.
struct RJointIslandView {
  const RStepBodies& bodies;
  RScalar dt;          // s
  std::size_t island;  // the contact solver's island (its index in BlockIslands())
  // The contact solver's bodies (per dense index, the world's at bodies.size()), whose
  // velocities the joints' impulses change and whose outputs they add to.
  std::vector<RSolverBody>& solverBodies;
  // The contact solver's rows and blocks; the island's rows are [rowsFirst, rowsLast) of
  // rows (empty for an island of joints only). Read: the joints' stiffness and the end's
  // projection look at the island's contacts.
  const RContactRow* rows;
  const RBlock* blocks;
  std::uint32_t rowsFirst, rowsLast;
  const RWorldSettings& settings;  // solverIterations, gravity_W
  const RWeldGroups& welds;        // a weld's members are predicted as one body
  // The step's contacts: the end's projection adds the impulses it gives the island's
  // contacts to their report (RPairSweep::SolverContact).
  RPairSweep& sweep;
};

class RJointSolver {
 public:
  // The step's joints (RStepJoint: its index into bodies.joints and its bodies' dense
  // indices, b = bodies.size() for the world): both bodies stepped (a joint of a disabled
  // body waits), one at least movable and awake, in the container's order. Read by the
  // contact solver (its islands), the welds (GatherWelds) and sleeping (SleepIslands).
  void GatherJoints(const RStepBodies& bodies);
  const std::vector<RStepJoint>& StepJoints() const { return m_stepJoints; }

  // The islands' joints, laid out as the contact solver lays out its islands
  // (RContactSolver::LayOutIslands): each joint counted at its island's root (the
  // representative in sets of its movable body), and, once the islands are numbered
  // (islandOfRoot, per root: its island), each island's joints in the step's order.
  // JointsAtRoot tells the contact solver which roots make an island of joints alone.
  void CountIslandJoints(const RStepBodies& bodies, RUnionFind& sets);
  bool JointsAtRoot(std::size_t root) const { return !m_stepJoints.empty() && m_jointRootCount[root] > 0; }
  void LayOutIslandJoints(const RStepBodies& bodies, RUnionFind& sets, const std::vector<std::uint32_t>& islandOfRoot,
                          std::size_t islands);
  // The joints' rows and their bodies' end poses sized for the step (bodyCount: the
  // stepped bodies), once it has joints and before the islands are solved.
  void SizeForStep(std::size_t bodyCount) {
    m_jointRows.resize(m_stepJoints.size() * RJoint::kMaxRows);
    m_jointPoses.resize(bodyCount);
    m_motorTurns.resize(m_stepJoints.size());
  }
  bool IslandHasJoints(std::size_t island) const {
    return !m_islandJointStart.empty() && m_islandJointStart[island + 1] > m_islandJointStart[island];
  }

  // An island's joints, in the order the contact solver calls them: rows built at the start
  // of the step, warm-started and factored, with the first prediction and targets
  // (BuildIslandJoints); one pass of the rows inside each of the contact solver's velocity
  // passes (SolveJointsPass, returning the largest change of a row's relative velocity it
  // made, m/s or rad/s); the Newton rounds' prediction of the end poses (PredictJoints,
  // returning how far the worst row is off beyond the tolerance there, m or rad, 0 when
  // none is) and new targets (SetJointTargets); the projection of what error the rounds
  // leave (ProjectJoints); the impulses reported to the solver bodies (ReportJoints); and
  // the end of the step's velocity projection at the end poses (SolveJointsAtEnd).
  void BuildIslandJoints(const RJointIslandView& v, RIslandScratch& sc);
  RScalar SolveJointsPass(const RJointIslandView& v, RIslandScratch& sc);
  RScalar PredictJoints(const RJointIslandView& v, RIslandScratch& sc);
  void SetJointTargets(const RJointIslandView& v, RIslandScratch& sc);
  void ProjectJoints(const RJointIslandView& v, RIslandScratch& sc);
  void ReportJoints(const RJointIslandView& v);
  void SolveJointsAtEnd(const RJointIslandView& v, RIslandScratch& sc);
  // The turn of a hinge motor that turns a body about a fixed axis, in the rounds
  // (RJointMotors.cpp): what the velocity level gives the body's angle over the step (its
  // force, or its speed, with the hinge holding to first order), and how far the predicted
  // end poses are off it; with the island's rows' errors beyond rounding, the largest of
  // them (m or rad, 0 when none: an island without such a motor, or stiffened).
  // SetMotorTargets then holds each such turn in the next round (the motor's row an equality
  // on it, within the step's whole impulse); ResetMotors gives the motors back their velocity
  // rows (the rounds' fallbacks).
  RScalar MotorRound(const RJointIslandView& v, RIslandScratch& sc);
  void SetMotorTargets(const RJointIslandView& v, RIslandScratch& sc);
  void ResetMotors(const RJointIslandView& v, RIslandScratch& sc);
  // The rounds of an island in which a joint body turns more than kFastTurn rad a step
  // (RJointTurning.cpp): TurnsFast says whether it does (and is neither stiffened nor has a
  // motor's turn held, nor welds); TurningErrors, after a prediction, gives the block rows
  // (equalities, pushing limits) the errors for which their Newton step through the rows of
  // the start asks the impulses that the motion's own response takes the predicted errors
  // out with (false, the errors left as they are: more than kTurningRows such rows, or
  // redundant ones).
  bool TurnsFast(const RJointIslandView& v, const RIslandScratch& sc) const;
  bool TurningErrors(const RJointIslandView& v, RIslandScratch& sc);
  static constexpr RScalar kFastTurn = 0.5;
  static constexpr int kTurningRows = 48;
  // For the rounds (RContactSolver::JointRounds): the equality rows' impulses taken out of
  // the solver bodies (with the rows' masses they were given with), and the plain velocity
  // constraint's targets (no relative velocity along an equality row, a limit closing no
  // faster than its gap at the start of the step allows) when the rounds diverge.
  void ClearEquality(const RJointIslandView& v);
  void SetPlainTargets(const RJointIslandView& v, const RIslandScratch& sc);
  // The joints' geometric stiffness (RJointStiffness.cpp). JointStiffness fills sc.stiffness
  // for the island's joint bodies and returns the largest (omega dt)^2 of their arms' modes;
  // Stiffen solves with it from there on (rows' masses again); Unstiffen gives the bodies
  // back their inertia, the motion the turn the solver gave them, and the island back what
  // that took from its angular momentum.
  RScalar JointStiffness(const RJointIslandView& v, RIslandScratch& sc);
  void Stiffen(const RJointIslandView& v, RIslandScratch& sc);
  void Unstiffen(const RJointIslandView& v, RIslandScratch& sc);
  // Above this (omega dt)^2 of an arm's mode an island's joints are solved stiffened
  // (RJointStiffness.cpp); the rounds lose a chain's links past about 2.
  static constexpr RScalar kUnresolved = 1;
  // Newton rounds of the joints' end-of-step prediction after the first, at most.
  static constexpr int kJointRounds = 6;
  // ... and of an island with a motor turning a body about a fixed axis, which goes on to
  // rounding while each round halves what is left (RJointMotors.cpp): a body turning off its
  // principal axes converges by about ten times a round.
  static constexpr int kMotorRounds = 16;
  // An island's joints in its impacts (RJointImpacts.cpp): their equality rows hold the
  // joined bodies' relative velocities through the impacts (sc.impactRows, a copy of the
  // rows with impulses of their own), solved with each impact (at its time t, s); then the
  // impulses reported and the joints' prediction made again from the velocities after
  // (impacts: whether some impact happened).
  void BeginImpactJoints(const RJointIslandView& v, RIslandScratch& sc);
  void ImpactJointsPass(const RJointIslandView& v, RScalar t, RIslandScratch& sc);
  void EndImpactJoints(const RJointIslandView& v, RIslandScratch& sc, bool impacts);

 private:
  // A joint body's pose at the start of the step, or at its end as predicted (end = true;
  // the world's: the origin, unturned).
  RJointPoseIn JointPose(const RJointIslandView& v, std::uint32_t i, bool end) const;
  // The pose the motion will give a movable body from its solver state s (RJointRows.cpp).
  static RJointPose PredictPose(const RBodyCore& b, const RSolverBody& s, RScalar dt);
  // The end bodies (RIslandScratch::endBodies) of the island's joints, each movable body
  // once (sc.mark: its index there; cleared by ClearJointMarks), each immovable end apart;
  // their rows at the predicted end poses in sc.endRows, errors in sc.jointC. atEnd: with
  // the end velocities (SolveJointsAtEnd), else at rest (ProjectJoints' pseudo-velocities).
  void BuildEndRows(const RJointIslandView& v, RIslandScratch& sc, bool atEnd);
  static void ClearJointMarks(RIslandScratch& sc);
  // EndStiffness does at the end of the step what Unstiffen does in the rounds, and takes
  // back what the position projection added to a free island's angular momentum.
  void EndStiffness(const RJointIslandView& v, RIslandScratch& sc, const RVec3* wBefore, const RVec3& projected);
  bool FreeJointIsland(const RJointIslandView& v, const RIslandScratch& sc) const;
  // A body's world inverse inertia invI with `added` of rotational inertia (kg m^2) about
  // every axis: the stiffened inertia's inverse.
  static RMat3 Stiffened(const RMat3& invI, RScalar added);
  // The rows' arms shifted after the impacts (solverBodies: per dense index).
  static void ShiftJointArms(RJointRow* rows, std::size_t count, const RSolverBody* solverBodies, RScalar dt);
  // What the arm's moment of a linear joint row along d gains on a body an impact hit:
  // (dt deferV) x d, of the free part of d on a body with linear locks (as the contacts').
  static RVec3 JointArmShift(const RSolverBody& s, const RVec3& d, RScalar dt) {
    if (s.deferV.isZero(0) || s.invM == 0) return RVec3::Zero();
    const RVec3 shift = dt * s.deferV;
    return s.linLocked ? RVec3(shift.cross(d.cwiseProduct(s.linMask))) : RVec3(shift.cross(d));
  }
  // A joint's tolerance (m or rad) near world point x: 1e-10, or a few ulps of x far from
  // the origin.
  static RScalar JointTolerance(const RVec3& x) {
    return std::max(RScalar(1e-10), RScalar(1e-15) * x.cwiseAbs().maxCoeff());
  }
  // A joint's motor (p: the joint's place in m_islandJoints) whose row holds a turn
  // (RJointMotors.cpp), how far its position at the end poses now is off that turn (for the
  // position projection), and its row at the end of the step: the rest of the step's impulse.
  bool MotorTurning(std::uint32_t p) const { return m_motorTurns[p].on; }
  RScalar MotorError(const RJointIslandView& v, std::uint32_t p) const;
  void EndMotorBounds(std::uint32_t p, const RJointRow& mid, RJointRow& end) const;
  void ResetMotor(const RJointIslandView& v, RIslandScratch& sc, std::uint32_t p);
  // Joints solved exactly as one skyline block per island up to this many equality rows (a
  // chain of 40 hinges), larger islands as one sparse system (RJointSparse.h).
  static constexpr int kJointBlockRows = 256;

  std::vector<RStepJoint> m_stepJoints;
  // Each island's joints: m_islandJoints[m_islandJointStart[k], m_islandJointStart[k + 1])
  // are indices into m_stepJoints, in its order (empty starts: the step has no joints).
  std::vector<std::uint32_t> m_islandJoints, m_islandJointStart;
  std::vector<std::uint32_t> m_jointRootCount, m_islandJointFill;  // (the layout's scratch)
  // The joints' rows, kMaxRows a joint, island by island: the island's joint at position p
  // of m_islandJoints has its rows at p * RJoint::kMaxRows.
  std::vector<RJointRow> m_jointRows;
  // Per movable body in some joint: its end pose, kept from the last prediction of the step.
  std::vector<RJointPose> m_jointPoses;
  // Per joint, as m_islandJoints, for its motor (RJointMotors.cpp): whether it turns a body
  // about a fixed axis (a hinge motor whose body has no other joint and is hinged to the
  // world or a static body), the hinge's angle at the start of the step and where the
  // rounds' turn ends it, the predicted end's error from that (measured: this round), its
  // half step's impulse (maxForce dt / 2), and whether its row holds the turn (on) or, after
  // the step's first passes, is still the velocity row it starts as.
  struct RMotorTurn {
    RScalar start = 0, end = 0, error = 0, nominal = 0;
    bool fixedAxis = false, measured = false, on = false;
  };
  std::vector<RMotorTurn> m_motorTurns;
};

}  // namespace REngine
