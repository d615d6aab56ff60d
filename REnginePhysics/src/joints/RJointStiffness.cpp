// The joints' geometric stiffness (the joint solver's, RJointSolver.h and RJoints.cpp).
//
// A joint's impulse turns with its arm: a body pulled by a force F at an arm r turns back
// towards the force's line with a stiffness |F| |r| (N m/rad), and the mode of a rotational
// inertia I under it has (omega dt)^2 = |F| |r| dt^2 / I. The RATTLE rounds hold the rows of
// the start of the step, so they integrate that mode explicitly, and past an (omega dt)^2 of
// a few they amplify it: a chain of 100 links of 2 cm (1 kg each) hanging from a pin has its
// links' mode at omega dt ~ 12, and swung at half its pendulum rate it gained 9 times its
// swing energy in 2 s and tore. Such an island is solved stiffened (Andrews, Teichmann and
// Kry 2017, "Geometric stiffness for real-time constrained multibody dynamics"): each joint
// body's rotational inertia gains dt^2 |F| |r| (from its joints' impulses of the last step,
// |lambda| |r| dt) in the rounds, the projection and the end's projection alike. That is the
// implicit treatment of the stiffness: it damps the modes the step cannot follow instead of
// amplifying them, and leaves the slow motion nearly as it is (that chain, of 100 or of 2000
// links: its energy within 0.3 % of the swing's over 2 s).
//
// The solver's velocities are then the stiffened ones. The motion is given the turn the
// solver gave each body (a torque -a dw beside the joints' impulses, a the added inertia),
// and what those torques sum to, which the joints did not exert, is taken back by a turn of
// the whole island about its centre of mass (which moves no joint) when the island is free:
// no joint to the world or an immovable body, no contact. Its angular momentum is kept so.
#include "joints/RJointSolver.h"

#include "joints/RJointRows.h"
#include "joints/RJointSystem.h"
#include "joints/RWeldGroups.h"
#include "solver/RSolverRows.h"
#include "world/RStepBodies.h"

#include <cmath>

namespace REngine {

using namespace joints;

namespace {

// The rows' masses again, from the solver bodies' inverse inertias.
void Remass(RJointRow* rows, std::size_t count, const RSolverBody* bodies) {
  for (std::size_t q = 0; q < count; ++q) {
    RJointRow& r = rows[q];
    if (r.kind == Kind::kOff) continue;
    SetJointMass(r.dir, bodies[r.a], bodies[r.b]);
  }
}

// The rigid turn (rad/s) that changes the island's angular momentum by -net about its centre
// of mass: its bodies' centres at x(i), their world inertias I(i); a turn moves no joint.
template <class Centre, class Inertia>
RVec3 IslandTurn(const std::vector<std::uint32_t>& island, const RSolverBody* solver, const RVec3& net,
                 Centre x, Inertia I, RVec3& centre) {
  RScalar mass = 0;
  centre = RVec3::Zero();
  for (std::uint32_t i : island) mass += 1 / solver[i].invM, centre += x(i) / solver[i].invM;
  centre /= mass;
  RMat3 inertia = RMat3::Zero();
  for (std::uint32_t i : island) {
    const RVec3 r = x(i) - centre;
    inertia += I(i) + (r.squaredNorm() * RMat3::Identity() - r * r.transpose()) / solver[i].invM;
  }
  return inertia.ldlt().solve(RVec3(-net));
}

}  // namespace

RMat3 RJointSolver::Stiffened(const RMat3& invI, RScalar added) {
  return RMat3(invI.inverse() + added * RMat3::Identity()).inverse();
}

RScalar RJointSolver::JointStiffness(const RJointIslandView& v, RIslandScratch& sc) {
  const RStepBodies& bodies = v.bodies;
  const std::size_t island = v.island;
  const RScalar dt = v.dt;
  if (sc.stiffness.size() < v.solverBodies.size()) sc.stiffness.resize(v.solverBodies.size(), 0);
  const std::uint32_t j0 = m_islandJointStart[island], j1 = m_islandJointStart[island + 1];
  const RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  // Each joint's pull (its impulses of the last step, times dt) at each arm: the stiffness it
  // adds to that body's turn (kg m^2 of inertia, times dt^2).
  auto pulls = [&](auto&& each) {
    for (std::uint32_t p = j0; p < j1; ++p) {
      const RStepJoint& sj = m_stepJoints[m_islandJoints[p]];
      const RJoint& J = bodies.joints[sj.joint];
      const RJointRow* jr = rows + std::size_t(p - j0) * kRows;
      RVec3 impulse = RVec3::Zero();
      for (int k = 0; k < kRows; ++k) {
        if (jr[k].kind == Kind::kOff || !std::isfinite(J.lambda[k]) || !std::isfinite(J.lambdaEnd[k])) continue;
        impulse += (J.lambda[k] + J.lambdaEnd[k]) * jr[k].dir.d;
      }
      const RScalar pull = impulse.norm() * dt;
      if (v.solverBodies[sj.a].invM != 0) each(sj.a, pull, J.anchorA_B.norm());
      if (v.solverBodies[sj.b].invM != 0) each(sj.b, pull, J.anchorB_B.norm());
    }
  };
  pulls([&](std::uint32_t i, RScalar pull, RScalar arm) { sc.stiffness[i] += pull * arm; });
  // A body in a contact keeps its inertia: the contacts' rows are built with it.
  for (std::uint32_t q = v.rowsFirst; q < v.rowsLast; ++q) sc.stiffness[v.rows[q].a] = 0, sc.stiffness[v.rows[q].b] = 0;
  // (A body with angular locks turns about its free axes alone; a weld's member with its group.)
  for (std::uint32_t i : sc.jointBodies) {
    if (bodies[i].m_angularLocked || v.welds.Welded(i)) sc.stiffness[i] = 0;
  }
  // The step follows a body's turn under one joint's pull while (omega dt)^2 is small: the
  // added inertia over the body's own about the anchor, I + m r^2 (its turn about its centre
  // moves the centre). (One pull, not their sum: a hub held by many spokes turns only as the
  // spokes' bodies move, whose inertia its own does not count.)
  RScalar worst = 0;
  pulls([&](std::uint32_t i, RScalar pull, RScalar arm) {
    if (!(sc.stiffness[i] > 0)) return;
    const RBodyCore& b = bodies[i];
    worst = std::max(worst, pull * arm / (1 / b.m_invI_B.maxCoeff() + arm * arm / v.solverBodies[i].invM));
  });
  return worst;
}

void RJointSolver::Stiffen(const RJointIslandView& v, RIslandScratch& sc) {
  sc.stiffened = true;
  const std::size_t n = sc.jointBodies.size();
  sc.keptInvI.resize(n), sc.keptW.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    RSolverBody& s = v.solverBodies[sc.jointBodies[k]];
    sc.keptInvI[k] = s.invI, sc.keptW[k] = s.w;
    const RScalar added = sc.stiffness[sc.jointBodies[k]];
    if (added > 0) s.invI = Stiffened(s.invI, added);
  }
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  Remass(rows, std::size_t(j1 - j0) * kRows, v.solverBodies.data());
  BeginJointBlocks(rows, std::size_t(j1 - j0) * kRows, sc);
}

// Whether the island is free: no joint to the world or an immovable body, no contact, no
// body with locks or in a weld (whose inertia is not a plain tensor).
bool RJointSolver::FreeJointIsland(const RJointIslandView& v, const RIslandScratch& sc) const {
  if (v.rowsFirst != v.rowsLast) return false;
  for (std::uint32_t p = m_islandJointStart[v.island]; p < m_islandJointStart[v.island + 1]; ++p) {
    const RStepJoint& sj = m_stepJoints[m_islandJoints[p]];
    if (v.solverBodies[sj.a].invM == 0 || v.solverBodies[sj.b].invM == 0) return false;
  }
  for (std::uint32_t i : sc.jointBodies) {
    if (v.bodies[i].m_angularLocked || v.solverBodies[i].linLocked || v.welds.Welded(i)) return false;
  }
  return true;
}

void RJointSolver::Unstiffen(const RJointIslandView& v, RIslandScratch& sc) {
  const RStepBodies& bodies = v.bodies;
  std::vector<RSolverBody>& solverBodies = v.solverBodies;
  RVec3 net = RVec3::Zero();
  for (std::size_t k = 0; k < sc.jointBodies.size(); ++k) {
    RSolverBody& s = solverBodies[sc.jointBodies[k]];
    const RScalar added = sc.stiffness[sc.jointBodies[k]];
    s.invI = sc.keptInvI[k];
    if (!(added > 0)) continue;
    const RVec3 torque = -added * (s.w - sc.keptW[k]);
    s.angularImpulse += torque;
    net += torque;
  }
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  Remass(rows, std::size_t(j1 - j0) * kRows, solverBodies.data());
  BeginJointBlocks(rows, std::size_t(j1 - j0) * kRows, sc);
  if (net.isZero(0) || !FreeJointIsland(v, sc)) return;
  // The island turned by -net about its centre of mass (at the start of the step).
  RVec3 centre;
  const RVec3 turn = IslandTurn(sc.jointBodies, solverBodies.data(), net, [&](std::uint32_t i) { return bodies[i].m_x_W; },
                                [&](std::uint32_t i) { return RMat3(solverBodies[i].invI.inverse()); }, centre);
  for (std::uint32_t i : sc.jointBodies) {
    RSolverBody& s = solverBodies[i];
    const RVec3 dv = turn.cross(RVec3(bodies[i].m_x_W - centre));
    s.v += dv, s.w += turn;
    s.impulse += dv / s.invM, s.angularImpulse += s.invI.inverse() * turn;
  }
}

// At the end of the step (SolveJointsAtEnd, its marks set): wBefore, per joint body, its end
// body's spin before the end's projection (when stiffened); projected, the angular momentum
// the position projection added to a free island.
void RJointSolver::EndStiffness(const RJointIslandView& v, RIslandScratch& sc, const RVec3* wBefore,
                                const RVec3& projected) {
  const RStepBodies& bodies = v.bodies;
  std::vector<RSolverBody>& solverBodies = v.solverBodies;
  RVec3 net = projected;
  if (sc.stiffened) {
    for (std::size_t k = 0; k < sc.jointBodies.size(); ++k) {
      const std::uint32_t i = sc.jointBodies[k];
      const RScalar added = sc.stiffness[i];
      if (!(added > 0)) continue;
      const RVec3 torque = -added * (sc.endBodies[sc.mark[i]].w - wBefore[k]);
      solverBodies[i].endAngular += torque;
      net += torque;
    }
    for (std::uint32_t i : sc.jointBodies) sc.stiffness[i] = 0;
    sc.stiffened = false;
  }
  if (net.isZero(0) || !FreeJointIsland(v, sc)) return;
  // The island turned by -net about its centre of mass where the step ends; the end impulses
  // are about the centres where it starts (SolveJointsAtEnd).
  auto inertiaOf = [&](std::uint32_t i) {
    const RMat3 R = m_jointPoses[i].q.toRotationMatrix();
    return RMat3(R * bodies[i].m_invI_B.cwiseInverse().asDiagonal() * R.transpose());
  };
  RVec3 centre;
  const RVec3 turn = IslandTurn(sc.jointBodies, solverBodies.data(), net, [&](std::uint32_t i) { return m_jointPoses[i].x; },
                                inertiaOf, centre);
  for (std::uint32_t i : sc.jointBodies) {
    RSolverBody& s = solverBodies[i];
    const RVec3 linear = turn.cross(RVec3(m_jointPoses[i].x - centre)) / s.invM;
    s.endLinear += linear;
    s.endAngular += inertiaOf(i) * turn + (m_jointPoses[i].x - bodies[i].m_x_W).cross(linear);
  }
}

}  // namespace REngine
