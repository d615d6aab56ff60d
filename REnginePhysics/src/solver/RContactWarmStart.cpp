// An island's warm starts (RContactSolver): last step's impulses applied as this step's first
// guess, and the rule that keeps the velocity phase's guess only when it does not put energy
// into the island.
#include "solver/RContactSolver.h"

#include "solver/RSolverRows.h"
#include "world/RStepBodies.h"

#include <cmath>

namespace REngine {

using namespace solver;

// Applies the rows' and patches' accumulated impulses of a phase (last step's, matched when
// the rows were built) to the solver bodies' velocities.
// Island by island, as the passes (SolveIslandBlocks): each island's rows in order, then its
// patches, which is the whole world's order restricted to the island.
RScalar RContactSolver::WarmStartIsland(RPhase phase, std::uint32_t first, std::uint32_t last, RScalar dt) {
  const int ph = phase == RPhase::kEnd ? 1 : 0;
  RScalar allowance = 0;
  // Each impulse against the kicks' speed change, and a sliver (kWarmRounding) of the speed
  // its direction has just before it is applied.
  auto allow = [&](RScalar lambda, RScalar speed, const RSolverBody& sa, const RSolverBody& sb) {
    allowance += std::abs(lambda) * (kWarmRounding * std::abs(speed) + (sa.accel.norm() + sb.accel.norm()) * dt);
  };
  for (std::uint32_t k = first; k < last; ++k) {
    const RBlock& blk = m_blocks[k];
    for (int i = 0; i < blk.count; ++i) {
      RContactRow& r = m_rows[blk.first + i];
      const RScalar lambda = Lambda(r, phase);
      if (lambda == 0) continue;
      RSolverBody& sa = m_solverBodies[r.a];
      RSolverBody& sb = m_solverBodies[r.b];
      if (dt > 0) allow(lambda, Speed(r.n, sa.v, sa.w, sb.v, sb.w), sa, sb);
      Push(r.n, lambda, sa, sb, sa.v, sa.w, sb.v, sb.w);
    }
  }
  for (std::uint32_t k = first; k < last; ++k) {
    const RBlock& blk = m_blocks[k];
    const RScalar l1 = blk.lambdaT1[ph], l2 = blk.lambdaT2[ph], lt = blk.lambdaTwist[ph];
    if (dt > 0 && (l1 != 0 || l2 != 0 || lt != 0)) {
      const RContactRow& r = m_rows[blk.first];
      const RSolverBody& sa = m_solverBodies[r.a];
      const RSolverBody& sb = m_solverBodies[r.b];
      // (The patch's three impulses at once: each against the speed before them, the
      // twist against the spin about the normal.)
      allow(l1, Speed(blk.t[0], sa.v, sa.w, sb.v, sb.w), sa, sb);
      allow(l2, Speed(blk.t[1], sa.v, sa.w, sb.v, sb.w), sa, sb);
      allowance += std::abs(lt) * kWarmRounding * std::abs(blk.normal.dot(sb.w - sa.w));
    }
    ApplyPatch(blk, l1, l2, lt);
  }
  return allowance;
}

// The velocity phase's warm start (last step's impulses as this step's first guess), kept
// unless it puts more energy into the island than a guess of resting contacts could. An
// impulse lambda at a row does work lambda times the row's mean relative speed while it
// acts; at a resting contact that speed is within the bodies' kicks, (|a_A| + |a_B|) dt
// (gravity, forces: the half-kicks before and after), so a good guess puts in at most
// sum |lambda| (|a_A| + |a_B|) dt (its friction alike). A guess that puts in more is last
// step's answer to a configuration that is gone (a small dense body that turned fast at an
// impact, bodies spawned deep inside one another: rows whose arms and normals have swung
// since), and the passes, which can take a warm start back only as far as they converge,
// would leave part of it in (an island of 260 such bodies gained 45 times its kinetic energy
// in a step). Such an island starts cold. The bound also holds kWarmRounding of each
// impulse times the speed it meets, the energy it exchanges: in zero gravity the kicks' part
// is 0, and a guess whose gain is that small against what it exchanges (a slow contact in a
// fast island) is rounding, which must not decide whether the whole island starts cold.
// (A kinematic body pushing the island loses its guess too, and the passes find its impulse
// again.) An island with joints keeps its guess: its contacts' impulses act with the
// joints' (warm-started after them, and solved in rounds to their end poses), and what the
// contacts alone do to its energy says nothing of the two together.
void RContactSolver::WarmStartIslandVelocities(const RStepBodies& bodies, RScalar dt, std::size_t island,
                                               RIslandScratch& sc) {
  const auto [first, last] = m_blockIslands[island];
  if (m_joints.IslandHasJoints(island)) {
    WarmStartIsland(RPhase::kVelocity, first, last, 0);
    return;
  }
  const std::uint32_t b0 = m_islandBodyStart[island], b1 = m_islandBodyStart[island + 1];
  sc.warmV.resize(b1 - b0), sc.warmW.resize(b1 - b0);
  for (std::uint32_t k = b0; k < b1; ++k) {
    const RSolverBody& s = m_solverBodies[m_islandBodies[k]];
    sc.warmV[k - b0] = s.v, sc.warmW[k - b0] = s.w;
  }
  const RScalar before = IslandKineticEnergy(bodies, island);
  const RScalar allowance = WarmStartIsland(RPhase::kVelocity, first, last, dt);
  // (With the rounding of the energies' sums.)
  if (!(IslandKineticEnergy(bodies, island) > before * (1 + RScalar(1e-12)) + allowance)) return;
  for (std::uint32_t k = b0; k < b1; ++k) {
    RSolverBody& s = m_solverBodies[m_islandBodies[k]];
    s.v = sc.warmV[k - b0], s.w = sc.warmW[k - b0];
  }
  for (std::uint32_t k = first; k < last; ++k) {
    RBlock& blk = m_blocks[k];
    for (int i = 0; i < blk.count; ++i) m_rows[blk.first + i].lambdaN = 0;
    blk.lambdaT1[0] = blk.lambdaT2[0] = blk.lambdaTwist[0] = 0;
  }
}

// The kinetic energy (J) of an island's movable bodies at their solver velocities: m v^2 / 2
// and the spin's w_B . I_B w_B / 2 in the body's principal frame (orientation of the start).
RScalar RContactSolver::IslandKineticEnergy(const RStepBodies& bodies, std::size_t island) const {
  RScalar e = 0;
  for (std::uint32_t k = m_islandBodyStart[island]; k < m_islandBodyStart[island + 1]; ++k) {
    const std::uint32_t i = m_islandBodies[k];
    const RSolverBody& s = m_solverBodies[i];
    if (s.invM == 0) continue;
    const RVec3 w_B = bodies[i].m_q_WB.conjugate() * s.w;
    e += s.v.squaredNorm() / s.invM + w_B.dot(bodies[i].m_I_B.cwiseProduct(w_B));
  }
  return RScalar(0.5) * e;
}

}  // namespace REngine
