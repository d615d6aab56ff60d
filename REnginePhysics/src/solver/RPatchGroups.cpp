// Friction patches shared across flush immovable bodies (RContactSolver::GroupPatches).
//
// Flush tiles are one surface for normals (collision/RCoveredFeatures.h); for friction they
// were not. A capsule or cylinder rolling with its line of contact split between two tiles
// has a one-point manifold on each: two patches, each at its own point, with no twist limit
// (a point's lever about itself is 0), solved one after the other. Sticking the first point
// turns the body about it, the second's then slips back, and the pair of patches settles on
// a twist the one line of contact would never take: the roller drifted (0.36 m/s at 50 m/s).
// On one floor the same line is one manifold: one patch at the middle of the line, limited
// by mu times both points' impulses and twisting within mu times their levers. So a body's
// manifolds on immovable bodies that move as one (static ones; kinematic ones translating
// at one velocity without turning, as the cover rule asks), whose normals agree to 1e-12
// (the cover rule gives them the same face normal) and whose points lie within the slop of
// one plane, get one patch, the group's first block's, set up as one manifold's would be:
// at the centroid of all their points, the limits summing all their rows. Their normal
// blocks stay each its own; the patch's impulse is split among them in proportion to their
// normal impulses for the contacts' reports and warm starts (PatchShare), so each pair
// reports its part, the parts sum to the patch, and next step's patch starts from their sum.
// An island with no such group computes exactly what it did.
#include "solver/RContactSolver.h"

#include "pairs/RPairSweep.h"
#include "solver/RSolverRows.h"
#include "world/RStepBodies.h"

#include <cmath>

namespace REngine {

using namespace solver;

namespace {

// Normals that agree to this (each component) are one surface's (the cover rule's face
// normal, the same bits up to a rotation's rounding).
constexpr RScalar kSameNormal = 1e-12;

}  // namespace

// Whether block k (a manifold of the same movable body as lead's) shares lead's patch.
bool RContactSolver::SharesPatch(std::uint32_t lead, std::uint32_t k) const {
  const RContact& cl = m_in->sweep.Contacts()[m_blockContact[lead]];
  const RContact& ck = m_in->sweep.Contacts()[m_blockContact[k]];
  const RBlock& bl = m_blocks[lead];
  const RBlock& bk = m_blocks[k];
  if (bl.friction != bk.friction) return false;
  const bool leadA = m_in->sweep.ImmovableAt(cl.a), kA = m_in->sweep.ImmovableAt(ck.a);
  const RSolverBody& sl = m_solverBodies[leadA ? cl.a : cl.b];
  const RSolverBody& sk = m_solverBodies[kA ? ck.a : ck.b];
  // Moving as one (RCoverSurface::MovesWith).
  if (!sl.w.isZero(0) || !sk.w.isZero(0) || sl.v != sk.v) return false;
  // Both normals out of the immovable body.
  const RVec3 nl = leadA ? cl.manifold.normal : RVec3(-cl.manifold.normal);
  const RVec3 nk = kA ? ck.manifold.normal : RVec3(-ck.manifold.normal);
  if (!((nl - nk).cwiseAbs().maxCoeff() <= kSameNormal)) return false;
  const RVec3& origin = cl.manifold.points[0].position;
  for (int i = 0; i < ck.manifold.pointCount; ++i) {
    if (!(std::abs(nl.dot(ck.manifold.points[i].position - origin)) <= m_in->settings.penetrationSlop)) return false;
  }
  return true;
}

// Groups the island's manifolds [first, last) (see the top). Deterministic: blocks in
// index order, each joining the first group of its body it fits, else starting one.
void RContactSolver::GroupPatches(const RStepBodies& bodies, std::uint32_t first, std::uint32_t last) {
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
    blk.flipped = m_in->sweep.ImmovableAt(m_rows[blk.first].a) != m_in->sweep.ImmovableAt(m_rows[m_blocks[lead].first].a);
    any = true;
  }
  if (!any) return;
  for (std::uint32_t k = first; k < last; ++k) {
    if (m_blocks[k].patch == k && m_blocks[k].nextInPatch != kNoBlock) SetUpGroupPatch(bodies, k);
  }
}

// The group's patch on its first block, as one manifold's (RContactSolver::BuildContactRows)
// of all the group's points: at their centroid, its rows' levers about it; started from the
// sum of what each of its manifolds remembered (their parts of last step's patch), and the
// others' patches left empty.
void RContactSolver::SetUpGroupPatch(const RStepBodies& bodies, std::uint32_t lead) {
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
  lb.rA = centroid - bodies[r0.a].m_x_W, lb.rB = centroid - bodies[r0.b].m_x_W;
  const RVec3 t1 = lb.t[0].d, t2 = lb.t[1].d;
  SetDirection(lb.t[0], t1, lb.rA, lb.rB, sa, sb);
  SetDirection(lb.t[1], t2, lb.rA, lb.rB, sa, sb);
  for (int ph = 0; ph < 2; ++ph) {
    lb.lambdaT1[ph] = tangent[ph].dot(t1), lb.lambdaT2[ph] = tangent[ph].dot(t2);
    lb.lambdaTwist[ph] = twist[ph];
  }
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
