// Private to REnginePhysics: the joints' rows solved as a system (RJoints.cpp,
// RJointEnd.cpp): the coupling of two rows, the island's equality rows factored as blocks,
// and one pass over an island's joints. Templates over the solver's body type: the
// solver bodies at the start of the step, the end bodies of its end.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RJoint.h>

#include "joints/RJointSparse.h"
#include "joints/RJointTypes.h"
#include "solver/RIslandScratch.h"
#include "solver/RSkyline.h"
#include "solver/RSolverRows.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace REngine::joints {

using solver::LinearCoupling;
using solver::SkylineCholesky;
using solver::SkylineSolve;
using Kind = RJointRowKind;
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

// Which of the island's rows (rows[0 .. count): 8 a joint, then any others) are in the exact block: every equality row,
// a limit that pushes, a motor within its force. Called once the rows are built; the block
// is factored at the next pass.
inline void BeginJointBlocks(const RJointRow* rows, std::size_t count, RIslandScratch& sc) {
  sc.jointActive.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const RJointRow& r = rows[i];
    sc.jointActive[i] = r.kind == Kind::kEquality || (r.kind == Kind::kLimit && r.lambda > 0) ||
                        (r.kind == Kind::kMotor && r.lambda > r.lo && r.lambda < r.hi);
  }
  sc.blockStale = true;
}

// Row ri's change of relative velocity per unit impulse at row rj through body x alone
// (one of JointCoupling's terms).
template <class Body>
RScalar CouplingThrough(const RJointRow& ri, const RJointRow& rj, std::uint32_t x, const Body& body) {
  const RScalar l = LinearCoupling(body, ri.dir.d, rj.dir.d, ri.dir.d.dot(rj.dir.d));
  RScalar k = 0;
  if (ri.a == x && rj.a == x) k += l + ri.dir.rAxd.dot(rj.dir.iA);
  if (ri.a == x && rj.b == x) k -= l + ri.dir.rAxd.dot(rj.dir.iB);
  if (ri.b == x && rj.a == x) k -= l + ri.dir.rBxd.dot(rj.dir.iA);
  if (ri.b == x && rj.b == x) k += l + ri.dir.rBxd.dot(rj.dir.iB);
  return k;
}

// The block's rows (sc.eq) as the sparse system of RJointSparse.h, factored. A movable body
// without locks is an unknown of its own (its 6 velocity changes, its mass and inertia
// on the diagonal, negated); a body with locks (its inverse mass or inertia singular) is
// not, and its rows couple directly through it. The ridge is the skyline block's.
template <class Body>
bool FactorSparse(const RJointRow* rows, const Body* bodies, RIslandScratch& sc, std::vector<std::uint32_t>& mark,
                  RScalar& ridge) {
  constexpr std::uint32_t kCoupled = kNone - 1;  // mark of a body whose rows couple directly
  const int m = static_cast<int>(sc.eq.size());
  int size = m;
  RScalar maxDiag = 0;
  sc.sparseBodies.clear(), sc.sparseLinks.clear();
  for (int i = 0; i < m; ++i) {
    const RJointRow& r = rows[sc.eq[i]];
    maxDiag = std::max(maxDiag, r.dir.k);
    for (std::uint32_t x : {r.a, r.b}) {
      const Body& body = bodies[x];
      if (body.invM == 0) continue;
      if (mark[x] == kNone) {
        // Angular locks leave the world inverse inertia singular (a zero pivot, or rounding's
        // 1e-16 of the others); the inertia ratio is at most 1e9 otherwise.
        bool free = !body.linLocked;
        if (free) {
          const Eigen::LDLT<RMat3> pivots(body.invI);
          free = pivots.vectorD().minCoeff() > RScalar(1e-13) * pivots.vectorD().maxCoeff();
        }
        mark[x] = free ? static_cast<std::uint32_t>(size) : kCoupled;
        if (free) size += 6;
        sc.sparseBodies.push_back(x);
      }
      if (mark[x] == kCoupled) sc.sparseLinks.push_back((std::uint64_t(x) << 32) | std::uint32_t(i));
    }
  }
  RJointSparse& S = sc.sparse.Get();
  S.Begin(size);
  ridge = RScalar(1e-9) * maxDiag;
  for (int i = 0; i < m; ++i) {
    const RJointRow& r = rows[sc.eq[i]];
    S.Add(i, i, ridge);
    for (int side = 0; side < 2; ++side) {
      const std::uint32_t x = side == 0 ? r.a : r.b;
      if (bodies[x].invM == 0 || mark[x] == kCoupled) continue;
      const int base = static_cast<int>(mark[x]);
      const RScalar sign = side == 0 ? -1 : 1;
      const RVec3& arm = side == 0 ? r.dir.rAxd : r.dir.rBxd;
      for (int p = 0; p < 3; ++p) S.Add(i, base + p, sign * r.dir.d[p]);
      for (int p = 0; p < 3; ++p) S.Add(i, base + 3 + p, sign * arm[p]);
    }
  }
  for (std::uint32_t x : sc.sparseBodies) {
    if (mark[x] == kCoupled) continue;
    const Body& body = bodies[x];
    const int base = static_cast<int>(mark[x]);
    for (int p = 0; p < 3; ++p) S.Add(base + p, base + p, -1 / body.invM);
    const RMat3 inertia = body.invI.inverse();
    for (int p = 0; p < 3; ++p) {
      for (int q = p; q < 3; ++q) S.Add(base + 3 + p, base + 3 + q, -inertia(p, q));
    }
  }
  // A forest: each joint (its rows consecutive, kRows apart) joins two sets (the immovable
  // bodies one), never two already joined; a locked body's rows count as a loop.
  sc.eqForest = sc.sparseLinks.empty();
  if (sc.eqForest) {
    sc.sparseSets.Reset(static_cast<std::size_t>(size) + 1);
    std::uint32_t joint = kNone;
    for (int i = 0; i < m && sc.eqForest; ++i) {
      const RJointRow& r = rows[sc.eq[i]];
      if (r.kind != Kind::kEquality) sc.eqForest = false;
      if (sc.eq[i] / kRows == joint) continue;
      joint = sc.eq[i] / kRows;
      const std::uint32_t a = bodies[r.a].invM == 0 ? static_cast<std::uint32_t>(size) : mark[r.a];
      const std::uint32_t b = bodies[r.b].invM == 0 ? static_cast<std::uint32_t>(size) : mark[r.b];
      if (sc.sparseSets.Find(a) == sc.sparseSets.Find(b)) sc.eqForest = false;
      sc.sparseSets.Union(a, b);
    }
  }
  std::sort(sc.sparseLinks.begin(), sc.sparseLinks.end());
  for (std::size_t u = 0; u < sc.sparseLinks.size();) {
    std::size_t v = u + 1;
    while (v < sc.sparseLinks.size() && sc.sparseLinks[v] >> 32 == sc.sparseLinks[u] >> 32) ++v;
    const std::uint32_t x = static_cast<std::uint32_t>(sc.sparseLinks[u] >> 32);
    for (std::size_t p = u; p < v; ++p) {
      const int i = static_cast<int>(sc.sparseLinks[p] & 0xffffffffu);
      for (std::size_t q = u; q <= p; ++q) {
        const int j = static_cast<int>(sc.sparseLinks[q] & 0xffffffffu);
        S.Add(i, j, CouplingThrough(rows[sc.eq[i]], rows[sc.eq[j]], x, bodies[x]));
      }
    }
    u = v;
  }
  for (std::uint32_t x : sc.sparseBodies) mark[x] = kNone;
  return maxDiag > 0 && S.Factor();
}

// The rows in the block (sc.jointActive) solved as one block, their factor in the scratch:
// a skyline factor of J M^-1 J^T when the island has at most blockRows of them, else the
// sparse system of FactorSparse. mark: per body, kNone (left so on return).
template <class Body>
void FactorBlocks(const RJointRow* rows, std::size_t count, const Body* bodies, RIslandScratch& sc,
                  std::vector<std::uint32_t>& mark, int blockRows) {
  sc.blockStale = false;
  sc.eq.clear(), sc.eqGroups.clear();
  for (std::uint32_t i = 0; i < count; ++i) {
    if (sc.jointActive[i] && rows[i].dir.k > 0) sc.eq.push_back(i);
  }
  const std::uint32_t total = static_cast<std::uint32_t>(sc.eq.size());
  sc.eqSparse = total > static_cast<std::uint32_t>(blockRows);
  if (total > 0) sc.eqGroups.emplace_back(0, total);
  sc.eqRhs.resize(total), sc.eqNull.resize(total);
  if (sc.eqSparse) {
    sc.eqRidge.assign(1, 0);
    sc.eqGroupOk.assign(1, FactorSparse(rows, bodies, sc, mark, sc.eqRidge[0]) ? 1 : 0);
    return;
  }
  sc.eqFirst.resize(total), sc.eqOffset.resize(total + 1);
  sc.eqInvDiag.resize(total), sc.eqRhs.resize(total);
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
  sc.eqRidge.assign(sc.eqGroups.size(), 0);
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
    sc.eqRidge[g] = ridge;
    for (int i = 0; i < m; ++i) sc.eqL[sc.eqOffset[e0 + i] + (i - sc.eqFirst[e0 + i])] += ridge;
    // (Offsets are global; the factor works on the group's rows with local columns.)
    sc.eqGroupOk[g] = maxDiag > 0 && SkylineCholesky(sc.eqL.data(), m, sc.eqFirst.data() + e0,
                                                      sc.eqOffset.data() + e0, sc.eqInvDiag.data() + e0);
  }
}

// Solves group g's block for rhs (its rows' velocity misses), in place: the impulses that
// take the misses out. Less what the ridge makes of a miss no impulse can take out: with
// redundant rows (a loop of joints, a mesh) J^T has a null space, a self-stress, and a miss
// along it (the second-order part of a loop's predicted error, rounding) comes out of the
// ridged factor as miss / ridge, 1e9 times its size. It moves no body now, but carried to
// the next step as a warm start, along rows that have turned, it is a blow: a 3 x 3 mesh
// spinning at 1 rad/s had impulses of 3e3 N s at its second step and 1e9 at its third. The
// ridge's solution x = (A + r I)^-1 b holds it as b0 / r; r x is then b0 plus r / s of the
// rest (s: A's eigenvalues, r / s <= 1e-5 up to the joints' mass-ratio limit), and a second
// solve of r x is x's null-space part, which is taken away. The rest's change is in the
// refinement's reach. Only a self-stress of the equality rows alone: a limit and a motor on
// one axis are redundant too, and there the blow-up is what the active set needs (the row
// whose target cannot be met is driven to its bound and leaves the block).
inline void SolveGroup(const RJointRow* rows, RIslandScratch& sc, std::size_t g, RScalar* rhs) {
  // (Not a structured binding: the lambda below captures them, which C++17 forbids.)
  const std::uint32_t e0 = sc.eqGroups[g].first, e1 = sc.eqGroups[g].second;
  const int m = static_cast<int>(e1 - e0);
  auto solve = [&](RScalar* x) {
    if (sc.eqSparse) {
      sc.sparse.Get().Solve(x, m);
    } else {
      SkylineSolve(sc.eqL.data(), m, sc.eqFirst.data() + e0, sc.eqOffset.data() + e0, sc.eqInvDiag.data() + e0, x);
    }
  };
  solve(rhs);
  if (sc.eqSparse && sc.eqForest) return;  // (no self-stress)
  RScalar* null = sc.eqNull.data() + e0;
  const RScalar ridge = sc.eqRidge[g];
  for (int i = 0; i < m; ++i) null[i] = ridge * rhs[i];
  solve(null);
  RScalar equality = 0, other = 0;
  for (int i = 0; i < m; ++i) {
    RScalar& part = rows[sc.eq[e0 + i]].kind == Kind::kEquality ? equality : other;
    part = std::max(part, std::abs(null[i]));
  }
  if (!(other <= RScalar(1e-9) * equality)) return;  // (none, or not the equality rows' alone)
  for (int i = 0; i < m; ++i) rhs[i] -= null[i];
}

// One pass over the island's joints: the block solved exactly (and refined against the
// velocities it leaves), then the active set checked, as the contacts' direct solve does: a
// limit that would pull leaves the block, a motor past its force stays at it, a limit
// crossed or a motor that would have to push back joins it; solved again while it changes.
// Rows the factor could not take are solved one at a time within their bounds. Returns the
// largest change of a row's relative velocity the pass made.
template <class Body>
RScalar JointPass(RJointRow* rows, std::size_t count, Body* bodies, RIslandScratch& sc, std::vector<std::uint32_t>& mark,
                  int blockRows) {
  RScalar change = 0;
  auto apply = [&](RJointRow& r, RScalar d) {
    if (d == 0) return;
    r.lambda += d;
    RowPush(r, d, bodies);
    change = std::max(change, std::abs(d) * r.dir.k);
  };
  constexpr int kActiveRounds = 8;
  for (int round = 0; round < kActiveRounds; ++round) {
    if (sc.blockStale) FactorBlocks(rows, count, bodies, sc, mark, blockRows);
    for (std::size_t g = 0; g < sc.eqGroups.size(); ++g) {
      const auto [e0, e1] = sc.eqGroups[g];
      const int m = static_cast<int>(e1 - e0);
      RScalar* rhs = sc.eqRhs.data() + e0;
      if (!sc.eqGroupOk[g]) {  // (not positive definite: a degenerate row; one at a time)
        for (int i = 0; i < m; ++i) {
          RJointRow& r = rows[sc.eq[e0 + i]];
          apply(r, std::clamp(r.lambda + (r.target - RowSpeed(r, bodies)) / r.dir.k, r.lo, r.hi) - r.lambda);
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
        SolveGroup(rows, sc, g, rhs);
        for (int i = 0; i < m; ++i) apply(rows[sc.eq[e0 + i]], rhs[i]);
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
    // The active set.
    bool changed = false;
    for (std::size_t i = 0; i < count; ++i) {
      RJointRow& r = rows[i];
      if ((r.kind != Kind::kLimit && r.kind != Kind::kMotor) || !(r.dir.k > 0)) continue;
      if (sc.jointActive[i]) {
        const RScalar clamped = std::clamp(r.lambda, r.lo, r.hi);
        if (clamped == r.lambda) continue;
        apply(r, clamped - r.lambda);
        // Exactly at the bound (lambda + (bound - lambda) may round off it, and a row just
        // inside would join again at once: the set would swap back and forth).
        r.lambda = clamped;
        sc.jointActive[i] = 0, changed = true;
      } else {
        const RScalar miss = r.target - RowSpeed(r, bodies);
        // Out of the block, the row sits at a bound: it joins when its solve would move it
        // off that bound (a limit crossed; a motor that would have to push back).
        const bool joins = (miss > kAtTarget && r.lambda < r.hi) || (miss < -kAtTarget && r.lambda > r.lo);
        if (joins) sc.jointActive[i] = 1, changed = true;
      }
    }
    if (!changed) break;
    sc.blockStale = true;
  }
  return change;
}

}  // namespace REngine::joints
