// The contact solver's rows (RContactSolver::BuildContactRows): for each resolved contact, a
// normal row per manifold point warm-started from last step's impulses, and its friction
// patch; its impact row where its island may impact (BuildImpactRow); see FindImpulses in
// RContactSolver.cpp.
#include "solver/RContactSolver.h"

#include "motion/RMotion.h"
#include "pairs/RPairSweep.h"
#include "solver/RSolverRows.h"
#include "world/RStepBodies.h"

#include <algorithm>
#include <cmath>

namespace REngine {

using namespace solver;

// The leading points of a manifold: its deepest, and the centre of those within the slop of
// it, where an impact acts. count is 0 when the separations are not numbers.
RLeadingPoints RContactSolver::LeadingPoints(const RContactManifold& m) const {
  RLeadingPoints lead;
  for (int k = 1; k < m.pointCount; ++k) {
    if (m.points[k].separation < m.points[lead.deepest].separation) lead.deepest = k;
  }
  const RScalar leadSeparation = m.points[lead.deepest].separation;
  lead.centre = RVec3::Zero();
  for (int k = 0; k < m.pointCount; ++k) {
    if (m.points[k].separation <= leadSeparation + m_in->settings.penetrationSlop) {
      lead.centre += m.points[k].position;
      ++lead.count;
    }
  }
  if (lead.count > 0) lead.centre /= lead.count;
  return lead;
}

// The first of last step's warm starts (sorted by pair) of `pair`, searched from `from`:
// every entry before it is of a smaller pair when the contacts come in increasing pairs,
// as they do unless bodies were added or removed, and the next contact's entries are then
// a few places on. A gallop from there (1, 2, 4, ... places) and a binary search within
// the last stride touch a few neighbouring entries instead of a binary search's ~16 over
// 5 MB. Otherwise (a pair below the start's) the whole list is searched. LayOutIslands
// searches in the contacts' order: the rows are built island by island, where a gallop
// from the last contact's entries would cross the list at every contact.
std::size_t RContactSolver::FindWarmStarts(const std::vector<RWarmStart>& warm, std::uint64_t pair, std::size_t from) {
  auto less = [](const RWarmStart& w, std::uint64_t key) { return w.pair < key; };
  if (from > warm.size() || (from > 0 && !(warm[from - 1].pair < pair))) from = 0;
  std::size_t lo = from, hi = from, stride = 1;
  while (hi < warm.size() && warm[hi].pair < pair) {
    lo = hi + 1;
    hi = std::min(warm.size(), hi + stride);
    stride *= 2;
  }
  return static_cast<std::size_t>(std::lower_bound(warm.begin() + static_cast<std::ptrdiff_t>(lo),
                                                   warm.begin() + static_cast<std::ptrdiff_t>(hi), pair, less) -
                                  warm.begin());
}

// Impacts bounce in a phase of their own, before the contacts are solved: each manifold
// gets one impact row at the centre of its leading points (those within the slop of the
// deepest). A whole face hitting flat bounces through the face's centre, with no torque, a
// corner through the corner: one constraint, whose outcome is the closed form and conserves
// energy at e = 1. Restitution targets at several points of one manifold, solved one after
// another, could return more energy than came in. Built only for an island some row of which
// approaches (SolveIsland), at its block's index.
void RContactSolver::BuildImpactRow(const RStepBodies& bodies, std::uint32_t ci, std::uint32_t block) {
  const RContact& c = m_in->sweep.Contacts()[ci];
  const RBodyCore& A = bodies[c.a];
  const RBodyCore& B = bodies[c.b];
  const RLeadingPoints lead = LeadingPoints(c.manifold);
  const RVec3& normal = c.manifold.normal;
  RImpactRow& r = m_impacts[block];  // written in place: its tangents' arms stay unset
  r.a = c.a, r.b = c.b, r.contact = ci, r.point = lead.deepest;
  const RVec3 rA = lead.centre - A.m_x_W, rB = lead.centre - B.m_x_W;
  // The normal's arms for the impact phase's approach test; the tangents are worked out
  // there, from their directions, only for a manifold that impacts.
  SetDirection(r.normal, normal, rA, rB, m_solverBodies[c.a], m_solverBodies[c.b]);
  OrthonormalBasis(normal, r.tangent[0], r.tangent[1]);
  r.rA = rA, r.rB = rB;
  r.gap = c.manifold.points[lead.deepest].separation;
  if (m_in->materials.Active()) {
    r.restitution = m_in->materials.At(ci).restitution;
    r.friction = m_in->materials.At(ci).friction;
  } else {
    r.restitution = Combine(m_in->settings.restitutionCombine, A.m_restitution, B.m_restitution);
    r.friction = Combine(m_in->settings.frictionCombine, A.m_friction, B.m_friction);
  }
  r.lambdaN = r.lambdaT1 = r.lambdaT2 = 0;
  r.impulse.setZero(), r.angularA.setZero(), r.angularB.setZero();
  r.frictionImpulse.setZero(), r.point_W.setZero(), r.normal_W = normal;
  r.miss = false, r.joined = false;
  r.sweptA = r.sweptB = ~std::uint32_t{0};  // (never swept)
}

// Asks for what BuildContactRows reads of contact ci: the contact and its pair's warm starts
// of last step (a manifold's worth, four entries).
void RContactSolver::PrefetchContact(std::uint32_t ci) const {
  PrefetchBytes(&m_in->sweep.Contacts()[ci], sizeof(RContact));
  const std::size_t w0 = m_rowStart[ci].warmFound, w1 = std::min(w0 + 4, m_warm.size());
  for (std::size_t w = w0; w < w1; ++w) {
    const char* p = reinterpret_cast<const char*>(&m_warm[w]);
    __builtin_prefetch(p), __builtin_prefetch(p + 64);
  }
}

// One resolved contact's rows (at m_rowStart): a contact row per manifold point
// warm-started from last step's impulses, and its friction patch. Returns how many rows
// found a warm start.
std::uint32_t RContactSolver::BuildContactRows(const RStepBodies& bodies, std::uint32_t ci, RScalar dt) {
  const RContact& c = m_in->sweep.Contacts()[ci];
  const std::uint32_t firstRow = m_rowStart[ci].row, blockIndex = m_rowStart[ci].block;
  const RBodyCore& A = bodies[c.a];
  const RBodyCore& B = bodies[c.b];
  std::uint32_t warmStarted = 0;
  const RSolverBody& sa = m_solverBodies[c.a];
  const RSolverBody& sb = m_solverBodies[c.b];
  const bool material = m_in->materials.Active();
  const RScalar mu = material ? m_in->materials.At(ci).friction
                              : Combine(m_in->settings.frictionCombine, A.m_friction, B.m_friction);
  const RVec3& normal = c.manifold.normal;
  RVec3 t1, t2;
  OrthonormalBasis(normal, t1, t2);
  const RWarmStart* patchWarm = nullptr;  // the first of its points found last step
  // Last step's points of this pair (m_warm is sorted by pair): found once for the manifold.
  const std::uint64_t pair = PairKey(c.handleA.index, c.handleB.index);
  const auto warmFirst = m_warm.begin() + static_cast<std::ptrdiff_t>(m_rowStart[ci].warmFound);
  // One contact row per manifold point: no restitution; the contact may close its gap
  // within the step (speculative: a fast body stops at the surface, not inside it) but
  // not approach beyond it.
  for (int k = 0; k < c.manifold.pointCount; ++k) {
    const RVec3& position = c.manifold.points[k].position;
    const RScalar gap = c.manifold.points[k].separation;
    // Written in place, every field: a row built aside and copied in cost a copy per row.
    RContactRow& r = m_rows[firstRow + k];
    r.a = c.a, r.b = c.b, r.contact = ci, r.point = k;
    r.rA = position - A.m_x_W;
    r.rB = position - B.m_x_W;
    SetDirection(r.n, normal, r.rA, r.rB, sa, sb);
    r.block = blockIndex;
    r.target = -std::max(gap, RScalar(0)) / dt;
    // Against a spinning kinematic body (a station's deck), resting is moving with the point
    // of its surface: along the chord that point travels in the step (KinematicDrift_W), as
    // friction's targets say for the tangents.
    if (A.m_isKinematic || B.m_isKinematic) {
      const RVec3& spin = A.m_isKinematic ? A.m_w_W : B.m_w_W;
      r.target += normal.dot(RMotion::ContactDrift_W(spin, r.rA, r.rB, dt, false));
    }
    r.pseudoTarget = gap < -m_in->settings.penetrationSlop
                         ? std::min(m_in->settings.positionCorrection * (-gap - m_in->settings.penetrationSlop),
                                    m_in->settings.maxPositionCorrection) / dt
                         : 0;
    r.gap = gap;
    r.deferN = 0;
    r.lambdaN = r.lambdaP = r.lambdaE = 0;
    r.endTarget = kNever;
    r.lever = 0;  // set with the patch below
    // Warm start from the same features last step, or else from the nearest of last
    // step's points of this pair (in a's frame, where a resting contact stays put).
    auto it = warmFirst;
    const RVec3 point_A = A.m_q_WB.conjugate() * (position - A.m_x_W);
    m_rowPoint_A[firstRow + k] = point_A;  // where next step looks for this row's impulse
    const std::uint32_t feature = c.manifold.points[r.point].featureId;
    const RScalar reach = kWarmMatchDistance * std::min(A.m_boundingRadius, B.m_boundingRadius);
    // The same feature wins over any nearer point. Two new rows may take the same old
    // point (a corner that became two clip points): each starts from its impulse, and
    // the passes below redistribute.
    const RWarmStart* match = nullptr;
    const RWarmStart* nearest = nullptr;
    RScalar bestD2 = reach * reach;
    for (; it != m_warm.end() && it->pair == pair; ++it) {
      // A body that took over a freed slot is not the one the memory is of.
      if (it->genA != c.handleA.generation || it->genB != c.handleB.generation) continue;
      if (it->feature == feature) {
        match = &*it;
        break;
      }
      const RScalar d2 = (it->point_A - point_A).squaredNorm();
      if (d2 < bestD2) bestD2 = d2, nearest = &*it;
    }
    if (!match) match = nearest;
    // A row with no effective mass (a body locked along the normal, nothing to turn, against
    // an infinitely heavy one) can change nothing: it never acts, so its impulse could not
    // be bounded (nor the friction limit that sums it).
    if (!(r.n.k > 0)) r.target = kNever, r.pseudoTarget = 0, match = nullptr;
    if (match) {
      ++warmStarted;
      r.lambdaN = match->lambdaN;
      r.lambdaE = match->lambdaE;
      if (!patchWarm) patchWarm = match;
    }
  }
  // The manifold's friction patch (see RBlock): at the centroid of its points, limited by
  // mu times their total normal impulse, and a twist limited by mu times the sum of each
  // point's normal impulse and distance from the centroid.
  RBlock& blk = m_blocks[blockIndex];  // in place, every field, as the rows
  blk.first = firstRow;
  blk.count = c.manifold.pointCount;
  blk.useBlock = blk.count > 1;
  blk.inverse = 0;
  blk.patch = blockIndex, blk.nextInPatch = blk.otherPatch = kNoBlock, blk.flipped = blk.groupRows = blk.groupInverse = false;  // (RPatchGroups.cpp)
  blk.pinv.setZero();  // filled when the passes first need it (SolveNormalBlock)
  RVec3 centroid = RVec3::Zero();
  for (int k = 0; k < c.manifold.pointCount; ++k) centroid += c.manifold.points[k].position;
  centroid /= c.manifold.pointCount;
  blk.rA = centroid - A.m_x_W, blk.rB = centroid - B.m_x_W;
  SetDirection(blk.t[0], t1, blk.rA, blk.rB, sa, sb);
  SetDirection(blk.t[1], t2, blk.rA, blk.rB, sa, sb);
  blk.normal = normal;
  blk.twistIA = sa.invI * normal, blk.twistIB = sb.invI * normal;
  blk.kTwist = normal.dot(blk.twistIA) + normal.dot(blk.twistIB);
  for (int k = 0; k < c.manifold.pointCount; ++k) {
    m_rows[firstRow + k].lever = (c.manifold.points[k].position - centroid).norm();
  }
  blk.friction = mu;
  // A conveyor's surface velocity (the game's contact callback): b's surface relative to a's.
  const RVec3 surface = material ? m_in->materials.At(ci).relativeSurfaceVelocity_W : RVec3::Zero();
  for (int ph = 0; ph < 2; ++ph) {
    blk.targetT[ph][0] = surface.dot(t1), blk.targetT[ph][1] = surface.dot(t2);
    if (!(A.m_isKinematic || B.m_isKinematic)) continue;
    const RVec3 drift = RMotion::ContactDrift_W(A.m_isKinematic ? A.m_w_W : B.m_w_W, blk.rA, blk.rB, dt, ph == 1);
    blk.targetT[ph][0] += drift.dot(t1), blk.targetT[ph][1] += drift.dot(t2);
  }
  for (int ph = 0; ph < 2; ++ph) blk.lambdaT1[ph] = blk.lambdaT2[ph] = blk.lambdaTwist[ph] = 0;
  if (patchWarm) {
    for (int ph = 0; ph < 2; ++ph) {
      blk.lambdaT1[ph] = patchWarm->tangentImpulse[ph].dot(t1);
      blk.lambdaT2[ph] = patchWarm->tangentImpulse[ph].dot(t2);
      blk.lambdaTwist[ph] = patchWarm->twistImpulse[ph];
    }
  }
  return warmStarted;
}

}  // namespace REngine
