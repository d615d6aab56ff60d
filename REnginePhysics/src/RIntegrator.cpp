#include <REnginePhysics/RIntegrator.h>

#include <REngineMath/RQuaternion.h>

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace REngine {

std::uint64_t NextCacheStamp() {
  static std::atomic<std::uint64_t> s_stamp{0};
  return ++s_stamp;
}

RScalar Combine(RCombineMode mode, RScalar a, RScalar b) {
  switch (mode) {
    case RCombineMode::kMin: return std::min(a, b);
    case RCombineMode::kMax: return std::max(a, b);
    case RCombineMode::kProduct: return a * b;
    case RCombineMode::kAverage: return RScalar(0.5) * (a + b);
    case RCombineMode::kGeometric: return std::sqrt(a * b);
  }
  return a;
}

namespace {
using Clock = std::chrono::steady_clock;

// When within the step the manifold's deepest point closes, moving with the bodies' step
// velocities: 0 when it is closed already, infinity when it does not close this step.
RScalar TimeOfImpact(const RRigidBody& a, const RRigidBody& b, const RVec3& va, const RVec3& vb,
                     const RContactManifold& m, RScalar dt) {
  if (m.pointCount == 0) return m.query.separation <= 0 ? 0 : std::numeric_limits<RScalar>::infinity();
  int deepest = 0;
  for (int k = 1; k < m.pointCount; ++k) {
    if (m.points[k].separation < m.points[deepest].separation) deepest = k;
  }
  const RScalar gap = m.points[deepest].separation;
  if (gap <= 0) return 0;
  const RVec3& p = m.points[deepest].position;
  const RVec3 wa = a.IsStatic() ? RVec3::Zero() : a.AngularVelocity_W();
  const RVec3 wb = b.IsStatic() ? RVec3::Zero() : b.AngularVelocity_W();
  const RScalar vn = m.normal.dot(vb + wb.cross(p - b.Position_W()) - va -
                                        wa.cross(p - a.Position_W()));
  if (vn < 0 && gap <= -vn * dt) return gap / -vn;
  return std::numeric_limits<RScalar>::infinity();
}
double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }
}  // namespace

void RIntegrator::Update(std::vector<RRigidBody>& bodies, RScalar dt) {
  if (!(std::isfinite(dt) && dt > 0)) {
    throw std::invalid_argument("RIntegrator::Update: dt must be finite and > 0 (got " +
                                std::to_string(dt) + ")");
  }
  const auto t0 = Clock::now();
  m_cacheStamp = NextCacheStamp();
  ++m_stepCount;
  WakeIslands(bodies);
  CollisionDetection(bodies, dt);
  const auto t1 = Clock::now();
  UpdateObjects(bodies, dt);
  SleepIslands(bodies);
  // The bodies moved: a new stamp, so world forms that detection cached at the old poses
  // are recomputed when game code asks after the step.
  m_cacheStamp = NextCacheStamp();
  const auto t2 = Clock::now();
  m_profile.collisionDetection = Ms(t1 - t0) - m_profile.findImpulses;
  m_profile.updateObjects = Ms(t2 - t1);
  m_profile.total = Ms(t2 - t0);
}

void RIntegrator::CollisionDetection(std::vector<RRigidBody>& bodies, RScalar dt) {
  std::uint64_t wakeRuns = 0;
  // A sweep that touched a sleeping island wakes it and runs again: the woken bodies' pairs
  // with each other, skipped while they slept, must be found too. Each rerun wakes at least
  // one island, so this ends.
  while (DetectPairs(bodies, dt)) {
    WakeMarked(bodies);
    ++wakeRuns;
  }
  m_pairStats.wakeRuns = wakeRuns;
  const auto t0 = Clock::now();
  FindImpulses(bodies, dt);
  m_profile.findImpulses = Ms(Clock::now() - t0);
}

bool RIntegrator::DetectPairs(std::vector<RRigidBody>& bodies, RScalar dt) {
  m_contacts.clear();
  m_pairStats = RPairStats{};
  const std::size_t n = bodies.size();
  const RWorldSettings::RShortcuts& shortcuts = m_settings.shortcuts;
  // Bounding spheres about the centres of mass, each grown by how far its surface can
  // move within the step (speed plus the farthest point's rotation, times dt): a pair
  // whose grown spheres are apart cannot touch before the next step. Stored as separate
  // arrays so the O(n^2) sweep below is a tight loop over contiguous doubles; the arrays
  // keep their capacity between steps.
  // The velocities are those the body will move with this step: a missile given its
  // launch impulse this step is as fast as one that has flown for a while.
  // Every pair is also looked at within a fixed allowance: two bodies that rest on each
  // other have no relative velocity at the start of a step, yet the lower one is held and
  // the upper one is not, so they close by up to g dt^2 within the step; and a contact
  // that overlaps by less than the slop must not flicker out when it floats up by a
  // rounding error. A contact found early is harmless: its row pushes only if needed.
  const RScalar allowance = m_settings.gravity_W.norm() * dt * dt + m_settings.penetrationSlop;
  m_cx.resize(n), m_cy.resize(n), m_cz.resize(n), m_reach.resize(n);
  m_moveV.resize(n), m_moveW.resize(n);
  const RScalar halfDt = RScalar(0.5) * dt;
  for (std::size_t i = 0; i < n; ++i) {
    RRigidBody& b = bodies[i];
    const RScalar r = b.BoundingRadius();
    m_cx[i] = b.m_x_W.x(), m_cy[i] = b.m_x_W.y(), m_cz[i] = b.m_x_W.z();
    if (b.m_sleeping) {
      // Reach and margin as if it were awake and resting (half a step of gravity), so that
      // the margin between a sleeper and a resting neighbour is the one two awake bodies
      // have: a neighbour beyond it while both were awake does not wake it.
      m_moveV[i] = m_settings.gravity_W * halfDt, m_moveW[i] = 0;
    } else if (b.m_isStatic) {
      m_moveV[i].setZero(), m_moveW[i] = 0;
      // Without the shortcut a static body's world form is recomputed every step, as a
      // moving body's is.
      if (b.m_isStatic && !shortcuts.staticForms) b.m_worldForm.stamp = 0;
    } else {
      m_moveV[i] = b.m_v_W + b.m_linearImpulse_W * b.m_invMass +
                   (b.m_force_W * b.m_invMass + m_settings.gravity_W) * halfDt;
      const RVec3 kick_B = b.m_q_WB.conjugate() * (b.m_angularImpulse_W + b.m_torque_W * halfDt);
      m_moveW[i] = (b.m_w_B + b.m_invI_B.cwiseProduct(kick_B)).norm();
    }
    m_reach[i] = r + (m_moveV[i].norm() + m_moveW[i] * r) * dt + allowance;
  }
  // Bodies that cannot start a contact: asleep, or static, and responding (a sensor keeps
  // reporting what sleeps on it). A pair of two of them is skipped; a sleeping body touched
  // by any other (in the speculative margin) wakes with its island.
  auto passive = [](const RRigidBody& b) {
    return (b.m_sleeping || b.m_isStatic) && b.m_responds;
  };
  bool woke = false;
  // The bodies that can start a contact, in index order. A passive body is only paired with
  // these, so a world that mostly sleeps costs O(n m) for m awake bodies, not O(n^2); and
  // the pairs are still visited in (i, then j) order.
  m_active.clear();
  std::uint64_t passiveCount = 0, staticCount = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (passive(bodies[i])) {
      ++passiveCount, staticCount += bodies[i].m_isStatic;
    } else {
      m_active.push_back(static_cast<std::uint32_t>(i));
    }
  }
  // The touching band, and a relative allowance for the rounding of the squares.
  constexpr RScalar kGrow = 1 + 1e-9;
  const bool bounds = shortcuts.boundsRejection;
  std::size_t nextActive = 0;  // first entry of m_active above i
  m_near.resize(n), m_candidates.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const RScalar xi = m_cx[i], yi = m_cy[i], zi = m_cz[i], ri = m_reach[i];
    const RRigidBody& a = bodies[i];
    while (nextActive < m_active.size() && m_active[nextActive] <= i) ++nextActive;
    const bool passiveA = passive(a);
    // The candidates j > i: every later body, or, for a passive body, the later awake ones.
    // First the bounding-sphere test for all of them: lim^2 - d^2, >= 0 when the grown
    // spheres touch, in a branch-free loop over contiguous arrays that the compiler
    // vectorises (the contiguous case; the awake list is a gather); then the pairs that
    // passed, in index order. A body with a non-finite position passes no test: UpdateObjects
    // never leaves one so, but game code could set it.
    const std::size_t count = passiveA ? m_active.size() - nextActive : n - i - 1;
    RScalar* near = m_near.data();
    if (!bounds) {
      std::fill(near, near + count, RScalar(0));
    } else if (!passiveA) {
      const RScalar* cx = m_cx.data() + i + 1;
      const RScalar* cy = m_cy.data() + i + 1;
      const RScalar* cz = m_cz.data() + i + 1;
      const RScalar* reach = m_reach.data() + i + 1;
      for (std::size_t k = 0; k < count; ++k) {
        const RScalar dx = cx[k] - xi, dy = cy[k] - yi, dz = cz[k] - zi;
        const RScalar lim = (ri + reach[k]) * kGrow;
        near[k] = lim * lim - (dx * dx + dy * dy + dz * dz);
      }
    } else {
      const std::uint32_t* active = m_active.data() + nextActive;
      for (std::size_t k = 0; k < count; ++k) {
        const std::size_t j = active[k];
        const RScalar dx = m_cx[j] - xi, dy = m_cy[j] - yi, dz = m_cz[j] - zi;
        const RScalar lim = (ri + m_reach[j]) * kGrow;
        near[k] = lim * lim - (dx * dx + dy * dy + dz * dz);
      }
    }
    // The few that passed, compacted by a tight loop of its own (kept apart from the pair
    // work below, whose register pressure would otherwise put this counter in memory).
    std::uint32_t* candidates = m_candidates.data();
    std::size_t found = 0;
    for (std::size_t k = 0; k < count; ++k) {
      candidates[found] = static_cast<std::uint32_t>(k);
      found += near[k] >= 0;
    }
    for (std::size_t c = 0; c < found; ++c) {
      const std::size_t k = candidates[c];
      const std::size_t j = passiveA ? m_active[nextActive + k] : i + 1 + k;
      const RRigidBody& b = bodies[j];
      if ((a.m_isStatic && b.m_isStatic) || !a.ShouldCheckCollision(b) ||
          (m_filter && !m_filter(a, b, m_filterUser))) {
        ++m_pairStats.rejectedFilter;
        continue;
      }
      // Bounding boxes from the stamped world forms, grown the same way: they reject the
      // many pairs whose spheres overlap only because a body is long or flat (the ground).
      const RWorldForm& fa = a.WorldForm(m_cacheStamp);
      const RWorldForm& fb = b.WorldForm(m_cacheStamp);
      const RScalar grow = (ri - fa.sphereRadius + m_reach[j] - fb.sphereRadius) * kGrow;
      if (bounds && (((fa.aabbMin_W.array() - grow) > fb.aabbMax_W.array()).any() ||
                     ((fb.aabbMin_W.array() - grow) > fa.aabbMax_W.array()).any())) {
        ++m_pairStats.rejectedBoxes;
        continue;
      }
      ++m_pairStats.narrowPhase;
      RContact contact;
      const RScalar approach = (m_moveV[j] - m_moveV[i]).norm() +
                               m_moveW[i] * a.BoundingRadius() + m_moveW[j] * b.BoundingRadius();
      if (RCollisionSolver::CheckCollisionWithMargin(a, b, approach * dt + allowance,
                                                     contact.manifold)) {
        // A sleeping body touched by one that responds wakes, with its island. A sensor
        // or a laser (does not respond) is reported against it without waking it.
        if ((a.m_sleeping || b.m_sleeping) && a.m_responds && b.m_responds) {
          const RRigidBody& sleeper = a.m_sleeping ? a : b;
          m_wakeMark[sleeper.m_sleepIsland] = 1;
          woke = true;
          continue;
        }
        contact.a = static_cast<std::uint32_t>(i);
        contact.b = static_cast<std::uint32_t>(j);
        contact.timeOfImpact = TimeOfImpact(a, b, m_moveV[i], m_moveV[j], contact.manifold, dt);
        m_contacts.push_back(contact);
      }
    }
  }
  // Pairs never visited: two passive static bodies (counted with the filter's), or two
  // passive bodies of which one at least sleeps. (Counts are those of the last sweep when
  // waking islands made it run again.)
  const std::uint64_t staticPairs = staticCount * (staticCount - (staticCount > 0)) / 2;
  m_pairStats.rejectedFilter += staticPairs;
  m_pairStats.rejectedSleeping = passiveCount * (passiveCount - (passiveCount > 0)) / 2 - staticPairs;
  m_pairStats.pairs = n * (n - (n > 0)) / 2;
  m_pairStats.rejectedBounds = m_pairStats.pairs - m_pairStats.rejectedFilter -
                               m_pairStats.rejectedSleeping - m_pairStats.rejectedBoxes -
                               m_pairStats.narrowPhase;
  m_pairStats.contacts = m_contacts.size();
  return woke;
}

void RIntegrator::KeepSleepingWarmStarts(const std::vector<RRigidBody>& bodies) {
  auto passive = [&bodies](std::uint32_t i) {
    return bodies[i].m_sleeping || bodies[i].m_isStatic;
  };
  for (const RWarmStart& w : m_warm) {
    const std::uint32_t a = static_cast<std::uint32_t>(w.pair >> 32);
    const std::uint32_t b = static_cast<std::uint32_t>(w.pair & 0xffffffffu);
    if (passive(a) && passive(b)) m_warmNext.push_back(w);
  }
}

void RIntegrator::WakeIslands(std::vector<RRigidBody>& bodies) {
  const std::size_t n = bodies.size();
  m_wakeMark.assign(n, 0);  // keeps its capacity: no allocation once the world's size is set
  // Island ids are body indices: when bodies were added or removed they mean nothing, and a
  // removed body may have held a sleeping stack up. A sleeping body ignores gravity, so a
  // change of gravity wakes everything too; and so does static geometry that the game moved,
  // which may have held sleeping bodies where it was (their contacts are not kept while they
  // sleep, so which ones is not known).
  // Any body not where this integrator left it (see RRigidBody::m_slot) wakes everything:
  // a removal and an addition in one frame keep the count and may still remove a support.
  bool moved = m_wakeAll;
  for (std::size_t i = 0; i < n && !moved; ++i) {
    const RRigidBody& b = bodies[i];
    moved = b.m_staticMoved || b.m_slot != i || b.m_slotWorld != m_worldId.value;
  }
  m_wakeAll = false;
  if (!m_settings.shortcuts.sleeping || n != m_sleepBodyCount || moved ||
      m_settings.gravity_W != m_sleepGravity_W) {
    m_sleepBodyCount = n;
    m_sleepGravity_W = m_settings.gravity_W;
    for (RRigidBody& b : bodies) {
      if (b.m_sleeping || b.m_sleepIsland != RRigidBody::kNoIsland) {
        b.m_sleeping = false, b.m_restTime = 0, b.m_sleepIsland = RRigidBody::kNoIsland;
      }
    }
    return;
  }
  // A body the game woke (RRigidBody::Wake) still names the island it slept with.
  bool any = false;
  for (const RRigidBody& b : bodies) {
    if (!b.m_sleeping && b.m_sleepIsland != RRigidBody::kNoIsland) {
      m_wakeMark[b.m_sleepIsland] = 1, any = true;
    }
  }
  if (any) WakeMarked(bodies);
}

void RIntegrator::WakeMarked(std::vector<RRigidBody>& bodies) {
  for (RRigidBody& b : bodies) {
    if (b.m_sleepIsland != RRigidBody::kNoIsland && m_wakeMark[b.m_sleepIsland]) {
      b.m_sleeping = false, b.m_restTime = 0, b.m_sleepIsland = RRigidBody::kNoIsland;
    }
  }
  std::fill(m_wakeMark.begin(), m_wakeMark.end(), 0);
}

// Islands are the bodies linked by this step's resolved contacts between two dynamic
// bodies. An island sleeps when every body in it has been slower than the sleep speed for
// the sleep time and either static geometry holds it (a static body pushed one of its
// bodies this step) or it is exactly still: a drifting body in space is never stopped.
void RIntegrator::SleepIslands(std::vector<RRigidBody>& bodies) {
  const std::size_t n = bodies.size();
  bool anyRested = false;
  std::uint64_t asleep = 0;
  for (std::size_t i = 0; i < n; ++i) {
    RRigidBody& b = bodies[i];
    b.m_staticMoved = false, b.m_slot = static_cast<std::uint32_t>(i), b.m_slotWorld = m_worldId.value;
    anyRested = anyRested || (!b.m_isStatic && !b.m_sleeping && b.m_restTime >= m_settings.sleepTime);
    asleep += b.m_sleeping;
  }
  m_pairStats.sleepingBodies = asleep;
  // Islands are built only in a step where some body has rested long enough.
  if (!m_settings.shortcuts.sleeping || !anyRested) return;
  m_sleepParent.resize(n);
  m_sleepRest.assign(n, std::numeric_limits<RScalar>::infinity());
  m_sleepSupported.assign(n, 0);
  m_sleepStill.assign(n, 1);
  for (std::size_t i = 0; i < n; ++i) m_sleepParent[i] = static_cast<std::uint32_t>(i);
  auto find = [this](std::uint32_t i) {
    while (m_sleepParent[i] != i) i = m_sleepParent[i] = m_sleepParent[m_sleepParent[i]];
    return i;
  };
  for (const RContact& c : m_contacts) {
    if (!c.resolved) continue;
    const bool staticA = bodies[c.a].m_isStatic, staticB = bodies[c.b].m_isStatic;
    if (staticA || staticB) {
      // Held: the static body pushed this step (a speculative contact, or a body sliding
      // along a floor in space, is not held).
      RScalar pushed = 0;
      for (int k = 0; k < c.manifold.pointCount; ++k) pushed += c.normalImpulse[k];
      if (pushed > 0) m_sleepSupported[staticA ? c.b : c.a] = 1;
      continue;
    }
    const std::uint32_t ra = find(c.a), rb = find(c.b);
    // The smaller index as the root: island ids do not depend on the order of contacts.
    if (ra != rb) m_sleepParent[std::max(ra, rb)] = std::min(ra, rb);
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const RRigidBody& b = bodies[i];
    if (b.m_isStatic || b.m_sleeping) continue;
    const std::uint32_t r = find(i);
    m_sleepRest[r] = std::min(m_sleepRest[r], b.m_restTime);
    if (m_sleepSupported[i]) m_sleepSupported[r] = 1;
    if (!(b.m_v_W.isZero(0) && b.m_w_B.isZero(0))) m_sleepStill[r] = 0;
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    RRigidBody& b = bodies[i];
    if (b.m_isStatic || b.m_sleeping) continue;
    const std::uint32_t r = find(i);
    if (m_sleepRest[r] >= m_settings.sleepTime && (m_sleepSupported[r] || m_sleepStill[r])) {
      b.m_sleeping = true;
      b.m_sleepIsland = r;
      b.m_v_W.setZero(), b.m_w_B.setZero();
      ++m_pairStats.sleepingBodies;
    }
  }
}

namespace {

std::uint64_t PairKey(std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; }

template <class Dir, class Body>
void SetDirection(Dir& dir, const RVec3& d, const RVec3& rA, const RVec3& rB, const Body& a,
                  const Body& b) {
  dir.d = d;
  dir.rAxd = rA.cross(d);
  dir.rBxd = rB.cross(d);
  dir.iA = a.invI * dir.rAxd;
  dir.iB = b.invI * dir.rBxd;
  dir.k = a.invM + b.invM + dir.rAxd.dot(dir.iA) + dir.rBxd.dot(dir.iB);
}

template <class Dir>
RScalar Speed(const Dir& dir, const RVec3& va, const RVec3& wa, const RVec3& vb,
              const RVec3& wb) {
  return dir.d.dot(vb - va) + dir.rBxd.dot(wb) - dir.rAxd.dot(wa);
}

template <class Dir>
void Push(const Dir& dir, RScalar lambda, RScalar invMA, RScalar invMB, RVec3& va, RVec3& wa,
          RVec3& vb, RVec3& wb) {
  va -= (invMA * lambda) * dir.d;
  wa -= lambda * dir.iA;
  vb += (invMB * lambda) * dir.d;
  wb += lambda * dir.iB;
}

// A previous point closer than this fraction of the pair's size to a new one is taken as
// the same contact when no feature id matches (a corner sliding past a reference edge
// changes its id, not its place).
constexpr RScalar kWarmMatchDistance = RScalar(0.05);

// The tangential impulses that stop the sliding velocity (v1, v2) along two tangents of a
// point, solved together through their 2 x 2 effective mass.
template <class Dir>
Eigen::Matrix<RScalar, 2, 1> TangentStep(const Dir& t1, const Dir& t2, RScalar v1, RScalar v2) {
  const RScalar k12 = t1.rAxd.dot(t2.iA) + t1.rBxd.dot(t2.iB);  // t1 . t2 = 0
  const RScalar det = t1.k * t2.k - k12 * k12;
  if (!(det > 0)) return {-v1 / t1.k, -v2 / t2.k};
  return {-(t2.k * v1 - k12 * v2) / det, -(t1.k * v2 - k12 * v1) / det};
}

// The target of a row that is not in contact at the end of the step: never reached.
constexpr RScalar kNever = -std::numeric_limits<RScalar>::infinity();

}  // namespace

// Sequential impulses (Catto 2005) over every contact point, with the velocities each body
// will move with during the step (its pending impulses and half the step's acceleration
// included: kick-drift-kick moves bodies with the mid-step velocity, so a resting contact
// that holds that velocity at zero does not sink at all). In phases: impacts (SolveImpacts),
// then the contacts: accumulated normal impulses clamped at zero (a contact pushes, never
// pulls: the separating-velocity guard), friction per manifold within the Coulomb disc of
// mu times the manifold's normal impulse (SolvePatch), every row starting from last step's
// impulses for the same features; small islands solved exactly (SolveIslands); then the
// end of the step (SolveEndOfStep). Penetration beyond a slop is removed by
// pseudo-velocities (split impulses), solved apart so that position correction never adds
// kinetic energy.
void RIntegrator::FindImpulses(std::vector<RRigidBody>& bodies, RScalar dt) {
  m_rows.clear();
  m_impacts.clear();
  m_blocks.clear();
  const std::size_t n = bodies.size();
  // Warm-start memory is keyed by body index: when the game adds or removes bodies the
  // indices shift, and another pair would inherit a stranger's impulses.
  if (n != m_warmBodyCount) m_warm.clear(), m_warmBodyCount = n;
  m_warmNext.clear();
  KeepSleepingWarmStarts(bodies);
  m_solverBodies.resize(n);
  const RScalar halfDt = RScalar(0.5) * dt;
  bool anyRow = false;
  for (const RContact& c : m_contacts) {
    const RRigidBody& a = bodies[c.a];
    const RRigidBody& b = bodies[c.b];
    anyRow = anyRow || (a.m_responds && b.m_responds && (!a.m_isStatic || !b.m_isStatic) &&
                        c.manifold.pointCount > 0);
  }
  if (!anyRow) {
    std::swap(m_warm, m_warmNext);
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const RRigidBody& b = bodies[i];
    RSolverBody& s = m_solverBodies[i];
    s.invM = b.m_invMass;
    s.vp.setZero(), s.wp.setZero(), s.vMid.setZero();
    if (b.m_isStatic) {
      s.v.setZero(), s.w.setZero(), s.invI.setZero();
      continue;
    }
    const RMat3 R = b.m_q_WB.toRotationMatrix();
    s.invI = R * b.m_invI_B.asDiagonal() * R.transpose();
    s.v = m_moveV[i];  // computed by CollisionDetection's pre-pass this step
    s.w = R * b.m_w_B + s.invI * (b.m_angularImpulse_W + b.m_torque_W * halfDt);
  }

  for (std::uint32_t ci = 0; ci < m_contacts.size(); ++ci) {
    RContact& c = m_contacts[ci];
    const RRigidBody& A = bodies[c.a];
    const RRigidBody& B = bodies[c.b];
    // A manifold without points (the narrow phase hit its iteration cap) gives no rows: its
    // impact point and centroid would be 0/0.
    c.resolved = A.m_responds && B.m_responds && (!A.m_isStatic || !B.m_isStatic) &&
                 c.manifold.pointCount > 0;
    if (!c.resolved) continue;
    const RSolverBody& sa = m_solverBodies[c.a];
    const RSolverBody& sb = m_solverBodies[c.b];
    const RScalar e = Combine(m_settings.restitutionCombine, A.m_restitution, B.m_restitution);
    const RScalar mu = Combine(m_settings.frictionCombine, A.m_friction, B.m_friction);
    // Impacts bounce in a phase of their own, before the contacts are solved (below): each
    // manifold gets one impact row at the centre of its leading points (those within the
    // slop of the deepest). A whole face hitting flat bounces through the face's centre,
    // with no torque, a corner through the corner: one constraint, whose outcome is the
    // closed form and conserves energy at e = 1. Restitution targets at several points of
    // one manifold, solved one after another, could return more energy than came in.
    int deepest = 0;
    for (int k = 1; k < c.manifold.pointCount; ++k) {
      if (c.manifold.points[k].separation < c.manifold.points[deepest].separation) deepest = k;
    }
    const RScalar leadSeparation = c.manifold.points[deepest].separation;
    RVec3 leadCentre = RVec3::Zero();
    int leads = 0;
    for (int k = 0; k < c.manifold.pointCount; ++k) {
      if (c.manifold.points[k].separation <= leadSeparation + m_settings.penetrationSlop) {
        leadCentre += c.manifold.points[k].position;
        ++leads;
      }
    }
    if (leads == 0) {  // separations that are not numbers (see ImpactGeometry): no rows
      c.resolved = false;
      continue;
    }
    leadCentre /= leads;
    const RVec3& normal = c.manifold.normal;
    RVec3 t1, t2;
    OrthonormalBasis(normal, t1, t2);
    {
      RImpactRow r;
      r.a = c.a, r.b = c.b, r.contact = ci, r.point = deepest;
      const RVec3 rA = leadCentre - A.m_x_W, rB = leadCentre - B.m_x_W;
      SetDirection(r.dir[0], normal, rA, rB, sa, sb);
      SetDirection(r.dir[1], t1, rA, rB, sa, sb);
      SetDirection(r.dir[2], t2, rA, rB, sa, sb);
      r.rA = rA, r.rB = rB;
      r.gap = leadSeparation;
      r.restitution = e;
      r.friction = mu;
      r.lambdaN = r.lambdaT1 = r.lambdaT2 = 0;
      r.impulse.setZero(), r.angularA.setZero(), r.angularB.setZero();
      r.miss = false;
      m_impacts.push_back(r);
    }
    const std::uint32_t firstRow = static_cast<std::uint32_t>(m_rows.size());
    const RWarmStart* patchWarm = nullptr;  // the first of its points found last step
    // One contact row per manifold point: no restitution; the contact may close its gap
    // within the step (speculative: a fast body stops at the surface, not inside it) but
    // not approach beyond it.
    for (int k = 0; k < c.manifold.pointCount; ++k) {
      const RVec3& position = c.manifold.points[k].position;
      const RScalar gap = c.manifold.points[k].separation;
      RContactRow r;
      r.a = c.a, r.b = c.b, r.contact = ci, r.point = k;
      r.rA = position - A.m_x_W;
      r.rB = position - B.m_x_W;
      SetDirection(r.n, normal, r.rA, r.rB, sa, sb);
      r.block = static_cast<std::uint32_t>(m_blocks.size());
      r.target = -std::max(gap, RScalar(0)) / dt;
      r.pseudoTarget = gap < -m_settings.penetrationSlop
                           ? std::min(m_settings.positionCorrection * (-gap - m_settings.penetrationSlop),
                                      m_settings.maxPositionCorrection) / dt
                           : 0;
      r.gap = gap;
      r.deferN = 0;
      r.lambdaN = r.lambdaP = r.lambdaE = 0;
      r.endTarget = kNever;
      r.lever = 0;  // set with the patch below
      // Warm start from the same features last step, or else from the nearest of last
      // step's points of this pair (in a's frame, where a resting contact stays put).
      const std::uint64_t pair = PairKey(c.a, c.b);
      auto it = std::lower_bound(m_warm.begin(), m_warm.end(), pair,
                                 [](const RWarmStart& w, std::uint64_t key) { return w.pair < key; });
      const RVec3 point_A = A.m_q_WB.conjugate() * (position - A.m_x_W);
      const std::uint32_t feature = c.manifold.points[r.point].featureId;
      const RScalar reach = kWarmMatchDistance * std::min(A.BoundingRadius(), B.BoundingRadius());
      // The same feature wins over any nearer point. Two new rows may take the same old
      // point (a corner that became two clip points): each starts from its impulse, and
      // the passes below redistribute.
      const RWarmStart* match = nullptr;
      const RWarmStart* nearest = nullptr;
      RScalar bestD2 = reach * reach;
      for (; it != m_warm.end() && it->pair == pair; ++it) {
        if (it->feature == feature) {
          match = &*it;
          break;
        }
        const RScalar d2 = (it->point_A - point_A).squaredNorm();
        if (d2 < bestD2) bestD2 = d2, nearest = &*it;
      }
      if (!match) match = nearest;
      if (match) {
        ++m_pairStats.warmStarted;
        r.lambdaN = match->lambdaN;
        r.lambdaE = match->lambdaE;
        if (!patchWarm) patchWarm = match;
      }
      m_rows.push_back(r);
    }
    // The manifold's friction patch (see RBlock): at the centroid of its points, limited by
    // mu times their total normal impulse, and a twist limited by mu times the sum of each
    // point's normal impulse and distance from the centroid.
    RBlock blk;
    blk.first = firstRow;
    blk.count = c.manifold.pointCount;
    blk.useBlock = blk.count > 1;
    blk.pinv.setZero();  // filled below, once every row is warm-started
    RVec3 centroid = RVec3::Zero();
    for (int k = 0; k < c.manifold.pointCount; ++k) centroid += c.manifold.points[k].position;
    centroid /= c.manifold.pointCount;
    blk.rA = centroid - A.m_x_W, blk.rB = centroid - B.m_x_W;
    SetDirection(blk.t[0], t1, blk.rA, blk.rB, sa, sb);
    SetDirection(blk.t[1], t2, blk.rA, blk.rB, sa, sb);
    blk.normal = normal;
    blk.twistIA = sa.invI * normal, blk.twistIB = sb.invI * normal;
    blk.kTwist = normal.dot(blk.twistIA) + normal.dot(blk.twistIB);
    for (int k = 0; k < c.manifold.pointCount; ++k) {
      m_rows[firstRow + k].lever = (c.manifold.points[k].position - centroid).norm();
    }
    blk.friction = mu;
    for (int ph = 0; ph < 2; ++ph) blk.lambdaT1[ph] = blk.lambdaT2[ph] = blk.lambdaTwist[ph] = 0;
    if (patchWarm) {
      for (int ph = 0; ph < 2; ++ph) {
        blk.lambdaT1[ph] = patchWarm->tangentImpulse[ph].dot(t1);
        blk.lambdaT2[ph] = patchWarm->tangentImpulse[ph].dot(t2);
        blk.lambdaTwist[ph] = patchWarm->twistImpulse[ph];
      }
    }
    m_blocks.push_back(blk);
  }

  m_pairStats.contactPoints = m_rows.size();
  WarmStart(RPhase::kVelocity);
  SolveImpacts(bodies, dt);
  // A manifold whose impact the narrow phase, run again along the motion, found not to
  // happen within this step keeps no speculative rows: their linear prediction from the
  // start of the step (which said it would) would stop the bodies short, an inelastic
  // collision that never happened. Points already touching keep their rows.
  // (Impact rows and blocks are both one per resolved contact, in the same order.)
  for (std::size_t i = 0; i < m_impacts.size(); ++i) {
    if (!m_impacts[i].miss || m_impacts[i].lambdaN != 0) continue;
    for (int k = 0; k < m_blocks[i].count; ++k) {
      RContactRow& r = m_rows[m_blocks[i].first + k];
      if (r.gap > 0 && r.lambdaN == 0) r.target = kNever;
    }
  }
  // Bodies that impacted move with their piecewise path's velocity, deferV less than the
  // velocity after the impacts that the contact phase works on; the end of the step needs
  // the difference to predict which contacts are then closed.
  for (RContactRow& r : m_rows) {
    r.deferN = r.n.d.dot(m_solverBodies[r.b].deferV - m_solverBodies[r.a].deferV);
  }
  const int iterations = std::max(1, m_settings.solverIterations);
  // Rows come grouped by contact. A manifold's normal rows are solved together: its points
  // share two bodies, and solving them one after another favours the first, leaving a
  // small torque that tilts stacked bodies step after step. The block's matrix is rank
  // deficient (four points of one face constrain three degrees of freedom), so the
  // minimum-norm least-squares inverse is precomputed once per step; when its answer
  // would pull at a point, that manifold falls back to one point at a time.
  for (RBlock& blk : m_blocks) {
    if (!blk.useBlock) continue;
    const std::uint32_t first = blk.first;
    const RSolverBody& sa = m_solverBodies[m_rows[first].a];
    const RSolverBody& sb = m_solverBodies[m_rows[first].b];
    // Padded with zeros to 4 x 4: the padding's eigenvalues are 0 and drop out of the
    // inverse, so one fixed-size symmetric eigensolver serves every point count.
    Eigen::Matrix<RScalar, 4, 4> K = Eigen::Matrix<RScalar, 4, 4>::Zero();
    for (int i = 0; i < blk.count; ++i) {
      const RDirection& di = m_rows[first + i].n;
      for (int j = 0; j <= i; ++j) {
        const RDirection& dj = m_rows[first + j].n;
        K(i, j) = K(j, i) =
            (sa.invM + sb.invM) * di.d.dot(dj.d) + di.rAxd.dot(dj.iA) + di.rBxd.dot(dj.iB);
      }
    }
    // Minimum-norm inverse: sum of v v^T / s over the eigenpairs with s above 1e-12 of the
    // largest. The directions below are the coplanar points' null space (exactly 0 but for
    // rounding, ~1e-16 of the largest); the softest real direction, a heavy body's, is
    // shared with the light body it touches and stays near the light body's stiffness.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<RScalar, 4, 4>> eigen(K);
    const Eigen::Matrix<RScalar, 4, 1>& s = eigen.eigenvalues();  // ascending
    const RScalar floor = RScalar(1e-14) * s[3];
    blk.pinv.setZero();
    for (int k = 0; k < 4; ++k) {
      if (!(s[k] > floor)) continue;
      const Eigen::Matrix<RScalar, 4, 1> v = eigen.eigenvectors().col(k);
      blk.pinv += (v / s[k]) * v.transpose();
    }
  }

  const std::size_t nBlocks = m_blocks.size();
  for (int it = 0; it < iterations; ++it) {
    // Alternate the sweep's direction, for the same reason as the blocks across manifolds.
    for (std::size_t bb = 0; bb < nBlocks; ++bb) {
      RBlock& blk = m_blocks[(it % 2 == 0) ? bb : nBlocks - 1 - bb];
      RContactRow* rows = &m_rows[blk.first];
      // Normal: reach the targets, never pull.
      SolveNormalBlock(blk, rows, RPhase::kVelocity);
      // Friction, bounded by this pass's normal impulses.
      SolvePatch(blk, false, RPhase::kVelocity);
      // Position correction on the pseudo-velocities, as a block like the velocities: one
      // point at a time, the first point of a face would be favoured and the correction
      // would tilt the box (a 20-box stack then leans further every step and falls).
      SolveNormalBlock(blk, rows, RPhase::kPosition);
    }
  }
  BuildIslands(bodies);
  SolveIslands(RPhase::kVelocity);
  SolveIslands(RPhase::kPosition);
  // What the contact phase changed after the impacts (see the deferred impulses below).
  for (RSolverBody& s : m_solverBodies) s.contactDeltaV = s.v - s.vImpacts;
  SolveEndOfStep(bodies, dt);

  // Accumulate on the bodies (applied by UpdateObjects), report, and remember.
  auto accumulate = [&bodies](std::uint32_t a, std::uint32_t b, const RVec3& rA,
                                    const RVec3& rB, const RVec3& J) {
    RRigidBody& A = bodies[a];
    RRigidBody& B = bodies[b];
    if (!A.m_isStatic) {
      A.m_linearImpulse_W -= J;
      A.m_angularImpulse_W -= rA.cross(J);
    }
    if (!B.m_isStatic) {
      B.m_linearImpulse_W += J;
      B.m_angularImpulse_W += rB.cross(J);
    }
  };
  // An impulse at the end of the step acts where the contact is then: the point moves with
  // the bodies, with the lighter one's displacement when one is much heavier (the ground's
  // contact with a sliding box moves with the box). The same point for both bodies keeps
  // angular momentum exact. Lever arms are about the centres at the start of the step;
  // UpdateObjects moves them to where the centres end.
  auto accumulateEnd = [&bodies, this, dt](std::uint32_t a, std::uint32_t b, const RVec3& rA,
                                           const RVec3& rB, const RVec3& J) {
    RRigidBody& A = bodies[a];
    RRigidBody& B = bodies[b];
    if (J.isZero(0)) return;
    const RSolverBody& sa = m_solverBodies[a];
    const RSolverBody& sb = m_solverBodies[b];
    const RVec3 moveA = (sa.vMid + sa.vp) * dt, moveB = (sb.vMid + sb.vp) * dt;
    const RVec3 shift = (sa.invM * moveA + sb.invM * moveB) / (sa.invM + sb.invM);
    if (!A.m_isStatic) {
      A.m_endLinearImpulse_W -= J;
      A.m_endAngularImpulse_W -= (rA + shift).cross(J);
    }
    if (!B.m_isStatic) {
      B.m_endLinearImpulse_W += J;
      B.m_endAngularImpulse_W += (rB + shift).cross(J);
    }
  };
  for (const RContactRow& r : m_rows) {
    accumulate(r.a, r.b, r.rA, r.rB, r.lambdaN * r.n.d);
    if (r.lambdaE != 0) accumulateEnd(r.a, r.b, r.rA, r.rB, r.lambdaE * r.n.d);
    m_contacts[r.contact].normalImpulse[r.point] = r.lambdaN + r.lambdaE;
    const RBlock& blk = m_blocks[r.block];
    const RContactPoint& p = m_contacts[r.contact].manifold.points[r.point];
    RWarmStart w;
    w.pair = PairKey(r.a, r.b);
    w.feature = p.featureId;
    w.point_A = bodies[r.a].m_q_WB.conjugate() * (p.position - bodies[r.a].m_x_W);
    w.lambdaN = r.lambdaN;
    w.lambdaE = r.lambdaE;
    bool finite = std::isfinite(w.lambdaN) && std::isfinite(w.lambdaE) && AllFinite(w.point_A);
    for (int ph = 0; ph < 2; ++ph) {
      w.tangentImpulse[ph] = blk.lambdaT1[ph] * blk.t[0].d + blk.lambdaT2[ph] * blk.t[1].d;
      w.twistImpulse[ph] = blk.lambdaTwist[ph];
      finite = finite && AllFinite(w.tangentImpulse[ph]) && std::isfinite(w.twistImpulse[ph]);
    }
    // A step that overflowed must not seed the next one (its bodies are put back).
    if (finite) m_warmNext.push_back(w);
  }
  for (const RBlock& blk : m_blocks) {
    const RContactRow& r = m_rows[blk.first];
    accumulate(r.a, r.b, blk.rA, blk.rB, blk.lambdaT1[0] * blk.t[0].d + blk.lambdaT2[0] * blk.t[1].d);
    accumulateEnd(r.a, r.b, blk.rA, blk.rB, blk.lambdaT1[1] * blk.t[0].d + blk.lambdaT2[1] * blk.t[1].d);
    // The twist: a pure torque about the normal.
    if (!bodies[r.a].m_isStatic) {
      bodies[r.a].m_angularImpulse_W -= blk.lambdaTwist[0] * blk.normal;
      bodies[r.a].m_endAngularImpulse_W -= blk.lambdaTwist[1] * blk.normal;
    }
    if (!bodies[r.b].m_isStatic) {
      bodies[r.b].m_angularImpulse_W += blk.lambdaTwist[0] * blk.normal;
      bodies[r.b].m_endAngularImpulse_W += blk.lambdaTwist[1] * blk.normal;
    }
  }
  // An impact's impulse is a one-off, not remembered: carried into the next step it would
  // push apart bodies that are already separating, energy from nowhere. It is reported at
  // the manifold's deepest point.
  for (const RImpactRow& r : m_impacts) {
    if (r.lambdaN == 0) continue;
    RRigidBody& A = bodies[r.a];
    RRigidBody& B = bodies[r.b];
    if (!A.m_isStatic) A.m_linearImpulse_W -= r.impulse, A.m_angularImpulse_W -= r.angularA;
    if (!B.m_isStatic) B.m_linearImpulse_W += r.impulse, B.m_angularImpulse_W += r.angularB;
    m_contacts[r.contact].normalImpulse[r.point] += r.lambdaN;
  }
  // Impacts within the step: the bodies move with their piecewise path's velocity and get
  // the rest at the end (SolveImpacts).
  for (std::size_t i = 0; i < n; ++i) {
    const RSolverBody& s = m_solverBodies[i];
    RRigidBody& b = bodies[i];
    if (b.m_isStatic || s.deferV.isZero(0)) continue;
    const RVec3 J = s.deferV / b.m_invMass;
    b.m_linearImpulse_W -= J;
    b.m_deferredImpulse_W = J;
    // The contact phase's impulses act on the body at its start-of-step pose, but it then
    // moves deferV dt less than its final velocity would take it: the spin that keeps
    // angular momentum exact (the orbital term x x m v misses dt deferV x J_contact).
    b.m_angularImpulse_W += dt * s.deferV.cross(s.contactDeltaV / b.m_invMass);
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (bodies[i].m_isStatic) continue;
    bodies[i].m_pseudoVelocity_W = m_solverBodies[i].vp;
    bodies[i].m_pseudoAngular_W = m_solverBodies[i].wp;
  }
  std::sort(m_warmNext.begin(), m_warmNext.end(), [](const RWarmStart& x, const RWarmStart& y) {
    return x.pair < y.pair || (x.pair == y.pair && x.feature < y.feature);
  });
  std::swap(m_warm, m_warmNext);
}

namespace {

// The change of row i's normal velocity per unit normal impulse at row j: the (i, j) entry
// of the contact system's matrix J M^-1 J^T, from the bodies the two rows share (a static
// body's inverse mass and inertia are zero, so it couples nothing).
template <class Row>
RScalar Coupling(const Row& ri, const Row& rj, RScalar invMai, RScalar invMbi) {
  const RScalar dd = ri.n.d.dot(rj.n.d);
  RScalar k = 0;
  if (ri.a == rj.a) k += invMai * dd + ri.n.rAxd.dot(rj.n.iA);
  if (ri.a == rj.b) k -= invMai * dd + ri.n.rAxd.dot(rj.n.iB);
  if (ri.b == rj.a) k -= invMbi * dd + ri.n.rBxd.dot(rj.n.iA);
  if (ri.b == rj.b) k += invMbi * dd + ri.n.rBxd.dot(rj.n.iB);
  return k;
}

// In-place Cholesky factorisation L L^T of a symmetric positive definite m x m matrix,
// row-major with leading dimension ld, lower triangle, that skips the zeros before each
// row's first non-zero (first[i] <= i): the factor keeps that envelope, so a chain of
// manifolds (a stack: each couples only with its neighbours) costs O(m b^2) for bandwidth b
// instead of O(m^3). False if the matrix is not positive definite.
bool EnvelopeCholesky(RScalar* M, int m, int ld, const int* first, RScalar* inverseDiagonal) {
  for (int j = 0; j < m; ++j) {
    RScalar* Lj = M + j * ld;
    for (int i = first[j]; i <= j; ++i) {
      const RScalar* Li = M + i * ld;
      RScalar s = Lj[i];
      for (int k = std::max(first[i], first[j]); k < i; ++k) s -= Lj[k] * Li[k];
      if (i < j) {
        Lj[i] = s * inverseDiagonal[i];
      } else {
        if (!(s > 0)) return false;
        Lj[j] = std::sqrt(s);
        inverseDiagonal[j] = 1 / Lj[j];
      }
    }
  }
  return true;
}
// Solves L L^T x = x in place with the factor above.
void EnvelopeCholeskySolve(const RScalar* L, int m, int ld, const int* first, RScalar* x) {
  for (int i = 0; i < m; ++i) {
    RScalar s = x[i];
    for (int k = first[i]; k < i; ++k) s -= L[i * ld + k] * x[k];
    x[i] = s / L[i * ld + i];
  }
  for (int i = m - 1; i >= 0; --i) {
    x[i] /= L[i * ld + i];
    for (int k = first[i]; k < i; ++k) x[k] -= L[i * ld + k] * x[i];
  }
}

}  // namespace

// Islands (bodies connected through contacts; static bodies connect nothing) of several
// manifolds and at most kDirectRows rows get their normal impulses solved exactly after the
// iterations: the linear complementarity problem v = b + K lambda >= target, lambda >= 0,
// one of the two tight per row, by an active-set method on the island's dense matrix K.
// Sequential impulses pass momentum along a chain a fraction at a time, as small as the
// mass ratio: 1000 kg on a 1 kg box takes thousands of passes to hold and sinks through it
// meanwhile; the direct solve holds it exactly in the first step. Friction keeps its
// iterated impulses, clamped again to the new cones. Larger islands (a whole pile) keep
// the iterated answer: a dense solve grows as the cube of the rows.
void RIntegrator::BuildIslands(const std::vector<RRigidBody>& bodies) {
  const std::size_t n = bodies.size();
  m_islandParent.resize(n);
  for (std::size_t i = 0; i < n; ++i) m_islandParent[i] = static_cast<std::uint32_t>(i);
  auto find = [this](std::uint32_t i) {
    while (m_islandParent[i] != i) i = m_islandParent[i] = m_islandParent[m_islandParent[i]];
    return i;
  };
  for (const RContactRow& r : m_rows) {
    if (bodies[r.a].m_isStatic || bodies[r.b].m_isStatic) continue;
    const std::uint32_t x = find(r.a), y = find(r.b);
    // The smaller index as root: the grouping does not depend on the order of unions.
    if (x != y) m_islandParent[std::max(x, y)] = std::min(x, y);
  }
  m_islandRows.clear();
  for (std::uint32_t i = 0; i < m_rows.size(); ++i) {
    const RContactRow& r = m_rows[i];
    m_islandRows.emplace_back(find(bodies[r.a].m_isStatic ? r.b : r.a), i);
  }
  std::sort(m_islandRows.begin(), m_islandRows.end());
  m_islands.clear();
  for (std::size_t first = 0; first < m_islandRows.size();) {
    std::size_t last = first + 1;
    while (last < m_islandRows.size() && m_islandRows[last].first == m_islandRows[first].first) {
      ++last;
    }
    // One manifold alone is already solved exactly by its block.
    const bool several = m_rows[m_islandRows[first].second].contact !=
                         m_rows[m_islandRows[last - 1].second].contact;
    if (several && last - first <= std::size_t(kDirectRows)) m_islands.emplace_back(first, last);
    first = last;
  }
}

void RIntegrator::SolveIslands(RPhase phase) {
  for (const auto& [first, last] : m_islands) {
    m_islandIndex.clear();
    for (std::size_t k = first; k < last; ++k) m_islandIndex.push_back(m_islandRows[k].second);
    m_islandKReady = false;
    SolveIslandDirect(phase);
  }
}

// The island's matrix K (m x m, row-major, in m_islandK), assembled from the pairs of
// manifolds that share a dynamic body: the others couple nothing, and in a stack or a pile
// a manifold touches only a few of the island's others.
void RIntegrator::AssembleIslandMatrix() {
  const int m = static_cast<int>(m_islandIndex.size());
  RScalar* K = m_islandK.data();
  std::fill(K, K + std::size_t(m) * m, RScalar(0));
  // Manifolds as runs of consecutive rows (rows come grouped by contact).
  m_islandRuns.clear();
  for (int i = 0; i < m;) {
    int j = i + 1;
    while (j < m && m_rows[m_islandIndex[j]].contact == m_rows[m_islandIndex[i]].contact) ++j;
    m_islandRuns.emplace_back(i, j);
    i = j;
  }
  // Each row's non-zero columns lie within [lo, hi]: the loops below visit only those.
  for (int i = 0; i < m; ++i) m_islandLo[i] = i, m_islandHi[i] = i;
  auto dynamic = [this](std::uint32_t body) { return m_solverBodies[body].invM > 0; };
  for (std::size_t s = 0; s < m_islandRuns.size(); ++s) {
    const RContactRow& rs = m_rows[m_islandIndex[m_islandRuns[s].first]];
    for (std::size_t t = s; t < m_islandRuns.size(); ++t) {
      const RContactRow& rt = m_rows[m_islandIndex[m_islandRuns[t].first]];
      const bool shared = ((rs.a == rt.a || rs.a == rt.b) && dynamic(rs.a)) ||
                          ((rs.b == rt.a || rs.b == rt.b) && dynamic(rs.b));
      if (!shared) continue;
      for (int i = m_islandRuns[s].first; i < m_islandRuns[s].second; ++i) {
        const RContactRow& ri = m_rows[m_islandIndex[i]];
        const RScalar invMa = m_solverBodies[ri.a].invM, invMb = m_solverBodies[ri.b].invM;
        for (int j = m_islandRuns[t].first; j < m_islandRuns[t].second; ++j) {
          const RScalar k = Coupling(ri, m_rows[m_islandIndex[j]], invMa, invMb);
          K[i * m + j] = k;
          K[j * m + i] = k;
        }
        const int first = m_islandRuns[t].first, last = m_islandRuns[t].second - 1;
        m_islandLo[i] = std::min(m_islandLo[i], first), m_islandHi[i] = std::max(m_islandHi[i], last);
        for (int j = first; j <= last; ++j) {
          m_islandLo[j] = std::min(m_islandLo[j], m_islandRuns[s].first);
          m_islandHi[j] = std::max(m_islandHi[j], m_islandRuns[s].second - 1);
        }
      }
    }
  }
  m_islandKReady = true;
}

// The active-set solve of one island's normal rows (m_islandIndex), on the velocities or on
// the pseudo-velocities. Applies the answer and returns true if it converged; otherwise
// leaves the iterated impulses as they are.
bool RIntegrator::SolveIslandDirect(RPhase phase) {
  const bool pseudo = phase == RPhase::kPosition;
  const int m = static_cast<int>(m_islandIndex.size());
  const int ld = m;
  m_islandK.resize(std::size_t(kDirectRows) * kDirectRows);
  m_islandL.resize(std::size_t(kDirectRows) * kDirectRows);
  m_islandB.resize(kDirectRows), m_islandX.resize(kDirectRows), m_islandActive.resize(kDirectRows);
  m_islandMap.resize(kDirectRows), m_islandFirst.resize(kDirectRows);
  m_islandLo.resize(kDirectRows), m_islandHi.resize(kDirectRows);
  m_islandInvDiag.resize(kDirectRows), m_islandR.resize(kDirectRows);
  RScalar* K = m_islandK.data();
  RScalar* b = m_islandB.data();
  RScalar* x = m_islandX.data();
  auto target = [phase](const RContactRow& r) { return Target(r, phase); };
  auto lambda = [phase](RContactRow& r) -> RScalar& { return Lambda(r, phase); };
  // An island the iterations left solved (a row that pushes is at its target, one that
  // does not is at or above it) is left alone. Only to rounding: with a looser test
  // (1e-6 m/s) a 1000 kg box on a 1 kg one, skipped step after step, lost its hold after
  // 170 steps and sank through.
  constexpr RScalar kSolved = 1e-9;  // m/s
  RScalar worst = 0;
  bool anyActive = false;
  for (int i = 0; i < m; ++i) {
    RContactRow& r = m_rows[m_islandIndex[i]];
    const RSolverBody& sa = m_solverBodies[r.a];
    const RSolverBody& sb = m_solverBodies[r.b];
    const RScalar v = pseudo ? Speed(r.n, sa.vp, sa.wp, sb.vp, sb.wp)
                             : Speed(r.n, sa.v, sa.w, sb.v, sb.w);
    b[i] = v;  // for now; b proper below
    const RScalar miss = target(r) - v;
    worst = std::max(worst, lambda(r) > 0 ? std::abs(miss) : miss);
    m_islandActive[i] = lambda(r) > 0 || miss > 0;
    anyActive = anyActive || m_islandActive[i];
  }
  if (!anyActive || worst <= kSolved) return true;
  if (!m_islandKReady) AssembleIslandMatrix();
  // b: the velocity each row would have with none of the island's normal impulses.
  for (int i = 0; i < m; ++i) {
    RScalar s = b[i];
    for (int j = m_islandLo[i]; j <= m_islandHi[i]; ++j) s -= K[i * ld + j] * lambda(m_rows[m_islandIndex[j]]);
    b[i] = s;
  }
  RScalar maxDiag = 0;
  for (int i = 0; i < m; ++i) maxDiag = std::max(maxDiag, K[i * ld + i]);
  // Four points of one face constrain three degrees of freedom: K is only semi-definite. A
  // relative 1e-9 on the diagonal makes it definite and picks (nearly) the minimum-norm
  // impulses among the equivalent ones; it costs a velocity error of 1e-9 of the impulse's.
  const RScalar ridge = 1e-9 * maxDiag;
  constexpr RScalar kTolerance = 1e-9;  // m/s: a violation smaller than this is rounding
  constexpr int kRounds = 16;
  const int* map = m_islandMap.data();
  for (int round = 0; round < kRounds; ++round) {
    int na = 0;
    for (int i = 0; i < m; ++i) {
      if (m_islandActive[i]) m_islandMap[na++] = i;
    }
    RScalar* L = m_islandL.data();
    int* envelope = m_islandFirst.data();
    for (int p = 0; p < na; ++p) {
      // Active rows before p whose columns may be non-zero: from the first at or after lo.
      const int start = static_cast<int>(std::lower_bound(map, map + p, m_islandLo[map[p]]) - map);
      envelope[p] = p;
      for (int q = start; q <= p; ++q) {
        const RScalar k = K[map[p] * ld + map[q]];
        L[p * na + q] = k;
        if (k != 0 && q < envelope[p]) envelope[p] = q;
      }
      L[p * na + p] += ridge;
    }
    if (!EnvelopeCholesky(L, na, na, envelope, m_islandInvDiag.data())) return false;
    for (int p = 0; p < na; ++p) {
      const RContactRow& r = m_rows[m_islandIndex[m_islandMap[p]]];
      x[p] = target(r) - b[m_islandMap[p]];
    }
    EnvelopeCholeskySolve(L, na, na, envelope, x);
    // Iterative refinement against K itself: the ridge biases the answer in the directions
    // of K whose eigenvalue s is small against it (a heavy body's, about 1/M), and each
    // correction through the same factor multiplies that bias by ridge / (s + ridge). The
    // light body's directions converge at once; at 1:1e7 it takes 5 to 10 corrections, at
    // 1:1e9 about 34 (x0.67 each); without them the light box is squeezed out. Corrections
    // go on while the velocity residual is above rounding (1e-12 m/s) and falls by at least
    // 5% a pass. At
    // 1:1e10 it falls by less (x0.95): the loop stops with 0.09 m/s left, and that ratio
    // breaks (README, stability envelope); a per-row ridge, tried, made stacks worse. The
    // corrections leave the null space of four coplanar points alone (its residual is 0).
    constexpr int kMaxRefinements = 64;
    constexpr RScalar kRefined = 1e-12;  // m/s
    RScalar* residual = m_islandR.data();
    RScalar previous = std::numeric_limits<RScalar>::infinity();
    for (int pass = 0; pass < kMaxRefinements; ++pass) {
      RScalar largest = 0;
      for (int p = 0; p < na; ++p) {
        const int i = map[p];
        RScalar v = b[i];
        for (int q = static_cast<int>(std::lower_bound(map, map + na, m_islandLo[i]) - map);
             q < na && map[q] <= m_islandHi[i]; ++q) {
          v += K[i * ld + map[q]] * x[q];
        }
        residual[p] = target(m_rows[m_islandIndex[i]]) - v;
        largest = std::max(largest, std::abs(residual[p]));
      }
      if (largest <= kRefined || !(largest < RScalar(0.95) * previous)) break;
      previous = largest;
      EnvelopeCholeskySolve(L, na, na, envelope, residual);
      for (int p = 0; p < na; ++p) x[p] += residual[p];
    }
    bool changed = false;
    for (int p = 0; p < na; ++p) {
      if (x[p] < 0) m_islandActive[m_islandMap[p]] = false, changed = true;
    }
    if (changed) continue;
    for (int i = 0; i < m; ++i) {
      if (m_islandActive[i]) continue;
      RScalar v = b[i];
      for (int p = static_cast<int>(std::lower_bound(map, map + na, m_islandLo[i]) - map);
           p < na && map[p] <= m_islandHi[i]; ++p) {
        v += K[i * ld + map[p]] * x[p];
      }
      const RContactRow& r = m_rows[m_islandIndex[i]];
      if (v < target(r) - kTolerance) m_islandActive[i] = true, changed = true;
    }
    if (changed) continue;
    // Converged: apply the differences.
    int p = 0;
    for (int i = 0; i < m; ++i) {
      RContactRow& r = m_rows[m_islandIndex[i]];
      const RScalar next = m_islandActive[i] ? x[p++] : RScalar(0);
      RScalar& current = lambda(r);
      const RScalar d = next - current;
      current = next;
      if (d == 0) continue;
      RSolverBody& sa = m_solverBodies[r.a];
      RSolverBody& sb = m_solverBodies[r.b];
      if (pseudo) {
        Push(r.n, d, sa.invM, sb.invM, sa.vp, sa.wp, sb.vp, sb.wp);
        continue;
      }
      Push(r.n, d, sa.invM, sb.invM, sa.v, sa.w, sb.v, sb.w);
    }
    // Friction back inside the cones of the new normal impulses.
    if (!pseudo) {
      for (int i = 0; i < m; ++i) {
        const std::uint32_t blk = m_rows[m_islandIndex[i]].block;
        if (i == 0 || blk != m_rows[m_islandIndex[i - 1]].block) SolvePatch(m_blocks[blk], true, phase);
      }
    }
    return true;
  }
  return false;
}

// Applies the rows' and patches' accumulated impulses of a phase (last step's, matched when
// the rows were built) to the solver bodies' velocities.
void RIntegrator::WarmStart(RPhase phase) {
  const int ph = phase == RPhase::kEnd ? 1 : 0;
  for (RContactRow& r : m_rows) {
    const RScalar lambda = Lambda(r, phase);
    if (lambda == 0) continue;
    RSolverBody& sa = m_solverBodies[r.a];
    RSolverBody& sb = m_solverBodies[r.b];
    Push(r.n, lambda, sa.invM, sb.invM, sa.v, sa.w, sb.v, sb.w);
  }
  for (const RBlock& blk : m_blocks) ApplyPatch(blk, blk.lambdaT1[ph], blk.lambdaT2[ph], blk.lambdaTwist[ph]);
}

// Applies patch impulses (tangential at the centroid, twist about the normal) to the solver
// bodies' velocities.
void RIntegrator::ApplyPatch(const RBlock& blk, RScalar d1, RScalar d2, RScalar dTwist) {
  const RContactRow& r = m_rows[blk.first];
  RSolverBody& sa = m_solverBodies[r.a];
  RSolverBody& sb = m_solverBodies[r.b];
  if (d1 != 0) Push(blk.t[0], d1, sa.invM, sb.invM, sa.v, sa.w, sb.v, sb.w);
  if (d2 != 0) Push(blk.t[1], d2, sa.invM, sb.invM, sa.v, sa.w, sb.v, sb.w);
  if (dTwist != 0) sa.w -= dTwist * blk.twistIA, sb.w += dTwist * blk.twistIB;
}

// A manifold's friction: the tangential impulse at its centroid stops the sliding there,
// within the Coulomb disc of mu times the manifold's total normal impulse, and the twist
// stops the spin about the normal within mu times the sum of each point's normal impulse
// times its distance from the centroid. One patch instead of friction at each point: the
// points' friction solved one after another twists the body a little and leaves each
// point's impulse slightly off the sliding direction, which loses about 1% of the friction
// of a box sliding down an incline. clampOnly: only bring the impulses back inside limits
// that the normal impulses changed.
void RIntegrator::SolvePatch(RBlock& blk, bool clampOnly, RPhase phase) {
  const int ph = phase == RPhase::kEnd ? 1 : 0;
  RContactRow* rows = &m_rows[blk.first];
  RScalar normal = 0, twistArm = 0;
  for (int i = 0; i < blk.count; ++i) {
    const RScalar l = Lambda(rows[i], phase);
    normal += l, twistArm += l * rows[i].lever;
  }
  const RSolverBody& sa = m_solverBodies[rows[0].a];
  const RSolverBody& sb = m_solverBodies[rows[0].b];
  RScalar lt1 = blk.lambdaT1[ph], lt2 = blk.lambdaT2[ph], lw = blk.lambdaTwist[ph];
  if (!clampOnly) {
    // Both tangents at once, through the 2 x 2 effective mass: one at a time the answer
    // would depend on which two tangents the basis picked, and that choice jumps when the
    // normal's z component changes sign (a slope moved 1e6 m away slid 1e-5 m further).
    const Eigen::Matrix<RScalar, 2, 1> step = TangentStep(blk.t[0], blk.t[1], Speed(blk.t[0], sa.v, sa.w, sb.v, sb.w),
                                 Speed(blk.t[1], sa.v, sa.w, sb.v, sb.w));
    lt1 += step.x(), lt2 += step.y();
    if (blk.kTwist > 0) lw -= blk.normal.dot(sb.w - sa.w) / blk.kTwist;
  }
  const RScalar limit = blk.friction * normal;
  const RScalar norm = std::sqrt(lt1 * lt1 + lt2 * lt2);  // std::hypot: 5% of a pile step
  if (norm > limit) lt1 *= limit / norm, lt2 *= limit / norm;
  const RScalar twistLimit = blk.friction * twistArm;
  lw = std::clamp(lw, -twistLimit, twistLimit);
  const RScalar d1 = lt1 - blk.lambdaT1[ph], d2 = lt2 - blk.lambdaT2[ph], dw = lw - blk.lambdaTwist[ph];
  blk.lambdaT1[ph] = lt1, blk.lambdaT2[ph] = lt2, blk.lambdaTwist[ph] = lw;
  ApplyPatch(blk, d1, d2, dw);
}

// The end of the step. The contact impulses found so far act at its start, on the velocity
// the bodies move with (the mid-step velocity of kick-drift-kick), which is what keeps a
// resting box exactly in place; but the step's second half-kick of gravity then leaves it
// with -g dt / 2 at the end, and a box stuck on a slope with g sin(theta) dt / 2 down the
// slope: at rest, reported moving. So every contact that is closed at the end of the step
// gets a second impulse there: no approach, friction within its cone, solved like the
// first (blocks, patches, islands) on the end velocities. A resting body then ends each
// step at rest, and the support it needs is shared between the two ends of the step, the
// way kick-drift-kick shares a force; a sliding box's friction is shared the same way. The
// impulses are inelastic (targets of zero, never pulling): they cannot add energy.
void RIntegrator::SolveEndOfStep(const std::vector<RRigidBody>& bodies, RScalar dt) {
  const RScalar halfDt = RScalar(0.5) * dt;
  bool any = false;
  for (RContactRow& r : m_rows) {
    const RSolverBody& sa = m_solverBodies[r.a];
    const RSolverBody& sb = m_solverBodies[r.b];
    // Closed at the end: the gap after moving with this step's velocities (a touching band
    // of a micrometre per metre of size for rounding).
    const RScalar vn = Speed(r.n, sa.v, sa.w, sb.v, sb.w);
    const RScalar gapEnd = r.gap + (vn - r.deferN) * dt;
    const RScalar band = 1e-6 * (bodies[r.a].BoundingRadius() + bodies[r.b].BoundingRadius());
    // A contact that closes faster than the restitution threshold is an impact, and the
    // next step's impact phase bounces it; stopped here it would end inelastic.
    auto accel = [&](std::uint32_t i) -> RVec3 {
      const RRigidBody& b = bodies[i];
      return b.m_isStatic ? RVec3::Zero() : RVec3(b.m_force_W * b.m_invMass + m_settings.gravity_W);
    };
    const RScalar vnEnd = vn + halfDt * r.n.d.dot(accel(r.b) - accel(r.a));
    // A body that had an impact this step is not at rest: its end-of-step velocity is the
    // impact's outcome, left as it is.
    const bool impacted = sa.tau > 0 || sb.tau > 0;
    // Nor is a polyhedron whose spin carries the contact point further than the slop within
    // the step: this impulse is solved with the lever arms of the step's start and applied
    // at its end, and on a cube spinning at 5 rad/s the arm has turned 0.08 m by then, so an
    // impulse that stops the approach in the solver's frame adds energy in the body's (a
    // pair in the debris cloud gained 1e-5 of its energy in one step). A sphere's contact
    // point does not turn with it.
    auto arc = [&](std::uint32_t i, const RSolverBody& s, const RVec3& arm) {
      return bodies[i].Polyhedron_B() ? s.w.norm() * arm.norm() * dt : RScalar(0);
    };
    const bool spinning = arc(r.a, sa, r.rA) + arc(r.b, sb, r.rB) > m_settings.penetrationSlop;
    r.endTarget = gapEnd <= band && vnEnd >= -m_settings.restitutionThreshold && !impacted &&
                          !spinning
                      ? RScalar(0) : kNever;
    if (r.endTarget == kNever) r.lambdaE = 0;
    any = any || r.endTarget == 0;
  }
  if (!any) {
    for (RContactRow& r : m_rows) r.lambdaE = 0;
    for (RBlock& blk : m_blocks) blk.lambdaT1[1] = blk.lambdaT2[1] = blk.lambdaTwist[1] = 0;
    return;
  }
  // The end velocities: the second half-kick of the applied forces and gravity.
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const RRigidBody& b = bodies[i];
    RSolverBody& s = m_solverBodies[i];
    s.vMid = s.v - s.deferV;
    if (b.m_isStatic) continue;
    s.v += (b.m_force_W * b.m_invMass + m_settings.gravity_W) * halfDt;
    s.w += s.invI * (b.m_torque_W * halfDt);
  }
  WarmStart(RPhase::kEnd);  // last step's end impulses, found with the rows
  const int iterations = std::max(1, m_settings.solverIterations);
  const std::size_t nBlocks = m_blocks.size();
  for (int it = 0; it < iterations; ++it) {
    for (std::size_t bb = 0; bb < nBlocks; ++bb) {
      RBlock& blk = m_blocks[(it % 2 == 0) ? bb : nBlocks - 1 - bb];
      SolveNormalBlock(blk, &m_rows[blk.first], RPhase::kEnd);
      SolvePatch(blk, false, RPhase::kEnd);
    }
  }
  SolveIslands(RPhase::kEnd);
}

// The geometry of an impact within the step, at time t (updated): the narrow phase again at
// the poses the bodies have then (moved along their paths; orientations as at the start),
// advanced conservatively until the leading points touch: t += gap / approach, which for
// two spheres converges to the exact moment, so an oblique collision gets the normal along
// the line of centres at contact, not at the start of the step. The impulse point is the
// centre of the leading points, the same for both bodies (lever arms from where their
// centres are at t), so angular momentum is exact. False if they do not meet this step.
template <class Advance>
bool RIntegrator::ImpactGeometry(const RRigidBody& A, const RRigidBody& B, RSolverBody& sa,
                                 RSolverBody& sb, const Advance& advance, RScalar& t, RScalar dt,
                                 RVec3& rA, RVec3& rB, RDirection* dir) const {
  const RConvexShape shapeA = ShapeOf(A), shapeB = ShapeOf(B);
  const RRelativePose X0 = RelativePose(A, B);
  const RMat3 R_WA = A.m_q_WB.toRotationMatrix();
  const RScalar tolerance = RCollisionSolver::kTouchingTolerance * (A.BoundingRadius() + B.BoundingRadius());
  constexpr int kAdvances = 16;
  for (int k = 0; k < kAdvances; ++k) {
    advance(sa, t), advance(sb, t);
    RRelativePose X = X0;
    X.t_AB += R_WA.transpose() * (sb.moved - sa.moved);
    const RContactManifold m =
        RCollisionSolver::Manifold(shapeA, shapeB, X, std::numeric_limits<RScalar>::max());
    if (m.pointCount == 0) return false;
    int deepest = 0;
    for (int i = 1; i < m.pointCount; ++i) {
      if (m.points[i].separation < m.points[deepest].separation) deepest = i;
    }
    const RScalar lead = m.points[deepest].separation;
    RVec3 centre_A = RVec3::Zero();
    int leads = 0;
    for (int i = 0; i < m.pointCount; ++i) {
      if (m.points[i].separation <= lead + m_settings.penetrationSlop) {
        centre_A += m.points[i].position, ++leads;
      }
    }
    // No point within the slop of the deepest: the separations are not numbers (bodies
    // flung to 1e300 m/s overflow the pair's pose). No impact to find (found by fuzz_world).
    if (leads == 0) return false;
    centre_A /= leads;
    // World, relative to each body's centre of mass at t.
    const RVec3 n = R_WA * m.normal;
    const RVec3 p = R_WA * centre_A + sa.moved;  // from A's centre at the start
    rA = p - sa.moved;
    rB = p - (B.m_x_W - A.m_x_W) - sb.moved;
    RVec3 t1, t2;
    OrthonormalBasis(n, t1, t2);
    SetDirection(dir[0], n, rA, rB, sa, sb);
    SetDirection(dir[1], t1, rA, rB, sa, sb);
    SetDirection(dir[2], t2, rA, rB, sa, sb);
    if (lead <= tolerance) return true;
    const RScalar vn = Speed(dir[0], sa.v, sa.w, sb.v, sb.w);
    if (vn >= 0) return false;
    // Meeting after the step: not an impact of this step, unless the gap left is within
    // the slop (a row of balls a micrometre apart: the impulse goes down the row now).
    if (t + lead / -vn > dt) return lead <= m_settings.penetrationSlop;
    t += lead / -vn;
  }
  return true;  // close enough: the remaining gap shrinks every advance
}

// The impact phase: every manifold approaching faster than the restitution threshold, and
// reaching contact within the step, bounces through its impact row: the impulse that turns
// the approach speed vn into -e vn, then friction at the same point bounded by mu times
// that impulse. Passes repeat while some manifold still impacts, so an impulse travels
// along a chain of touching bodies the way it does in a Newton's cradle (the striker stops,
// the last ball leaves), instead of being shared out as a block. Each application changes
// the kinetic energy by (e^2 - 1) vn^2 / (2 k) <= 0, and friction only removes sliding, so
// no pass can add energy whatever the order.
//
// Impacts happen at their time within the step, not at its start: a contact that is gap
// away at approach speed vn hits at t = gap / -vn (never before an earlier impact of either
// body). Each body keeps the displacement it has travelled up to its last impact; the
// impulse acts where the contact then is (one point for both bodies, moved with the lighter
// one, so angular momentum is exact); and the body moves during the step with the
// velocity that gives the piecewise path (before the impact, then after it). The velocity
// it ends with is the one after its impacts: the difference is deferred to the end of the
// step. A missile at 2 km/s stops at the face of the plate it hits, not a step short of it.
void RIntegrator::SolveImpacts(const std::vector<RRigidBody>& bodies, RScalar dt) {
  for (RSolverBody& s : m_solverBodies) {
    s.moved.setZero(), s.tau = 0;
    s.deferV.setZero();
  }
  const std::size_t count = m_impacts.size();
  if (count == 0) {
    for (RSolverBody& s : m_solverBodies) s.vImpacts = s.v;
    return;
  }
  // Moves a body along its present velocity up to time t of the step.
  auto advance = [](RSolverBody& s, RScalar t) {
    if (t <= s.tau) return;
    s.moved += s.v * (t - s.tau), s.tau = t;
  };
  bool anyImpact = false;
  const int passes = std::max(1, m_settings.solverIterations);
  for (int pass = 0; pass < passes; ++pass) {
    bool any = false;
    for (std::size_t ii = 0; ii < count; ++ii) {
      RImpactRow& r = m_impacts[(pass % 2 == 0) ? ii : count - 1 - ii];
      RSolverBody& sa = m_solverBodies[r.a];
      RSolverBody& sb = m_solverBodies[r.b];
      const RScalar vn0 = Speed(r.dir[0], sa.v, sa.w, sb.v, sb.w);
      if (vn0 >= -m_settings.restitutionThreshold || r.gap > -vn0 * dt) continue;
      // When: the gap closed at this approach, and no earlier than either body's last.
      RScalar t = std::max(sa.tau, sb.tau);
      if (r.gap > 0) t = std::max(t, r.gap / -vn0);
      if (t > dt) continue;
      advance(sa, t), advance(sb, t);
      RDirection dir[3];
      RVec3 rA, rB;
      if (t == 0) {
        // At the start: the manifold's own impact point and normal.
        rA = r.rA, rB = r.rB;
        for (int k = 0; k < 3; ++k) SetDirection(dir[k], r.dir[k].d, rA, rB, sa, sb);
      } else if (!ImpactGeometry(bodies[r.a], bodies[r.b], sa, sb, advance, t, dt, rA, rB, dir)) {
        r.miss = true;  // they pass each other, or meet only after the step
        continue;
      }
      const RScalar vn = Speed(dir[0], sa.v, sa.w, sb.v, sb.w);
      if (vn >= 0) continue;
      any = anyImpact = true;
      const RScalar dn = -(1 + r.restitution) * vn / dir[0].k;
      r.lambdaN += dn;
      Push(dir[0], dn, sa.invM, sb.invM, sa.v, sa.w, sb.v, sb.w);
      // Friction at the same point, within mu times this row's normal impulse so far.
      const Eigen::Matrix<RScalar, 2, 1> step = TangentStep(dir[1], dir[2], Speed(dir[1], sa.v, sa.w, sb.v, sb.w),
                                     Speed(dir[2], sa.v, sa.w, sb.v, sb.w));
      const RScalar lt1 = r.lambdaT1 + step.x(), lt2 = r.lambdaT2 + step.y();
      const RScalar limit = r.friction * r.lambdaN;
      const RScalar norm = std::sqrt(lt1 * lt1 + lt2 * lt2);
      const RScalar scale = norm > limit ? limit / norm : RScalar(1);
      const RScalar d1 = lt1 * scale - r.lambdaT1, d2 = lt2 * scale - r.lambdaT2;
      r.lambdaT1 += d1, r.lambdaT2 += d2;
      if (d1 != 0) Push(dir[1], d1, sa.invM, sb.invM, sa.v, sa.w, sb.v, sb.w);
      if (d2 != 0) Push(dir[2], d2, sa.invM, sb.invM, sa.v, sa.w, sb.v, sb.w);
      const RVec3 J = dn * dir[0].d + d1 * dir[1].d + d2 * dir[2].d;
      r.impulse += J, r.angularA += rA.cross(J), r.angularB += rB.cross(J);
    }
    if (!any) break;
  }
  for (RSolverBody& s : m_solverBodies) s.vImpacts = s.v;
  if (!anyImpact) return;
  // The velocity each body moves with this step gives its piecewise path; the rest of the
  // change waits for the end of the step. The contact phase works on the velocities after
  // the impacts, the bodies' real ones, so that its impulses, inelastic there, cannot add
  // energy; the difference is taken out of the motion only (FindImpulses).
  for (RSolverBody& s : m_solverBodies) {
    if (s.tau <= 0 || s.invM == 0) continue;
    advance(s, dt);
    // Rotation is not split: moving a body's orientation along a piecewise spin and then
    // handing it the deferred angular momentum would change its kinetic energy (which
    // depends on the orientation for unequal moments). It turns with its spin after the
    // impact for the whole step.
    s.deferV = s.v - s.moved / dt;
  }
}

// One manifold's normal rows: the block's minimum-norm answer when it pushes at every point,
// else one point at a time. On the velocities (towards the rows' targets, impulses lambdaN)
// or on the pseudo-velocities of position correction (pseudoTarget, lambdaP).
void RIntegrator::SolveNormalBlock(const RBlock& blk, RContactRow* rows, RPhase phase) {
  const bool pseudo = phase == RPhase::kPosition;
  RSolverBody& sa = m_solverBodies[rows[0].a];
  RSolverBody& sb = m_solverBodies[rows[0].b];
  RVec3& va = pseudo ? sa.vp : sa.v;
  RVec3& wa = pseudo ? sa.wp : sa.w;
  RVec3& vb = pseudo ? sb.vp : sb.v;
  RVec3& wb = pseudo ? sb.wp : sb.w;
  auto lambda = [phase](RContactRow& r) -> RScalar& { return Lambda(r, phase); };
  auto target = [phase](const RContactRow& r) { return Target(r, phase); };
  if (phase != RPhase::kVelocity) {
    // Most contacts need no position correction, and many are not in contact at the end of
    // the step: nothing to do unless some row does or did.
    bool active = false;
    for (int i = 0; i < blk.count; ++i) active = active || target(rows[i]) > 0 || lambda(rows[i]) > 0 || (phase == RPhase::kEnd && target(rows[i]) == 0);
    if (!active) return;
  }
  bool allTargets = true;
  for (int i = 0; i < blk.count; ++i) allTargets = allTargets && target(rows[i]) != kNever;
  if (blk.useBlock && allTargets) {
    Eigen::Matrix<RScalar, 4, 1> rhs = Eigen::Matrix<RScalar, 4, 1>::Zero();
    for (int i = 0; i < blk.count; ++i) rhs[i] = target(rows[i]) - Speed(rows[i].n, va, wa, vb, wb);
    const Eigen::Matrix<RScalar, 4, 1> delta = blk.pinv * rhs;
    bool valid = true;
    for (int i = 0; i < blk.count; ++i) valid = valid && lambda(rows[i]) + delta[i] >= 0;
    if (valid) {
      for (int i = 0; i < blk.count; ++i) {
        lambda(rows[i]) += delta[i];
        if (delta[i] != 0) Push(rows[i].n, delta[i], sa.invM, sb.invM, va, wa, vb, wb);
      }
      return;
    }
  }
  for (int i = 0; i < blk.count; ++i) {
    RContactRow& r = rows[i];
    const RScalar l = std::max(
        lambda(r) - (Speed(r.n, va, wa, vb, wb) - target(r)) / r.n.k, RScalar(0));
    const RScalar d = l - lambda(r);
    lambda(r) = l;
    if (d != 0) Push(r.n, d, sa.invM, sb.invM, va, wa, vb, wb);
  }
}

void RIntegrator::UpdateObjects(std::vector<RRigidBody>& bodies, RScalar dt) {
  const RScalar halfDt = RScalar(0.5) * dt;
  m_nonFiniteLast.clear();
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    RRigidBody& b = bodies[i];
    // A sleeping body has no velocity, and nothing touched it: it stays where it is.
    if (b.m_isStatic || b.m_sleeping) {
      b.m_force_W.setZero(), b.m_torque_W.setZero();
      b.m_linearImpulse_W.setZero(), b.m_angularImpulse_W.setZero();
      b.m_endLinearImpulse_W.setZero(), b.m_endAngularImpulse_W.setZero();
      b.m_deferredImpulse_W.setZero();
      continue;
    }
    const RVec3 x0 = b.m_x_W, v0 = b.m_v_W, w0 = b.m_w_B;
    const RQuat q0 = b.m_q_WB;

    // Linear: impulse, then kick-drift-kick with constant acceleration.
    const RVec3 accel = b.m_force_W * b.m_invMass + m_settings.gravity_W;
    const RVec3 vHalf = b.m_v_W + b.m_linearImpulse_W * b.m_invMass + accel * halfDt;
    b.m_x_W += vHalf * dt;
    b.m_v_W = vHalf + accel * halfDt;

    // Angular: impulse and half the torque's impulse, exact free flow, other half. A kick
    // is applied only when non-zero so that a free body's omega passes through bit for bit
    // (which is what lets RFreeRotation reuse its cached elliptic constants).
    const bool torque = !b.m_torque_W.isZero(0);
    const RVec3 kick0_W = b.m_angularImpulse_W + b.m_torque_W * halfDt;
    if (!kick0_W.isZero(0)) {
      b.m_w_B += b.m_invI_B.cwiseProduct(b.m_q_WB.conjugate() * kick0_W);
    }
    b.m_rotation.Advance(dt, b.m_w_B, b.m_q_WB);
    if (torque) {
      b.m_w_B += b.m_invI_B.cwiseProduct(b.m_q_WB.conjugate() * (b.m_torque_W * halfDt));
    }

    // Position correction: displacement without velocity (split impulses). A body it moves
    // faster than the sleep speed is not at rest.
    RScalar pseudoSpeed = 0;
    if (!b.m_pseudoVelocity_W.isZero(0) || !b.m_pseudoAngular_W.isZero(0)) {
      pseudoSpeed = b.m_pseudoVelocity_W.norm() + b.m_pseudoAngular_W.norm() * b.m_boundingRadius;
      b.m_x_W += b.m_pseudoVelocity_W * dt;
      b.m_q_WB = QuatExp(b.m_pseudoAngular_W * dt) * b.m_q_WB;
      b.m_q_WB.normalize();
      b.m_pseudoVelocity_W.setZero(), b.m_pseudoAngular_W.setZero();
    }

    // Impacts within the step: the velocity change deferred to its end.
    if (!b.m_deferredImpulse_W.isZero(0)) {
      b.m_v_W += b.m_deferredImpulse_W * b.m_invMass;
      b.m_deferredImpulse_W.setZero();
    }
    // Contact impulses at the end of the step, in the body frame the step ends with. Their
    // angular part was summed about the centre of mass at the start of the step; about the
    // centre it ends at, each impulse J acting at a point p has the lever arm
    // (p - x0) - (x - x0).
    if (!b.m_endLinearImpulse_W.isZero(0) || !b.m_endAngularImpulse_W.isZero(0)) {
      const RVec3 h_W = b.m_endAngularImpulse_W - (b.m_x_W - x0).cross(b.m_endLinearImpulse_W);
      b.m_v_W += b.m_endLinearImpulse_W * b.m_invMass;
      b.m_w_B += b.m_invI_B.cwiseProduct(b.m_q_WB.conjugate() * h_W);
      b.m_endLinearImpulse_W.setZero(), b.m_endAngularImpulse_W.setZero();
    }

    b.m_force_W.setZero(), b.m_torque_W.setZero();
    b.m_linearImpulse_W.setZero(), b.m_angularImpulse_W.setZero();

    // How long it has been at rest: its centre and the farthest point of its bounding
    // sphere slower than the sleep speed (SleepIslands).
    const RScalar speed = std::max(b.m_v_W.norm() + b.m_w_B.norm() * b.m_boundingRadius, pseudoSpeed);
    b.m_restTime = speed < m_settings.sleepSpeed ? b.m_restTime + dt : 0;

    if (!(AllFinite(b.m_x_W) && AllFinite(b.m_v_W) && AllFinite(b.m_w_B) &&
          AllFinite(b.m_q_WB))) {
      b.m_x_W = x0, b.m_v_W = v0, b.m_w_B = w0, b.m_q_WB = q0;
      b.m_restTime = 0;
      m_nonFiniteLast.push_back(RNonFiniteBody{i, b.m_name, m_stepCount});
      if (!m_nonFinite) m_nonFinite = m_nonFiniteLast.back();
    }
  }
  // A body put back lost this step's impulses, and the contact memory of its pairs holds
  // what made it overflow: started warm from that, it would overflow again every step.
  if (!m_nonFiniteLast.empty()) {
    auto reverted = [this](std::uint32_t i) {
      for (const RNonFiniteBody& nf : m_nonFiniteLast) {
        if (nf.bodyIndex == i) return true;
      }
      return false;
    };
    m_warm.erase(std::remove_if(m_warm.begin(), m_warm.end(),
                                [&](const RWarmStart& w) {
                                  return reverted(static_cast<std::uint32_t>(w.pair >> 32)) ||
                                         reverted(static_cast<std::uint32_t>(w.pair));
                                }),
                 m_warm.end());
  }
}

}  // namespace REngine
