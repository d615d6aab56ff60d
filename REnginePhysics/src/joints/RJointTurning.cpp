// Newton rounds for an island in which a joint body turns fast (the joint solver's,
// RJointSolver.h; the rounds are RContactSolver::JointRounds).
//
// Why. Each round asks the passes for the impulses that take the predicted end errors C out
// to first order, through the rows of the start of the step: it takes the errors' response
// to the rows' impulses to be dt K, K = J M^-1 J^T, what it is for a body that moves on a
// straight line and turns by a small angle about a fixed axis. The end poses come from the
// exact free flow, though, and for a body that turns far in a step the flow answers an
// angular impulse otherwise. A spinning body's angular momentum L takes the impulse, and
// its axis then cones about the new L at |L| / I_perp: a gyroscope's plate spinning at
// 40 rad/s about its normal (I3 = 2 I_perp) cones at 80 rad/s, 1.33 rad in a step at 60 Hz,
// so its end pose answers a small torque impulse along a direction turned by about half of
// that (0.67 rad) from the one dt K assumes. (Rebuilding the rows at the predicted poses
// does not change that: the ball joint's arm lies on the spin axis and the plate's inertia
// is symmetric about it, so the rows at the end poses differ from the start's only by the
// precession's turn over the step, 0.03 rad.) The
// rounds then shrink the error by about |1 - e^(0.67 i)| = 0.65 a round instead of
// squaring it, fail the solver's test (each round at least halves it), and the island falls
// back to the plain velocity constraint and a position projection, which hold the joint but
// not the gyroscopic coupling: the gyroscope precessed 1.64 rad of 2.04 in 1 s, its axis
// fell 0.71 rad.
//
// How. Where a joint body turns more than kFastTurn rad a step, each round works out G, the
// response of the predicted end errors of the island's block rows (equalities and pushing
// limits) to the rows' impulses through the motion itself: per joint body, the errors'
// derivatives with respect to its velocity (finite differences of the prediction, the exact
// flow included: a translation is exact, a turn of kProbe rad over the step has a relative
// error of about kProbe), times what each row's unit impulse gives the body. The impulses
// that take C out are then -G^-1 C (a dense solve: the island has at most kTurningRows such
// rows), and the rows are given the errors dt K G^-1 C, for which their own Newton step
// asks exactly those impulses: the passes, the blocks and the contacts stay as they are.
// The rounds then converge as Newton's method does (the gyroscope's, a step: 5e-5 m, then
// 3e-9, then below the tolerance).
#include "joints/RJointSolver.h"

#include "joints/RJointRows.h"
#include "joints/RJointSystem.h"
#include "joints/RWeldGroups.h"
#include "world/RStepBodies.h"

#include <algorithm>
#include <cmath>

namespace REngine {

using namespace joints;

namespace {

// The turn (rad over the step) of the probes of a body's spin. The derivatives' relative
// error is about this (the flow's curvature) plus the rounding of the poses over it (1e-16
// of the coordinates over 1e-7 m): a round then leaves about 1e-7 of the error.
constexpr RScalar kProbe = 1e-7;

// What a unit impulse of row r gives body x (its velocity change, linear and angular), side
// a or b as Push gives it.
void UnitResponse(const RJointRow& r, bool sideA, const RSolverBody& x, RVec3& dv, RVec3& dw) {
  const RScalar sign = sideA ? -1 : 1;
  dv = (sign * x.invM) * r.dir.d;
  if (x.linLocked) dv = dv.cwiseProduct(x.linMask);
  dw = sign * (sideA ? r.dir.iA : r.dir.iB);
}

// Solves the n x n system G y = c in place (row-major G, partial pivoting); false when G is
// singular to rounding (redundant rows: the plain Newton step is kept then).
bool SolveDense(RScalar* G, RScalar* c, int n) {
  RScalar scale = 0;
  for (int i = 0; i < n * n; ++i) scale = std::max(scale, std::abs(G[i]));
  if (!(scale > 0)) return false;
  for (int k = 0; k < n; ++k) {
    int pivot = k;
    for (int i = k + 1; i < n; ++i) {
      if (std::abs(G[i * n + k]) > std::abs(G[pivot * n + k])) pivot = i;
    }
    if (!(std::abs(G[pivot * n + k]) > RScalar(1e-12) * scale)) return false;
    if (pivot != k) {
      for (int j = 0; j < n; ++j) std::swap(G[k * n + j], G[pivot * n + j]);
      std::swap(c[k], c[pivot]);
    }
    for (int i = k + 1; i < n; ++i) {
      const RScalar f = G[i * n + k] / G[k * n + k];
      if (f == 0) continue;
      for (int j = k; j < n; ++j) G[i * n + j] -= f * G[k * n + j];
      c[i] -= f * c[k];
    }
  }
  for (int k = n - 1; k >= 0; --k) {
    RScalar s = c[k];
    for (int j = k + 1; j < n; ++j) s -= G[k * n + j] * c[j];
    c[k] = s / G[k * n + k];
  }
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(c[k])) return false;
  }
  return true;
}

}  // namespace

bool RJointSolver::TurnsFast(const RJointIslandView& v, const RIslandScratch& sc) const {
  // An island whose rounds hold a motor's turn (RJointMotors.cpp) converges by its own
  // rounds; a weld's members are predicted as their group.
  if (sc.jointMotors) return false;
  bool fast = false;
  for (std::uint32_t i : sc.jointBodies) {
    if (v.welds.Welded(i)) return false;
    fast = fast || v.solverBodies[i].w.norm() * v.dt > kFastTurn;
  }
  return fast;
}

bool RJointSolver::TurningErrors(const RJointIslandView& v, RIslandScratch& sc) {
  const RStepBodies& bodies = v.bodies;
  const RScalar dt = v.dt;
  const std::uint32_t j0 = m_islandJointStart[v.island], j1 = m_islandJointStart[v.island + 1];
  const RJointRow* rows = m_jointRows.data() + std::size_t(j0) * kRows;
  const std::size_t count = std::size_t(j1 - j0) * kRows;
  // The block rows (what the rounds drive to 0), and each row's place among them.
  sc.turnRows.clear();
  sc.turnPlace.assign(count, kNone);
  for (std::uint32_t i = 0; i < count; ++i) {
    const RJointRow& r = rows[i];
    const bool block = r.kind == Kind::kEquality || (r.kind == Kind::kLimit && r.lambda > 0);
    if (!block || !(r.dir.k > 0)) continue;
    sc.turnPlace[i] = static_cast<std::uint32_t>(sc.turnRows.size());
    sc.turnRows.push_back(i);
  }
  const int n = static_cast<int>(sc.turnRows.size());
  if (n == 0 || n > kTurningRows) return false;
  // Per block row, the derivatives of its end error with respect to the velocities of its
  // bodies a and b (linear, angular: 4 vectors a row).
  sc.turnD.assign(std::size_t(4) * n, RVec3::Zero());
  RScalar C[kRows];
  for (std::uint32_t x : sc.jointBodies) {
    const RSolverBody& s = v.solverBodies[x];
    const RJointPose base = m_jointPoses[x];
    const RScalar probeX = JointTolerance(base.x) * 1e3;  // m: a translation's error is rounding
    const RScalar probeW = kProbe / dt;                   // rad/s
    for (int k = 0; k < 6; ++k) {
      RJointPoseIn moved{base.x, base.q};
      RScalar per = 0;  // the probe's velocity, m/s or rad/s
      if (k < 3) {
        moved.x[k] += probeX, per = probeX / dt;
      } else {
        RSolverBody probe = s;
        probe.w[k - 3] += probeW, per = probeW;
        const RJointPose p = PredictPose(bodies[x], probe, dt);
        moved = {p.x, p.q};
      }
      for (std::uint32_t p = j0; p < j1; ++p) {
        const RStepJoint& sj = m_stepJoints[m_islandJoints[p]];
        if (sj.a != x && sj.b != x) continue;
        const RJointRow* jr = rows + std::size_t(p - j0) * kRows;
        const RJointPoseIn pa = sj.a == x ? moved : JointPose(v, sj.a, true);
        const RJointPoseIn pb = sj.b == x ? moved : JointPose(v, sj.b, true);
        JointErrors(bodies.joints[sj.joint], pa, pb, jr, C);
        for (int q = 0; q < kRows; ++q) {
          const std::uint32_t e = sc.turnPlace[std::size_t(p - j0) * kRows + q];
          if (e == kNone) continue;
          const RScalar slope = (C[q] - sc.jointC[std::size_t(p - j0) * kRows + q]) / per;
          const int side = sj.a == x ? 0 : 2;
          sc.turnD[std::size_t(4) * e + side + (k < 3 ? 0 : 1)][k % 3] = slope;
        }
      }
    }
  }
  // G: row e's error per unit impulse of row c, through the bodies they share; beside it
  // dt K, what the rows' own Newton step takes it for.
  sc.turnG.assign(std::size_t(n) * n, 0);
  sc.turnY.resize(n);
  for (int e = 0; e < n; ++e) {
    const RJointRow& re = rows[sc.turnRows[e]];
    for (int c = 0; c < n; ++c) {
      const RJointRow& rc = rows[sc.turnRows[c]];
      RScalar g = 0;
      for (int side = 0; side < 2; ++side) {
        const std::uint32_t x = side == 0 ? re.a : re.b;
        const RSolverBody& body = v.solverBodies[x];
        if (body.invM == 0 || (rc.a != x && rc.b != x)) continue;
        RVec3 dv, dw;
        UnitResponse(rc, rc.a == x, body, dv, dw);
        g += sc.turnD[std::size_t(4) * e + 2 * side].dot(dv) + sc.turnD[std::size_t(4) * e + 2 * side + 1].dot(dw);
        // (A joint between a body and itself is refused at the door: rc's sides differ.)
      }
      sc.turnG[std::size_t(e) * n + c] = g;
    }
    sc.turnY[e] = sc.jointC[sc.turnRows[e]];
  }
  if (!SolveDense(sc.turnG.data(), sc.turnY.data(), n)) return false;
  const RSolverBody* solverBodies = v.solverBodies.data();
  for (int e = 0; e < n; ++e) {
    const RJointRow& re = rows[sc.turnRows[e]];
    RScalar Ky = 0;
    for (int c = 0; c < n; ++c) Ky += JointCoupling(re, rows[sc.turnRows[c]], solverBodies) * sc.turnY[c];
    sc.jointC[sc.turnRows[e]] = dt * Ky;
  }
  return true;
}

}  // namespace REngine
