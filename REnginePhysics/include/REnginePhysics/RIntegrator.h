// RIntegrator: the one entry point that advances a set of bodies by a time step.
//
//   Update(bodies, dt)
//     1. bump the cache stamp      bodies move only inside Update, so any world-space form
//                                  cached with an older stamp is stale, and one with the
//                                  current stamp is reused by every pair that asks (it is
//                                  bumped again after step 3, for queries between steps)
//     2. CollisionDetection        pairs -> contacts -> FindImpulses -> accumulated impulses
//     3. UpdateObjects             apply impulses; integrate forces and motion
//     4. contact events            begin, persist, end of touching pairs (Events())
//
// Motion. Linear: kick-drift-kick with the step's constant acceleration a = F/m + g, which
// is exact for constant a (x0 + v0 t + a t^2/2 to rounding). Angular: half the torque's
// impulse, the exact torque-free flow for dt (RFreeRotation), the other half: exact when
// torque-free, second order in dt with torques, and exact again for a torque along a
// principal axis of a body spinning about it.
#pragma once

#include <REnginePhysics/RAbi.h>
#include <REngineMath/RMath.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RContactEvents.h>
#include <REnginePhysics/RJobSystem.h>
#include <REnginePhysics/RRigidBody.h>

#include <cstdint>
#include <memory>
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
  // Solver passes per step (contacts and joints), 1 to kMaxSolverIterations: past a few
  // hundred the passes change nothing a game can see, and a step must stay bounded in time.
  // Update throws RError ("solverIterations") outside that range, and the scene and state loaders
  // refuse it.
  int solverIterations = 10;
  static constexpr int kMaxSolverIterations = 1000;
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
    // pose, forces, drag or gravity scale, or wakes them; a static or kinematic body the game
    // adds, removes, refilters or moves with SetShapePose wakes the sleepers whose boxes touch
    // where it was or is; everything wakes when gravity changes or a plain vector's body count
    // changes. A kinematic body holds like static geometry; it never sleeps, and while its
    // velocities move it, it wakes only the islands it touches. Not exact: a sleeping body's residual velocity (< sleepSpeed) is
    // zeroed. A body that no static geometry holds (a drifting rock in space) sleeps only
    // when its island is exactly still, which is exact.
    bool sleeping = true;
    // Pairs whose bounding spheres (and then boxes), grown by how far the bodies can move
    // within the step, are apart skip the narrow phase. Exact. Off: every pair that the
    // filters allow goes to the narrow phase.
    bool boundsRejection = true;
    // With boundsRejection: bounding-volume trees find the pairs whose grown spheres may
    // touch without visiting every pair (O(n log n) instead of O(n^2)), in the steps where
    // that costs less than the loop (a dense pile of a thousand boxes keeps the loop). Exact:
    // the same pairs in the same order as the all-pairs loop (scene key solver.broadphase).
    bool broadPhase = true;
    // The trees every step, even where the loop costs less (tests and measurements).
    bool broadPhaseAlways = false;
    // A static body's world form (vertices, planes, bounds) is computed once and kept until
    // the game moves it, not once per step. Exact.
    bool staticForms = true;
    // A pair whose relative pose has moved less than the touching band (1e-9 of the pair's
    // size, RCollisionSolver::kTouchingTolerance) since its manifold was computed keeps that
    // manifold, moved with the bodies, instead of running the narrow phase again (the
    // resting contacts of a pile, after it settles). Not bit-identical: a point is off by at
    // most that band, as a contact within the band counts as touching.
    bool contactReuse = true;
  } shortcuts;
  // Sleeping: the speed (m/s) below which a body counts as at rest, for its centre of mass
  // and for the farthest point of its bounding sphere (|omega| times its radius) ...
  RScalar sleepSpeed = 0.01;
  // ... and how long (s) its whole island must stay below it before it sleeps.
  RScalar sleepTime = 0.5;
  // Threads the step runs on, the caller's included: 0 is what the machine has
  // (std::thread::hardware_concurrency), 1 runs everything on the caller. The results are
  // bit-identical for every value (see RJobSystem.h). Ignored while a job system of the
  // game's is set (RIntegrator::SetJobSystem). Update throws RError ("threads") for a
  // value below 0 or above kMaxThreads.
  int threads = 0;
  static constexpr int kMaxThreads = 1024;
  // Contact events (RIntegrator::Events, RContactEvents.h): begin, persist and end of every
  // touching pair, found after the motion. Off: Events() stays empty and the step skips their
  // work (a pass over the contacts: the narrow phase again at the end poses where the motion
  // leaves touching open, a shape cast for pairs the solver does not resolve), 1 to 2% of a
  // step in the reference scenes (scenes/). They only observe: the motion is the same either
  // way.
  bool contactEvents = true;
};

// Wall-clock time of each stage of the last Update, milliseconds.
struct RStepProfile {
  double collisionDetection = 0;  // pair loop and narrow phase
  double findImpulses = 0;        // contact solver (included in neither of the others)
  double updateObjects = 0;
  double contactEvents = 0;       // RIntegrator::Events' work, after the motion
  double total = 0;
};

// A body whose state stopped being finite: which, and in which step (1-based count of
// Update calls on this integrator), or whose position left the ±1e15 m the API accepts (it
// ran away). A dynamic body is put back at its last pose, at rest (velocities zero: with
// those that carried it out it would leave again at every step); a kinematic body at its last
// pose, its velocities the game's. Its pending forces and impulses are dropped, and so is the
// contact memory of its pairs, so the next step starts it afresh. It stays in the world.
struct RNonFiniteBody {
  std::size_t bodyIndex = 0;  // dense index in the step (RBodies: position, see HandleAt)
  RBodyHandle handle;         // RBodies' handle (a plain vector's: index, generation 0)
  std::string bodyName;
  std::uint64_t step = 0;
};

// A pair of bodies in contact (or about to be, within the step) found by the last Update,
// with its manifold in world space (normal from bodies[a] to bodies[b]).
struct RContact {
  // Dense indices of the two bodies in the step (a plain vector's indices, an RBodies'
  // positions), and their handles: a has the lower slot (a plain vector: a < b).
  std::uint32_t a = 0, b = 0;
  RBodyHandle handleA, handleB;
  RContactManifold manifold;
  // Normal impulse the solver applied at each manifold point this step, N s (0 when either
  // body does not respond: such contacts are reported, not resolved).
  RScalar normalImpulse[4] = {0, 0, 0, 0};
  // The step's friction impulse on B (A gets its opposite), world, N s: the manifold's
  // friction patch at the start and the end of the step and the impact's (0 when not
  // resolved). The twist about the normal (N m s) is not in it.
  RVec3 frictionImpulse_W = RVec3::Zero();
  // Both bodies respond, at least one is dynamic, and the manifold has points.
  bool resolved = false;
  // When within the step the bodies touch (s from its start; 0: touching or overlapping at
  // the start), moving with their velocities; infinity: they come within the speculative
  // margin but do not touch this step. A game reacts to contacts with a finite time (a
  // missile that does not respond is reported here, hitting, and flies on).
  RScalar timeOfImpact = 0;
};

// A contact's material, as RIntegrator::SetContactCallback shows it to the game for a new
// contact and takes it back: what the solver uses for the pair while it stays in contact.
struct RContactSettings {
  RScalar friction = 0;     // Coulomb coefficient, finite, >= 0 (given: the bodies' combined)
  RScalar restitution = 0;  // in [0, 1] (given: the bodies' combined)
  // The velocity friction drives b's surface to relative to a's at the contact, m/s, world;
  // its part in the contact plane acts (given: zero). A conveyor belt a under a crate b:
  // the belt's speed along its length.
  RVec3 relativeSurfaceVelocity_W = RVec3::Zero();
  // false: the pair is found and reported (RContact::resolved false), not resolved: bodies
  // pass through each other while the pair stays in contact (given: true; false for a body
  // meeting a one-way body otherwise than from above, RBodyDef::oneWay).
  bool enabled = true;
};

// Game code's say on a new contact: a pair in contact (within the step's speculative
// margin) that was not in the last step. `contact` holds the pair and its manifold (normal
// from a to b, world); its impulses and `resolved` are not known yet. It may change
// `settings`. Called on the stepping thread, in the
// contacts' order (the same on any thread count), before the solver; it must not change the
// bodies. A plain function pointer with a user pointer: no virtual call per pair.
using RContactCallback = void (*)(const RRigidBody& a, const RRigidBody& b, const RContact& contact,
                                  RContactSettings& settings, void* user);

// Game code's veto on a pair (a missile leaving its own launch tube): return false to skip
// it. A plain function pointer with a user pointer: no virtual call per pair.
using RPairFilter = bool (*)(const RRigidBody& a, const RRigidBody& b, void* user);

// Counts of the last step's pair loop, for profiling and for tests.
struct RPairStats {
  std::uint64_t pairs = 0;          // i < j pairs considered
  // Bounding spheres (grown by motion) apart; with the broad phase, also the pairs whose
  // boxes it found apart without testing them (rejectedBounds + rejectedBoxes is the same
  // with it or without).
  std::uint64_t rejectedBounds = 0;
  // Bounding-sphere tests made: every pair that can start a contact without the broad
  // phase, only the pairs whose boxes overlap with it (the broad phase's saving).
  std::uint64_t sphereTests = 0;
  // Whether the last sweep used the broad phase's trees: with RShortcuts::broadPhase on, the
  // sweep takes them only where they cost less than the loop (same pairs either way).
  bool broadPhase = false;
  std::uint64_t rejectedFilter = 0; // after the boxes: static-static, ignore lists, the game's filter
  std::uint64_t rejectedBoxes = 0;  // world bounding boxes (grown by motion) apart
  // Not visited at all: both asleep, or one asleep and one static (static pairs are counted
  // in rejectedFilter).
  std::uint64_t rejectedSleeping = 0;
  std::uint64_t sleepingBodies = 0;    // bodies asleep after the step
  std::uint64_t wakeRuns = 0;          // pair loops re-run this step because islands woke
  std::uint64_t narrowPhase = 0;    // CheckCollision calls (manifolds reused included)
  std::uint64_t reusedManifolds = 0;  // of those, manifolds kept from an earlier step (contactReuse)
  // Block inverses the solver needed (a resting manifold's block is solved already, and
  // needs none): kept with a manifold (contactReuse), or worked out (an eigen-solve).
  std::uint64_t reusedInverses = 0;
  std::uint64_t computedInverses = 0;
  std::uint64_t contacts = 0;       // pairs reported
  std::uint64_t contactPoints = 0;  // solver rows (points of resolved contacts)
  std::uint64_t warmStarted = 0;    // rows that found last step's impulses
};


class RWorldStep;  // the working state (private to REnginePhysics)
struct RStepBodies;

// The integrator's working state (RWorldStep, private to the library, behind a pointer so
// that none of it is in an installed header): RIntegrator holds it as a private base; save
// and load reach it through the engine's private header body/RBodyAccess.h.
struct RIntegratorCore {
  std::unique_ptr<RWorldStep> m_w;
};

class RIntegrator : private RIntegratorCore {
 public:
  RIntegrator();
  explicit RIntegrator(const RWorldSettings& settings);
  ~RIntegrator();
  // A copy is another world with the same settings, contact memory and outputs: stepping it
  // and a copy of the bodies goes on bit for bit as the original would, sleepers asleep
  // (until its first step it takes the original's bodies as its own; bodies the original
  // steps after that wake everything when the copy steps them). RWorldState.h saves a world
  // to bytes.
  RIntegrator(const RIntegrator& other);
  RIntegrator& operator=(const RIntegrator& other);
  RIntegrator(RIntegrator&&) noexcept;
  RIntegrator& operator=(RIntegrator&&) noexcept;

  // The longest step, s. Games step at 30 Hz or faster and slow simulations at a few Hz; a
  // step of seconds is a unit mistake (16 for 1/60 s, milliseconds given as seconds), and
  // at 1 s a motor's impulse in one step (its force times dt) stays within the impulses the
  // engine accepts. The scene loader and rengine-sim's --dt refuse more.
  static constexpr RScalar kMaxDt = 1;

  // Advances every enabled body by dt seconds. dt must be finite, > 0 and at most kMaxDt:
  // anything else throws RError ("dt") before anything moves (a negative dt would
  // run time backwards, zero would divide by zero). Contact memory and sleeping islands are keyed by
  // handle (see RBodies): adding, removing or disabling bodies between calls forgets nothing
  // else and wakes only what they touched.
  void Update(RBodies& bodies, RScalar dt);
  // The same for a plain vector, where a body is known by its index: when the count changes
  // contact memory is forgotten and every island wakes (so is a body found at another index).
  void Update(std::vector<RRigidBody>& bodies, RScalar dt);
  // Forgets last step's contact impulses and wakes every sleeping body: call after
  // reordering a plain vector of bodies without changing their count, so no pair inherits
  // another's warm start. (Reordering is also detected for sleeping: every body remembers
  // its index.)
  void ForgetContacts();

  const RWorldSettings& Settings() const;
  RWorldSettings& Settings();
  const RStepProfile& Profile() const;
  std::uint64_t StepCount() const;
  // World-space caches tagged with this stamp are current. Update draws one before its
  // collision detection and another after moving the bodies, so between steps this stamp
  // describes the bodies' present poses.
  std::uint64_t CacheStamp() const;
  // The first body that became non-finite, if any; stepping continues for the others.
  const std::optional<RNonFiniteBody>& NonFinite() const;
  // Every body that became non-finite in the last Update (and was put back), in index order.
  const std::vector<RNonFiniteBody>& NonFiniteInLastStep() const;

  // Contacts found by the last Update (valid until the next), in the pair sweep's order.
  const std::vector<RContact>& Contacts() const;
  // Contact events of the last Update (valid until the next; RContactEvents.h says what
  // each means), sorted by handleA, handleB, then begin, persist, end. Empty when
  // RWorldSettings::contactEvents is off.
  const std::vector<RContactEvent>& Events() const;
  // The last Update's events that name `body`, as handleA or handleB, in the order of
  // Events() (a handle whose body was removed names its end events). Update indexes the
  // events by body as it finds them, O(events + bodies), so a call is a lookup.
  RBodyContactEvents EventsOf(RBodyHandle body) const;
  // The last Update's events between a and b (either order): begin, persist or end, or a
  // begin then an end (RContactEvents.h). A binary search in Events().
  RContactEventSpan EventsBetween(RBodyHandle a, RBodyHandle b) const;
  const RPairStats& PairStats() const;
  // Asked only for pairs whose bounding boxes, grown by the step's motion, overlap.
  // Sleeping pairs are not asked: setting a filter wakes everything, and a filter whose
  // answer changes for a pair must Wake() its dynamic body. On more than one thread the
  // filter is called from several threads at once (for different pairs): it must only read,
  // and must not throw (an exception on a worker thread ends the program).
  void SetPairFilter(RPairFilter filter, void* user);
  // The game's contact callback (RContactCallback; null: none). A pair's settings are kept
  // while it stays in contact, step after step; a pair that wakes from sleep, or comes back
  // into contact, is new again. One-way bodies (RBodyDef::oneWay) are decided first: a
  // contact with one is enabled when its normal, from the one-way body to the other, is
  // within 45 degrees of up (opposite gravity; with zero gravity a one-way body is solid).
  // Update throws RError ("contact_callback.friction", ...) for settings out of their
  // ranges, before any body moves.
  void SetContactCallback(RContactCallback callback, void* user);
  // Runs the step's parallel stages on the game's job system instead of the integrator's
  // own threads (RWorldSettings::threads); null goes back to those. The job system must
  // outlive its use here; a copy of the integrator uses the same one.
  void SetJobSystem(RJobSystem* jobs);

 private:
  // The step, as the design reads: stamp, CollisionDetection, UpdateObjects; then the events.
  void Step(const RStepBodies& bodies, RScalar dt);
  // Pairs -> CheckCollision -> FindImpulses: impulses accumulated on the bodies.
  void CollisionDetection(const RStepBodies& bodies, RScalar dt);
  // Applies the accumulated impulses and integrates the motion; then sleeping.
  void UpdateObjects(const RStepBodies& bodies, RScalar dt);

  // The integrator's own threads, started at the first step that asks for more than one
  // (and again when RWorldSettings::threads changes); a copy starts its own.
  std::unique_ptr<RThreadPool> m_pool;
  RJobSystem* m_gameJobs = nullptr;
  // Points the working state at this step's job system and task count.
  void PrepareJobs();
};

// Process-wide stamp source: every Update of every integrator draws a new value, so a cache
// tagged by one world is never mistaken as current by another.
std::uint64_t NextCacheStamp();

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_INTEGRATOR(X) \
  X(RWorldSettings) \
  X(RIntegratorCore) \
  X(RStepProfile) \
  X(RContact) \
  X(RContactSettings) \
  X(RPairStats) \
  X(RIntegrator)
RENGINE_ABI_CHECK(kIntegrator, RENGINE_ABI_TYPES_INTEGRATOR)
