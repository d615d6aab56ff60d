// The contact phase's outputs (RContactSolver::ReportIsland): an island's impulses accumulated
// on its bodies (applied by UpdateObjects), reported on its contacts, and kept as next
// step's warm starts; and the warm starts of the pairs that sleep, kept while they sleep
// (KeepSleepingWarmStarts).
#include "solver/RContactSolver.h"

#include "pairs/RPairSweep.h"
#include "solver/RSolverRows.h"
#include "world/RStepBodies.h"

#include <cmath>

namespace REngine {

using namespace solver;

void RContactSolver::KeepSleepingWarmStarts(const RStepBodies& bodies) {
  // Without sleeping nothing sleeps here (WakeIslands woke everything), and no pair is kept.
  if (!m_in->settings.shortcuts.sleeping) return;
  // The body in a slot, if it is the one the memory is of and it is stepped.
  auto passive = [&bodies](std::uint32_t slot, std::uint32_t generation) {
    if (slot >= bodies.slotCount) return false;
    const std::uint32_t i = bodies.denseOfSlot[slot];
    if (i >= bodies.count || bodies.handles[i].generation != generation) return false;
    return bodies[i].m_sleeping || bodies[i].m_isStatic || RPairSweep::StillKinematic(bodies[i]);
  };
  for (const RWarmStart& w : m_warm) {
    const std::uint32_t a = static_cast<std::uint32_t>(w.pair >> 32);
    const std::uint32_t b = static_cast<std::uint32_t>(w.pair & 0xffffffffu);
    if (passive(a, w.genA) && passive(b, w.genB)) m_warmNext.push_back(w);
  }
}

// Summed on the solver bodies (which start from the bodies' own impulses, and whose inverse
// mass is 0 exactly when the body is static or kinematic), then written to the bodies: the
// same sums in the same order, without a visit per row to bodies a kilobyte each. Contact
// by contact, in their order within the island (each movable body's contacts are all in its
// island): each body's impulses add up in the order they always did.
void RContactSolver::ReportIsland(const RStepBodies& bodies, RScalar dt, std::size_t island, std::size_t warmBase,
                                  RIslandTally& tally) {
  const auto [first, last] = m_blockIslands[island];
  auto accumulate = [this](std::uint32_t a, std::uint32_t b, const RVec3& rA,
                           const RVec3& rB, const RVec3& J) {
    RSolverBody& A = m_solverBodies[a];
    RSolverBody& B = m_solverBodies[b];
    if (A.invM != 0) {
      A.impulse -= J;
      A.angularImpulse -= rA.cross(J);
    }
    if (B.invM != 0) {
      B.impulse += J;
      B.angularImpulse += rB.cross(J);
    }
  };
  // An impulse at the end of the step acts where the contact is then: the point moves with
  // the bodies, with the lighter one's displacement when one is much heavier (the ground's
  // contact with a sliding box moves with the box). The same point for both bodies keeps
  // angular momentum exact. Lever arms are about the centres at the start of the step;
  // UpdateObjects moves them to where the centres end.
  auto accumulateEnd = [this, dt](std::uint32_t a, std::uint32_t b, const RVec3& rA,
                                           const RVec3& rB, const RVec3& J) {
    if (J.isZero(0)) return;
    RSolverBody& sa = m_solverBodies[a];
    RSolverBody& sb = m_solverBodies[b];
    const RVec3 moveA = (sa.vMid + sa.vp) * dt, moveB = (sb.vMid + sb.vp) * dt;
    const RVec3 shift = (sa.invM * moveA + sb.invM * moveB) / (sa.invM + sb.invM);
    if (!m_in->sweep.ImmovableAt(a)) {
      sa.endLinear -= J;
      sa.endAngular -= (rA + shift).cross(J);
    }
    if (!m_in->sweep.ImmovableAt(b)) {
      sb.endLinear += J;
      sb.endAngular += (rB + shift).cross(J);
    }
  };
  for (std::uint32_t k = first; k < last; ++k) {
    const RBlock& blk = m_blocks[k];
    const RContact& c = m_in->sweep.Contacts()[m_blockContact[k]];
    tally.reusedInverses += blk.inverse == 2;
    tally.computedInverses += blk.inverse == 1;
    RWarmStart* warm = &m_warmNext[warmBase + m_rowStart[m_blockContact[k]].warm];
    // The manifold's friction, which each of its points remembers: its part of its group's
    // patch (RPatchGroups.cpp), when it shares one.
    RVec3 tangentImpulse[2];
    RScalar twistImpulse[2];
    bool patchFinite = true;
    for (int ph = 0; ph < 2; ++ph) {
      if (Grouped(blk)) {
        PatchShare(k, ph, tangentImpulse[ph], twistImpulse[ph]);
      } else {
        tangentImpulse[ph] = blk.lambdaT1[ph] * blk.t[0].d + blk.lambdaT2[ph] * blk.t[1].d;
        twistImpulse[ph] = blk.lambdaTwist[ph];
      }
      patchFinite = patchFinite && AllFinite(tangentImpulse[ph]) && std::isfinite(twistImpulse[ph]);
    }
    const std::uint64_t pair = PairKey(c.handleA.index, c.handleB.index);
    for (int i = 0; i < blk.count; ++i) {
      const RContactRow& r = m_rows[blk.first + i];
      accumulate(r.a, r.b, r.rA, r.rB, r.lambdaN * r.n.d);
      if (r.lambdaE != 0) accumulateEnd(r.a, r.b, r.rA, r.rB, r.lambdaE * r.n.d);
      m_in->sweep.SolverContact(r.contact).normalImpulse[r.point] = r.lambdaN + r.lambdaE;
      RWarmStart& w = warm[i];
      w.pair = pair;
      w.genA = c.handleA.generation, w.genB = c.handleB.generation;
      w.feature = c.manifold.points[r.point].featureId;
      if (i > 0 && w.feature < warm[i - 1].feature) tally.warmUnordered = true;
      w.point_A = m_rowPoint_A[blk.first + i];
      w.lambdaN = r.lambdaN;
      w.lambdaE = r.lambdaE;
      for (int ph = 0; ph < 2; ++ph) w.tangentImpulse[ph] = tangentImpulse[ph], w.twistImpulse[ph] = twistImpulse[ph];
      // A step that overflowed must not seed the next one (its bodies are put back).
      if (!(patchFinite && std::isfinite(w.lambdaN) && std::isfinite(w.lambdaE) && AllFinite(w.point_A))) {
        w.pair = kDroppedWarm, tally.dropped = true;
      }
    }
  }
  for (std::uint32_t k = first; k < last; ++k) {
    const RBlock& blk = m_blocks[k];
    const RContactRow& r = m_rows[blk.first];
    if (Grouped(blk)) {
      // Each pair reports its part of its group's patch; the group's first block applies it.
      RVec3 part[2];
      RScalar twist;
      for (int ph = 0; ph < 2; ++ph) PatchShare(k, ph, part[ph], twist);
      m_in->sweep.SolverContact(r.contact).frictionImpulse_W = part[0] + part[1];
      if (blk.patch != k) continue;
    }
    accumulate(r.a, r.b, blk.rA, blk.rB, blk.lambdaT1[0] * blk.t[0].d + blk.lambdaT2[0] * blk.t[1].d);
    accumulateEnd(r.a, r.b, blk.rA, blk.rB, blk.lambdaT1[1] * blk.t[0].d + blk.lambdaT2[1] * blk.t[1].d);
    if (!Grouped(blk)) {
      m_in->sweep.SolverContact(r.contact).frictionImpulse_W = (blk.lambdaT1[0] + blk.lambdaT1[1]) * blk.t[0].d +
                                                           (blk.lambdaT2[0] + blk.lambdaT2[1]) * blk.t[1].d;
    }
    // The twist: a pure torque about the normal.
    RSolverBody& sa = m_solverBodies[r.a];
    RSolverBody& sb = m_solverBodies[r.b];
    if (sa.invM != 0) {
      sa.angularImpulse -= blk.lambdaTwist[0] * blk.normal;
      sa.endAngular -= blk.lambdaTwist[1] * blk.normal;
    }
    if (sb.invM != 0) {
      sb.angularImpulse += blk.lambdaTwist[0] * blk.normal;
      sb.endAngular += blk.lambdaTwist[1] * blk.normal;
    }
  }
  // An impact's impulse is a one-off, not remembered: carried into the next step it would
  // push apart bodies that are already separating, energy from nowhere. It is reported at
  // the manifold's deepest point.
  for (std::uint32_t k = first; k < (m_islandImpacts[island] ? last : first); ++k) {
    const RImpactRow& r = m_impacts[k];
    if (r.lambdaN == 0) continue;
    RSolverBody& A = m_solverBodies[r.a];
    RSolverBody& B = m_solverBodies[r.b];
    if (A.invM != 0) A.impulse -= r.impulse, A.angularImpulse -= r.angularA;
    if (B.invM != 0) B.impulse += r.impulse, B.angularImpulse += r.angularB;
    m_in->sweep.SolverContact(r.contact).normalImpulse[r.point] += r.lambdaN;
    m_in->sweep.SolverContact(r.contact).frictionImpulse_W += r.frictionImpulse;
  }
  // Impacts within the step: the bodies move with their piecewise path's velocity and get
  // the rest at the end (SolveIslandImpacts).
  for (std::uint32_t k = m_islandBodyStart[island]; k < m_islandBodyStart[island + 1]; ++k) {
    const std::uint32_t i = m_islandBodies[k];
    RSolverBody& s = m_solverBodies[i];
    if (s.invM == 0) continue;
    RBodyCore& b = bodies[i];
    if (!s.deferV.isZero(0)) {
      const RVec3 J = s.deferV / b.m_invMass;
      s.impulse -= J;
      s.deferredImpulse = J;
      // The contact phase's impulses act on the body at its start-of-step pose, but it then
      // moves deferV dt less than its final velocity would take it: the spin that keeps
      // angular momentum exact (the orbital term x x m v misses dt deferV x J_contact). It
      // is the moment of the lever arms' shift that the contact phase was solved with (see
      // ShiftArmsAfterImpacts), so it costs no energy the solve did not see. (A body that
      // turned at an impact takes the solve's spin itself, turnW_W, which has it.)
      s.angularImpulse += dt * s.deferV.cross(s.contactDeltaV / b.m_invMass);
    }
    b.m_linearImpulse_W = s.impulse, b.m_angularImpulse_W = s.angularImpulse;
  }
}

}  // namespace REngine
