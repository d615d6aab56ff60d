// Private to REnginePhysics: the contact solver, the step's collision response (see
// RIntegrator.h and FindImpulses in RContactSolver.cpp). It solves the contacts the pair
// sweep found, island by island (bodies linked through contacts or joints between two
// movable bodies): each island's rows, warm starts, impacts at their time within the step,
// sequential-impulse passes with each manifold's normal rows as one block and its friction
// as one patch, small islands' exact solve, the end of the step's impulses and the report;
// the island's joints are solved with its contacts by the joint solver it holds
// (joints/RJointSolver.h), which the island solve drives. It owns the step's rows, impact
// rows, blocks and solver bodies (its outputs, which the motion, the events and sleeping
// read), the islands' layout, the per-task scratch (solver/RIslandScratch.h) and tallies,
// and the warm-start memory carried from step to step. The settings, the pair sweep (its
// contacts, flags, velocities, block-inverse cache and counts), the welds and the job system
// come in as an RSolverInputs. Every vector keeps its capacity between steps. Definitions:
// RContactSolver.cpp (FindImpulses, SolveIsland, impacts joined, the normal blocks),
// RIslandSolver.cpp (the layout, the direct solve), RContactRows.cpp, RImpactPhase.cpp,
// RContactPasses.cpp (the passes, patches, the end, the joints' rounds), RContactWarmStart.cpp
// (the warm starts and their energy rule), RImpactSweep.cpp, RPatchGroups.cpp and
// RContactReport.cpp.
#pragma once

#include "state/RLoadKey.h"

#include <REngineMath/RMath.h>
#include <REnginePhysics/RIntegrator.h>

#include "joints/RJointSolver.h"
#include "solver/RContactMaterials.h"
#include "solver/RIslandScratch.h"
#include "solver/RSolverTypes.h"
#include "world/RUnionFind.h"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace REngine {

class RJobSystem;
class RPairSweep;
class RWeldGroups;
struct RStepBodies;

class RContactSolver {
 public:
  // What the solver reads and writes of the step's other subsystems, this step.
  struct RSolverInputs {
    const RWorldSettings& settings;
    // The pair sweep: the step's contacts (the solver marks which it resolves and reports
    // its impulses on them), the bodies' flags and mid-step velocities, the block-inverse
    // cache in its manifold memory, and the counts the solver adds to (RPairStats).
    RPairSweep& sweep;
    // The weld groups, gathered from the step's joints here (GatherWelds), then read.
    RWeldGroups& welds;
    RJobSystem* jobs;    // null: one thread
    std::size_t tasks;   // how many tasks a parallel stage is cut into
    // Each contact's material when Active() (one-way bodies, the game's callback); else the
    // bodies' coefficients combined.
    const RContactMaterials& materials;
  };
  // Solves the contacts found this step for impulses and accumulates them on the bodies;
  // called from CollisionDetection. Sequential impulses, warm-started, with each manifold's
  // normal rows solved as one block and an impacting manifold bouncing through one row.
  void FindImpulses(const RStepBodies& bodies, RScalar dt, const RSolverInputs& in);

  // What the others read after the solve. Solved: whether FindImpulses solved this step
  // (else no body has solver outputs). InRows: per body (dense index), whether it is in
  // some resolved contact's or joint's rows: only those have solver state. SolverBodies:
  // per dense index (the world's at bodies.size()), their outputs for the motion (world,
  // N s and N m s: RSolverBody's endLinear, endAngular, deferredImpulse).
  bool Solved() const { return m_solved; }
  const std::vector<char>& InRows() const { return m_inRows; }
  const std::vector<RSolverBody>& SolverBodies() const { return m_solverBodies; }
  // The impact rows, by block (their impulses, N s, and where they last acted, world, m);
  // per island, whether its impact rows were written this step (the others' are not); each
  // island's [first, last) of the blocks (islands in the order of their smallest body).
  const std::vector<RImpactRow>& Impacts() const { return m_impacts; }
  const std::vector<char>& IslandImpacts() const { return m_islandImpacts; }
  const std::vector<std::pair<std::uint32_t, std::uint32_t>>& BlockIslands() const { return m_blockIslands; }
  // The step's joints (RJointSolver::StepJoints), which sleeping joins islands by.
  const std::vector<RStepJoint>& StepJoints() const { return m_joints.StepJoints(); }

  // Forgets the warm starts: the next step starts every contact cold
  // (RIntegrator::ForgetContacts).
  void ForgetWarmStarts() { m_warm.clear(); }
  // The warm-start memory, for the motion to drop the pairs of a body it puts back
  // (RMotion::Integrate): started warm from what made it overflow, it would overflow again.
  std::vector<RWarmStart>& MutableWarmStarts() { return m_warm; }

  // Save/load's (state/RStateStep.cpp, RWorldState.cpp): the warm-start memory (sorted by
  // pair, then feature) and the plain vector's body count it was kept for (0 for an
  // RBodies), written and restored exactly; a load forgets the last step's solve
  // (Solved() false), which is not saved.
  const std::vector<RWarmStart>& WarmStarts() const { return m_warm; }
  std::size_t WarmBodyCount() const { return m_warmBodyCount; }
  // A rollback snapshot's (RSnapshot.h): copied into the memory's capacity.
  void RestoreForSnapshot(RLoadKey, const std::vector<RWarmStart>& warm, std::size_t warmBodyCount) {
    m_warm = warm;
    m_warmBodyCount = warmBodyCount;
    m_solved = false;
  }
  void RestoreForLoad(RLoadKey, std::vector<RWarmStart> warm, std::size_t warmBodyCount) {
    m_warm = std::move(warm);
    m_warmBodyCount = warmBodyCount;
    m_solved = false;
  }

 private:
  // Islands of the resolved contacts (bodies linked through two movable bodies) and each
  // contact's slots, islands in the order of their smallest body, contacts in order within.
  void LayOutIslands(const RStepBodies& bodies);
  // One island's contact phase, start to end (FindImpulses): its bodies' solver state, rows,
  // warm starts, impacts, passes, direct solves, the end of the step and the report.
  void SolveIsland(const RStepBodies& bodies, RScalar dt, std::size_t island, std::size_t warmBase,
                   RIslandScratch& sc, RIslandTally& tally);
  // The island as the joint solver works on it (joints/RJointSolver.h).
  RJointIslandView JointView(const RStepBodies& bodies, RScalar dt, std::size_t island);

  RLeadingPoints LeadingPoints(const RContactManifold& m) const;
  std::uint32_t BuildContactRows(const RStepBodies& bodies, std::uint32_t ci, RScalar dt);
  void PrefetchContact(std::uint32_t ci) const;  // (only speed depends on it)
  void BuildImpactRow(const RStepBodies& bodies, std::uint32_t ci, std::uint32_t block);
  void JoinPairImpacts(const RStepBodies& bodies, std::uint32_t first, std::uint32_t last);
  void JoinWeldImpacts(const RStepBodies& bodies, std::uint32_t first, std::uint32_t last);
  static std::size_t FindWarmStarts(const std::vector<RWarmStart>& warm, std::uint64_t pair, std::size_t from);
  // Both return the largest change of a row's relative speed their impulses made, m/s
  // (|delta lambda| k: what SolveIslandBlocks stops on).
  RScalar SolveNormalBlock(RBlock& blk, RContactRow* rows, RPhase phase);
  RScalar SolvePatch(RBlock& blk, bool clampOnly, RPhase phase);
  // Whether some row of the island may approach faster than the
  // restitution threshold: the impact phase has work, and the island gets impact rows.
  bool MayImpact(std::size_t island) const;
  // The island's impact phase (RImpactPhase.cpp), then its rows' arms after the impacts.
  // jointView: the island for its joints, which act within the impacts (RJointImpacts.cpp).
  void SolveIslandImpacts(const RStepBodies& bodies, RScalar dt, std::size_t island,
                          const RJointIslandView& jointView, RIslandScratch& sc);
  void ShiftArmsAfterImpacts(RScalar dt, std::size_t island);
  // The phase's parts (RImpactPhase.cpp): which of the island's bodies turn on their paths;
  // one row's impact in a pass (returns whether it pushed), and its impact at a time; the
  // geometry of an impact at its time; and (RImpactSweep.cpp) the time from t0 on at which a pair whose turning
  // changed at an impact next closes (infinity: not within the step).
  void BeginTurns(const RStepBodies& bodies, std::size_t island, bool joints);
  bool ImpactRow(const RStepBodies& bodies, RImpactRow& r, RScalar dt, bool joints, const RJointIslandView& jointView,
                 RIslandScratch& sc);
  bool ImpactAt(const RStepBodies& bodies, RImpactRow& r, RSolverBody& sa, RSolverBody& sb, RScalar t, RScalar dt,
                bool swept, bool joints, const RJointIslandView& jointView, RIslandScratch& sc);
  bool ImpactGeometry(const RBodyCore& A, const RBodyCore& B, RSolverBody& sa, RSolverBody& sb, RScalar& t,
                      RScalar dt, RVec3& rA, RVec3& rB, RDirection* dir, std::uint32_t childA, std::uint32_t childB,
                      bool whole) const;
  RScalar SweepImpact(const RBodyCore& A, const RBodyCore& B, const RSolverBody& sa, const RSolverBody& sb,
                      RScalar t0, RScalar dt, std::uint32_t childA, std::uint32_t childB,
                      bool pastTouching) const;
  // With dt > 0, returns sum |lambda| ((|a_A| + |a_B|) dt + kWarmRounding |v|) over the
  // impulses it applied, v the speed of each one's direction just before it (J): what a
  // guess of resting contacts can put in, and the rounding of what it exchanges
  // (WarmStartIslandVelocities).
  RScalar WarmStartIsland(RPhase phase, std::uint32_t first, std::uint32_t last, RScalar dt);
  // 1e4 times the rounding of the energy an impulse exchanges (some 1e3 operations of 1.1e-16
  // each), and far below any gain that matters.
  static constexpr RScalar kWarmRounding = 1e-9;
  // The velocity phase's warm start of an island, kept only when it does not raise the
  // island's kinetic energy (RContactWarmStart.cpp).
  void WarmStartIslandVelocities(const RStepBodies& bodies, RScalar dt, std::size_t island, RIslandScratch& sc);
  RScalar IslandKineticEnergy(const RStepBodies& bodies, std::size_t island) const;
  // The island's friction patches shared by manifolds of one body on flush immovable bodies
  // (RPatchGroups.cpp): grouped, and each group's patch set up as one manifold's.
  void GroupPatches(const RStepBodies& bodies, std::uint32_t first, std::uint32_t last, RIslandScratch& sc);
  bool SharesPatch(std::uint32_t lead, std::uint32_t k) const;
  void SetUpGroupPatch(const RStepBodies& bodies, std::uint32_t lead, std::uint32_t& slots);
  // A group's normal rows as one block (groupRows), as SolveNormalBlock a manifold's.
  RScalar SolveGroupNormals(RBlock& lead, RPhase phase, RIslandScratch& sc);
  // Block k's part of its group's patch impulse in a phase (0 start, 1 end): the patch's
  // tangential impulse (world, on the pair's b, N s) and twist (N m s) in proportion to
  // its normal impulses; a patch alone, all of its own.
  void PatchShare(std::uint32_t k, int ph, RVec3& tangent, RScalar& twist) const;
  bool Grouped(const RBlock& blk) const { return blk.nextInPatch != kNoBlock || &m_blocks[blk.patch] != &blk; }
  // An island's contact phase after its impacts (RContactPasses.cpp): passes, direct solves,
  // the joints' rounds, and, when some row is closed at the end of the step, the end's.
  void SolveIslandContacts(const RStepBodies& bodies, RScalar dt, std::size_t island,
                           const RJointIslandView& joints, RIslandScratch& sc);
  // The joints' Newton rounds after the island's passes (RContactPasses.cpp): the joint
  // solver's predictions and targets, the passes again, the stiffened rounds and the
  // projection.
  void JointRounds(const RJointIslandView& joints, RIslandScratch& sc);
  // The island's impulses accumulated on its bodies, reported on its contacts and kept as
  // next step's warm starts, at m_warmNext[warmBase + the contact's warm slot] (RContactReport.cpp).
  void ReportIsland(const RStepBodies& bodies, RScalar dt, std::size_t island, std::size_t warmBase,
                    RIslandTally& tally);
  bool BlockInverse(RBlock& blk);
  bool CloseAtEnd(RContactRow& r, RScalar dt) const;
  void ApplyPatch(const RBlock& blk, RScalar d1, RScalar d2, RScalar dTwist);
  // An island's passes: blocks [first, last).
  // Returns whether its last pass changed nothing at all (every manifold at its targets).
  // The velocity passes also solve the island's joints (joints, sc) when it has some.
  bool SolveIslandBlocks(RPhase phase, int iterations, std::uint32_t first, std::uint32_t last,
                         const RJointIslandView* joints = nullptr, RIslandScratch* sc = nullptr);
  // An island's rows, [first, last) of m_rows (its blocks' rows are one run).
  std::pair<std::uint32_t, std::uint32_t> IslandRows(std::size_t island) const {
    if (m_blockIslands[island].first == m_blockIslands[island].second) return {0, 0};  // joints only
    const RBlock& lastBlock = m_blocks[m_blockIslands[island].second - 1];
    return {m_blocks[m_blockIslands[island].first].first, lastBlock.first + static_cast<std::uint32_t>(lastBlock.count)};
  }
  void IslandDirectSolves(std::size_t island, RIslandScratch& sc, bool settled);
  bool SolveIslandDirect(RPhase phase, RIslandScratch& sc);
  // Points the scratch at a direct island's rows, its matrix to be assembled.
  void PrepareIslandDirect(std::size_t island, RIslandScratch& sc);
  void AssembleIslandMatrix(RIslandScratch& sc);
  // Keeps the warm starts of pairs that sleep (both bodies asleep, or one asleep and one
  // static): they are not solved while asleep, and start warm when woken.
  void KeepSleepingWarmStarts(const RStepBodies& bodies);

  // FindImpulses' inputs, while it runs (null between steps): the call's context, which its
  // island functions read.
  const RSolverInputs* m_in = nullptr;
  // Whether FindImpulses solved this step (else no body has solver outputs).
  bool m_solved = false;
  // The contact solver's rows, impact rows, bodies and blocks this step (solver/RSolverTypes.h).
  std::vector<RContactRow> m_rows;
  std::vector<RImpactRow> m_impacts;
  std::vector<RSolverBody> m_solverBodies;
  std::vector<RBlock> m_blocks;
  std::vector<RContactSlots> m_rowStart;  // per resolved contact (LayOutIslands)
  std::vector<std::uint32_t> m_blockContact;  // the contact of each block
  // Per body: in some resolved contact's rows this step. Only those have solver state (the
  // others' m_solverBodies entries are not read: Integrate asks m_inRows), so a 30 000-body
  // cloud with 3000 contacts sets up 3000 entries, not 30 000. The movable ones by island
  // (island k's are m_islandBodies[m_islandBodyStart[k], m_islandBodyStart[k + 1]), in index
  // order), the static and kinematic ones apart: islands share them, and only read them.
  std::vector<char> m_inRows;
  std::vector<std::uint32_t> m_islandBodies, m_islandBodyStart, m_islandBodyFill, m_islandOfRoot;
  std::vector<std::uint32_t> m_immovableRowBodies;
  // Per body: the first of its friction patches against immovable bodies, while its island
  // groups them (GroupPatches; a movable body's entry is only its island's).
  std::vector<std::uint32_t> m_patchHead;
  std::vector<RVec3> m_rowPoint_A;  // per row: its point in body a's frame (next warm start)
  std::vector<RIslandTally> m_islandTallies;  // per task of the islands' solve
  // The resolved contacts' pair keys increase from one to the next (LayOutIslands): next
  // step's warm starts are then in order unless some contact's features are not.
  bool m_warmPairsIncrease = false;
  // The manifolds lie island by island (LayOutIslands), each island's in the contacts' order;
  // m_blockIslands holds each island's [first, last) of m_blocks.
  std::vector<std::uint32_t> m_blockStart;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_blockIslands;
  // Whether each island is solved directly (LayOutIslands); whether it has impact rows this
  // step (MayImpact; the others' entries of m_impacts are not written).
  std::vector<char> m_islandDirect;
  std::vector<char> m_islandImpacts;
  std::vector<char> m_islandRowsBuilt;  // its rows built before the islands' tasks (FindImpulses)
  // One island's direct solve and joints' scratch, one per task so that islands are solved
  // side by side.
  std::vector<RIslandScratch> m_islandScratch;
  // Islands up to this many rows get their normal impulses solved directly (see
  // SolveIslandContacts): 128 rows, 32 boxes resting face on face, cost about 0.1 ms.
  static constexpr int kDirectRows = 128;
  // An island the passes left solved to this (m/s) is left alone by its direct solve.
  static constexpr RScalar kDirectSolved = 1e-9;
  RUnionFind m_islandSets;  // bodies linked by rows between two dynamic bodies
  std::vector<RWarmStart> m_warm, m_warmNext;  // sorted by pair, then feature
  static constexpr std::uint64_t kDroppedWarm = ~std::uint64_t{0};  // not a pair: dropped
  std::size_t m_warmBodyCount = 0;
  // The joints (joints/RJointSolver.h): solved with the contacts, island by island.
  RJointSolver m_joints;
};

}  // namespace REngine
