// An island's contact phase after its impacts (RContactSolver::SolveIslandContacts): block
// inverses, sequential-impulse passes over the manifolds, their friction patches, warm
// starts, the joints' Newton rounds that drive the passes again, which rows close at the end
// of the step, island by island.
#include "solver/RContactSolver.h"

#include "motion/RMotion.h"
#include "pairs/RPairSweep.h"
#include "solver/RSolverRows.h"
#include "world/RStepBodies.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace solver;

// A manifold's block inverse (see FindImpulses): returns whether it was kept from the
// manifold's memory.
bool RContactSolver::BlockInverse(RBlock& blk) {
  if (!blk.useBlock) return false;
  const std::uint32_t first = blk.first;
  const RSolverBody& sa = m_solverBodies[m_rows[first].a];
  const RSolverBody& sb = m_solverBodies[m_rows[first].b];
  // Padded with zeros to 4 x 4: the padding's eigenvalues are 0 and drop out of the
  // inverse, so one fixed-size symmetric eigensolver serves every point count.
  Eigen::Matrix<RScalar, 4, 4> K = Eigen::Matrix<RScalar, 4, 4>::Zero();
  for (int i = 0; i < blk.count; ++i) {
    const RDirection& di = m_rows[first + i].n;
    for (int j = 0; j <= i; ++j) {
      const RDirection& dj = m_rows[first + j].n;
      const RScalar dd = di.d.dot(dj.d);
      const RScalar linear = sa.linLocked || sb.linLocked
                                 ? LinearCoupling(sa, di.d, dj.d, dd) + LinearCoupling(sb, di.d, dj.d, dd)
                                 : (sa.invM + sb.invM) * dd;
      K(i, j) = K(j, i) = linear + di.rAxd.dot(dj.iA) + di.rBxd.dot(dj.iB);
    }
  }
  // A manifold kept from an earlier step (contact reuse) keeps its inverse while the
  // matrix stays within 1e-12 of the one it was computed for: the bodies have moved by
  // less than the touching band, and the inverse's error is then 1e-12 of the block's
  // condition, far below what the passes resolve. (The eigen-solve is the costliest
  // part of building a resting pile's rows.)
  RManifoldMemory* mem = m_in->sweep.MemoryOf(m_rows[first].contact);
  if (mem && mem->hasInverse &&
      (K - mem->K).cwiseAbs().maxCoeff() <= RScalar(1e-12) * mem->K.cwiseAbs().maxCoeff()) {
    blk.pinv = mem->pinv;
    return true;
  }
  // Minimum-norm inverse: sum of v v^T / s over the eigenpairs with s above 1e-12 of the
  // largest. The directions below are the coplanar points' null space (exactly 0 but for
  // rounding, ~1e-16 of the largest); the softest real direction, a heavy body's, is
  // shared with the light body it touches and stays near the light body's stiffness.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<RScalar, 4, 4>> eigen(K);
  const Eigen::Matrix<RScalar, 4, 1>& s = eigen.eigenvalues();  // ascending
  const RScalar floor = RScalar(1e-14) * s[3];
  blk.pinv.setZero();
  for (int k = 0; k < 4; ++k) {
    if (!(s[k] > floor)) continue;
    const Eigen::Matrix<RScalar, 4, 1> v = eigen.eigenvectors().col(k);
    blk.pinv += (v / s[k]) * v.transpose();
  }
  if (mem) mem->hasInverse = true, mem->K = K, mem->pinv = blk.pinv;
  return false;
}

// An island's contact phase after its impacts: its passes (each block's inverse worked out
// the first time it has something to solve: SolveNormalBlock), its direct
// solves (velocities, then positions) and which of its rows are closed at the end of the
// step; then, when some row is closed at the end, the second half-kick and the end's warm
// starts, passes and direct solves. One island at a time, start to end (SolveIsland), its
// rows, blocks and bodies are read from the cache, not gathered again from all over memory
// by a sweep per stage (a 10000-box pile's rows and blocks are 15 MB). Islands share no
// body an impulse moves: solved side by side on any number of threads, each gives the same
// answer bit for bit.
void RContactSolver::SolveIslandContacts(const RStepBodies& bodies, RScalar dt, std::size_t island,
                                         const RJointIslandView& joints, RIslandScratch& sc) {
  const RScalar halfDt = RScalar(0.5) * dt;
  const int iterations = std::max(1, m_in->settings.solverIterations);
  const auto [first, last] = m_blockIslands[island];
  const std::uint32_t* islandBodies = m_islandBodies.data() + m_islandBodyStart[island];
  const std::size_t bodyCount = m_islandBodyStart[island + 1] - m_islandBodyStart[island];
  // A direct solve leaves an island alone that its passes left solved to 1e-9 m/s. A last
  // pass that changed nothing found every row it solves at its target to 1e-12 m/s (the
  // blocks' and patches' kAtTarget, or a row's own solve giving no change), so there is
  // nothing to check (a resting pile: every island, three times a step). The passes leave
  // out only what the direct solve leaves out too (rows never in contact), but for
  // position correction, which they skip in a manifold with none of its own: the island
  // must have none at all (its bodies then have no pseudo-velocity).
  const bool settled = SolveIslandBlocks(RPhase::kVelocity, iterations, first, last, &joints, &sc);
  const auto [rowsFirst, rowsLast] = IslandRows(island);
  const bool direct = m_islandDirect[island];
  if (direct) IslandDirectSolves(island, sc, settled);
  // The joints' Newton rounds and their projection (JointRounds, below): passes again while
  // some joint would end the step off its constraint.
  if (m_joints.IslandHasJoints(island)) JointRounds(joints, sc);
  bool closes = false;
  for (std::uint32_t i = rowsFirst; i < rowsLast; ++i) closes = CloseAtEnd(m_rows[i], dt) || closes;
  // What the contact phase changed after the impacts (see the deferred impulses, ReportIsland),
  // and the spin a body that turned at an impact turns with from its last one on.
  for (std::size_t k = 0; k < bodyCount; ++k) {
    RSolverBody& s = m_solverBodies[islandBodies[k]];
    s.contactDeltaV = s.v - s.vImpacts;
    if (s.turned) s.turnW_W = s.w;
  }
  if (!closes) {
    for (std::uint32_t i = rowsFirst; i < rowsLast; ++i) m_rows[i].lambdaE = 0;
    for (std::uint32_t k = first; k < last; ++k) {
      RBlock& blk = m_blocks[k];
      blk.lambdaT1[1] = blk.lambdaT2[1] = blk.lambdaTwist[1] = 0;
    }
    return;
  }
  // The end velocities: the second half-kick of the applied forces and gravity.
  for (std::size_t k = 0; k < bodyCount; ++k) {
    const std::uint32_t i = islandBodies[k];
    const RBodyCore& b = bodies[i];
    RSolverBody& s = m_solverBodies[i];
    s.vMid = s.v - s.deferV;
    s.v += RMotion::Acceleration(b, m_in->settings.gravity_W) * halfDt;
    s.w += s.invI * RMotion::EndAngularKick_W(b, halfDt);
  }
  WarmStartIsland(RPhase::kEnd, first, last, 0);  // last step's end impulses, found with the rows
  const bool settledAtEnd = SolveIslandBlocks(RPhase::kEnd, iterations, first, last, nullptr, &sc);
  if (direct && !settledAtEnd) {
    PrepareIslandDirect(island, sc);
    SolveIslandDirect(RPhase::kEnd, sc);
  }
}

// The island's direct solves after its velocity passes: velocities (unless the passes left
// them solved) and position correction, on the same matrix.
// The island has no position correction to solve when no row pushes (lambdaP) and none asks
// for more than half the direct solve's kDirectSolved: the island's pseudo-velocities are
// then those of impulses that came back to zero (rounding of targets that small, if any),
// each row misses its target by no more than the target itself, and the position solve
// would return at once. A resting pile's boxes stay up to 3.3e-14 m beyond the slop (the
// passes' at-target band, 1e-12 m/s, times dt over the correction's 0.5: closer than that,
// halving the excess no longer moves them), and in the 10000-box pile 99% of the directly
// solved islands' steps had such a row.
void RContactSolver::IslandDirectSolves(std::size_t island, RIslandScratch& sc, bool settled) {
  const auto [rowsFirst, rowsLast] = IslandRows(island);
  bool positions = false;
  for (std::uint32_t i = rowsFirst; i < rowsLast && !positions; ++i) {
    positions = m_rows[i].pseudoTarget > RScalar(0.5) * kDirectSolved || m_rows[i].lambdaP > 0;
  }
  if (!settled || positions) {
    PrepareIslandDirect(island, sc);
    if (!settled) SolveIslandDirect(RPhase::kVelocity, sc);
    if (positions) SolveIslandDirect(RPhase::kPosition, sc);  // the same matrix
  }
}

// The joints' Newton rounds (see the top of joints/RJoints.cpp): after the island's passes,
// the end poses predicted again, and while some joint would end the step off its
// constraint, new targets and the passes (and the island's direct solves: passes) again, as
// long as each round at least halves the worst error. An island whose arms' modes the step
// cannot follow is solved stiffened (RJointStiffness.cpp): its equality impulses solved
// again from nothing, the rounds again. The joint solver predicts, sets the targets,
// stiffens and projects; the passes are the contact solver's, joints and contacts together.
// An island in which a joint body turns far in a step takes its Newton steps through the
// motion's own response to the rows' impulses (joints/RJointTurning.cpp), not the rows'.
void RContactSolver::JointRounds(const RJointIslandView& joints, RIslandScratch& sc) {
  const std::size_t island = joints.island;
  // (Not a structured binding: the lambda below captures them, which C++17 forbids.)
  const std::uint32_t first = m_blockIslands[island].first, last = m_blockIslands[island].second;
  const int iterations = std::max(1, m_in->settings.solverIterations);
  auto passes = [&] {
    const bool settled = SolveIslandBlocks(RPhase::kVelocity, iterations, first, last, &joints, &sc);
    if (m_islandDirect[island]) IslandDirectSolves(island, sc, settled);
  };
  enum class RRounds { kMet, kLeft, kDiverged };
  // An island with a motor turning a body about a fixed axis goes on past the joints'
  // tolerance to rounding (fine: what is beyond it, the motors' turns included;
  // joints/RJointMotors.cpp) while the rounds still halve it; then it is met whatever is left
  // below the tolerance.
  const bool turning = m_joints.TurnsFast(joints, sc);
  auto rounds = [&] {
    RScalar previous = std::numeric_limits<RScalar>::infinity();
    for (int round = 0;; ++round) {
      const RScalar worst = m_joints.PredictJoints(joints, sc);
      const RScalar fine = m_joints.MotorRound(joints, sc);
      if (worst == 0 && fine == 0) return RRounds::kMet;
      const RScalar off = worst > 0 ? worst : fine;
      if (!(off < RScalar(0.5) * previous)) return worst == 0 ? RRounds::kMet : RRounds::kDiverged;
      if (round == (fine > 0 ? RJointSolver::kMotorRounds : RJointSolver::kJointRounds)) {
        return worst == 0 ? RRounds::kMet : RRounds::kLeft;
      }
      previous = off;
      if (turning && !sc.stiffened) m_joints.TurningErrors(joints, sc);
      m_joints.SetJointTargets(joints, sc);
      m_joints.SetMotorTargets(joints, sc);
      passes();
    }
  };
  // Rounds as they are while the step follows the arms' modes; else, or when they diverge,
  // stiffened from nothing.
  RRounds outcome = RRounds::kDiverged;
  if (!(m_joints.JointStiffness(joints, sc) > RJointSolver::kUnresolved)) {
    outcome = rounds();
    if (outcome != RRounds::kDiverged) {
      for (std::uint32_t i : sc.jointBodies) sc.stiffness[i] = 0;
      if (outcome == RRounds::kMet) return;
    }
  }
  if (outcome == RRounds::kDiverged) {
    m_joints.ClearEquality(joints);
    m_joints.ResetMotors(joints, sc);
    m_joints.Stiffen(joints, sc);
    outcome = rounds();
    if (outcome == RRounds::kDiverged) m_joints.ClearEquality(joints);
  }
  if (outcome == RRounds::kDiverged) {
    // Not converging: the velocities of a diverging round are not physics. The plain
    // velocity constraint instead (no relative velocity along an equality row, a limit
    // closing no faster than its gap allows), which is always well posed; ProjectJoints
    // takes the error it leaves out of the positions. Its equality rows solved from
    // nothing: the rounds' impulses hold what they asked of the near-singular directions
    // (a nearly flat mesh of joints, whose tension grows without bound as it flattens),
    // which the plain constraint would leave in place, moving nothing now and flinging
    // the bodies as the next step's warm start (a 6 x 6 mesh tumbling at 1 rad/s was
    // asked 1e3 m of correction there, the step after a round 1e-5 m off). Stiffened,
    // as the rounds that could not follow the arms' modes are.
    m_joints.SetPlainTargets(joints, sc);
    passes();
  }
  if (sc.stiffened) m_joints.Unstiffen(joints, sc);
  m_joints.PredictJoints(joints, sc);
  m_joints.ProjectJoints(joints, sc);
}

// The sequential-impulse passes over the manifolds, alternating the sweep's direction (for
// the same reason as the blocks across manifolds). kVelocity: each manifold's normal rows
// (reach the targets, never pull), its friction bounded by this pass's normal impulses,
// then position correction on the pseudo-velocities, as a block like the velocities (one
// point at a time, the first point of a face would be favoured and the correction would
// tilt the box: a 20-box stack then leans further every step and falls). kEnd: normal rows
// and friction on the end velocities.
//
// Manifolds of different islands (bodies linked through dynamic bodies, LayOutIslands)
// share no body that an impulse moves, so each island's passes are those of the whole
// sweep restricted to its manifolds, in the same order: the islands are solved apart, on
// as many threads as there are, with bit-identical results.
//
// An island's passes stop early once one changes no row's relative speed by more than
// kConverged: the passes after it would only move rounding about. A resting pile's warm
// starts are right to 1e-13 m/s, and most of its islands stop after the first pass or two
// instead of running all ten (twice a step, with the end's). A pass that changes nothing
// at all is followed by passes that change nothing (each manifold's solve depends only on
// its bodies' velocities and its impulses), so a stop at rounding changes the answer by no
// more than rounding's worth per pass it skips.
bool RContactSolver::SolveIslandBlocks(RPhase phase, int iterations, std::uint32_t first, std::uint32_t last,
                                       const RJointIslandView* joints, RIslandScratch* sc) {
  constexpr RScalar kConverged = 1e-12;  // m/s
  constexpr int kGroupSweeps = 4;  // (two suffice in seams_tests' crossings)
  const bool withJoints = joints && sc && phase == RPhase::kVelocity && m_joints.IslandHasJoints(joints->island);
  RScalar change = 0;
  for (int it = 0; it < iterations; ++it) {
    change = withJoints ? m_joints.SolveJointsPass(*joints, *sc) : 0;
    const bool forward = it % 2 == 0;
    for (std::uint32_t k = first; k < last; ++k) {
      RBlock& blk = m_blocks[forward ? k : last - 1 - (k - first)];
      RContactRow* rows = &m_rows[blk.first];
      // A patch shared by a group of manifolds (RPatchGroups.cpp) is solved after the
      // group's last normal block in the sweep's direction, as a manifold's after its own.
      // A group whose normal rows are one block has them solved there too, as one manifold.
      const bool patchDue = forward ? blk.nextInPatch == kNoBlock : &m_blocks[blk.patch] == &blk;
      RBlock& patch = m_blocks[blk.patch];
      if (patch.groupRows && sc) {  // (an island with groups is solved with its scratch)
        if (!patchDue) continue;
        // The group's normal block and patch in turn until they agree (kGroupSweeps at most):
        // friction at the line of contact, below the centre, tilts the body about the line and
        // the normal rows stop the tilt, which slides the line again. A manifold's points stay
        // put from step to step and its warm start leaves nothing to converge there; a group's
        // points move with the seams, and the island's passes alone left 1e-9 m/s.
        const RPhase normals = phase == RPhase::kVelocity ? RPhase::kVelocity : RPhase::kEnd;
        for (int sweep = 0; sweep < kGroupSweeps; ++sweep) {
          const RScalar normalChange = SolveGroupNormals(patch, normals, *sc);  // (first, then the patch)
          const RScalar groupChange = std::max(normalChange, SolvePatch(patch, false, normals));
          change = std::max(change, groupChange);
          if (!(groupChange > kConverged)) break;
        }
        if (phase == RPhase::kVelocity) change = std::max(change, SolveGroupNormals(patch, RPhase::kPosition, *sc));
        continue;
      }
      if (phase == RPhase::kVelocity) {
        change = std::max(change, SolveNormalBlock(blk, rows, RPhase::kVelocity));
        if (patchDue) change = std::max(change, SolvePatch(patch, false, RPhase::kVelocity));
        change = std::max(change, SolveNormalBlock(blk, rows, RPhase::kPosition));
      } else {
        change = std::max(change, SolveNormalBlock(blk, rows, RPhase::kEnd));
        if (patchDue) change = std::max(change, SolvePatch(patch, false, RPhase::kEnd));
      }
    }
    if (!(change > kConverged)) break;
  }
  return change == 0;
}

// Applies patch impulses (tangential at the centroid, twist about the normal) to the solver
// bodies' velocities.
void RContactSolver::ApplyPatch(const RBlock& blk, RScalar d1, RScalar d2, RScalar dTwist) {
  const RContactRow& r = m_rows[blk.first];
  RSolverBody& sa = m_solverBodies[r.a];
  RSolverBody& sb = m_solverBodies[r.b];
  if (d1 != 0) Push(blk.t[0], d1, sa, sb, sa.v, sa.w, sb.v, sb.w);
  if (d2 != 0) Push(blk.t[1], d2, sa, sb, sa.v, sa.w, sb.v, sb.w);
  if (dTwist != 0) {
    if (sa.invM != 0) sa.w -= dTwist * blk.twistIA;
    if (sb.invM != 0) sb.w += dTwist * blk.twistIB;
  }
}

// A manifold's friction: the tangential impulse at its centroid stops the sliding there,
// within the Coulomb disc of mu times the manifold's total normal impulse, and the twist
// stops the spin about the normal within mu times the sum of each point's normal impulse
// times its distance from the centroid. One patch instead of friction at each point: the
// points' friction solved one after another twists the body a little and leaves each
// point's impulse slightly off the sliding direction, which loses about 1% of the friction
// of a box sliding down an incline. clampOnly: only bring the impulses back inside limits
// that the normal impulses changed.
//
// A group of manifolds on flush immovable bodies (RPatchGroups.cpp) has one patch, its
// first block's: the limits sum all the group's rows, the others' patches are empty.
RScalar RContactSolver::SolvePatch(RBlock& blk, bool clampOnly, RPhase phase) {
  if (&m_blocks[blk.patch] != &blk) return 0;  // its group's patch is another block's
  const int ph = phase == RPhase::kEnd ? 1 : 0;
  RContactRow* rows = &m_rows[blk.first];
  RScalar normal = 0, twistArm = 0, reach = 0;
  for (const RBlock* g = &blk;; g = &m_blocks[g->nextInPatch]) {
    RContactRow* gRows = &m_rows[g->first];
    for (int i = 0; i < g->count; ++i) {
      const RScalar l = Lambda(gRows[i], phase);
      normal += l, twistArm += l * gRows[i].lever;
      reach = std::max(reach, gRows[i].lever);
    }
    if (g->nextInPatch == kNoBlock) break;
  }
  const RSolverBody& sa = m_solverBodies[rows[0].a];
  const RSolverBody& sb = m_solverBodies[rows[0].b];
  RScalar lt1 = blk.lambdaT1[ph], lt2 = blk.lambdaT2[ph], lw = blk.lambdaTwist[ph];
  const RScalar limit = blk.friction * normal;
  const RScalar twistLimit = blk.friction * twistArm;
  if (!clampOnly) {
    const RScalar v1 = Speed(blk.t[0], sa.v, sa.w, sb.v, sb.w) - blk.targetT[ph][0];
    const RScalar v2 = Speed(blk.t[1], sa.v, sa.w, sb.v, sb.w) - blk.targetT[ph][1];
    const RScalar spin = blk.kTwist > 0 ? blk.normal.dot(sb.w - sa.w) : RScalar(0);
    // Already stuck, to the passes' tolerance (as SolveNormalBlock's kAtTarget), with
    // impulses inside their limits: nothing to change (a resting manifold).
    constexpr RScalar kAtTarget = 1e-12;  // m/s
    if (std::abs(v1) <= kAtTarget && std::abs(v2) <= kAtTarget && std::abs(spin) * reach <= kAtTarget &&
        lt1 * lt1 + lt2 * lt2 <= limit * limit && std::abs(lw) <= twistLimit) {
      return 0;
    }
    // Both tangents at once, through the 2 x 2 effective mass: one at a time the answer
    // would depend on which two tangents the basis picked, and that choice jumps when the
    // normal's z component changes sign (a slope moved 1e6 m away slid 1e-5 m further).
    const Eigen::Matrix<RScalar, 2, 1> step = TangentStep(blk.t[0], blk.t[1], v1, v2, sa, sb);
    lt1 += step.x(), lt2 += step.y();
    if (blk.kTwist > 0) lw -= spin / blk.kTwist;
  }
  const RScalar norm = std::sqrt(lt1 * lt1 + lt2 * lt2);  // std::hypot: 5% of a pile step
  if (norm > limit) lt1 *= limit / norm, lt2 *= limit / norm;
  lw = std::clamp(lw, -twistLimit, twistLimit);
  const RScalar d1 = lt1 - blk.lambdaT1[ph], d2 = lt2 - blk.lambdaT2[ph], dw = lw - blk.lambdaTwist[ph];
  blk.lambdaT1[ph] = lt1, blk.lambdaT2[ph] = lt2, blk.lambdaTwist[ph] = lw;
  ApplyPatch(blk, d1, d2, dw);
  // The twist's change of spin (rad/s) as the speed it gives the patch's farthest point.
  return std::max({std::abs(d1) * blk.t[0].k, std::abs(d2) * blk.t[1].k, std::abs(dw) * blk.kTwist * reach});
}

// The end of the step. The contact impulses found so far act at its start, on the velocity
// the bodies move with (the mid-step velocity of kick-drift-kick), which is what keeps a
// resting box exactly in place; but the step's second half-kick of gravity then leaves it
// with -g dt / 2 at the end, and a box stuck on a slope with g sin(theta) dt / 2 down the
// slope: at rest, reported moving. So every contact that is closed at the end of the step
// gets a second impulse there (SolveIslandContacts): no approach, friction within its cone, solved like the
// first (blocks, patches, islands) on the end velocities. A resting body then ends each
// step at rest, and the support it needs is shared between the two ends of the step, the
// way kick-drift-kick shares a force; a sliding box's friction is shared the same way. The
// impulses are inelastic (targets of zero, never pulling): they cannot add energy.
// Whether row r is closed at the end of the step (endTarget its end velocity), or not
// (kNever, and no end impulse).
bool RContactSolver::CloseAtEnd(RContactRow& r, RScalar dt) const {
  const RScalar halfDt = RScalar(0.5) * dt;
  const RSolverBody& sa = m_solverBodies[r.a];
  const RSolverBody& sb = m_solverBodies[r.b];
  // Closed at the end: the gap after moving with this step's velocities (a touching band
  // of a micrometre per metre of size for rounding).
  // A spinning kinematic body's surface point moves on an arc: the gap closes by the motion
  // relative to the chord that point travels (KinematicDrift_W), and the contact ends at
  // rest with the velocity that surface has at the end, where the point then is.
  const bool kinematic = (sa.invM == 0 && !sa.w.isZero(0)) || (sb.invM == 0 && !sb.w.isZero(0));
  auto surfaceDrift = [&](bool end) {
    return r.n.d.dot(RMotion::ContactDrift_W(sa.invM == 0 ? sa.w : sb.w, r.rA, r.rB, dt, end));
  };
  const RScalar vn = Speed(r.n, sa.v, sa.w, sb.v, sb.w);
  const RScalar gapEnd = r.gap + (kinematic ? vn - surfaceDrift(false) - r.deferN : vn - r.deferN) * dt;
  const RScalar band = 1e-6 * (sa.radius + sb.radius);
  // A contact that closes faster than the restitution threshold is an impact, and the
  // next step's impact phase bounces it; stopped here it would end inelastic. What this
  // step's acceleration alone adds (a resting body's g dt / 2 into the ground) is not an
  // approach: the support acts all through the step.
  const RScalar vnEnd = vn + halfDt * r.n.d.dot(sb.accel - sa.accel);
  const bool approaching = vnEnd < -m_in->settings.restitutionThreshold && vn < -m_in->settings.restitutionThreshold;
  // A body that had an impact this step is not at rest: its end-of-step velocity is the
  // impact's outcome, left as it is.
  const bool impacted = sa.tau > 0 || sb.tau > 0;
  // Nor is a polyhedron whose spin carries the contact point further than the slop within
  // the step: this impulse is solved with the lever arms of the step's start and applied
  // at its end, and on a cube spinning at 5 rad/s the arm has turned 0.08 m by then, so an
  // impulse that stops the approach in the solver's frame adds energy in the body's (a
  // pair in the debris cloud gained 1e-5 of its energy in one step). A sphere's contact
  // point does not turn with it, and a kinematic body's impulse is not applied (a crate on
  // a turntable keeps its end impulses).
  // Against a kinematic body it is the spin relative to its surface that carries the point
  // (a crate turning with a station's deck does not move on it).
  auto arc = [dt](const RSolverBody& s, const RSolverBody& other, const RVec3& arm) {
    if (!s.armTurns) return RScalar(0);
    return (other.invM == 0 ? RVec3(s.w - other.w) : s.w).norm() * arm.norm() * dt;
  };
  // (Its square roots only for a row that is otherwise closed.)
  auto spinning = [&] { return arc(sa, sb, r.rA) + arc(sb, sa, r.rB) > m_in->settings.penetrationSlop; };
  const bool closed = gapEnd <= band && !approaching && !impacted && r.n.k > 0 && !spinning();
  // Closed, the contact ends the step at rest on the other body's surface: with no normal
  // velocity against it, or, against a spinning kinematic body (a station's deck), with the
  // surface's own there (its acceleration, w x (w x r) for a steady spin, taken into
  // account, as gravity's is above).
  r.endTarget = closed ? (kinematic ? surfaceDrift(true) : RScalar(0)) : kNever;
  if (!closed) r.lambdaE = 0;
  return closed;
}

}  // namespace REngine
