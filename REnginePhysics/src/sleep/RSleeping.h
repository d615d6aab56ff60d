// Private to REnginePhysics: sleeping islands (RWorldSettings::RShortcuts::sleeping). Before
// the step it wakes every island one of whose bodies the game woke, that a moved static or
// kinematic body's box touches, or that is joined to something that moves (or all, when
// gravity, a plain vector's count or a body's place changed); during it, the islands the pair
// sweep found touched (Mark, WakeMarked); after it, it puts to sleep the islands that have
// rested long enough. It owns the islands to wake, the wake boxes, the union-find and
// per-island scratch of the islands that fall asleep, what the last step saw (the body count,
// gravity) and this integrator's identity as the bodies it stepped remember it (RWorldId).
// The bodies' own sleep state (m_sleeping, m_sleepIsland, m_restTime) is theirs, in RBodyCore.
#pragma once

#include "state/RLoadKey.h"

#include <REnginePhysics/RIntegrator.h>

#include "joints/RJointTypes.h"
#include "world/RUnionFind.h"

#include <cstdint>
#include <vector>

namespace REngine {

struct RStepBodies;

class RSleeping {
 public:
  // Before the step: wakes what the game woke or moved (see above), or everything when
  // sleeping is off; reads and clears the container's departures (bodies.wakeIslands,
  // wakeAll, wakeBoxes).
  void WakeIslands(const RStepBodies& bodies, const RWorldSettings& settings);
  // Marks a sleeping island (its id: a slot) that this step's pair sweep touched, to be woken
  // by WakeMarked (an id beyond the slot count the step started with names no island).
  void Mark(std::uint32_t island) {
    if (island < m_wakeMark.size()) m_wakeMark[island] = 1;
  }
  // Wakes the bodies of the marked islands and clears the marks.
  void WakeMarked(const RStepBodies& bodies);
  // After the motion: stamps every body with its slot and this world's id, and puts to sleep
  // the islands (bodies linked by this step's resolved contacts between two dynamic bodies,
  // and by its joints) that have rested for settings.sleepTime and that static geometry held
  // this step or that are exactly still. contacts: this step's, with their normal impulses
  // (N s); bodyFlags: per body, RPairSweep::kFlagImmovable for a static or kinematic one;
  // joints: the step's joints (joint, its index in bodies.joints; a and b, its bodies' dense
  // indices, b == bodies.size() for the world). Returns how many bodies sleep after the step.
  std::uint64_t SleepIslands(const RStepBodies& bodies, const RWorldSettings& settings,
                             const std::vector<RContact>& contacts, const std::vector<std::uint8_t>& bodyFlags,
                             const std::vector<RStepJoint>& joints);

  // The next step wakes everything (RIntegrator::ForgetContacts, SetPairFilter).
  void WakeAllNextStep() { m_wakeAll = true; }

  // This integrator's id as the bodies it steps carry it (RBodyCore::m_slotWorld): the
  // state's loader gives the bodies it restores this id.
  std::uint64_t WorldId() const { return m_worldId.value; }
  // Whether a body that carries slotWorld was last stepped by this world (or, before this
  // integrator's first step, by the one it was copied from).
  bool OwnsBody(std::uint64_t slotWorld) const { return m_worldId.Owns(slotWorld); }

  // Save/load's (src/state/): what a saved state carries of sleeping, written and restored
  // exactly. bodyCount: the bodies the last step saw (a plain vector whose count changes
  // wakes everything); wakeAll: the next step wakes everything; gravity_W: the gravity the
  // sleepers sleep under (world, m/s^2; a change wakes everything).
  struct RSaved {
    std::uint64_t bodyCount = 0;
    bool wakeAll = false;
    RVec3 gravity_W = RVec3::Zero();
  };
  RSaved Saved() const { return {m_sleepBodyCount, m_wakeAll, m_sleepGravity_W}; }
  // Restores what Saved gave; from then on the bodies carry this integrator's own id (the
  // loaded bodies were given it), not an original's.
  // A rollback snapshot's (RSnapshot.h), saved by this integrator: its identity stays.
  void RestoreForSnapshot(RLoadKey, const RSaved& saved) {
    m_sleepBodyCount = static_cast<std::size_t>(saved.bodyCount);
    m_wakeAll = saved.wakeAll;
    m_sleepGravity_W = saved.gravity_W;
  }
  void RestoreForLoad(RLoadKey, const RSaved& saved) {
    m_sleepBodyCount = static_cast<std::size_t>(saved.bodyCount);
    m_wakeAll = saved.wakeAll;
    m_sleepGravity_W = saved.gravity_W;
    m_worldId.inherited = 0;
  }

 private:
  // Islands to wake (by island id), union-find and per-island state (scratch).
  std::vector<char> m_wakeMark;
  std::vector<RVec3> m_wakeBoxes;  // WakeIslands: boxes whose sleepers wake (min, max, ...)
  RUnionFind m_sleepSets;
  std::vector<RScalar> m_sleepRest;
  std::vector<char> m_sleepSupported, m_sleepStill;
  std::size_t m_sleepBodyCount = 0;
  bool m_wakeAll = false;  // ForgetContacts, SetPairFilter
  // This integrator, as the bodies it stepped remember it (a process-wide count). A copy of
  // an integrator draws its own id, and until its first step also takes the bodies the
  // original stepped as its own: a world copied with its bodies goes on as the original
  // would, sleepers asleep, while bodies the original steps after the copy's first step wake
  // everything when the copy steps them (their island ids are another world's). A load
  // (RWorldState.cpp) gives the bodies it restores this integrator's id.
  struct RWorldId {
    std::uint64_t value = NextCacheStamp();
    std::uint64_t inherited = 0;  // the original's id until the first step; 0: none
    RWorldId() = default;
    RWorldId(const RWorldId& other) : value(NextCacheStamp()), inherited(other.Lineage()) {}
    RWorldId& operator=(const RWorldId& other) {
      value = NextCacheStamp(), inherited = other.Lineage();
      return *this;
    }
    // The id the bodies of this world carry: a copy not yet stepped has only its original's.
    std::uint64_t Lineage() const { return inherited != 0 ? inherited : value; }
    bool Owns(std::uint64_t slotWorld) const { return slotWorld == value || (inherited != 0 && slotWorld == inherited); }
  } m_worldId;
  RVec3 m_sleepGravity_W = RVec3::Zero();
};

}  // namespace REngine
