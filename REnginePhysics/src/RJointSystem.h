// Private to REnginePhysics: the joints' rows solved as a system (RJoints.cpp,
// RJointEnd.cpp): the coupling of two rows, the island's equality rows factored as blocks,
// and one pass over an island's joints. Templates over the solver's body type: the
// solver bodies at the start of the step, the end bodies of its end.
#pragma once

#include "RWorldStep.h"

#include "RSkyline.h"
#include "RSolverRows.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace REngine::joints {

using solver::LinearCoupling;
using solver::SkylineCholesky;
using solver::SkylineSolve;
using RJointRow = RWorldStep::RJointRow;
using Kind = RWorldStep::RJointRowKind;
using RIslandScratch = RWorldStep::RIslandScratch;
inline constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
inline constexpr int kRows = RJoint::kMaxRows;
// A row this close to its target is at it (m/s, rad/s): the contacts' kAtTarget.
inline constexpr RScalar kAtTarget = 1e-12;

// The change of row i's relative velocity per unit impulse at row j: J_i M^-1 J_j^T
// through the bodies they share.
template <class Body>
RScalar JointCoupling(const RJointRow& ri, const RJointRow& rj, const Body* bodies) {
  const Body& ai = bodies[ri.a];
  const Body& bi = bodies[ri.b];
  const RScalar dd = ri.dir.d.dot(rj.dir.d);
  RScalar k = 0;
  if (ai.invM != 0) {
    const RScalar la = LinearCoupling(ai, ri.dir.d, rj.dir.d, dd);
    if (ri.a == rj.a) k += la + ri.dir.rAxd.dot(rj.dir.iA);
    if (ri.a == rj.b) k -= la + ri.dir.rAxd.dot(rj.dir.iB);
  }
  if (bi.invM != 0) {
    const RScalar lb = LinearCoupling(bi, ri.dir.d, rj.dir.d, dd);
    if (ri.b == rj.a) k -= lb + ri.dir.rBxd.dot(rj.dir.iA);
    if (ri.b == rj.b) k += lb + ri.dir.rBxd.dot(rj.dir.iB);
  }
  return k;
}

template <class Body>
RScalar RowSpeed(const RJointRow& r, const Body* bodies) {
  const Body& a = bodies[r.a];
  const Body& b = bodies[r.b];
  return solver::Speed(r.dir, a.v, a.w, b.v, b.w);
}

template <class Body>
void RowPush(const RJointRow& r, RScalar lambda, Body* bodies) {
  Body& a = bodies[r.a];
  Body& b = bodies[r.b];
  solver::Push(r.dir, lambda, a, b, a.v, a.w, b.v, b.w);
}

// The island's equality rows (rows[0 .. 8 nj)) in groups solved as one block each, their
// skyline factors in the scratch. One group when the island has at most kJointBlockRows
// of them, else one a joint. mark: per body, kNone (left so on return).
template <class Body>
void FactorEquality(const RJointRow* rows, int nj, const Body* bodies, RIslandScratch& sc,
                    std::vector<std::uint32_t>& mark, int blockRows) {
  sc.eq.clear(), sc.eqGroups.clear();
  for (int t = 0; t < nj; ++t) {
    for (int k = 0; k < kRows; ++k) {
      if (rows[t * kRows + k].kind == Kind::kEquality) sc.eq.push_back(static_cast<std::uint32_t>(t * kRows + k));
    }
  }
  const std::uint32_t total = static_cast<std::uint32_t>(sc.eq.size());
  if (total <= static_cast<std::uint32_t>(blockRows)) {
    if (total > 0) sc.eqGroups.emplace_back(0, total);
  } else {
    for (std::uint32_t e = 0; e < total;) {
      std::uint32_t f = e + 1;
      while (f < total && sc.eq[f] / kRows == sc.eq[e] / kRows) ++f;
      sc.eqGroups.emplace_back(e, f);
      e = f;
    }
  }
  sc.eqFirst.resize(total), sc.eqOffset.resize(total + 1);
  sc.eqInvDiag.resize(total), sc.eqRhs.resize(total), sc.eqX.resize(total);
  // Each row's envelope: from the first row of the group that shares a movable body.
  std::size_t size = 0;
  for (const auto& [e0, e1] : sc.eqGroups) {
    for (std::uint32_t e = e0; e < e1; ++e) {
      const RJointRow& r = rows[sc.eq[e]];
      std::uint32_t first = e - e0;
      for (std::uint32_t body : {r.a, r.b}) {
        if (bodies[body].invM == 0) continue;
        if (mark[body] == kNone) mark[body] = e - e0;
        first = std::min(first, mark[body]);
      }
      sc.eqFirst[e] = first;
      sc.eqOffset[e] = static_cast<std::uint32_t>(size);
      size += e - e0 - first + 1;
    }
    for (std::uint32_t e = e0; e < e1; ++e) mark[rows[sc.eq[e]].a] = mark[rows[sc.eq[e]].b] = kNone;
  }
  sc.eqOffset[total] = static_cast<std::uint32_t>(size);
  sc.eqL.resize(size);
  sc.eqGroupOk.assign(sc.eqGroups.size(), 1);
  for (std::size_t g = 0; g < sc.eqGroups.size(); ++g) {
    const auto [e0, e1] = sc.eqGroups[g];
    const int m = static_cast<int>(e1 - e0);
    RScalar maxDiag = 0;
    for (int i = 0; i < m; ++i) {
      const RJointRow& ri = rows[sc.eq[e0 + i]];
      RScalar* Li = sc.eqL.data() + sc.eqOffset[e0 + i];
      for (int j = static_cast<int>(sc.eqFirst[e0 + i]); j <= i; ++j) {
        Li[j - static_cast<int>(sc.eqFirst[e0 + i])] = JointCoupling(ri, rows[sc.eq[e0 + j]], bodies);
      }
      maxDiag = std::max(maxDiag, Li[i - static_cast<int>(sc.eqFirst[e0 + i])]);
    }
    // Redundant rows (two hinges on one axis, a loop of links) make the matrix singular: a
    // relative 1e-9 on its diagonal makes it definite, and the refinement through the
    // bodies' velocities (JointPass) takes out the bias that leaves.
    const RScalar ridge = RScalar(1e-9) * maxDiag;
    for (int i = 0; i < m; ++i) sc.eqL[sc.eqOffset[e0 + i] + (i - sc.eqFirst[e0 + i])] += ridge;
    // (Offsets are global; the factor works on the group's rows with local columns.)
    sc.eqGroupOk[g] = maxDiag > 0 && SkylineCholesky(sc.eqL.data(), m, sc.eqFirst.data() + e0,
                                                      sc.eqOffset.data() + e0, sc.eqInvDiag.data() + e0);
  }
}

// One pass over the island's joints: each equality group solved exactly (and refined
// against the velocities it leaves), then the limits and motors one row at a time within
// their bounds. Returns the largest change of a row's relative velocity it made.
template <class Body>
RScalar JointPass(RJointRow* rows, int nj, Body* bodies, RIslandScratch& sc) {
  RScalar change = 0;
  for (std::size_t g = 0; g < sc.eqGroups.size(); ++g) {
    const auto [e0, e1] = sc.eqGroups[g];
    const int m = static_cast<int>(e1 - e0);
    RScalar* rhs = sc.eqRhs.data() + e0;
    if (!sc.eqGroupOk[g]) {  // (not positive definite: a degenerate row; one at a time)
      for (int i = 0; i < m; ++i) {
        RJointRow& r = rows[sc.eq[e0 + i]];
        if (!(r.dir.k > 0)) continue;
        const RScalar d = (r.target - RowSpeed(r, bodies)) / r.dir.k;
        r.lambda += d;
        if (d != 0) RowPush(r, d, bodies);
        change = std::max(change, std::abs(d) * r.dir.k);
      }
      continue;
    }
    RScalar worst = 0;
    for (int i = 0; i < m; ++i) {
      const RJointRow& r = rows[sc.eq[e0 + i]];
      rhs[i] = r.target - RowSpeed(r, bodies);
      worst = std::max(worst, std::abs(rhs[i]));
    }
    // Refinement: the factor carries the ridge, so each solve leaves a residual of 1e-9 of
    // the answer in the stiff directions and more in the soft ones (a heavy weight's): it
    // is solved again while it shrinks.
    for (int refine = 0; refine < 8 && worst > kAtTarget; ++refine) {
      SkylineSolve(sc.eqL.data(), m, sc.eqFirst.data() + e0, sc.eqOffset.data() + e0, sc.eqInvDiag.data() + e0, rhs);
      for (int i = 0; i < m; ++i) {
        RJointRow& r = rows[sc.eq[e0 + i]];
        if (rhs[i] == 0) continue;
        r.lambda += rhs[i];
        RowPush(r, rhs[i], bodies);
        change = std::max(change, std::abs(rhs[i]) * r.dir.k);
      }
      const RScalar before = worst;
      worst = 0;
      for (int i = 0; i < m; ++i) {
        const RJointRow& r = rows[sc.eq[e0 + i]];
        rhs[i] = r.target - RowSpeed(r, bodies);
        worst = std::max(worst, std::abs(rhs[i]));
      }
      if (!(worst < RScalar(0.5) * before)) break;
    }
  }
  for (int i = 0; i < nj * kRows; ++i) {
    RJointRow& r = rows[i];
    if (r.kind != Kind::kLimit && r.kind != Kind::kMotor) continue;
    if (!(r.dir.k > 0)) continue;
    const RScalar l = std::clamp(r.lambda + (r.target - RowSpeed(r, bodies)) / r.dir.k, r.lo, r.hi);
    const RScalar d = l - r.lambda;
    r.lambda = l;
    if (d != 0) RowPush(r, d, bodies);
    change = std::max(change, std::abs(d) * r.dir.k);
  }
  return change;
}

}  // namespace REngine::joints
