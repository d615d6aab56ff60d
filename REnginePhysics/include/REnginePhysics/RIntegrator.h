// RIntegrator: the one entry point that advances a set of bodies by a time step.
//
//   Update(bodies, dt)
//     1. bump the cache stamp      bodies move only inside Update, so any world-space form
//                                  cached with an older stamp is stale, and one with the
//                                  current stamp is reused by every pair that asks (it is
//                                  bumped again after step 3, for queries between steps)
//     2. CollisionDetection        pairs -> contacts -> FindImpulse -> accumulated impulses
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
};

// Wall-clock time of each stage of the last Update, milliseconds.
struct RStepProfile {
  double collisionDetection = 0;
  double updateObjects = 0;
  double total = 0;
};

// A body whose state stopped being finite: which, and in which step (1-based count of
// Update calls on this integrator). The body is left at its last finite state.
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
};

// Game code's veto on a pair (a missile leaving its own launch tube): return false to skip
// it. A plain function pointer with a user pointer: no virtual call per pair.
using RPairFilter = bool (*)(const RRigidBody& a, const RRigidBody& b, void* user);

// Counts of the last step's pair loop, for profiling and for tests.
struct RPairStats {
  std::uint64_t pairs = 0;          // i < j pairs considered
  std::uint64_t rejectedBounds = 0; // bounding spheres (grown by motion) apart
  std::uint64_t rejectedFilter = 0; // then: static-static, ignore lists, the game's filter
  std::uint64_t rejectedBoxes = 0;  // then: world bounding boxes (grown by motion) apart
  std::uint64_t narrowPhase = 0;    // CheckCollision calls
  std::uint64_t contacts = 0;       // pairs reported
};

class RIntegrator {
 public:
  RIntegrator() = default;
  explicit RIntegrator(const RWorldSettings& settings) : m_settings(settings) {}

  // Advances every body by dt seconds (dt > 0). The bodies vector must not be resized by
  // the callee; bodies may be added or removed by the game between calls.
  void Update(std::vector<RRigidBody>& bodies, RScalar dt);

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

  // Contacts found by the last Update (valid until the next), in pair order (a, then b).
  const std::vector<RContact>& Contacts() const { return m_contacts; }
  const RPairStats& PairStats() const { return m_pairStats; }
  void SetPairFilter(RPairFilter filter, void* user) { m_filter = filter, m_filterUser = user; }

 private:
  void CollisionDetection(std::vector<RRigidBody>& bodies, RScalar dt);
  void UpdateObjects(std::vector<RRigidBody>& bodies, RScalar dt);

  RWorldSettings m_settings;
  RStepProfile m_profile;
  std::uint64_t m_stepCount = 0;
  std::uint64_t m_cacheStamp = 0;
  std::optional<RNonFiniteBody> m_nonFinite;
  std::vector<RContact> m_contacts;  // capacity kept between steps: no per-step allocation
  std::vector<RScalar> m_cx, m_cy, m_cz, m_reach;  // pair sweep: centres and grown radii
  RPairStats m_pairStats;
  RPairFilter m_filter = nullptr;
  void* m_filterUser = nullptr;
};

// Process-wide stamp source: every Update of every integrator draws a new value, so a cache
// tagged by one world is never mistaken as current by another.
std::uint64_t NextCacheStamp();

}  // namespace REngine
