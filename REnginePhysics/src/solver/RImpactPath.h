// Private to REnginePhysics: where a body is at a time t of the step in the impact phase
// (RImpactPhase.cpp, RImpactSweep.cpp). Its centre moves on the line or parabola of its
// velocity since its last impact (moved, tau); a body that turns on its path
// (RSolverBody::turns) turns on the torque-free flow of the motion (RFreeRotation) from the
// orientation and spin it had at its last impact (turnQ, turnW_B at turnTau), which is where
// the motion continues from (RMotion::Integrate). Every other body keeps the orientation
// of the start of the step through the phase.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/detail/RBodyCore.h>

#include "body/RBodyAccess.h"
#include "solver/RSolverTypes.h"

#include <algorithm>
#include <cmath>

namespace REngine::solver {

// Body s's displacement from its start at time t >= s.tau (m): what it had moved by tau,
// then its velocity's line, or with an acceleration its parabola (mean velocity
// v + a ((t + tau)/2 - dt/2)): the impact phase's advance, without moving the body.
inline RVec3 MovedAt(const RSolverBody& s, RScalar t, RScalar halfDt) {
  if (t <= s.tau) return s.moved;
  if (s.accel.isZero(0)) return s.moved + s.v * (t - s.tau);
  return s.moved + (s.v + s.accel * (RScalar(0.5) * (t + s.tau) - halfDt)) * (t - s.tau);
}

// A turning body's orientation and body spin at time t: the free flow from its last impact.
inline void TurnedAt(const RBodyCore& b, const RSolverBody& s, RScalar t, RQuat& q, RVec3& w_B) {
  q = s.turnQ, w_B = s.turnW_B;
  if (t != s.turnTau) b.m_rotation.Flow(t - s.turnTau, w_B, q);
}

// Turns body s to time t for the geometry and impulses of an impact then: its orientation
// (qAt at atTau), world spin and inverse inertia there. An impulse at t then changes the
// spin with the inertia the body has at that moment, so that its kinetic energy, which
// depends on the orientation, changes by what the impulse does and nothing else.
inline void TurnTo(const RBodyCore& b, RSolverBody& s, RScalar t) {
  if (!s.turning) return;
  RVec3 w_B;
  // (Never back past where its turning is known from: the geometry's advance steps back
  // from an overlap, as its centre's path does not.)
  t = std::max(t, s.turnTau);
  s.atTau = t;
  TurnedAt(b, s, t, s.qAt, w_B);
  const RMat3 R = s.qAt.toRotationMatrix();
  s.w = R * w_B;
  s.invI = R * b.m_invI_B.asDiagonal() * R.transpose();
}

// Whether spin w (rad/s) turns body s's surface further than the slop in time h: w R h, R
// its bounding radius. Below that, the body at one orientation is where it is along the
// way to the slop: the phase's geometry keeps it there (turnQ), and the motion turns it
// with its spin after its impacts, as a body that turns only so little always did.
inline bool TurnsFar(const RSolverBody& s, RScalar w, RScalar h, RScalar slop) { return w * s.radius * h > slop; }

// Whether spin w curves body s's surface away from the lines of its points' velocities by
// more than the slop in time h: w^2 R h^2 / 2. Below that, the contact rows and the impact
// rows' approach, which follow those lines (v + w x r), are where its surface goes to the
// slop.
inline bool CurvesFar(const RSolverBody& s, RScalar w, RScalar h, RScalar slop) {
  return RScalar(0.5) * w * w * s.radius * h * h > slop;
}

// A body that turns far but whose turning the phase does not follow (a kinematic body, one
// with angular locks or drag, welded, or in an island with joints; a sphere's turning moves
// no contact): the phase keeps it at its start's orientation, so no sweep of a pair with it
// could say where its surface goes.
inline bool Unfollowed(const RBodyCore& b, const RSolverBody& s, RScalar dt, RScalar slop) {
  const bool round = !b.m_polyhedron_B && b.m_coreHalfHeight == 0 && b.m_childCount == 0 && !b.m_mesh;
  return !s.turns && !round && TurnsFar(s, s.w.norm(), dt, slop);
}

// A body an impulse of the phase has left turning so that its surface curves far from its
// rows' lines within the rest of the step: the rows it is in are swept along its turning
// path (SweepImpact) instead of being judged from the start's geometry.
inline bool Spun(const RSolverBody& s, RScalar dt, RScalar slop) {
  return s.turns && s.impacts > 0 && CurvesFar(s, s.turnW_B.norm(), dt - s.turnTau, slop);
}

// A bound on the acceleration (m/s^2) the turning gives a point of the body at unit
// distance from its centre while it turns torque-free from body spin w_B: |alpha| +
// |omega|^2 over the flow. Spherical: omega is constant. Symmetric (unique axis s): |omega|
// is constant and omega's part across s turns about s at (1 - I_s/I_t) omega_s. General:
// I_min |omega|^2 <= 2E, and Euler's I omega' = (I omega) x omega = ((I - c) omega) x omega
// for any c, with c midway between the extreme moments, gives |omega'| <= (I_max -
// I_min) / (2 I_min) |omega|^2.
inline RScalar TurnAcceleration(const RBodyCore& b, const RVec3& w_B) {
  const RVec3& I = b.m_I_B;
  switch (b.m_rotation.Symmetry()) {
    case RInertiaSymmetry::kSpherical:
      return w_B.squaredNorm();
    case RInertiaSymmetry::kSymmetric: {
      const int s = Core(b.m_rotation).m_axisUnique, t = (s + 1) % 3;
      const RScalar across = std::hypot(w_B[t], w_B[(s + 2) % 3]);
      return w_B.squaredNorm() + std::abs(w_B[s] * (1 - I[s] / I[t])) * across;
    }
    case RInertiaSymmetry::kGeneral:
      break;
  }
  const RScalar lo = I.minCoeff(), hi = I.maxCoeff();
  const RScalar omega2 = w_B.dot(I.cwiseProduct(w_B)) / lo;
  return omega2 * (1 + (hi - lo) / (2 * lo));
}

}  // namespace REngine::solver
