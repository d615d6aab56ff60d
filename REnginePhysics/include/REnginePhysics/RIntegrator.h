// RIntegrator: the one entry point that advances a set of bodies by a time step.
//
//   Update(bodies, dt)
//     1. bump the cache stamp      bodies move only inside Update, so any world-space form
//                                  cached with an older stamp is stale, and one with the
//                                  current stamp is reused by every pair that asks (it is
//                                  bumped again after step 3, for queries between steps)
//     2. CollisionDetection        pairs -> contacts -> FindImpulses -> accumulated impulses
//     3. UpdateObjects             apply impulses; integrate forces and motion
//
// Motion. Linear: kick-drift-kick with the step's constant acceleration a = F/m + g, which
// is exact for constant a (x0 + v0 t + a t^2/2 to rounding). Angular: half the torque's
// impulse, the exact torque-free flow for dt (RFreeRotation), the other half: exact when
// torque-free, second order in dt with torques, and exact again for a torque along a
// principal axis of a body spinning about it.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RRigidBody.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace REngine {

// How two bodies' coefficients combine into a pair's (the scene's *_combine fields).
enum class RCombineMode : std::uint8_t { kMin, kMax, kProduct, kAverage, kGeometric };
RScalar Combine(RCombineMode mode, RScalar a, RScalar b);

struct RWorldSettings {
  RVec3 gravity_W = RVec3::Zero();  // m/s^2, world frame (zero: space)
  RCombineMode restitutionCombine = RCombineMode::kMin;
  RCombineMode frictionCombine = RCombineMode::kGeometric;
  int solverIterations = 10;        // contact solver passes per step
  // Approach speed (m/s) below which restitution is ignored: resting and slowly settling
  // bodies do not bounce. Above it a collision bounces with its restitution: exactly the
  // closed-form outcome for a single point of contact (spheres, a corner, a flat face hitting
  // flat), through one row at the centre of the manifold's leading points otherwise.
  RScalar restitutionThreshold = 0.5;
  // Penetration (m) left alone by position correction: removing the last fraction of a
  // millimetre every step would make stacked bodies jitter.
  RScalar penetrationSlop = 5e-4;
  // Fraction of the penetration beyond the slop removed per step by position correction
  // (split impulses: positions move, velocities and energy do not change).
  RScalar positionCorrection = 0.5;
  // Most a contact's position correction may move its bodies apart in one step, m: a body
  // found deep inside another (spawned there, or a bad shape) comes out over several steps
  // instead of being thrown out in one (Box2D caps it at 0.2 m the same way).
  RScalar maxPositionCorrection = 0.2;

  // Work the engine skips when a scene does not need it. Each switch can be turned off to
  // measure what it buys and what it costs (rengine-bench --shortcuts); all are on by default.
  struct RShortcuts {
    // Islands of bodies that rest on static geometry, every body slower than sleepSpeed for
    // sleepTime, go to sleep: they are neither moved nor checked against each other or the
    // static geometry until an awake body touches them, the game changes their velocity,
    // pose or forces, or wakes them; everything wakes when gravity changes, the body count
    // changes or the game moves a static body. Not exact: a sleeping body's residual velocity (< sleepSpeed) is
    // zeroed. A body that no static geometry holds (a drifting rock in space) sleeps only
    // when its island is exactly still, which is exact.
    bool sleeping = true;
    // Pairs whose bounding spheres (and then boxes), grown by how far the bodies can move
    // within the step, are apart skip the narrow phase. Exact. Off: every pair that the
    // filters allow goes to the narrow phase.
    bool boundsRejection = true;
    // A static body's world form (vertices, planes, bounds) is computed once and kept until
    // the game moves it, not once per step. Exact.
    bool staticForms = true;
  } shortcuts;
  // Sleeping: the speed (m/s) below which a body counts as at rest, for its centre of mass
  // and for the farthest point of its bounding sphere (|omega| times its radius) ...
  RScalar sleepSpeed = 0.01;
  // ... and how long (s) its whole island must stay below it before it sleeps.
  RScalar sleepTime = 0.5;
};

// Wall-clock time of each stage of the last Update, milliseconds.
struct RStepProfile {
  double collisionDetection = 0;  // pair loop and narrow phase
  double findImpulses = 0;        // contact solver (included in neither of the others)
  double updateObjects = 0;
  double total = 0;
};

// A body whose state stopped being finite: which, and in which step (1-based count of
// Update calls on this integrator). The body is left at its last finite state, its pending
// forces and impulses are dropped, and so is the contact memory of its pairs, so the next
// step starts it afresh.
struct RNonFiniteBody {
  std::size_t bodyIndex = 0;
  std::string bodyName;
  std::uint64_t step = 0;
};

// A pair of bodies in contact (or about to be, within the step) found by the last Update,
// with its manifold in world space (normal from bodies[a] to bodies[b]).
struct RContact {
  std::uint32_t a = 0, b = 0;  // indices into the bodies vector, a < b
  RContactManifold manifold;
  // Normal impulse the solver applied at each manifold point this step, N s (0 when either
  // body does not respond: such contacts are reported, not resolved).
  RScalar normalImpulse[4] = {0, 0, 0, 0};
  // Both bodies respond, at least one is dynamic, and the manifold has points.
  bool resolved = false;
  // When within the step the bodies touch (s from its start; 0: touching or overlapping at
  // the start), moving with their velocities; infinity: they come within the speculative
  // margin but do not touch this step. A game reacts to contacts with a finite time (a
  // missile that does not respond is reported here, hitting, and flies on).
  RScalar timeOfImpact = 0;
};

// Game code's veto on a pair (a missile leaving its own launch tube): return false to skip
// it. A plain function pointer with a user pointer: no virtual call per pair.
using RPairFilter = bool (*)(const RRigidBody& a, const RRigidBody& b, void* user);

// Counts of the last step's pair loop, for profiling and for tests.
struct RPairStats {
  std::uint64_t pairs = 0;          // i < j pairs considered
  std::uint64_t rejectedBounds = 0; // bounding spheres (grown by motion) apart
  std::uint64_t rejectedFilter = 0; // static-static; then: ignore lists, the game's filter
  std::uint64_t rejectedBoxes = 0;  // then: world bounding boxes (grown by motion) apart
  // Not visited at all: both asleep, or one asleep and one static (static pairs are counted
  // in rejectedFilter).
  std::uint64_t rejectedSleeping = 0;
  std::uint64_t sleepingBodies = 0;    // bodies asleep after the step
  std::uint64_t wakeRuns = 0;          // pair loops re-run this step because islands woke
  std::uint64_t narrowPhase = 0;    // CheckCollision calls
  std::uint64_t contacts = 0;       // pairs reported
  std::uint64_t contactPoints = 0;  // solver rows (points of resolved contacts)
  std::uint64_t warmStarted = 0;    // rows that found last step's impulses
};

std::uint64_t NextCacheStamp();

class RIntegrator {
 public:
  RIntegrator() = default;
  explicit RIntegrator(const RWorldSettings& settings) : m_settings(settings) {}

  // Advances every body by dt seconds. dt must be finite and > 0: anything else throws
  // std::invalid_argument before anything moves (a negative dt would run time backwards,
  // zero would divide by zero). Bodies may be added or removed by the game
  // between calls; contact memory (warm starts) is keyed by index and forgotten when the
  // count changes.
  void Update(std::vector<RRigidBody>& bodies, RScalar dt);
  // Forgets last step's contact impulses and wakes every sleeping body: call after
  // reordering bodies without changing their count, so no pair inherits another's warm
  // start. (Reordering is also detected for sleeping: every body remembers its index.)
  void ForgetContacts() { m_warm.clear(), m_wakeAll = true; }

  const RWorldSettings& Settings() const { return m_settings; }
  RWorldSettings& Settings() { return m_settings; }
  const RStepProfile& Profile() const { return m_profile; }
  std::uint64_t StepCount() const { return m_stepCount; }
  // World-space caches tagged with this stamp are current. Update draws one before its
  // collision detection and another after moving the bodies, so between steps this stamp
  // describes the bodies' present poses.
  std::uint64_t CacheStamp() const { return m_cacheStamp; }
  // The first body that became non-finite, if any; stepping continues for the others.
  const std::optional<RNonFiniteBody>& NonFinite() const { return m_nonFinite; }
  // Every body that became non-finite in the last Update (and was put back), in index order.
  const std::vector<RNonFiniteBody>& NonFiniteInLastStep() const { return m_nonFiniteLast; }

  // Contacts found by the last Update (valid until the next), in pair order (a, then b).
  const std::vector<RContact>& Contacts() const { return m_contacts; }
  const RPairStats& PairStats() const { return m_pairStats; }
  // Sleeping pairs are not asked: setting a filter wakes everything, and a filter whose
  // answer changes for a pair must Wake() its dynamic body.
  void SetPairFilter(RPairFilter filter, void* user) {
    m_filter = filter, m_filterUser = user, m_wakeAll = true;
  }

 private:
  void CollisionDetection(std::vector<RRigidBody>& bodies, RScalar dt);
  // One sweep over the pairs, filling m_contacts. Returns true when it found a sleeping
  // island touched (marked in m_wakeMark): the islands are woken and the sweep runs again.
  bool DetectPairs(std::vector<RRigidBody>& bodies, RScalar dt);
  // Sleeping (RWorldSettings::RShortcuts::sleeping): before the step, wakes every island
  // one of whose bodies the game woke (or all, when the body count or gravity changed);
  // after it, puts to sleep the islands that have rested long enough.
  void WakeIslands(std::vector<RRigidBody>& bodies);
  void WakeMarked(std::vector<RRigidBody>& bodies);
  void SleepIslands(std::vector<RRigidBody>& bodies);
  // Solves the contacts found this step for impulses and accumulates them on the bodies;
  // called from CollisionDetection. Sequential impulses, warm-started, with each manifold's
  // normal rows solved as one block and an impacting manifold bouncing through one row.
  void FindImpulses(std::vector<RRigidBody>& bodies, RScalar dt);
  void UpdateObjects(std::vector<RRigidBody>& bodies, RScalar dt);

  // One direction of a contact point's constraint, with everything the solver's inner
  // loop needs precomputed (Catto's formulation): relative velocity along d is
  // d.(vB - vA) + rBxd.wB - rAxd.wA, and an impulse lambda d changes wA by -lambda iA and
  // wB by lambda iB.
  struct RDirection {
    RVec3 d;                   // unit direction, world
    RVec3 rAxd, rBxd;          // lever arms crossed with d, m
    RVec3 iA, iB;              // inverse inertia times the lever arms, 1/(kg m)
    RScalar k;                 // inverse effective mass along d, 1/kg
  };
  // One contact point's normal constraint, built once per step (solver scratch). Friction
  // acts per manifold (RBlock).
  struct RContactRow {
    std::uint32_t a, b;        // body indices
    std::uint32_t contact;     // index into m_contacts
    std::uint32_t block;       // index into m_blocks
    int point;                 // index into its manifold
    RDirection n;              // the normal, A to B
    RVec3 rA, rB;              // contact point from each centre of mass, world, m
    RScalar lever;             // distance from the manifold's centroid, m
    RScalar gap;               // separation at the start of the step, m
    RScalar deferN;            // normal velocity the impacts deferred to the step's end, m/s
    RScalar target;            // normal relative velocity to reach, m/s
    RScalar pseudoTarget;      // normal pseudo-velocity for position correction, m/s
    RScalar endTarget;         // at the end of the step: 0, or -inf when not in contact
    // Accumulated normal impulses, N s: at the start of the step, of position correction,
    // at the end of the step.
    RScalar lambdaN, lambdaP, lambdaE;
  };
  // What a solve works on: the velocities with the impulses at the start of the step, the
  // pseudo-velocities of position correction, or the velocities at the end of the step.
  enum class RPhase : std::uint8_t { kVelocity, kPosition, kEnd };
  static RScalar& Lambda(RContactRow& r, RPhase phase) {
    return phase == RPhase::kVelocity ? r.lambdaN : phase == RPhase::kPosition ? r.lambdaP : r.lambdaE;
  }
  static RScalar Target(const RContactRow& r, RPhase phase) {
    return phase == RPhase::kVelocity ? r.target : phase == RPhase::kPosition ? r.pseudoTarget : r.endTarget;
  }
  // A manifold's impact constraint: one point at the centre of its leading points, where
  // restitution acts (solver scratch, built once per step for every resolved contact).
  struct RImpactRow {
    std::uint32_t a, b;        // body indices
    std::uint32_t contact;     // index into m_contacts
    int point;                 // the manifold's deepest point, where the impulse is reported
    RDirection dir[3];         // normal (A to B) and two tangents
    RVec3 rA, rB;              // the point from each centre of mass, world, m
    RScalar gap;               // the leading points' separation, m (negative: overlap)
    RScalar restitution;       // combined coefficient
    RScalar friction;          // combined Coulomb coefficient
    RScalar lambdaN, lambdaT1, lambdaT2;  // accumulated impulses, N s
    // The impulse on B (world, N s) and its moments about each centre of mass, N m s: the
    // lever arms depend on when within the step each application happened.
    RVec3 impulse, angularA, angularB;
    bool miss;                 // found, along the motion, not to meet within the step
  };
  // Working state of a body during the solve: velocities that include every pending change.
  struct RSolverBody {
    RVec3 v, w;                // linear and angular velocity, world
    RVec3 vp, wp;              // pseudo-velocities (position correction), world
    RVec3 vMid;                // the velocity it moves with, kept for the end of the step
    // Impacts within the step (SolveImpacts): displacement travelled up to time tau of the
    // step, and the velocity change deferred to the step's end.
    RVec3 moved;
    RScalar tau;
    RVec3 deferV;
    RVec3 vImpacts;            // its velocity after the impact phase
    RVec3 contactDeltaV;      // the contact phase's velocity change after that, m/s
    RMat3 invI;                // inverse inertia, world, 1/(kg m^2)
    RScalar invM;              // 1/kg
  };
  // Warm-start memory: last step's impulses by (body a, body b, feature id).
  struct RWarmStart {
    std::uint64_t pair;        // (body a, body b)
    std::uint32_t feature;
    RVec3 point_A;             // contact point in body a's frame, m
    RScalar lambdaN, lambdaE;  // at the start and at the end of the step, N s
    // Its manifold's friction impulse (world, N s) and twist (N m s), start and end.
    RVec3 tangentImpulse[2];
    RScalar twistImpulse[2];
  };

  RWorldSettings m_settings;
  RStepProfile m_profile;
  std::uint64_t m_stepCount = 0;
  std::uint64_t m_cacheStamp = 0;
  std::optional<RNonFiniteBody> m_nonFinite;
  std::vector<RNonFiniteBody> m_nonFiniteLast;
  std::vector<RContact> m_contacts;  // capacity kept between steps: no per-step allocation
  std::vector<RScalar> m_cx, m_cy, m_cz, m_reach;  // pair sweep: centres and grown radii
  std::vector<std::uint32_t> m_active;  // pair sweep: bodies neither asleep nor static
  std::vector<RScalar> m_near;  // pair sweep: one body's candidates, lim^2 - d^2 (m^2)
  std::vector<std::uint32_t> m_candidates;  // pair sweep: those with lim^2 - d^2 >= 0
  std::vector<RVec3> m_moveV;    // velocity each body moves with this step, world, m/s
  std::vector<RScalar> m_moveW;  // its angular speed this step, rad/s
  std::vector<RContactRow> m_rows;
  std::vector<RImpactRow> m_impacts;
  std::vector<RSolverBody> m_solverBodies;
  // A manifold: its rows, the minimum-norm inverse of their normal block (up to 4 x 4), and
  // its friction patch at the centroid of its points.
  struct RBlock {
    std::uint32_t first;
    int count;
    bool useBlock;
    Eigen::Matrix<RScalar, 4, 4> pinv;
    RDirection t[2];           // tangents at the centroid
    RVec3 rA, rB;              // the centroid from each centre of mass, world, m
    RVec3 normal;              // world, A to B
    RVec3 twistIA, twistIB;    // inverse inertias times the normal, 1/(kg m^2)
    RScalar kTwist;            // inverse effective inertia about the normal, 1/(kg m^2)
    RScalar friction;          // combined Coulomb coefficient
    // Tangential impulses (N s) and twist about the normal (N m s), at the start [0] and
    // at the end [1] of the step.
    RScalar lambdaT1[2], lambdaT2[2];
    RScalar lambdaTwist[2];
  };
  std::vector<RBlock> m_blocks;
  void SolveNormalBlock(const RBlock& blk, RContactRow* rows, RPhase phase);
  void SolveImpacts(const std::vector<RRigidBody>& bodies, RScalar dt);
  template <class Advance>
  bool ImpactGeometry(const RRigidBody& A, const RRigidBody& B, RSolverBody& sa, RSolverBody& sb,
                      const Advance& advance, RScalar& t, RScalar dt, RVec3& rA, RVec3& rB,
                      RDirection* dir) const;
  void SolvePatch(RBlock& blk, bool clampOnly, RPhase phase);
  void WarmStart(RPhase phase);
  void SolveEndOfStep(const std::vector<RRigidBody>& bodies, RScalar dt);
  void ApplyPatch(const RBlock& blk, RScalar d1, RScalar d2, RScalar dTwist);
  void BuildIslands(const std::vector<RRigidBody>& bodies);
  void SolveIslands(RPhase phase);
  bool SolveIslandDirect(RPhase phase);
  void AssembleIslandMatrix();
  // Islands up to this many rows get their normal impulses solved directly (see
  // SolveIslands): 128 rows, 32 boxes resting face on face, cost about 0.1 ms.
  static constexpr int kDirectRows = 128;
  std::vector<std::uint32_t> m_islandParent;                        // union-find over bodies
  std::vector<std::pair<std::uint32_t, std::uint32_t>> m_islandRows;  // (island, row)
  std::vector<std::uint32_t> m_islandIndex;                         // rows of one island
  std::vector<std::pair<std::size_t, std::size_t>> m_islands;  // solved directly: [first, last) of m_islandRows
  std::vector<RScalar> m_islandK, m_islandL, m_islandB, m_islandX, m_islandInvDiag, m_islandR;  // scratch
  std::vector<int> m_islandMap, m_islandFirst, m_islandLo, m_islandHi;
  std::vector<std::pair<int, int>> m_islandRuns;  // one island's manifolds: [first, last)
  bool m_islandKReady = false;
  std::vector<char> m_islandActive;
  std::vector<RWarmStart> m_warm, m_warmNext;  // sorted by pair, then feature
  std::size_t m_warmBodyCount = 0;
  // Keeps the warm starts of pairs that sleep (both bodies asleep, or one asleep and one
  // static): they are not solved while asleep, and start warm when woken.
  void KeepSleepingWarmStarts(const std::vector<RRigidBody>& bodies);
  // Sleeping: islands to wake (by island id), union-find and per-island state (scratch).
  std::vector<char> m_wakeMark;
  std::vector<std::uint32_t> m_sleepParent;
  std::vector<RScalar> m_sleepRest;
  std::vector<char> m_sleepSupported, m_sleepStill;
  std::size_t m_sleepBodyCount = 0;
  bool m_wakeAll = false;  // ForgetContacts, SetPairFilter
  // This integrator, as the bodies it stepped remember it (a process-wide count). A copy of
  // an integrator is another world: it draws its own id.
  struct RWorldId {
    std::uint64_t value = NextCacheStamp();
    RWorldId() = default;
    RWorldId(const RWorldId&) : value(NextCacheStamp()) {}
    RWorldId& operator=(const RWorldId&) {
      value = NextCacheStamp();
      return *this;
    }
  } m_worldId;
  RVec3 m_sleepGravity_W = RVec3::Zero();
  RPairStats m_pairStats;
  RPairFilter m_filter = nullptr;
  void* m_filterUser = nullptr;
};

// Process-wide stamp source: every Update of every integrator draws a new value, so a cache
// tagged by one world is never mistaken as current by another.
std::uint64_t NextCacheStamp();

}  // namespace REngine
