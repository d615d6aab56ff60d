// Contact events: when two bodies begin to touch, go on touching and stop touching, handed
// out after each step (RIntegrator::Events), for every pair the pair sweep looks at, bodies
// that do not respond (sensors, missiles) included. Computed in RContactEvents.cpp.
//
// What "touching" means. A pair touches when its separation is at most the narrow phase's
// touching band (RCollisionSolver::kTouchingTolerance times the sum of the two bounding
// radii: 1e-9 of the pair's size), at some moment within the step; a pair that only comes
// within the speculative margin does not. A pair touched during a step when it touched at
// its start, touches at its end, bounced within it (the impact phase applied an impulse at
// the moment of contact), or, for a pair the solver does not resolve (a body that does not
// respond), its relative motion over the step carries one through the other: a straight
// shape cast of B against A along the step's relative displacement, orientations as at the
// start (a 3 km/s missile crossing a 10 cm sensor plate inside one 1/60 s step is found).
//
// Per pair and step, at most one of:
//   begin            it did not touch at the step's start and touches at its end
//   begin, then end  it touched only within the step (a bounce, a missile through a sensor)
//   persist          it touched at the start and touches at the end
//   end              it touched at the start and does not at the end; or one of its bodies
//                    was removed or disabled since the last step (the event names its
//                    handle, now stale)
// A pair that falls asleep in contact stays in contact: no end, and no persist events while
// it sleeps (the pair sweep does not look at it); waking it gives no new begin.
//
// Order: by handleA, then handleB (RBodyHandle's operator<: slot, then generation), then
// begin, persist, end. The same for any thread count and job system.
//
// Views, so that a game does not filter the whole list itself (RIntegrator::EventsOf, one
// body's; RIntegrator::EventsBetween, one pair's): each reads the integrator's storage, is
// valid until its next Update, and allocates nothing.
#pragma once

#include <REnginePhysics/RAbi.h>
#include <REngineMath/RMath.h>
#include <REnginePhysics/RBodies.h>

#include <cstddef>
#include <cstdint>
#include <iterator>

namespace REngine {

enum class RContactEventType : std::uint8_t { kBegin, kPersist, kEnd };

// "begin", "persist", "end" (the CLI's words).
const char* ToString(RContactEventType type);

struct RContactEvent {
  RContactEventType type = RContactEventType::kBegin;
  // The two bodies; handleA has the lower slot (as RContact's). In a plain vector of bodies
  // (RIntegrator::Update's other overload) a handle is {index, 0}.
  RBodyHandle handleA, handleB;
  // Where the two touch and the normal there, from A to B (unit), world frame, m: for a
  // pair that bounced this step, where the impact phase met it (the centre of the leading
  // points at the moment of impact); for a body that does not respond crossing or entering
  // another, where the swept shapes first touch; otherwise the deepest point of the
  // manifold the pair sweep found at the start of the step (for a pair that closed a gap
  // without an impact, a slow approach, midway across that gap). An end without a contact
  // this step (a body removed, or taken beyond the margin by game code) repeats the last
  // ones reported.
  RVec3 point_W = RVec3::Zero();
  RVec3 normal_W = RVec3::UnitX();
  // The step's total normal impulse between the two (N s, >= 0): every manifold point's, at
  // the start and end of the step, and the impact's (restitution). 0 for a pair the solver
  // does not resolve (a sensor touches without pushing).
  RScalar normalImpulse = 0;
  // The magnitude of the step's total friction impulse (N s): the manifold's friction patch
  // at the start and the end of the step and the impact's, summed as vectors. The twist
  // about the normal (a torque impulse, N m s) is not in it.
  RScalar frictionImpulse = 0;
};

// The body of an event that is not `body` (the other one of its pair).
inline RBodyHandle OtherBody(const RContactEvent& event, RBodyHandle body) {
  return event.handleA == body ? event.handleB : event.handleA;
}

// A contiguous run of events (RIntegrator::EventsBetween), in the order of Events().
class RContactEventSpan {
 public:
  RContactEventSpan() = default;
  RContactEventSpan(const RContactEvent* first, const RContactEvent* last) : m_first(first), m_last(last) {}
  const RContactEvent* begin() const { return m_first; }
  const RContactEvent* end() const { return m_last; }
  std::size_t size() const { return static_cast<std::size_t>(m_last - m_first); }
  bool empty() const { return m_first == m_last; }
  const RContactEvent& operator[](std::size_t k) const { return m_first[k]; }

 private:
  const RContactEvent* m_first = nullptr;
  const RContactEvent* m_last = nullptr;
};

// The events that name one body, as handleA or handleB (RIntegrator::EventsOf), in the order
// of Events(): positions into it, read through an iterator.
class RBodyContactEvents {
 public:
  class Iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = RContactEvent;
    using difference_type = std::ptrdiff_t;
    using pointer = const RContactEvent*;
    using reference = const RContactEvent&;
    Iterator() = default;
    Iterator(const RContactEvent* events, const std::uint32_t* at) : m_events(events), m_at(at) {}
    reference operator*() const { return m_events[*m_at]; }
    pointer operator->() const { return &m_events[*m_at]; }
    Iterator& operator++() { return ++m_at, *this; }
    Iterator operator++(int) {
      Iterator before = *this;
      ++m_at;
      return before;
    }
    friend bool operator==(const Iterator& a, const Iterator& b) { return a.m_at == b.m_at; }
    friend bool operator!=(const Iterator& a, const Iterator& b) { return a.m_at != b.m_at; }

   private:
    const RContactEvent* m_events = nullptr;
    const std::uint32_t* m_at = nullptr;
  };

  RBodyContactEvents() = default;
  RBodyContactEvents(const RContactEvent* events, const std::uint32_t* first, const std::uint32_t* last)
      : m_events(events), m_first(first), m_last(last) {}
  Iterator begin() const { return {m_events, m_first}; }
  Iterator end() const { return {m_events, m_last}; }
  std::size_t size() const { return static_cast<std::size_t>(m_last - m_first); }
  bool empty() const { return m_first == m_last; }
  const RContactEvent& operator[](std::size_t k) const { return m_events[m_first[k]]; }

 private:
  const RContactEvent* m_events = nullptr;
  const std::uint32_t* m_first = nullptr;
  const std::uint32_t* m_last = nullptr;
};

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_CONTACT_EVENTS(X) \
  X(RContactEvent) \
  X(RContactEventSpan) \
  X(RBodyContactEvents)
RENGINE_ABI_CHECK(kContactEvents, RENGINE_ABI_TYPES_CONTACT_EVENTS)
