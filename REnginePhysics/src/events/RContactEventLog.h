// Private to REnginePhysics: the contact events (RContactEvents.h says what they mean), kept
// by the step. Before the motion it keeps every body's pose; after it, it decides which of
// the step's contacts touched within the step and at its end, and merges them with the
// pairs that touched at the end of the last step into begin, persist and end events, with
// an index of them by body. It owns the poses, the touching pairs carried from step to step,
// the per-contact scratch and the events; what it reads of the other subsystems (the
// step's contacts, the contact solver's impact rows, the pair sweep's passive flags, the
// settings, the job system) comes in as parameters. Definitions: RContactEvents.cpp. Every
// vector keeps its capacity between steps.
#pragma once

#include "state/RLoadKey.h"

#include <REnginePhysics/RContactEvents.h>
#include <REnginePhysics/RIntegrator.h>

#include "solver/RSolverTypes.h"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace REngine {

class RJobSystem;
struct RStepBodies;

class RContactEventLog {
 public:
  // What FindContactEvents reads of the step's other subsystems, this step.
  struct RStepInputs {
    bool enabled;                           // RWorldSettings::contactEvents
    const std::vector<RContact>& contacts;  // the step's contacts, as the pair sweep found them
    // The contact solver's impact rows are by block; islandImpacts (per island) says whose
    // were written this step, blockIslands gives each island's [first, last) of blocks.
    const std::vector<char>& islandImpacts;
    const std::vector<std::pair<std::uint32_t, std::uint32_t>>& blockIslands;
    // Per body (dense index): passive in the pair sweep (asleep, static, or a still
    // kinematic body, and responding): a pair of two such bodies was not looked at.
    const std::vector<char>& passive;
    RJobSystem* jobs;   // null: one thread
    std::size_t tasks;  // how many tasks a parallel stage is cut into
  };

  // Before the motion: every body's pose (when enabled, RWorldSettings::contactEvents).
  // (On the step's job system: a pass over every body, split into ranges.)
  void KeepStartPoses(const RStepBodies& bodies, bool enabled, RJobSystem* jobs, std::size_t tasks);
  // After the motion: this step's events (Events()) and the pairs touching at its end.
  // impacts: the contact solver's impact rows, by block (see RStepInputs).
  void FindContactEvents(const RStepBodies& bodies, const RStepInputs& in, const std::vector<RImpactRow>& impacts);

  // The last step's events, by handles (handleA, handleB), then in the order they happened.
  const std::vector<RContactEvent>& Events() const { return m_events; }
  // The events that name `body`, in the order of Events() (empty after a load).
  RBodyContactEvents EventsOf(RBodyHandle body) const;
  // The events of the pair (a, b), either order: a binary search in Events().
  RContactEventSpan EventsBetween(RBodyHandle a, RBodyHandle b) const;

  // A pair that touched at the end of the last step (or sleeps in contact since), with the
  // point and normal last reported (world, m; unit, A to B); a is the lower slot.
  struct RTouchingPair {
    RBodyHandle a, b;
    RVec3 point_W, normal_W;
  };
  // Save/load's (state/RStateStep.cpp, RWorldState.cpp): the touching pairs, sorted by
  // (a, b), are what carries to the next step; a load restores them and drops the last
  // step's events, which are not saved.
  const std::vector<RTouchingPair>& Touching() const { return m_touching; }
  // A rollback snapshot's (RSnapshot.h): copied into the list's capacity.
  void RestoreForSnapshot(RLoadKey, const std::vector<RTouchingPair>& touching) {
    m_touching = touching;
    m_events.clear(), m_eventsBySlot.clear(), m_eventsByBody.clear();
  }
  void RestoreForLoad(RLoadKey, std::vector<RTouchingPair> touching) {
    m_touching = std::move(touching);
    m_events.clear(), m_eventsBySlot.clear(), m_eventsByBody.clear();
  }

 private:
  struct RStartPose {
    RVec3 x_W;   // centre of mass, m
    RQuat q_WB;
  };
  std::vector<RStartPose> m_startPoses;  // per body, this step
  // Sorted by (a, b); m_touchingNext is FindContactEvents' list for the next step.
  std::vector<RTouchingPair> m_touching, m_touchingNext;
  // Per contact of this step: what it did (REventFlags) and the point and normal to report.
  struct REventContact {
    std::uint8_t flags;
    RVec3 point_W, normal_W;
  };
  std::vector<REventContact> m_eventContacts;
  std::vector<std::uint32_t> m_eventOrder;  // this step's contacts, sorted by handles
  std::vector<RContactEvent> m_events;
  // m_events by body (EventsOf): per slot, where its run of event positions starts in
  // m_eventsByBody (by generation, then in m_events' order); two per event.
  std::vector<std::uint32_t> m_eventsBySlot, m_eventsByBody, m_eventsFill;
  void IndexEventsByBody();
};

}  // namespace REngine
