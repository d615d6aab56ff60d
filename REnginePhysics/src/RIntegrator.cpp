// RIntegrator::Update, the step as a table of contents: the stamp, CollisionDetection (pair
// sweep, contact solver), UpdateObjects (the motion), sleeping. The subsystems live in
// RPairSweep.cpp, RContactSolver.cpp, RImpactPhase.cpp, RIslandSolver.cpp, RSleeping.cpp.
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
