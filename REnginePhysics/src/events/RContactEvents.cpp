// Contact events (RContactEventLog.h; RContactEvents.h says what they mean): after the
// motion, each of the step's contacts is classified (did it touch at the start, within the
// step, at the end), then merged with the pairs that touched at the end of the last step,
// both in handle order, into begin, persist and end events.
#include "events/RContactEventLog.h"

#include "world/RStepBodies.h"

#include "collision/RGjkEpa.h"

#include <REnginePhysics/RJobSystem.h>
#include <REnginePhysics/RQueries.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

namespace REngine {

const char* ToString(RContactEventType type) {
  switch (type) {
    case RContactEventType::kBegin: return "begin";
    case RContactEventType::kPersist: return "persist";
    case RContactEventType::kEnd: return "end";
  }
  return "?";
}

namespace {

// What a contact did this step (REventContact::flags).
enum : std::uint8_t {
  kImpact = 1,         // the impact phase pushed: the pair met at the moment of its impact
  kTouchedDuring = 2,  // touched at some moment of the step (the start and end included)
  kTouchingEnd = 4,    // touches at the end of the step
};

bool PairBefore(RBodyHandle a0, RBodyHandle b0, RBodyHandle a1, RBodyHandle b1) {
  return a0 < a1 || (a0 == a1 && b0 < b1);
}

// The dense index of a body stepped this step, or npos: removed, disabled or beyond a plain
// vector's count.
constexpr std::size_t kGone = std::numeric_limits<std::size_t>::max();
std::size_t DenseOf(const RStepBodies& bodies, RBodyHandle h) {
  if (h.index >= bodies.slotCount) return kGone;
  const std::uint32_t d = bodies.denseOfSlot[h.index];
  return d < bodies.count && bodies.handles[d] == h ? d : kGone;
}

}  // namespace

// The poses the contacts' manifolds were computed at: after the motion they say how far
// each pair moved (whether its end needs the narrow phase again) and along which path (the
// shape cast of a body that does not respond). Copied for every body: 56 bytes each.
void RContactEventLog::KeepStartPoses(const RStepBodies& bodies, bool enabled, RJobSystem* jobs, std::size_t tasks) {
  if (!enabled) return;
  m_startPoses.resize(bodies.size());
  ParallelRanges(jobs, bodies.size(), tasks, 256, [&](std::size_t i0, std::size_t i1, std::size_t) {
    for (std::size_t i = i0; i < i1; ++i) {
      m_startPoses[i].x_W = bodies[i].m_x_W;
      m_startPoses[i].q_WB = bodies[i].m_q_WB;
    }
  });
}

void RContactEventLog::FindContactEvents(const RStepBodies& bodies, const RStepInputs& in,
                                         const std::vector<RImpactRow>& impacts) {
  const std::vector<RContact>& contacts = in.contacts;
  m_events.clear();
  m_touchingNext.clear();
  if (!in.enabled) {
    m_touching.clear();  // turned on again, it starts afresh: every touching pair begins
    IndexEventsByBody();
    return;
  }
  const std::size_t count = contacts.size();
  m_eventContacts.resize(count);
  for (REventContact& e : m_eventContacts) e.flags = 0;
  // An impact row pushes only once ImpactGeometry has brought its bodies to touching (or to
  // within the slop, where the solver treats them as touching) at its moment in the step;
  // where and along which normal is the pair's point of touch.
  // (Only islands with impact rows this step wrote theirs: SolveIsland.)
  for (std::size_t isl = 0; isl < in.islandImpacts.size(); ++isl) {
    if (!in.islandImpacts[isl]) continue;
    for (std::uint32_t k = in.blockIslands[isl].first; k < in.blockIslands[isl].second; ++k) {
      const RImpactRow& r = impacts[k];
      if (!(r.lambdaN > 0)) continue;
      REventContact& e = m_eventContacts[r.contact];
      e.flags |= kImpact, e.point_W = r.point_W, e.normal_W = r.normal_W;
    }
  }

  // Each contact alone (tasks over contacts, each writing its own entry).
  ParallelRanges(in.jobs, count, in.tasks, 64, [&](std::size_t c0, std::size_t c1, std::size_t) {
    for (std::size_t ci = c0; ci < c1; ++ci) {
      const RContact& c = contacts[ci];
      REventContact& e = m_eventContacts[ci];
      const RBodyCore& A = bodies[c.a];
      const RBodyCore& B = bodies[c.b];
      const RContactManifold& m = c.manifold;
      if (e.flags & kImpact) {
        // Where the impact phase found them touching (above).
      } else if (m.pointCount > 0) {
        int deepest = 0;
        for (int k = 1; k < m.pointCount; ++k) {
          if (m.points[k].separation < m.points[deepest].separation) deepest = k;
        }
        e.point_W = m.points[deepest].position, e.normal_W = m.normal;
      } else {
        e.point_W = RScalar(0.5) * (m.query.witnessA + m.query.witnessB), e.normal_W = m.query.normal;
      }
      const RScalar radiusB = B.m_boundingRadius;
      const RScalar band = RCollisionSolver::kTouchingTolerance * (A.m_boundingRadius + radiusB);
      // The signed distance where the manifold was computed (a manifold kept from an earlier
      // step, RShortcuts::contactReuse, was computed within the band of the start).
      const RScalar s0 = m.query.separation;
      const bool start = c.timeOfImpact == 0 || s0 <= band;
      // At the end: the separation changes by at most how far any point of B moved in A's
      // frame (|dt| + |dR|_F r_B), so a pair that moved less than its distance from the band
      // is decided without the narrow phase (a resting pile: every contact).
      const RStartPose& pa = m_startPoses[c.a];
      const RStartPose& pb = m_startPoses[c.b];
      const RQuat q_AW0 = pa.q_WB.conjugate();
      RRelativePose X0;
      X0.R_AB = (q_AW0 * pb.q_WB).toRotationMatrix();
      X0.t_AB = q_AW0 * (pb.x_W - pa.x_W);
      const RRelativePose X1 = RelativePose(Body(A), Body(B));
      const RScalar moved = (X1.t_AB - X0.t_AB).norm() + (X1.R_AB - X0.R_AB).norm() * radiusB;
      const RConvexShape shapeA = ShapeOf(Body(A)), shapeB = ShapeOf(Body(B));
      bool end = false;
      if (s0 + moved <= band) {
        end = true;
      } else if (!(s0 - moved > band)) {
        // The gap along the start's normal (kept in A's frame) at the end, from the two
        // supports: the gap along any direction bounds the distance from below, so a pair
        // apart along it by more than the band is apart (a speculative contact of bodies
        // that did not meet) without the narrow phase.
        const RVec3 n_A = q_AW0 * m.query.normal;
        // (A mesh has no support mapping worth its cost: the intersection test decides.)
        RPairSupport support(shapeA, shapeB, X1);
        const RScalar gap = shapeA.mesh || shapeB.mesh
                                ? -std::numeric_limits<RScalar>::infinity()
                                : n_A.dot(support.SupportB(-n_A)) - shapeB.radius - n_A.dot(support.SupportA(n_A)) -
                                      shapeA.radius;
        end = !(gap > band) && RCollisionSolver::Intersect(shapeA, shapeB, X1);
      }
      bool during = start || end || (e.flags & kImpact) != 0;
      // A pair the solver leaves alone (a body that does not respond) moves through: B swept
      // against A along the step's relative displacement, orientations as at the start,
      // decides whether it touched, and where it first did. Not the time of impact: its
      // linear prediction at one point (spin included) can miss a body that translates into
      // another. A pair moving apart costs one distance query (ShapeCastShape stops there).
      if (!c.resolved && !start) {
        const RVec3 movedA_W = A.m_x_W - pa.x_W;
        const RVec3 D_A = q_AW0 * (B.m_x_W - pb.x_W - movedA_W);
        RShapeCastResult cast;
        if (ShapeCastShape(shapeA, shapeB, X0, D_A, 1, cast) && cast.converged) {
          during = true;
          e.point_W = pa.q_WB * cast.point + pa.x_W + movedA_W * cast.fraction;
          e.normal_W = pa.q_WB * cast.normal;
        }
      }
      e.flags |= (during ? kTouchedDuring : 0) | (end ? kTouchingEnd : 0);
    }
  });

  // This step's contacts in handle order: already so while storage order follows the
  // slots (no removal has moved a body), else sorted (in place, capacity kept).
  m_eventOrder.resize(count);
  std::iota(m_eventOrder.begin(), m_eventOrder.end(), std::uint32_t(0));
  // (A compound's child pairs are contacts of one pair of bodies: kept in their order.)
  const auto contactBefore = [&contacts](std::uint32_t x, std::uint32_t y) {
    const RContact& cx = contacts[x];
    const RContact& cy = contacts[y];
    if (PairBefore(cx.handleA, cx.handleB, cy.handleA, cy.handleB)) return true;
    return cx.handleA == cy.handleA && cx.handleB == cy.handleB && x < y;
  };
  if (!std::is_sorted(m_eventOrder.begin(), m_eventOrder.end(), contactBefore)) {
    std::sort(m_eventOrder.begin(), m_eventOrder.end(), contactBefore);
  }

  const auto emit = [this](RContactEventType type, RBodyHandle a, RBodyHandle b, const RVec3& point_W,
                           const RVec3& normal_W, RScalar normalImpulse, RScalar frictionImpulse) {
    RContactEvent ev;
    ev.type = type, ev.handleA = a, ev.handleB = b;
    ev.point_W = point_W, ev.normal_W = normal_W;
    ev.normalImpulse = normalImpulse, ev.frictionImpulse = frictionImpulse;
    m_events.push_back(ev);
  };
  // A pair that touched at the end of the last step and has no contact now: a body left
  // (removed, disabled), the pair sleeps (both bodies passive in the sweep: not looked at,
  // still in contact), or it came apart beyond the margin in one go (game code moved it).
  const auto lone = [&](const RTouchingPair& p) {
    const std::size_t ia = DenseOf(bodies, p.a), ib = DenseOf(bodies, p.b);
    if (ia != kGone && ib != kGone && in.passive[ia] && in.passive[ib]) {
      m_touchingNext.push_back(p);
    } else {
      emit(RContactEventType::kEnd, p.a, p.b, p.point_W, p.normal_W, 0, 0);
    }
  };
  // The merge of two lists in handle order gives the events in that order.
  std::size_t p = 0;
  for (std::size_t k = 0; k < count;) {
    const std::uint32_t ci = m_eventOrder[k];
    const RContact& c = contacts[ci];
    REventContact e = m_eventContacts[ci];
    RScalar normalImpulse = c.normalImpulse[0] + c.normalImpulse[1] + c.normalImpulse[2] + c.normalImpulse[3];
    RVec3 friction = c.frictionImpulse_W;
    // A compound's child pairs: one pair of bodies, one event. It touches when any of them
    // does, at the first one's point that touched; the impulses add.
    for (++k; k < count && contacts[m_eventOrder[k]].handleA == c.handleA &&
              contacts[m_eventOrder[k]].handleB == c.handleB; ++k) {
      const RContact& c2 = contacts[m_eventOrder[k]];
      const REventContact& e2 = m_eventContacts[m_eventOrder[k]];
      constexpr std::uint8_t kTouches = kTouchedDuring | kTouchingEnd;
      if (!(e.flags & kTouches) && (e2.flags & kTouches)) e.point_W = e2.point_W, e.normal_W = e2.normal_W;
      e.flags |= e2.flags;
      normalImpulse += c2.normalImpulse[0] + c2.normalImpulse[1] + c2.normalImpulse[2] + c2.normalImpulse[3];
      friction += c2.frictionImpulse_W;
    }
    while (p < m_touching.size() && PairBefore(m_touching[p].a, m_touching[p].b, c.handleA, c.handleB)) lone(m_touching[p++]);
    const bool before = p < m_touching.size() && m_touching[p].a == c.handleA && m_touching[p].b == c.handleB;
    p += before;
    const bool after = (e.flags & kTouchingEnd) != 0;
    if (!before && !(e.flags & kTouchedDuring)) continue;
    const RScalar frictionImpulse = friction.norm();
    const auto report = [&](RContactEventType type) {
      emit(type, c.handleA, c.handleB, e.point_W, e.normal_W, normalImpulse, frictionImpulse);
    };
    if (before) {
      report(after ? RContactEventType::kPersist : RContactEventType::kEnd);
    } else {
      report(RContactEventType::kBegin);
      if (!after) report(RContactEventType::kEnd);
    }
    if (after) m_touchingNext.push_back({c.handleA, c.handleB, e.point_W, e.normal_W});
  }
  while (p < m_touching.size()) lone(m_touching[p++]);
  std::swap(m_touching, m_touchingNext);
  IndexEventsByBody();
}

// A counting sort of the events' two sides by slot, O(events + slots): a stable pass keeps
// each slot's run in m_events' order.
void RContactEventLog::IndexEventsByBody() {
  m_eventsBySlot.clear(), m_eventsByBody.clear();
  if (m_events.empty()) return;
  std::uint32_t slots = 0;
  for (const RContactEvent& e : m_events) slots = std::max({slots, e.handleA.index + 1, e.handleB.index + 1});
  m_eventsBySlot.assign(std::size_t(slots) + 1, 0);
  for (const RContactEvent& e : m_events) ++m_eventsBySlot[e.handleA.index + 1], ++m_eventsBySlot[e.handleB.index + 1];
  std::partial_sum(m_eventsBySlot.begin(), m_eventsBySlot.end(), m_eventsBySlot.begin());
  m_eventsFill.assign(m_eventsBySlot.begin(), m_eventsBySlot.end() - 1);
  m_eventsByBody.resize(2 * m_events.size());
  for (std::uint32_t k = 0; k < m_events.size(); ++k) {
    m_eventsByBody[m_eventsFill[m_events[k].handleA.index]++] = k;
    m_eventsByBody[m_eventsFill[m_events[k].handleB.index]++] = k;
  }
  // A slot that named two bodies in one step (the end of a removed one, the begin of the one
  // added in its place): its run by generation, each body's events together.
  for (std::uint32_t s = 0; s < slots; ++s) {
    const auto first = m_eventsByBody.begin() + m_eventsBySlot[s], last = m_eventsByBody.begin() + m_eventsBySlot[s + 1];
    const auto generation = [&](std::uint32_t k) {
      return m_events[k].handleA.index == s ? m_events[k].handleA.generation : m_events[k].handleB.generation;
    };
    if (last - first > 1 && !std::all_of(first, last, [&](std::uint32_t k) { return generation(k) == generation(*first); })) {
      // An insertion sort: stable, and it allocates nothing (std::stable_sort takes a
      // temporary buffer from the heap, in the step); a slot's run is a few events.
      for (auto i = first + 1; i < last; ++i) {
        const std::uint32_t k = *i;
        auto j = i;
        for (; j > first && generation(k) < generation(*(j - 1)); --j) *j = *(j - 1);
        *j = k;
      }
    }
  }
}

RBodyContactEvents RContactEventLog::EventsOf(RBodyHandle body) const {
  // (Empty when the index does not describe m_events: a load cleared them.)
  if (body.index + std::size_t(1) >= m_eventsBySlot.size() || m_eventsByBody.size() != 2 * m_events.size()) {
    return {};
  }
  const std::uint32_t* first = m_eventsByBody.data() + m_eventsBySlot[body.index];
  const std::uint32_t* last = m_eventsByBody.data() + m_eventsBySlot[body.index + 1];
  const auto names = [&](std::uint32_t k) {
    const RContactEvent& e = m_events[k];
    return e.handleA == body || e.handleB == body;
  };
  first = std::find_if(first, last, names);
  return {m_events.data(), first, std::find_if_not(first, last, names)};
}

RContactEventSpan RContactEventLog::EventsBetween(RBodyHandle a, RBodyHandle b) const {
  const std::vector<RContactEvent>& events = m_events;
  if (b.index < a.index) std::swap(a, b);  // handleA has the lower slot
  const auto before = [](const RContactEvent& e, std::pair<RBodyHandle, RBodyHandle> key) {
    return e.handleA < key.first || (e.handleA == key.first && e.handleB < key.second);
  };
  const auto after = [](std::pair<RBodyHandle, RBodyHandle> key, const RContactEvent& e) {
    return key.first < e.handleA || (key.first == e.handleA && key.second < e.handleB);
  };
  const auto first = std::lower_bound(events.begin(), events.end(), std::make_pair(a, b), before);
  const auto last = std::upper_bound(first, events.end(), std::make_pair(a, b), after);
  return {events.data() + (first - events.begin()), events.data() + (last - events.begin())};
}

}  // namespace REngine
