// The joints in the impact phase (SolveIslandImpacts, RImpactPhase.cpp).
//
// Why. An impact is solved at its instant, before the contact phase where the joints are
// solved with the contacts. Solved without the joints, a ball hitting a hinged door bounced
// off it as off a free body and the hinge opened by millimetres (a ragdoll pile landing
// opened its joints by 6 cm); skipped (what jointed islands did before), every contact in
// them met inelastically, and the ball did not bounce at all.
//
// How. The joints act in the impact as impulses too: their equality rows (a copy of the
// step's rows, with impulses of their own) hold the joined bodies' relative velocities at
// what they were before the impacts, solved as the contact phase solves them (the exact
// block). Each impact is one bounce, as in an island without joints (so that a cradle of
// pendulums passes the impulse down the row, the striker stopping and the last ball leaving,
// instead of sharing it out as a block): its impulse turns the approach speed vn into
// -e vn with the joints' reaction included. That reaction is linear in the impulse, so its
// rate is measured by applying the free bodies' impulse and solving the joints; the rest of
// the impulse and friction follow, and the joints again. The joints' impulses are the
// bodies' like any other (reported with the impacts'), and the joints' end-of-step
// prediction is made again from the velocities after the impacts.
//
// Limits and motors do not act in the impact (a door hit while at its limit is stopped by
// the limit in the contact phase, inelastically).
#include "joints/RJointSolver.h"

#include "joints/RJointRows.h"
#include "joints/RJointSystem.h"
#include "solver/RSolverRows.h"

namespace REngine {

using namespace joints;

void RJointSolver::BeginImpactJoints(const RJointIslandView& v, RIslandScratch& sc) {
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  const RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  const std::size_t count = std::size_t(j1 - j0) * kRows;
  sc.impactRows.assign(rows, rows + count);
  for (RJointRow& r : sc.impactRows) {
    if (r.kind != Kind::kEquality) {
      r.kind = Kind::kOff;
      continue;
    }
    r.lambda = 0;
    r.target = RowSpeed(r, v.solverBodies.data());
  }
  BeginJointBlocks(sc.impactRows.data(), count, sc);
}

// The joints' answer to an impact at time t of the step: the island's joint bodies moved
// along their paths up to t first (the joints' impulses act at the impact's instant), as the
// impact phase moves a body it hits.
void RJointSolver::ImpactJointsPass(const RJointIslandView& v, RScalar t, RIslandScratch& sc) {
  for (std::uint32_t i : sc.jointBodies) {
    RSolverBody& s = v.solverBodies[i];
    if (t > s.tau) s.moved += s.v * (t - s.tau), s.tau = t;
  }
  JointPass(sc.impactRows.data(), sc.impactRows.size(), v.solverBodies.data(), sc, sc.mark, kJointBlockRows);
}

// The contact phase's impulses on a body an impact hit act with the arms r + dt deferV (see
// ShiftArmsAfterImpacts, RContactSolver.cpp: the body's post-impact path runs back through
// x - dt deferV, and ReportIsland hands it the moment that keeps angular momentum exact):
// the joints' rows too, or the spin the motion gives the body is not the one their solve
// and the prediction of the end poses weighed (a chain landing opened its joints by 2 mm).
// Angular rows have no arm.
void RJointSolver::ShiftJointArms(RJointRow* rows, std::size_t count, const RSolverBody* solverBodies, RScalar dt) {
  for (std::size_t i = 0; i < count; ++i) {
    RJointRow& r = rows[i];
    if (r.kind == Kind::kOff || r.dir.d.isZero(0)) continue;
    const RSolverBody& a = solverBodies[r.a];
    const RSolverBody& b = solverBodies[r.b];
    if (a.deferV.isZero(0) && b.deferV.isZero(0)) continue;
    r.dir.rAxd += JointArmShift(a, r.dir.d, dt), r.dir.rBxd += JointArmShift(b, r.dir.d, dt);
    r.dir.iA = a.invI * r.dir.rAxd, r.dir.iB = b.invI * r.dir.rBxd;
    r.dir.k = solver::LinearCoupling(a, r.dir.d, r.dir.d, 1) + solver::LinearCoupling(b, r.dir.d, r.dir.d, 1) +
              r.dir.rAxd.dot(r.dir.iA) + r.dir.rBxd.dot(r.dir.iB);
  }
}

void RJointSolver::EndImpactJoints(const RJointIslandView& v, RIslandScratch& sc, bool impacts) {
  for (const RJointRow& r : sc.impactRows) {
    if (r.kind == Kind::kOff || r.lambda == 0) continue;
    RSolverBody& a = v.solverBodies[r.a];
    RSolverBody& b = v.solverBodies[r.b];
    if (a.invM != 0) a.impulse -= r.lambda * r.dir.d, a.angularImpulse -= r.lambda * r.dir.rAxd;
    if (b.invM != 0) b.impulse += r.lambda * r.dir.d, b.angularImpulse += r.lambda * r.dir.rBxd;
  }
  // The step's own rows again: their block (the scratch held the impact rows'), and their
  // targets from where the bodies now go.
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  const std::size_t count = std::size_t(j1 - j0) * kRows;
  if (impacts) ShiftJointArms(rows, count, v.solverBodies.data(), v.dt);
  BeginJointBlocks(rows, count, sc);
  if (!impacts) return;
  PredictJoints(v, sc);
  SetJointTargets(v, sc);
}

}  // namespace REngine
