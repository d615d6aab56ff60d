// Friction patches shared across flush immovable bodies (RContactSolver::GroupPatches).
//
// Flush tiles are one surface for normals (collision/RCoveredFeatures.h), and must be for
// friction too. A capsule or cylinder rolling with its line of contact split between two tiles
// has a manifold on each (the piece's ends, or one point): a patch each, at its own centroid,
// the twist limited by its own piece, solved one after the other with a normal block each.
// Friction stopping the line's sliding at one piece tilts the body about it, the other's
// rows and patch answer, and what is left drifts the roller (0.36 m/s at 50 m/s) where on
// one floor the same line, one manifold, stays exact. So a body's manifolds on immovable
// bodies that move as one (static ones; kinematic ones translating at one velocity without
// turning, as the cover rule asks), whose normals agree to 1e-12 (the cover rule gives them
// the same face normal) and whose points lie within the slop of one plane, are solved as
// one manifold: one patch, the group's first block's, at the centroid of all their points,
// its limits summing all their rows; and their normal rows one block (SolveGroupNormals),
// up to kGroupRows of them. The manifolds stay the pairs' own: the patch's impulse is split
// among them in proportion to their normal impulses for the contacts' reports and warm
// starts (PatchShare), so each pair reports its part, the parts sum to the patch, and next
// step's patch starts from their sum. An island with no such group computes exactly what
// it did (islands with joints are not grouped: the joints' end reads each manifold's patch).
#include "solver/RContactSolver.h"

#include "pairs/RPairSweep.h"
#include "solver/RSolverRows.h"
#include "world/RStepBodies.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

using namespace solver;

namespace {

// Normals that agree to this (each component) are one surface's (the cover rule's face
// normal, the same bits up to a rotation's rounding).
constexpr RScalar kPatchSameNormal = 1e-12;

}  // namespace

// Whether block k (a manifold of the same movable body as lead's) shares lead's patch.
bool RContactSolver::SharesPatch(std::uint32_t lead, std::uint32_t k) const {
  const RContact& cl = m_in->sweep.Contacts()[m_blockContact[lead]];
  const RContact& ck = m_in->sweep.Contacts()[m_blockContact[k]];
  const RBlock& bl = m_blocks[lead];
  const RBlock& bk = m_blocks[k];
  if (bl.friction != bk.friction) return false;
  const bool leadA = m_in->sweep.ImmovableAt(cl.a), kA = m_in->sweep.ImmovableAt(ck.a);
  const std::uint32_t il = leadA ? cl.a : cl.b, ik = kA ? ck.a : ck.b;
  const RSolverBody& sl = m_solverBodies[il];
  const RSolverBody& sk = m_solverBodies[ik];
  // Moving as one (RCoverSurface::MovesWith): one body's children, however it turns, or
  // bodies neither of which turns, at one velocity.
  if (il != ik && (!sl.w.isZero(0) || !sk.w.isZero(0) || sl.v != sk.v)) return false;
  // Both normals out of the immovable body.
  const RVec3 nl = leadA ? cl.manifold.normal : RVec3(-cl.manifold.normal);
  const RVec3 nk = kA ? ck.manifold.normal : RVec3(-ck.manifold.normal);
  if (!((nl - nk).cwiseAbs().maxCoeff() <= kPatchSameNormal)) return false;
  const RVec3& origin = cl.manifold.points[0].position;
  for (int i = 0; i < ck.manifold.pointCount; ++i) {
    if (!(std::abs(nl.dot(ck.manifold.points[i].position - origin)) <= m_in->settings.penetrationSlop)) return false;
  }
  return true;
}

// Groups the island's manifolds [first, last) (see the top). Deterministic: blocks in
// index order, each joining the first group of its body it fits, else starting one.
void RContactSolver::GroupPatches(const RStepBodies& bodies, std::uint32_t first, std::uint32_t last,
                                  RIslandScratch& sc) {
  // The movable body of a manifold against an immovable one, or kNoBlock.
  auto mover = [this](std::uint32_t k) {
    const RContact& c = m_in->sweep.Contacts()[m_blockContact[k]];
    const bool immA = m_in->sweep.ImmovableAt(c.a), immB = m_in->sweep.ImmovableAt(c.b);
    return immA == immB ? kNoBlock : immA ? c.b : c.a;
  };
  for (std::uint32_t k = first; k < last; ++k) {
    const std::uint32_t m = mover(k);
    if (m != kNoBlock) m_patchHead[m] = kNoBlock;
  }
  bool any = false;
  for (std::uint32_t k = first; k < last; ++k) {
    const std::uint32_t m = mover(k);
    if (m == kNoBlock) continue;
    std::uint32_t lead = m_patchHead[m], tail = kNoBlock;
    while (lead != kNoBlock && !SharesPatch(lead, k)) tail = lead, lead = m_blocks[lead].otherPatch;
    if (lead == kNoBlock) {  // a patch of its own, so far: the body's last
      if (tail == kNoBlock) m_patchHead[m] = k;
      else m_blocks[tail].otherPatch = k;
      continue;
    }
    std::uint32_t end = lead;
    while (m_blocks[end].nextInPatch != kNoBlock) end = m_blocks[end].nextInPatch;
    m_blocks[end].nextInPatch = k;
    RBlock& blk = m_blocks[k];
    blk.patch = lead;
    const std::uint32_t a = m_rows[blk.first].a, leadA = m_rows[m_blocks[lead].first].a;
    blk.flipped = m_in->sweep.ImmovableAt(a) != m_in->sweep.ImmovableAt(leadA);
    any = true;
  }
  if (!any) return;
  std::uint32_t slots = 0;
  for (std::uint32_t k = first; k < last; ++k) {
    if (m_blocks[k].patch == k && m_blocks[k].nextInPatch != kNoBlock) SetUpGroupPatch(bodies, k, slots);
  }
  // (Its capacity kept from island to island and step to step.)
  const std::size_t size = std::size_t(slots) * kGroupRows * kGroupRows;
  if (sc.groupPinv.size() < size) sc.groupPinv.resize(size);
}

// The group's patch on its first block, as one manifold's (RContactSolver::BuildContactRows)
// of all the group's points: at their centroid, its rows' levers about it; started from the
// sum of what each of its manifolds remembered (their parts of last step's patch), and the
// others' patches left empty.
void RContactSolver::SetUpGroupPatch(const RStepBodies& bodies, std::uint32_t lead, std::uint32_t& slots) {
  RBlock& lb = m_blocks[lead];
  const RContactRow& r0 = m_rows[lb.first];
  const RSolverBody& sa = m_solverBodies[r0.a];
  const RSolverBody& sb = m_solverBodies[r0.b];
  RVec3 centroid = RVec3::Zero();
  int count = 0;
  for (std::uint32_t k = lead; k != kNoBlock; k = m_blocks[k].nextInPatch) {
    const RContactManifold& m = m_in->sweep.Contacts()[m_blockContact[k]].manifold;
    for (int i = 0; i < m.pointCount; ++i) centroid += m.points[i].position, ++count;
  }
  centroid /= count;
  RVec3 tangent[2] = {RVec3::Zero(), RVec3::Zero()};
  RScalar twist[2] = {0, 0};
  for (std::uint32_t k = lead; k != kNoBlock; k = m_blocks[k].nextInPatch) {
    RBlock& blk = m_blocks[k];
    const RContactManifold& m = m_in->sweep.Contacts()[m_blockContact[k]].manifold;
    for (int i = 0; i < blk.count; ++i) m_rows[blk.first + i].lever = (m.points[i].position - centroid).norm();
    // Its remembered part, on the lead's b (a flipped pair's b is the lead's a; the twist
    // about its own normal, the lead's reversed, turns the lead's b the same way).
    const RScalar sign = blk.flipped ? -1 : 1;
    for (int ph = 0; ph < 2; ++ph) {
      tangent[ph] += sign * (blk.lambdaT1[ph] * blk.t[0].d + blk.lambdaT2[ph] * blk.t[1].d);
      twist[ph] += blk.lambdaTwist[ph];
      if (k != lead) blk.lambdaT1[ph] = blk.lambdaT2[ph] = blk.lambdaTwist[ph] = 0;
    }
  }
  lb.groupRows = count <= kGroupRows;
  if (lb.groupRows) lb.groupSlot = slots++;
  lb.rA = centroid - bodies[r0.a].m_x_W, lb.rB = centroid - bodies[r0.b].m_x_W;
  const RVec3 t1 = lb.t[0].d, t2 = lb.t[1].d;
  SetDirection(lb.t[0], t1, lb.rA, lb.rB, sa, sb);
  SetDirection(lb.t[1], t2, lb.rA, lb.rB, sa, sb);
  for (int ph = 0; ph < 2; ++ph) {
    lb.lambdaT1[ph] = tangent[ph].dot(t1), lb.lambdaT2[ph] = tangent[ph].dot(t2);
    lb.lambdaTwist[ph] = twist[ph];
  }
}

// A group's normal rows (at most kGroupRows) as one block: the minimum-norm answer when it
// pushes at every row, else one row at a time, as SolveNormalBlock a manifold's. Solved one manifold
// after the other, the rows of a line split between two tiles pass the load from one to the
// other a fraction at a time, the patch in between holding what they have not yet taken
// (the roller tilts, friction stops the tilt's sliding), and the island's direct solve,
// which settles the normal impulses alone, left that friction sliding the roller along its
// axis (5e-5 m/s at 1 m/s). The rows share only the movable body (the others are immovable:
// no inverse mass or inertia), through which the block's matrix couples them.
RScalar RContactSolver::SolveGroupNormals(RBlock& lead, RPhase phase, RIslandScratch& sc) {
  using RVecG = Eigen::Matrix<RScalar, Eigen::Dynamic, 1, 0, kGroupRows, 1>;
  using RMatG = Eigen::Matrix<RScalar, Eigen::Dynamic, Eigen::Dynamic, 0, kGroupRows, kGroupRows>;
  RContactRow* rows[kGroupRows];
  int count = 0;
  for (std::uint32_t k = lead.patch; k != kNoBlock; k = m_blocks[k].nextInPatch) {  // (lead.patch: lead)
    for (int i = 0; i < m_blocks[k].count; ++i) rows[count++] = &m_rows[m_blocks[k].first + i];
  }
  const RContactRow& r0 = *rows[0];
  const bool moverIsB = !m_in->sweep.ImmovableAt(r0.b);
  const std::uint32_t mover = moverIsB ? r0.b : r0.a;
  RSolverBody& sm = m_solverBodies[mover];
  const bool pseudo = phase == RPhase::kPosition;
  auto lambda = [phase](RContactRow& r) -> RScalar& { return Lambda(r, phase); };
  auto target = [phase](const RContactRow& r) { return Target(r, phase); };
  auto speed = [&](const RContactRow& r) {
    const RSolverBody& sa = m_solverBodies[r.a];
    const RSolverBody& sb = m_solverBodies[r.b];
    return pseudo ? Speed(r.n, sa.vp, sa.wp, sb.vp, sb.wp) : Speed(r.n, sa.v, sa.w, sb.v, sb.w);
  };
  auto push = [&](RContactRow& r, RScalar d) {
    RSolverBody& sa = m_solverBodies[r.a];
    RSolverBody& sb = m_solverBodies[r.b];
    if (pseudo) Push(r.n, d, sa, sb, sa.vp, sa.wp, sb.vp, sb.wp);
    else Push(r.n, d, sa, sb, sa.v, sa.w, sb.v, sb.w);
  };
  if (phase != RPhase::kVelocity) {
    bool active = false;
    for (int i = 0; i < count; ++i) {
      RContactRow& r = *rows[i];
      active = active || target(r) > 0 || lambda(r) > 0 || (phase == RPhase::kEnd && target(r) == 0);
    }
    if (!active) return 0;
  }
  constexpr RScalar kAtTarget = 1e-12;  // m/s (SolveNormalBlock's)
  RScalar change = 0;
  bool allTargets = true;
  for (int i = 0; i < count; ++i) allTargets = allTargets && target(*rows[i]) != kNever && rows[i]->n.k > 0;
  if (count > 1 && allTargets) {
    RVecG rhs(count);
    bool solved = true;
    for (int i = 0; i < count; ++i) {
      rhs[i] = target(*rows[i]) - speed(*rows[i]);
      solved = solved && (lambda(*rows[i]) > 0 ? std::abs(rhs[i]) <= kAtTarget : rhs[i] <= kAtTarget);
    }
    if (solved) return 0;
    Eigen::Map<Eigen::Matrix<RScalar, Eigen::Dynamic, Eigen::Dynamic>> pinv(
        sc.groupPinv.data() + std::size_t(lead.groupSlot) * kGroupRows * kGroupRows, count, count);
    if (!lead.groupInverse) {  // worked out the first time the group has something to solve
      // Row i's speed per unit impulse at row j, through the movable body alone.
      RMatG K(count, count);
      for (int i = 0; i < count; ++i) {
        const bool bi = rows[i]->b == mover;
        const RVec3& arm_i = bi ? rows[i]->n.rBxd : rows[i]->n.rAxd;
        for (int j = 0; j <= i; ++j) {
          const bool bj = rows[j]->b == mover;
          const RVec3& inertia_j = bj ? rows[j]->n.iB : rows[j]->n.iA;
          const RScalar dd = rows[i]->n.d.dot(rows[j]->n.d);
          const RScalar k = LinearCoupling(sm, rows[i]->n.d, rows[j]->n.d, dd) + arm_i.dot(inertia_j);
          K(i, j) = K(j, i) = bi == bj ? k : -k;
        }
      }
      const Eigen::SelfAdjointEigenSolver<RMatG> eigen(K);
      const RVecG& s = eigen.eigenvalues();  // ascending
      const RScalar floor = RScalar(1e-14) * s[count - 1];
      pinv.setZero();
      for (int k = 0; k < count; ++k) {
        if (!(s[k] > floor)) continue;
        const RVecG v = eigen.eigenvectors().col(k);
        pinv += (v / s[k]) * v.transpose();
      }
      lead.groupInverse = true;
    }
    const RVecG delta = pinv * rhs;
    bool valid = true;
    for (int i = 0; i < count; ++i) valid = valid && lambda(*rows[i]) + delta[i] >= 0;
    if (valid) {
      for (int i = 0; i < count; ++i) {
        lambda(*rows[i]) += delta[i];
        if (delta[i] != 0) push(*rows[i], delta[i]);
        change = std::max(change, std::abs(delta[i]) * rows[i]->n.k);
      }
      return std::max(change, std::numeric_limits<RScalar>::denorm_min());
    }
  }
  bool missed = false;
  for (int i = 0; i < count; ++i) {
    RContactRow& r = *rows[i];
    if (!(r.n.k > 0)) continue;
    const RScalar miss = target(r) - speed(r);
    missed = missed || (lambda(r) > 0 ? std::abs(miss) > kAtTarget : miss > kAtTarget);
    const RScalar l = std::max(lambda(r) + miss / r.n.k, RScalar(0));
    const RScalar d = l - lambda(r);
    lambda(r) = l;
    if (d != 0) push(r, d);
    change = std::max(change, std::abs(d) * r.n.k);
  }
  return missed ? std::max(change, std::numeric_limits<RScalar>::denorm_min()) : change;
}

void RContactSolver::PatchShare(std::uint32_t k, int ph, RVec3& tangent, RScalar& twist) const {
  const RBlock& blk = m_blocks[k];
  const RBlock& lb = m_blocks[blk.patch];
  tangent = lb.lambdaT1[ph] * lb.t[0].d + lb.lambdaT2[ph] * lb.t[1].d;
  twist = lb.lambdaTwist[ph];
  if (!Grouped(blk)) return;
  auto normal = [this, ph](const RBlock& b) {
    RScalar sum = 0;
    for (int i = 0; i < b.count; ++i) sum += ph == 0 ? m_rows[b.first + i].lambdaN : m_rows[b.first + i].lambdaE;
    return sum;
  };
  RScalar total = 0;
  int members = 0;
  for (std::uint32_t g = blk.patch; g != kNoBlock; g = m_blocks[g].nextInPatch) total += normal(m_blocks[g]), ++members;
  // With no normal impulse the patch has none either (its limit is 0): shared evenly.
  const RScalar share = total > 0 ? normal(blk) / total : RScalar(1) / members;
  tangent *= blk.flipped ? -share : share;
  twist *= share;
}

}  // namespace REngine
