// Private to REnginePhysics: the integrator's working state, behind RIntegrator (which holds
// one through a pointer, so none of this is in an installed header). It holds one of each
// subsystem (docs/ARCHITECTURE.md, "Subsystems and folders": the pair sweep, the broad
// phase, sleeping, the motion, the weld groups, the contact events) and runs them in the
// step's order (RIntegrator.cpp). The contact solver's and the joints' solver's functions
// are its own, over the members below: solver/*.cpp (FindImpulses and the island's
// phases) and joints/*.cpp (the joints' rows, rounds, projections and impacts).
// Stages that run as tasks (RJobSystem, m_jobs and m_tasks) write only their own outputs:
// per-task scratch, or slots counted beforehand; the results do not depend on the threads.
#pragma once

#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RJobSystem.h>
#include <REnginePhysics/RJoint.h>

#include "events/RContactEventLog.h"
#include "pairs/RBoundsTree.h"
#include "pairs/RBroadPhase.h"
#include "pairs/RPairSweep.h"
#include "body/RBodyAccess.h"
#include "joints/RJointSparse.h"
#include "joints/RJointTypes.h"
#include "joints/RWeldGroups.h"
#include "motion/RMotion.h"
#include "sleep/RSleeping.h"
#include "solver/RSolverTypes.h"
#include "world/RUnionFind.h"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace REngine {

// The bodies one step works on: contiguous storage and each body's stable identity. From
// an RBodies, its enabled range and handles; from a plain vector, identity by position
// (a body's handle is its index, generation 0).
// A pass over the bodies in storage order waits for each body's first lines: bodies are 19
// cache lines apart, and the hardware's stream prefetch stops at every page (a body in
// three or four). A pass asks for the lines it reads (the first `bytes` of the body) a
// couple of bodies ahead: the motion of a 30000-body cloud 16.8 -> 11.2 ms a step
// (medians of 5 interleaved runs). Only speed depends on it.
// The lines of [from, from + bytes) (bytes > 0), the last one too when the range is not
// line-aligned (a 48-byte box may straddle two).
inline void PrefetchBytes(const void* from, std::size_t bytes) {
  const char* p = static_cast<const char*>(from);
  for (std::size_t line = 0; line < bytes; line += 64) __builtin_prefetch(p + line);
  __builtin_prefetch(p + bytes - 1);
}
inline void PrefetchBody(const RBodyCore& b, std::size_t bytes) { PrefetchBytes(&b, bytes); }

struct RStepBodies {
  RRigidBody* data = nullptr;
  std::size_t count = 0;
  const RBodyHandle* handles = nullptr;       // per dense index
  const std::uint32_t* denseOfSlot = nullptr; // per slot: dense index (>= count: not stepped)
  std::size_t slotCount = 0;
  // A plain vector: identity is position, so a change of count forgets contact memory and
  // wakes everything, and a body found at another index wakes everything.
  bool byIndex = true;
  // An RBodies' departures since the last step: islands to wake, or all (read and cleared).
  std::vector<std::uint32_t>* wakeIslands = nullptr;
  bool* wakeAll = nullptr;
  std::vector<RVec3>* wakeBoxes = nullptr;  // static and kinematic departures' boxes
  // An RBodies' joints (a plain vector has none), and the pairs of slots joined by a joint
  // whose bodies do not collide (lower slot << 32 | higher, sorted).
  RJoint* joints = nullptr;
  std::size_t jointCount = 0;
  const std::uint64_t* noCollidePairs = nullptr;
  std::size_t noCollideCount = 0;
  // Whether two bodies (dense indices) are joined by a joint that keeps them from colliding.
  bool JointedNoCollide(std::size_t i, std::size_t j) const;

  // A body's state (the engine's view, body/RBodyAccess.h); Body(i) is the game's view of it.
  RBodyCore& operator[](std::size_t i) const { return Core(data[i]); }
  RRigidBody& Body(std::size_t i) const { return data[i]; }
  std::size_t size() const { return count; }
  // A pass over the bodies' states, in storage order.
  struct RIterator {
    RRigidBody* p;
    RBodyCore& operator*() const { return Core(*p); }
    RIterator& operator++() { return ++p, *this; }
    bool operator!=(const RIterator& other) const { return p != other.p; }
  };
  RIterator begin() const { return {data}; }
  RIterator end() const { return {data + count}; }
  std::uint32_t Slot(std::size_t i) const { return handles[i].index; }
};

class RWorldStep {
 public:
  // The motion (motion/RMotion.h): the step's one definition of the bodies' velocities (its
  // static functions), Integrate, and the bodies put back.
  RMotion m_motion;
  // A body's solver state at the start of FindImpulses: vMove its mid-step velocity (m/s).
  static void InitSolverBody(RSolverBody& s, const RBodyCore& b, const RVec3& vMove, RScalar halfDt,
                             const RVec3& gravity_W);

  // The pair sweep (pairs/RPairSweep.h): the step's contacts, found with the broad phase.
  RPairSweep m_sweep;
  RBroadPhase m_broad;  // the broad phase (pairs/RBroadPhase.h): stage 1 with a tree
  // The step's job system (null: one thread) and how many tasks a parallel stage is cut
  // into (1 on one thread). Set by RIntegrator before each step.
  RJobSystem* m_jobs = nullptr;
  std::size_t m_tasks = 1;
  // Solves the contacts found this step for impulses and accumulates them on the bodies;
  // called from CollisionDetection. Sequential impulses, warm-started, with each manifold's
  // normal rows solved as one block and an impacting manifold bouncing through one row.
  void FindImpulses(const RStepBodies& bodies, RScalar dt);

  // Whether FindImpulses solved this step (else no body has solver outputs).
  bool m_solved = false;

  RWorldSettings m_settings;
  RStepProfile m_profile;
  std::uint64_t m_stepCount = 0;
  std::uint64_t m_cacheStamp = 0;
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
  std::vector<RVec3> m_rowPoint_A;  // per row: its point in body a's frame (next warm start)
  std::vector<RIslandTally> m_islandTallies;  // per task of the islands' solve
  // The resolved contacts' pair keys increase from one to the next (LayOutIslands): next
  // step's warm starts are then in order unless some contact's features are not.
  bool m_warmPairsIncrease = false;
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
  struct RIslandScratch;
  // One island's contact phase, start to end (FindImpulses): its bodies' solver state, rows,
  // warm starts, impacts, passes, direct solves, the end of the step and the report.
  void SolveIsland(const RStepBodies& bodies, RScalar dt, std::size_t island, std::size_t warmBase,
                   RIslandScratch& sc, RIslandTally& tally);
  // Whether some row of the island may approach faster than the
  // restitution threshold: the impact phase has work, and the island gets impact rows.
  bool MayImpact(std::size_t island) const;
  // The island's impact phase (RImpactPhase.cpp), then its rows' arms after the impacts.
  void SolveIslandImpacts(const RStepBodies& bodies, RScalar dt, std::size_t island, RIslandScratch& sc);
  // An island's joints in its impacts (RJointImpacts.cpp): their equality rows hold the
  // joined bodies' relative velocities through the impacts (sc.impactRows, a copy of the
  // rows with impulses of their own), solved with each impact (at its time t); then the
  // impulses reported and the joints' prediction made again from the velocities after.
  void BeginImpactJoints(std::size_t island, RIslandScratch& sc);
  void ImpactJointsPass(RScalar t, RIslandScratch& sc);
  void EndImpactJoints(const RStepBodies& bodies, std::size_t island, RScalar dt, RIslandScratch& sc, bool impacts);
  void ShiftJointArms(RJointRow* rows, std::size_t count, RScalar dt);
  // What the arm's moment of a linear joint row along d gains on a body an impact hit:
  // (dt deferV) x d, of the free part of d on a body with linear locks (as the contacts').
  static RVec3 JointArmShift(const RSolverBody& s, const RVec3& d, RScalar dt) {
    if (s.deferV.isZero(0) || s.invM == 0) return RVec3::Zero();
    const RVec3 shift = dt * s.deferV;
    return s.linLocked ? RVec3(shift.cross(d.cwiseProduct(s.linMask))) : RVec3(shift.cross(d));
  }
  void ShiftArmsAfterImpacts(RScalar dt, std::size_t island);
  template <class Advance>
  bool ImpactGeometry(const RBodyCore& A, const RBodyCore& B, RSolverBody& sa, RSolverBody& sb,
                      const Advance& advance, RScalar& t, RScalar dt, RVec3& rA, RVec3& rB,
                      RDirection* dir, std::uint32_t childA, std::uint32_t childB) const;
  RScalar SolvePatch(RBlock& blk, bool clampOnly, RPhase phase);
  void WarmStartIsland(RPhase phase, std::uint32_t first, std::uint32_t last);
  // An island's contact phase after its impacts (RContactPasses.cpp): passes, direct solves,
  // and, when some row is closed at the end of the step, the end's.
  void SolveIslandContacts(const RStepBodies& bodies, RScalar dt, std::size_t island, RIslandScratch& sc);
  // The island's impulses accumulated on its bodies, reported on its contacts and kept as
  // next step's warm starts, at m_warmNext[warmBase + the contact's warm slot] (RContactReport.cpp).
  void ReportIsland(const RStepBodies& bodies, RScalar dt, std::size_t island, std::size_t warmBase,
                    RIslandTally& tally);
  bool BlockInverse(RBlock& blk);
  bool CloseAtEnd(RContactRow& r, RScalar dt) const;
  void ApplyPatch(const RBlock& blk, RScalar d1, RScalar d2, RScalar dTwist);
  // Islands of the resolved contacts (bodies linked through two movable bodies) and each
  // contact's slots, islands in the order of their smallest body, contacts in order within.
  void LayOutIslands(const RStepBodies& bodies);
  // An island's passes: blocks [first, last).
  // Returns whether its last pass changed nothing at all (every manifold at its targets).
  // The velocity passes also solve the island's joints (island, sc) when it has some.
  bool SolveIslandBlocks(RPhase phase, int iterations, std::uint32_t first, std::uint32_t last,
                         std::size_t island = 0, RIslandScratch* sc = nullptr);
  // The manifolds lie island by island (LayOutIslands), each island's in the contacts' order;
  // m_blockIslands holds each island's [first, last) of m_blocks.
  std::vector<std::uint32_t> m_blockStart;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_blockIslands;
  // An island's rows, [first, last) of m_rows (its blocks' rows are one run).
  std::pair<std::uint32_t, std::uint32_t> IslandRows(std::size_t island) const {
    if (m_blockIslands[island].first == m_blockIslands[island].second) return {0, 0};  // joints only
    const RBlock& lastBlock = m_blocks[m_blockIslands[island].second - 1];
    return {m_blocks[m_blockIslands[island].first].first, lastBlock.first + static_cast<std::uint32_t>(lastBlock.count)};
  }
  // Whether each island is solved directly (LayOutIslands); whether it has impact rows this
  // step (MayImpact; the others' entries of m_impacts are not written).
  std::vector<char> m_islandDirect;
  std::vector<char> m_islandImpacts;
  std::vector<char> m_islandRowsBuilt;  // its rows built before the islands' tasks (FindImpulses)

  // One island's direct solve: its rows and the dense scratch (kDirectRows^2 at most),
  // one per task so that islands are solved side by side.
  struct RIslandScratch {
    std::vector<std::uint32_t> index;  // the island's rows
    std::vector<RScalar> K, L, b, x, invDiag, residual;
    std::vector<int> map, envelope, lo, hi, columnsFrom, columnsTo;
    std::vector<std::pair<int, int>> runs;  // the island's manifolds: [first, last)
    std::vector<char> active;
    bool kReady = false;
    // The island's joints (RJoints.cpp): their equality rows (indices into the rows), the
    // group of them solved as one block ([first, last) of eq), its skyline factor, the end
    // of the step's rows and bodies.
    std::vector<std::uint32_t> eq, eqFirst, eqOffset;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> eqGroups;
    std::vector<char> eqGroupOk;  // factored (else its rows are solved one at a time)
    // Past kJointBlockRows rows the one group is solved as a sparse system (RJointSparse.h):
    // its explicit bodies (the island's movable bodies without locks), and the (body, row)
    // links of the others, whose rows couple directly.
    bool eqSparse = false;
    joints::RJointSparseSlot sparse;
    std::vector<std::uint32_t> sparseBodies;
    std::vector<std::uint64_t> sparseLinks;
    // Whether the sparse block's rows are a forest of joints (equality rows only, no loop
    // through bodies or the immovable ones): then they have no self-stress to take out.
    bool eqForest = false;
    RUnionFind sparseSets;
    std::vector<char> jointActive;  // per row: in the block (equality, pushing limit, motor within its force)
    bool blockStale = true;         // the block's factor is not the active set's
    std::vector<RScalar> eqL, eqInvDiag, eqRhs, eqNull, eqRidge;  // (eqRidge: per group)
    std::vector<std::uint32_t> jointBodies;  // the island's movable joint bodies
    // Per solver body (mark) and per end body (endMark): scratch, kNone between uses.
    std::vector<std::uint32_t> mark, endMark;
    std::vector<RJointRow> endRows;
    std::vector<RJointRow> impactRows;  // the joints' rows in the impact phase
    std::vector<std::uint32_t> endContacts;  // the contact rows solved with the joints at the end
    std::vector<std::uint32_t> endPatches;   // their manifolds (blocks) whose friction is solved with them
    // Per row: its error at the start of the step, and as predicted at the end.
    std::vector<RScalar> startC, jointC;
    struct REndBody {
      RVec3 v, w;
      RMat3 invI;
      RScalar invM;
      RVec3 linMask;
      bool linLocked;
    };
    std::vector<REndBody> endBodies;
    // The joints' geometric stiffness (RJointStiffness.cpp): per solver body, the rotational
    // inertia added while an unresolved island is solved (kg m^2, 0 else); per joint body,
    // its inverse inertia and spin kept meanwhile.
    std::vector<RScalar> stiffness;
    bool stiffened = false;
    std::vector<RMat3> keptInvI;
    std::vector<RVec3> keptW;
  };
  std::vector<RIslandScratch> m_islandScratch;
  bool SolveIslandDirect(RPhase phase, RIslandScratch& sc);
  // Points the scratch at a direct island's rows, its matrix to be assembled.
  void PrepareIslandDirect(std::size_t island, RIslandScratch& sc);
  void AssembleIslandMatrix(RIslandScratch& sc);
  // Islands up to this many rows get their normal impulses solved directly (see
  // SolveIslandContacts): 128 rows, 32 boxes resting face on face, cost about 0.1 ms.
  static constexpr int kDirectRows = 128;
  // An island the passes left solved to this (m/s) is left alone by its direct solve.
  static constexpr RScalar kDirectSolved = 1e-9;
  RUnionFind m_islandSets;  // bodies linked by rows between two dynamic bodies
  std::vector<RWarmStart> m_warm, m_warmNext;  // sorted by pair, then feature
  static constexpr std::uint64_t kDroppedWarm = ~std::uint64_t{0};  // not a pair: dropped
  std::size_t m_warmBodyCount = 0;
  // Keeps the warm starts of pairs that sleep (both bodies asleep, or one asleep and one
  // static): they are not solved while asleep, and start warm when woken.
  void KeepSleepingWarmStarts(const RStepBodies& bodies);
  RSleeping m_sleep;  // sleeping islands (sleep/RSleeping.h)
  // Contact events (RWorldSettings::contactEvents): poses before the motion, events after.
  RContactEventLog m_eventLog;
  // Identity handles for the plain-vector path (RStepBodies::byIndex).
  std::vector<RBodyHandle> m_indexHandles;
  std::vector<std::uint32_t> m_indexSlots;

  // Joints (RJoints.cpp, RJointRows.cpp): the step's joints (joints/RJointTypes.h).
  std::vector<RStepJoint> m_stepJoints;
  void GatherJoints(const RStepBodies& bodies);
  // Welds (joints/RWeldGroups.h): the fixed joints' bodies in groups moved as one rigid body.
  RWeldGroups m_welds;
  // Each island's joints: m_islandJoints[m_islandJointStart[k], m_islandJointStart[k + 1])
  // are indices into m_stepJoints, in its order (LayOutIslands).
  std::vector<std::uint32_t> m_islandJoints, m_islandJointStart;
  std::vector<std::uint32_t> m_jointRootCount, m_islandJointFill;  // (LayOutIslands' scratch)
  // The joints' rows, kMaxRows a joint, island by island: the island's joint at position p
  // of m_islandJoints has its rows at p * RJoint::kMaxRows.
  std::vector<RJointRow> m_jointRows;
  // Per movable body in some joint: its end pose, kept from the last prediction of the step.
  std::vector<RJointPose> m_jointPoses;
  RJointPose PredictPose(const RBodyCore& b, std::uint32_t i, RScalar dt) const;
  // A joint body's pose at the start of the step, or at its end as predicted (end = true;
  // the world's: the origin, unturned).
  RJointPoseIn JointPose(const RStepBodies& bodies, std::uint32_t i, RScalar dt, bool end) const;
  // The island's joints: rows built at the start of the step, warm-started and factored
  // (BuildIslandJoints); the Newton rounds after the passes (JointRounds, with
  // PredictJoints and SetJointTargets), the projection of what error they leave
  // (ProjectJoints); the impulses reported to the solver bodies (ReportJoints); and the end
  // of the step's velocity projection at the end poses (SolveJointsAtEnd).
  void BuildIslandJoints(const RStepBodies& bodies, std::size_t island, RScalar dt, RIslandScratch& sc);
  RScalar PredictJoints(const RStepBodies& bodies, std::size_t island, RScalar dt, RIslandScratch& sc);
  void SetJointTargets(std::size_t island, RScalar dt, RIslandScratch& sc);
  void JointRounds(const RStepBodies& bodies, std::size_t island, RScalar dt, RIslandScratch& sc);
  void ProjectJoints(const RStepBodies& bodies, std::size_t island, RScalar dt, RIslandScratch& sc);
  RScalar SolveJointsPass(std::size_t island, RIslandScratch& sc);
  void ReportJoints(std::size_t island, RScalar dt);
  void SolveJointsAtEnd(const RStepBodies& bodies, std::size_t island, RScalar dt, RIslandScratch& sc);
  // The end bodies (RIslandScratch::endBodies) of the island's joints, each movable body
  // once (sc.mark: its index there; cleared by ClearJointMarks), each immovable end apart;
  // their rows at the predicted end poses in sc.endRows, errors in sc.jointC. atEnd: with
  // the end velocities (SolveJointsAtEnd), else at rest (ProjectJoints' pseudo-velocities).
  void BuildEndRows(const RStepBodies& bodies, std::size_t island, RScalar dt, RIslandScratch& sc, bool atEnd);
  void ClearJointMarks(RIslandScratch& sc);
  void IslandDirectSolves(std::size_t island, RIslandScratch& sc, bool settled);
  // The joints' geometric stiffness (RJointStiffness.cpp). JointStiffness fills sc.stiffness
  // for the island's joint bodies and returns the largest (omega dt)^2 of their arms' modes;
  // Stiffen solves with it from there on (rows' masses again); Unstiffen gives the bodies
  // back their inertia, the motion the turn the solver gave them, and the island back what
  // that took from its angular momentum; EndStiffness does the same at the end of the step,
  // and takes back what the position projection added to a free island's.
  RScalar JointStiffness(const RStepBodies& bodies, std::size_t island, RScalar dt, RIslandScratch& sc);
  void Stiffen(std::size_t island, RIslandScratch& sc);
  void Unstiffen(const RStepBodies& bodies, std::size_t island, RIslandScratch& sc);
  void EndStiffness(const RStepBodies& bodies, std::size_t island, RIslandScratch& sc, const RVec3* wBefore,
                    const RVec3& projected);
  bool FreeJointIsland(const RStepBodies& bodies, std::size_t island, const RIslandScratch& sc) const;
  // Above this (omega dt)^2 of an arm's mode an island's joints are solved stiffened
  // (RJointStiffness.cpp); the rounds lose a chain's links past about 2.
  static constexpr RScalar kUnresolved = 1;
  // A joint's tolerance (m or rad) near world point x: 1e-10, or a few ulps of x far from
  // the origin.
  static RScalar JointTolerance(const RVec3& x) {
    return std::max(RScalar(1e-10), RScalar(1e-15) * x.cwiseAbs().maxCoeff());
  }
  bool IslandHasJoints(std::size_t island) const {
    return !m_islandJointStart.empty() && m_islandJointStart[island + 1] > m_islandJointStart[island];
  }
  // Joints solved exactly as one skyline block per island up to this many equality rows (a
  // chain of 40 hinges), larger islands as one sparse system (RJointSparse.h).
  static constexpr int kJointBlockRows = 256;
  // Newton rounds of the joints' end-of-step prediction after the first, at most.
  static constexpr int kJointRounds = 6;
};

}  // namespace REngine
