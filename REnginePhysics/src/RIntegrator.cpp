#include <REnginePhysics/RIntegrator.h>

#include <REngineMath/RQuaternion.h>

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

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
double Ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }
}  // namespace

void RIntegrator::Update(std::vector<RRigidBody>& bodies, RScalar dt) {
  const auto t0 = Clock::now();
  m_cacheStamp = NextCacheStamp();
  ++m_stepCount;
  CollisionDetection(bodies, dt);
  const auto t1 = Clock::now();
  UpdateObjects(bodies, dt);
  // The bodies moved: a new stamp, so world forms that detection cached at the old poses
  // are recomputed when game code asks after the step.
  m_cacheStamp = NextCacheStamp();
  const auto t2 = Clock::now();
  m_profile.collisionDetection = Ms(t1 - t0) - m_profile.findImpulses;
  m_profile.updateObjects = Ms(t2 - t1);
  m_profile.total = Ms(t2 - t0);
}

void RIntegrator::CollisionDetection(std::vector<RRigidBody>& bodies, RScalar dt) {
  m_contacts.clear();
  m_pairStats = RPairStats{};
  const std::size_t n = bodies.size();
  // Bounding spheres about the centres of mass, each grown by how far its surface can
  // move within the step (speed plus the farthest point's rotation, times dt): a pair
  // whose grown spheres are apart cannot touch before the next step. Stored as separate
  // arrays so the O(n^2) sweep below is a tight loop over contiguous doubles; the arrays
  // keep their capacity between steps.
  // The velocities are those the body will move with this step: a missile given its
  // launch impulse this step is as fast as one that has flown for a while.
  m_cx.resize(n), m_cy.resize(n), m_cz.resize(n), m_reach.resize(n);
  m_moveV.resize(n), m_moveW.resize(n);
  const RScalar halfDt = RScalar(0.5) * dt;
  for (std::size_t i = 0; i < n; ++i) {
    const RRigidBody& b = bodies[i];
    const RScalar r = b.BoundingRadius();
    m_cx[i] = b.m_x_W.x(), m_cy[i] = b.m_x_W.y(), m_cz[i] = b.m_x_W.z();
    if (b.m_isStatic) {
      m_moveV[i].setZero(), m_moveW[i] = 0;
    } else {
      m_moveV[i] = b.m_v_W + b.m_linearImpulse_W * b.m_invMass +
                   (b.m_force_W * b.m_invMass + m_settings.gravity_W) * halfDt;
      const RVec3 kick_B = b.m_q_WB.conjugate() * (b.m_angularImpulse_W + b.m_torque_W * halfDt);
      m_moveW[i] = (b.m_w_B + b.m_invI_B.cwiseProduct(kick_B)).norm();
    }
    m_reach[i] = r + (m_moveV[i].norm() + m_moveW[i] * r) * dt;
  }
  // The touching band, and a relative allowance for the rounding of the squares.
  constexpr RScalar kGrow = 1 + 1e-9;
  for (std::size_t i = 0; i < n; ++i) {
    const RScalar xi = m_cx[i], yi = m_cy[i], zi = m_cz[i], ri = m_reach[i];
    const RRigidBody& a = bodies[i];
    for (std::size_t j = i + 1; j < n; ++j) {
      const RScalar dx = m_cx[j] - xi, dy = m_cy[j] - yi, dz = m_cz[j] - zi;
      const RScalar lim = (ri + m_reach[j]) * kGrow;
      if (dx * dx + dy * dy + dz * dz > lim * lim) continue;
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
      if (((fa.aabbMin_W.array() - grow) > fb.aabbMax_W.array()).any() ||
          ((fb.aabbMin_W.array() - grow) > fa.aabbMax_W.array()).any()) {
        ++m_pairStats.rejectedBoxes;
        continue;
      }
      ++m_pairStats.narrowPhase;
      RContact contact;
      const RScalar approach = (m_moveV[j] - m_moveV[i]).norm() +
                               m_moveW[i] * a.BoundingRadius() + m_moveW[j] * b.BoundingRadius();
      if (RCollisionSolver::CheckCollisionWithMargin(a, b, approach * dt, contact.manifold)) {
        contact.a = static_cast<std::uint32_t>(i);
        contact.b = static_cast<std::uint32_t>(j);
        m_contacts.push_back(contact);
      }
    }
  }
  m_pairStats.pairs = n * (n - (n > 0)) / 2;
  m_pairStats.rejectedBounds = m_pairStats.pairs - m_pairStats.rejectedFilter -
                               m_pairStats.rejectedBoxes - m_pairStats.narrowPhase;
  m_pairStats.contacts = m_contacts.size();
  const auto t0 = Clock::now();
  FindImpulses(bodies, dt);
  m_profile.findImpulses = Ms(Clock::now() - t0);
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

}  // namespace

// Sequential impulses (Catto 2005) over every contact point, with the velocities each body
// will move with during the step (its pending impulses and half the step's acceleration
// included: kick-drift-kick moves bodies with the mid-step velocity, so a resting contact
// that holds that velocity at zero does not sink at all). Accumulated normal impulses are
// clamped at zero (a contact pushes, never pulls: the separating-velocity guard), friction
// to the Coulomb disc mu * lambda_n, and every row starts from last step's impulses for the
// same features. Penetration beyond a slop is removed by pseudo-velocities (split
// impulses), solved apart so that position correction never adds kinetic energy.
void RIntegrator::FindImpulses(std::vector<RRigidBody>& bodies, RScalar dt) {
  m_rows.clear();
  m_impacts.clear();
  const std::size_t n = bodies.size();
  // Warm-start memory is keyed by body index: when the game adds or removes bodies the
  // indices shift, and another pair would inherit a stranger's impulses.
  if (n != m_warmBodyCount) m_warm.clear(), m_warmBodyCount = n;
  m_solverBodies.resize(n);
  const RScalar halfDt = RScalar(0.5) * dt;
  bool anyRow = false;
  for (const RContact& c : m_contacts) {
    const RRigidBody& a = bodies[c.a];
    const RRigidBody& b = bodies[c.b];
    anyRow = anyRow || (a.m_responds && b.m_responds && (!a.m_isStatic || !b.m_isStatic));
  }
  if (!anyRow) {
    m_warm.clear();
    return;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const RRigidBody& b = bodies[i];
    RSolverBody& s = m_solverBodies[i];
    s.invM = b.m_invMass;
    s.vp.setZero(), s.wp.setZero();
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
    c.resolved = A.m_responds && B.m_responds && (!A.m_isStatic || !B.m_isStatic);
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
    leadCentre /= leads;
    const RVec3& normal = c.manifold.query.normal;
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
      m_impacts.push_back(r);
    }
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
      SetDirection(r.dir[0], normal, r.rA, r.rB, sa, sb);
      SetDirection(r.dir[1], t1, r.rA, r.rB, sa, sb);
      SetDirection(r.dir[2], t2, r.rA, r.rB, sa, sb);
      r.friction = mu;
      r.target = -std::max(gap, RScalar(0)) / dt;
      r.pseudoTarget = gap < -m_settings.penetrationSlop ? m_settings.positionCorrection * (-gap - m_settings.penetrationSlop) / dt : 0;
      r.lambdaN = r.lambdaT1 = r.lambdaT2 = r.lambdaP = 0;
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
      RWarmStart* match = nullptr;
      RWarmStart* nearest = nullptr;
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
        const RWarmStart* const it2 = match;
        ++m_pairStats.warmStarted;
        r.lambdaN = it2->lambdaN;
        r.lambdaT1 = it2->tangentImpulse.dot(r.dir[1].d);
        r.lambdaT2 = it2->tangentImpulse.dot(r.dir[2].d);
      }
      m_rows.push_back(r);
    }
  }

  m_pairStats.contactPoints = m_rows.size();
  auto push = [&](const RContactRow& r, int k, RScalar lambda, bool pseudo) {
    RSolverBody& sa = m_solverBodies[r.a];
    RSolverBody& sb = m_solverBodies[r.b];
    if (pseudo) {
      Push(r.dir[k], lambda, sa.invM, sb.invM, sa.vp, sa.wp, sb.vp, sb.wp);
    } else {
      Push(r.dir[k], lambda, sa.invM, sb.invM, sa.v, sa.w, sb.v, sb.w);
    }
  };
  for (const RContactRow& r : m_rows) {
    if (r.lambdaN != 0) push(r, 0, r.lambdaN, false);
    if (r.lambdaT1 != 0) push(r, 1, r.lambdaT1, false);
    if (r.lambdaT2 != 0) push(r, 2, r.lambdaT2, false);
  }
  SolveImpacts(dt);
  const int iterations = std::max(1, m_settings.solverIterations);
  // Rows come grouped by contact. A manifold's normal rows are solved together: its points
  // share two bodies, and solving them one after another favours the first, leaving a
  // small torque that tilts stacked bodies step after step. The block's matrix is rank
  // deficient (four points of one face constrain three degrees of freedom), so the
  // minimum-norm least-squares inverse is precomputed once per step; when its answer
  // would pull at a point, that manifold falls back to one point at a time.
  m_blocks.clear();
  for (std::size_t first = 0; first < m_rows.size();) {
    std::size_t last = first + 1;
    while (last < m_rows.size() && m_rows[last].contact == m_rows[first].contact) ++last;
    RBlock blk;
    blk.first = static_cast<std::uint32_t>(first);
    blk.count = static_cast<int>(last - first);
    blk.useBlock = blk.count > 1;
    if (blk.useBlock) {
      const RSolverBody& sa = m_solverBodies[m_rows[first].a];
      const RSolverBody& sb = m_solverBodies[m_rows[first].b];
      Eigen::Matrix<RScalar, 4, 4> K = Eigen::Matrix<RScalar, 4, 4>::Identity();
      for (int i = 0; i < blk.count; ++i) {
        const RDirection& di = m_rows[first + i].dir[0];
        for (int j = 0; j < blk.count; ++j) {
          const RDirection& dj = m_rows[first + j].dir[0];
          K(i, j) = (sa.invM + sb.invM) * di.d.dot(dj.d) + di.rAxd.dot(dj.iA) + di.rBxd.dot(dj.iB);
        }
      }
      blk.pinv.setZero();
      blk.pinv.topLeftCorner(blk.count, blk.count) =
          K.topLeftCorner(blk.count, blk.count).completeOrthogonalDecomposition().pseudoInverse();
    }
    m_blocks.push_back(blk);
    first = last;
  }

  const std::size_t nBlocks = m_blocks.size();
  for (int it = 0; it < iterations; ++it) {
    // Alternate the sweep's direction, for the same reason as the blocks across manifolds.
    for (std::size_t bb = 0; bb < nBlocks; ++bb) {
      const RBlock& blk = m_blocks[(it % 2 == 0) ? bb : nBlocks - 1 - bb];
      RContactRow* rows = &m_rows[blk.first];
      const RSolverBody& sa = m_solverBodies[rows[0].a];
      const RSolverBody& sb = m_solverBodies[rows[0].b];
      // Normal: reach the targets, never pull.
      SolveNormalBlock(blk, rows, false);
      for (int i = 0; i < blk.count; ++i) {
        RContactRow& r = rows[i];
        // Friction, bounded by this pass's normal impulse.
        const RScalar lt1 = r.lambdaT1 - Speed(r.dir[1], sa.v, sa.w, sb.v, sb.w) / r.dir[1].k;
        const RScalar lt2 = r.lambdaT2 - Speed(r.dir[2], sa.v, sa.w, sb.v, sb.w) / r.dir[2].k;
        const RScalar limit = r.friction * r.lambdaN;
        const RScalar norm = std::sqrt(lt1 * lt1 + lt2 * lt2);
        const RScalar scale = norm > limit ? limit / norm : RScalar(1);
        const RScalar d1 = lt1 * scale - r.lambdaT1, d2 = lt2 * scale - r.lambdaT2;
        r.lambdaT1 += d1, r.lambdaT2 += d2;
        if (d1 != 0) push(r, 1, d1, false);
        if (d2 != 0) push(r, 2, d2, false);
      }
      // Position correction on the pseudo-velocities, as a block like the velocities: one
      // point at a time, the first point of a face would be favoured and the correction
      // would tilt the box (a 20-box stack then leans further every step and falls).
      SolveNormalBlock(blk, rows, true);
    }
  }

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
  m_warmNext.clear();
  for (const RContactRow& r : m_rows) {
    accumulate(r.a, r.b, r.rA, r.rB,
               r.lambdaN * r.dir[0].d + r.lambdaT1 * r.dir[1].d + r.lambdaT2 * r.dir[2].d);
    m_contacts[r.contact].normalImpulse[r.point] = r.lambdaN;
    const RContactPoint& p = m_contacts[r.contact].manifold.points[r.point];
    m_warmNext.push_back(RWarmStart{PairKey(r.a, r.b), p.featureId,
                                    bodies[r.a].m_q_WB.conjugate() * (p.position - bodies[r.a].m_x_W),
                                    r.lambdaN, r.lambdaT1 * r.dir[1].d + r.lambdaT2 * r.dir[2].d});
  }
  // An impact's impulse is a one-off, not remembered: carried into the next step it would
  // push apart bodies that are already separating, energy from nowhere. It is reported at
  // the manifold's deepest point.
  for (const RImpactRow& r : m_impacts) {
    if (r.lambdaN == 0) continue;
    accumulate(r.a, r.b, r.rA, r.rB,
               r.lambdaN * r.dir[0].d + r.lambdaT1 * r.dir[1].d + r.lambdaT2 * r.dir[2].d);
    m_contacts[r.contact].normalImpulse[r.point] += r.lambdaN;
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

// The impact phase: every manifold approaching faster than the restitution threshold, and
// reaching contact within the step, bounces through its impact row: the impulse that turns
// the approach speed vn into -e vn, then friction at the same point bounded by mu times
// that impulse. Passes repeat while some manifold still impacts, so an impulse travels
// along a chain of touching bodies the way it does in a Newton's cradle (the striker stops,
// the last ball leaves), instead of being shared out as a block. Each application changes
// the kinetic energy by (e^2 - 1) vn^2 / (2 k) <= 0, and friction only removes sliding, so
// no pass can add energy whatever the order.
void RIntegrator::SolveImpacts(RScalar dt) {
  const std::size_t count = m_impacts.size();
  const int passes = std::max(1, m_settings.solverIterations);
  for (int pass = 0; pass < passes; ++pass) {
    bool any = false;
    for (std::size_t ii = 0; ii < count; ++ii) {
      RImpactRow& r = m_impacts[(pass % 2 == 0) ? ii : count - 1 - ii];
      RSolverBody& sa = m_solverBodies[r.a];
      RSolverBody& sb = m_solverBodies[r.b];
      const RScalar vn = Speed(r.dir[0], sa.v, sa.w, sb.v, sb.w);
      if (vn >= -m_settings.restitutionThreshold || r.gap > -vn * dt) continue;
      any = true;
      const RScalar dn = -(1 + r.restitution) * vn / r.dir[0].k;
      r.lambdaN += dn;
      Push(r.dir[0], dn, sa.invM, sb.invM, sa.v, sa.w, sb.v, sb.w);
      const RScalar lt1 = r.lambdaT1 - Speed(r.dir[1], sa.v, sa.w, sb.v, sb.w) / r.dir[1].k;
      const RScalar lt2 = r.lambdaT2 - Speed(r.dir[2], sa.v, sa.w, sb.v, sb.w) / r.dir[2].k;
      const RScalar limit = r.friction * r.lambdaN;
      const RScalar norm = std::sqrt(lt1 * lt1 + lt2 * lt2);
      const RScalar scale = norm > limit ? limit / norm : RScalar(1);
      const RScalar d1 = lt1 * scale - r.lambdaT1, d2 = lt2 * scale - r.lambdaT2;
      r.lambdaT1 += d1, r.lambdaT2 += d2;
      if (d1 != 0) Push(r.dir[1], d1, sa.invM, sb.invM, sa.v, sa.w, sb.v, sb.w);
      if (d2 != 0) Push(r.dir[2], d2, sa.invM, sb.invM, sa.v, sa.w, sb.v, sb.w);
    }
    if (!any) break;
  }
}

// One manifold's normal rows: the block's minimum-norm answer when it pushes at every point,
// else one point at a time. On the velocities (towards the rows' targets, impulses lambdaN)
// or on the pseudo-velocities of position correction (pseudoTarget, lambdaP).
void RIntegrator::SolveNormalBlock(const RBlock& blk, RContactRow* rows, bool pseudo) {
  RSolverBody& sa = m_solverBodies[rows[0].a];
  RSolverBody& sb = m_solverBodies[rows[0].b];
  RVec3& va = pseudo ? sa.vp : sa.v;
  RVec3& wa = pseudo ? sa.wp : sa.w;
  RVec3& vb = pseudo ? sb.vp : sb.v;
  RVec3& wb = pseudo ? sb.wp : sb.w;
  auto lambda = [pseudo](RContactRow& r) -> RScalar& { return pseudo ? r.lambdaP : r.lambdaN; };
  auto target = [pseudo](const RContactRow& r) { return pseudo ? r.pseudoTarget : r.target; };
  if (pseudo) {
    // Most contacts need no correction: nothing to do unless some row does or did.
    bool active = false;
    for (int i = 0; i < blk.count; ++i) active = active || rows[i].pseudoTarget > 0 || rows[i].lambdaP > 0;
    if (!active) return;
  }
  if (blk.useBlock) {
    Eigen::Matrix<RScalar, 4, 1> rhs = Eigen::Matrix<RScalar, 4, 1>::Zero();
    for (int i = 0; i < blk.count; ++i) rhs[i] = target(rows[i]) - Speed(rows[i].dir[0], va, wa, vb, wb);
    const Eigen::Matrix<RScalar, 4, 1> delta = blk.pinv * rhs;
    bool valid = true;
    for (int i = 0; i < blk.count; ++i) valid = valid && lambda(rows[i]) + delta[i] >= 0;
    if (valid) {
      for (int i = 0; i < blk.count; ++i) {
        lambda(rows[i]) += delta[i];
        if (delta[i] != 0) Push(rows[i].dir[0], delta[i], sa.invM, sb.invM, va, wa, vb, wb);
      }
      return;
    }
  }
  for (int i = 0; i < blk.count; ++i) {
    RContactRow& r = rows[i];
    const RScalar l = std::max(
        lambda(r) - (Speed(r.dir[0], va, wa, vb, wb) - target(r)) / r.dir[0].k, RScalar(0));
    const RScalar d = l - lambda(r);
    lambda(r) = l;
    if (d != 0) Push(r.dir[0], d, sa.invM, sb.invM, va, wa, vb, wb);
  }
}

void RIntegrator::UpdateObjects(std::vector<RRigidBody>& bodies, RScalar dt) {
  const RScalar halfDt = RScalar(0.5) * dt;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    RRigidBody& b = bodies[i];
    if (b.m_isStatic) {
      b.m_force_W.setZero(), b.m_torque_W.setZero();
      b.m_linearImpulse_W.setZero(), b.m_angularImpulse_W.setZero();
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

    // Position correction: displacement without velocity (split impulses).
    if (!b.m_pseudoVelocity_W.isZero(0) || !b.m_pseudoAngular_W.isZero(0)) {
      b.m_x_W += b.m_pseudoVelocity_W * dt;
      b.m_q_WB = QuatExp(b.m_pseudoAngular_W * dt) * b.m_q_WB;
      b.m_q_WB.normalize();
      b.m_pseudoVelocity_W.setZero(), b.m_pseudoAngular_W.setZero();
    }

    b.m_force_W.setZero(), b.m_torque_W.setZero();
    b.m_linearImpulse_W.setZero(), b.m_angularImpulse_W.setZero();

    if (!(AllFinite(b.m_x_W) && AllFinite(b.m_v_W) && AllFinite(b.m_w_B) &&
          AllFinite(b.m_q_WB))) {
      b.m_x_W = x0, b.m_v_W = v0, b.m_w_B = w0, b.m_q_WB = q0;
      if (!m_nonFinite) m_nonFinite = RNonFiniteBody{i, b.m_name, m_stepCount};
    }
  }
}

}  // namespace REngine
