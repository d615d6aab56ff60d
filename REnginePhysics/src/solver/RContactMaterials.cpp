// Each contact's material (RContactMaterials.h).
#include "solver/RContactMaterials.h"

#include <algorithm>
#include <cmath>

namespace REngine {

namespace {

bool Before(const RContactMaterials::RRemembered& x, RBodyHandle a, RBodyHandle b) {
  return x.a != a ? x.a < a : x.b < b;
}

bool Same(RBodyHandle x, RBodyHandle y) { return x.index == y.index && x.generation == y.generation; }

void Check(const RContactSettings& s) {
  if (!(std::isfinite(s.friction) && s.friction >= 0)) {
    throw RError("contact_callback.friction", "must be finite and >= 0");
  }
  if (!(s.restitution >= 0 && s.restitution <= 1)) {
    throw RError("contact_callback.restitution", "must be in [0, 1]");
  }
  if (!(AllFinite(s.relativeSurfaceVelocity_W) && s.relativeSurfaceVelocity_W.cwiseAbs().maxCoeff() <= 1e15)) {
    throw RError("contact_callback.relative_surface_velocity", "must be finite, within 1e15 m/s");
  }
}

}  // namespace

void RContactMaterials::Prepare(const RStepBodies& bodies, const std::vector<RContact>& contacts,
                                const RWorldSettings& settings) {
  // Off unless a callback is set, a one-way body is in a contact, or pairs are remembered
  // (whose memory ends now).
  bool oneWay = false;
  if (!m_callback) {
    for (const RContact& c : contacts) oneWay = oneWay || bodies[c.a].m_oneWay || bodies[c.b].m_oneWay;
  }
  m_active = m_callback || oneWay;
  m_next.clear();
  if (!m_active) {
    m_memory.clear();
    return;
  }
  const RScalar g = settings.gravity_W.norm();
  const RVec3 up = g > 0 ? RVec3(-settings.gravity_W / g) : RVec3::Zero();
  constexpr RScalar kCos45 = RScalar(0.70710678118654757);
  m_perContact.resize(contacts.size());
  for (std::size_t ci = 0; ci < contacts.size(); ++ci) {
    const RContact& c = contacts[ci];
    const auto at = std::lower_bound(m_memory.begin(), m_memory.end(), c,
                                     [](const RRemembered& x, const RContact& k) { return Before(x, k.handleA, k.handleB); });
    RContactSettings s;
    if (at != m_memory.end() && Same(at->a, c.handleA) && Same(at->b, c.handleB)) {
      s = at->settings;
    } else {
      const RBodyCore& A = bodies[c.a];
      const RBodyCore& B = bodies[c.b];
      s.friction = Combine(settings.frictionCombine, A.m_friction, B.m_friction);
      s.restitution = Combine(settings.restitutionCombine, A.m_restitution, B.m_restitution);
      // A one-way body holds what comes down onto it: the normal from it to the other
      // within 45 degrees of up. (Both one-way: neither holds the other from below.)
      if ((A.m_oneWay || B.m_oneWay) && g > 0) {
        const RScalar rise = c.manifold.normal.dot(up);
        const bool fromAbove = (!A.m_oneWay || rise >= kCos45) && (!B.m_oneWay || -rise >= kCos45);
        s.enabled = fromAbove;
      }
      if (m_callback) {
        m_callback(bodies.Body(c.a), bodies.Body(c.b), c, s, m_user);
        Check(s);
      }
    }
    m_perContact[ci] = s;
    m_next.push_back({c.handleA, c.handleB, s});
  }
  std::sort(m_next.begin(), m_next.end(),
            [](const RRemembered& x, const RRemembered& y) { return Before(x, y.a, y.b); });
  m_memory.swap(m_next);
}

}  // namespace REngine
