#include <REnginePhysics/RIntegrator.h>

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
  m_profile.collisionDetection = Ms(t1 - t0);
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
  m_cx.resize(n), m_cy.resize(n), m_cz.resize(n), m_reach.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const RRigidBody& b = bodies[i];
    const RScalar r = b.BoundingRadius();
    m_cx[i] = b.m_x_W.x(), m_cy[i] = b.m_x_W.y(), m_cz[i] = b.m_x_W.z();
    m_reach[i] = r + (b.m_v_W.norm() + b.m_w_B.norm() * r) * dt;
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
      if (RCollisionSolver::CheckCollision(a, b, dt, contact.manifold)) {
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
