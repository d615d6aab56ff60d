// The covered-feature rule over the step's contacts (RPairSweep::CoveredFeatures, called by
// DetectPairs in RPairSweep.cpp once the tasks' contacts are joined): separate immovable
// bodies laid flush (tiles) as one surface. The geometry is collision/RCoveredFeatures.cpp's;
// here, which contacts it looks at and against which bodies.
//
// A contact on a covered feature of immovable body B can only come with another immovable
// body A that covers it next to the moving body, so A is one of the moving body's other
// immovable partners this step: the candidates need no query of their own. A moving body
// touching one immovable body only (a pile on the ground: nearly every body) costs a look at
// two flags in the narrow phase and one at a per-body counter here.
#include "pairs/RPairSweep.h"

#include "collision/RGjkEpa.h"
#include "shape/RCompound.h"
#include "world/RWorldStep.h"

#include <algorithm>

namespace REngine {

namespace {

// A compound child's world box (m): its polyhedron's corners posed, or its bounding sphere.
void ChildBox(RCoverSurface& s) {
  if (s.shape.polyhedron) {
    s.boxMin_W = s.boxMax_W = s.R_WB * s.shape.polyhedron->Vertices()[0] + s.x_W;
    for (const RVec3& v : s.shape.polyhedron->Vertices()) {
      const RVec3 p_W = s.R_WB * v + s.x_W;
      s.boxMin_W = s.boxMin_W.cwiseMin(p_W), s.boxMax_W = s.boxMax_W.cwiseMax(p_W);
    }
    return;
  }
  s.boxMin_W = s.x_W.array() - s.shape.boundingRadius;
  s.boxMax_W = s.x_W.array() + s.shape.boundingRadius;
}

}  // namespace

void RPairSweep::CoveredFeatures(const RStepBodies& bodies, RScalar dt, RScalar allowance, std::size_t pairTasks,
                                 const RStepInputs& in) {
  // Which moving bodies touch several immovable ones: each body's first such contact in
  // m_coverFirst, marked when a second comes (tasks in order: contacts in order).
  std::size_t listed = 0;
  for (std::size_t t = 0; t < pairTasks; ++t) listed += m_sweepTasks[t].immovable.size();
  if (listed < 2) return;
  if (m_coverFirst.size() < bodies.size()) m_coverFirst.resize(bodies.size(), kNoCover);
  auto movingOf = [&](const RContact& c) { return ImmovableAt(c.a) ? c.b : c.a; };
  bool several = false;
  for (std::size_t t = 0; t < pairTasks; ++t) {
    const RSweepTask& st = m_sweepTasks[t];
    for (const std::uint32_t k : st.immovable) {
      std::uint32_t& first = m_coverFirst[movingOf(m_contacts[st.contactsAt + k])];
      if (first == kNoCover) {
        first = static_cast<std::uint32_t>(st.contactsAt + k);
      } else {
        first |= kSeveralCovers, several = true;
      }
    }
  }
  // Those bodies' contacts as (body, contact), sorted; every entry put back to kNoCover.
  m_coverContacts.clear();
  for (std::size_t t = 0; t < pairTasks; ++t) {
    const RSweepTask& st = m_sweepTasks[t];
    for (const std::uint32_t k : st.immovable) {
      const std::uint32_t c = static_cast<std::uint32_t>(st.contactsAt + k);
      const std::uint32_t moving = movingOf(m_contacts[c]);
      if (several && (m_coverFirst[moving] & kSeveralCovers)) m_coverContacts.emplace_back(moving, c);
    }
  }
  for (std::size_t t = 0; t < pairTasks; ++t) {
    const RSweepTask& st = m_sweepTasks[t];
    for (const std::uint32_t k : st.immovable) m_coverFirst[movingOf(m_contacts[st.contactsAt + k])] = kNoCover;
  }
  if (m_coverContacts.empty()) return;
  std::sort(m_coverContacts.begin(), m_coverContacts.end());
  m_coverDropped.clear();
  bool dropped = false;
  for (std::size_t g = 0; g < m_coverContacts.size();) {
    std::size_t end = g + 1;
    while (end < m_coverContacts.size() && m_coverContacts[end].first == m_coverContacts[g].first) ++end;
    dropped = CoverBody(bodies, dt, allowance, in.settings.penetrationSlop, g, end, in.cacheStamp) || dropped;
    g = end;
  }
  if (!dropped) return;
  // The dropped contacts closed up, with their entries of the manifold memory.
  std::sort(m_coverDropped.begin(), m_coverDropped.end());
  const bool memory = !m_contactMemory.empty();
  std::size_t to = m_coverDropped.front(), next = 0;
  for (std::size_t c = to; c < m_contacts.size(); ++c) {
    if (next < m_coverDropped.size() && m_coverDropped[next] == c) {
      ++next;
      continue;
    }
    m_contacts[to] = m_contacts[c];
    if (memory) m_contactMemory[to] = m_contactMemory[c];
    ++to;
  }
  m_contacts.resize(to);
  if (memory) m_contactMemory.resize(to);
}

bool RPairSweep::CoverBody(const RStepBodies& bodies, RScalar dt, RScalar allowance, RScalar slop, std::size_t first,
                           std::size_t last, std::uint64_t cacheStamp) {
  // The immovable surfaces this body touches, once each: a body's shape, or each child of a
  // compound that a contact names (a body's contacts with one of them follow one another:
  // a compound's children, a mesh's groups).
  m_coverSurfaces.clear();
  auto childOf = [&](const RContact& c, const RConvexShape& shapeB) {
    return shapeB.children ? (ImmovableAt(c.a) ? c.manifold.childA : c.manifold.childB) : RCoverSurface::kWhole;
  };
  auto find = [&](std::uint32_t id, std::uint32_t child) {
    std::size_t s = 0;
    while (s < m_coverSurfaces.size() && !(m_coverSurfaces[s].id == id && m_coverSurfaces[s].child == child)) ++s;
    return s;
  };
  for (std::size_t k = first; k < last; ++k) {
    const RContact& c = m_contacts[m_coverContacts[k].second];
    const std::uint32_t immovable = ImmovableAt(c.a) ? c.a : c.b;
    const RBodyCore& B = bodies[immovable];
    const RConvexShape shapeB = ShapeOf(Body(B));
    const std::uint32_t child = childOf(c, shapeB);
    if (find(immovable, child) < m_coverSurfaces.size()) continue;
    RCoverSurface s;
    s.shape = shapeB;
    s.R_WB = B.m_q_WB.toRotationMatrix();
    s.x_W = B.m_x_W;
    s.id = immovable, s.child = child;
    s.v_W = B.m_v_W, s.w_W = B.m_w_W;
    if (child == RCoverSurface::kWhole) {
      const RWorldForm& form = Body(B).WorldForm(cacheStamp);
      s.boxMin_W = form.aabbMin_W, s.boxMax_W = form.aabbMax_W;
    } else {
      if (child >= shapeB.childCount) continue;
      const RShapeChild& ch = shapeB.children[child];
      s.shape = ch.shape;
      s.x_W = s.x_W + s.R_WB * ch.p_BC;
      s.R_WB = s.R_WB * ch.R_BC;
      ChildBox(s);
    }
    m_coverSurfaces.push_back(s);
  }
  if (m_coverSurfaces.size() < 2) return false;
  const std::uint32_t moving = m_coverContacts[first].first;
  const RBodyCore& M = bodies[moving];
  const RConvexShape shapeM = ShapeOf(Body(M));
  const RMat3 R_WM = M.m_q_WB.toRotationMatrix();
  bool dropped = false;
  for (std::size_t k = first; k < last; ++k) {
    const std::uint32_t ci = m_coverContacts[k].second;
    RContact& c = m_contacts[ci];
    const bool bIsA = ImmovableAt(c.a);
    const std::uint32_t immovable = bIsA ? c.a : c.b;
    const std::size_t surface = find(immovable, childOf(c, ShapeOf(Body(bodies[immovable]))));
    if (surface == m_coverSurfaces.size()) continue;
    // M's piece in the contact: its shape, or the compound's child that touches.
    RPosedShape piece;
    piece.shape = shapeM, piece.R_W = R_WM, piece.x_W = M.m_x_W;
    if (shapeM.children) {
      const RShapeChild& child = shapeM.children[bIsA ? c.manifold.childB : c.manifold.childA];
      piece.shape = child.shape;
      piece.R_W = R_WM * child.R_BC, piece.x_W = M.m_x_W + R_WM * child.p_BC;
    }
    const RBodyCore& B = bodies[immovable];
    // (A compound's child by its own size: the whole compound's would widen the tolerances
    // with the level it belongs to, and a small body at the foot of a child standing on
    // another would be taken for covered there and fall through.)
    const RCoverSurface& on = m_coverSurfaces[surface];
    const RScalar radiusB = on.child == RCoverSurface::kWhole ? B.m_boundingRadius : on.shape.boundingRadius;
    const RCoverTolerances tol = CoverTolerances(slop, radiusB, M.m_boundingRadius);
    // The margin the narrow phase used (CheckCollisionInA's: the pair's, plus its band).
    const RScalar margin =
        PairMargin(bodies, immovable, moving, dt, allowance) + Band(shapeM, m_coverSurfaces[surface].shape);
    const RCoverResult r = CoverContact(m_coverSurfaces[surface], bIsA, piece, m_coverSurfaces.data(),
                                        static_cast<int>(m_coverSurfaces.size()), tol, margin, c.manifold);
    if (r == RCoverResult::kDropped) {
      m_coverDropped.push_back(ci), dropped = true;
    } else if (r == RCoverResult::kReplaced) {
      c.timeOfImpact = TimeOfImpact(bodies[c.a], bodies[c.b], m_moveV[c.a], m_moveV[c.b], c.manifold, dt);
    }
  }
  return dropped;
}

}  // namespace REngine
