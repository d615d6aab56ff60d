// The motion (UpdateObjects): every accumulated impulse applied, then the step's one
// definition of the bodies' velocities; see RIntegrator.h for the scheme.
#include "motion/RMotion.h"

#include "joints/RWeldGroups.h"
#include "world/RStepBodies.h"

#include <REnginePhysics/RLimits.h>

#include <REngineMath/RQuaternion.h>

#include <algorithm>
#include <cmath>

namespace REngine {

// Whether a body's new state is one the world can hold: finite, and inside the positions the
// API accepts (kMaxPosition). A body past them has run away (a joint island blown up, an
// impulse of 1e300): it is put back and reported, as a non-finite one, rather than carried
// on to 1e60 m.
bool RMotion::Kept(const RBodyCore& b) {
  return AllFinite(b.m_v_W) && AllFinite(b.m_w_B) && AllFinite(b.m_q_WB) &&
         b.m_x_W.cwiseAbs().maxCoeff() <= kMaxPosition;  // (false for NaN)
}

void RMotion::Integrate(const RStepBodies& bodies, RScalar dt, const RStepInputs& in,
                        const std::vector<RSolverBody>& solverBodies, std::vector<RWarmStart>& warm) {
  const RScalar halfDt = RScalar(0.5) * dt;
  m_nonFiniteLast.clear();
  // Every body moves on its own: the bodies are cut into ranges, one task each; the bodies
  // put back are listed afterwards, in index order.
  m_putBack.assign(bodies.size(), 0);
  ParallelRanges(in.jobs, bodies.size(), in.tasks, 128, [&](std::size_t i0, std::size_t i1, std::size_t) {
    for (std::size_t i = i0; i < i1; ++i) {
      // What the motion reads of the body six ahead: its first seven lines (state,
      // accumulators, inverse inertia, drag, masks) and the rotation's cache, not the
      // material, shape and names between them (PrefetchBody).
      if (i + 6 < i1) {
        const RBodyCore& ahead = bodies[i + 6];
        PrefetchBody(ahead, 7 * 64);
        PrefetchBytes(&ahead.m_rotation, sizeof(RFreeRotation));
      }
      RBodyCore& b = bodies[i];
      // A welded body moves with its group (below).
      if (in.welds.Welded(i)) continue;
      // A sleeping body has no velocity, and nothing touched it: it stays where it is. A
      // kinematic body moves with its own velocities, whatever pushed it.
      if (b.m_isStatic || b.m_sleeping || b.m_isKinematic) {
        b.m_force_W.setZero(), b.m_torque_W.setZero();
        b.m_linearImpulse_W.setZero(), b.m_angularImpulse_W.setZero();
        if (b.m_isKinematic) {
          const RVec3 x0 = b.m_x_W, w0 = b.m_w_B;
          const RQuat q0 = b.m_q_WB;
          MoveKinematic(b, dt);
          if (!Kept(b)) {  // (its velocities are the game's: kept, and reported each step)
            b.m_x_W = x0, b.m_q_WB = q0, b.m_w_B = w0;
            m_putBack[i] = 1;
          }
        }
        continue;
      }
      const RVec3 x0 = b.m_x_W;
      const RQuat q0 = b.m_q_WB;

      // Linear: impulse, then kick-drift-kick with constant acceleration. With drag the
      // mid-step velocity is the exact flow's mean over the step (DragFlow); the flow's end
      // velocity is set apart, and what the impulses add decays from mid-step to the end.
      const RVec3 accel = Acceleration(b, in.settings.gravity_W);
      const RVec3 vHalf = MidStepVelocity(b, in.settings.gravity_W, halfDt);
      b.m_x_W += vHalf * dt;
      RVec3 vDragEnd = RVec3::Zero();
      if (b.m_linearDamping != 0) {
        const RDragFlow d = DragFlow(b.m_linearDamping, dt);
        vDragEnd = b.m_v_W * d.E + accel * (d.M * dt);
        b.m_v_W = LinearKick(b, b.m_linearImpulse_W);
      } else {
        b.m_v_W = vHalf + accel * halfDt;
      }

      // Angular: impulse and half the torque's impulse, exact free flow, other half. A kick
      // is applied only when non-zero so that a free body's omega passes through bit for bit
      // (which is what lets RFreeRotation reuse its cached elliptic constants). Drag scales
      // omega by e^(-c dt/2) before and after: a scalar, so the flow between is the free
      // flow's (at a lower speed), in the world frame as in the body frame. A body with
      // angular locks turns about the world axis of its spin (TurnLocked).
      // With drag the spin is scaled by the flow's mean factor M through the turn, and by
      // E/M after it: the damped free flow is the free flow at e^(-ct) the spin, along the
      // free flow's time (1 - e^(-ct))/c = M t (L in the body frame obeys Euler's equations
      // with a scalar factor on both sides).
      const RScalar spinEnd = b.m_angularDamping != 0 ? [&] {
        const RDragFlow d = DragFlow(b.m_angularDamping, dt);
        return d.E / d.M;
      }() : RScalar(1);
      const RSolverBody* out = in.solved && in.inRows[i] ? &solverBodies[i] : nullptr;
      if (b.m_angularLocked) {
        TurnLocked(b, dt);
      } else {
        if (b.m_angularDamping != 0) b.m_w_B *= DragFlow(b.m_angularDamping, dt).M;
        const bool torque = !b.m_torque_W.isZero(0);
        if (out && out->turned) {
          // An impact within the step changed how it turns: it turned on the free flow from
          // the start to its last impact (the impact phase's path, which found its contacts
          // there), and goes on from its orientation then with its spin after the contact
          // phase, which its start's kicks and every impulse since are in.
          b.m_q_WB = out->turnQ;
          b.m_w_B = out->turnQ.conjugate() * out->turnW_W;
          b.m_rotation.Advance(dt - out->turnTau, b.m_w_B, b.m_q_WB);
        } else {
          const RVec3 kick0_W = StartAngularKick_W(b, halfDt);
          if (!kick0_W.isZero(0)) {
            b.m_w_B += b.m_invI_B.cwiseProduct(b.m_q_WB.conjugate() * kick0_W);
          }
          b.m_rotation.Advance(dt, b.m_w_B, b.m_q_WB);
        }
        if (torque) {
          b.m_w_B += b.m_invI_B.cwiseProduct(b.m_q_WB.conjugate() * EndAngularKick_W(b, halfDt));
        }
      }

      // Position correction: displacement without velocity (split impulses). A body it moves
      // faster than the sleep speed is not at rest.
      RScalar pseudoSpeed = 0;
      if (out && (!out->vp.isZero(0) || !out->wp.isZero(0))) {
        pseudoSpeed = out->vp.norm() + out->wp.norm() * b.m_boundingRadius;
        b.m_x_W += out->vp * dt;
        b.m_q_WB = QuatExp(out->wp * dt) * b.m_q_WB;
        b.m_q_WB.normalize();
      }

      // Impacts within the step: the velocity change deferred to its end.
      if (out && !out->deferredImpulse.isZero(0)) b.m_v_W += LinearKick(b, out->deferredImpulse);
      // Contact impulses at the end of the step, in the body frame the step ends with. Their
      // angular part was summed about the centre of mass at the start of the step; about the
      // centre it ends at, each impulse J acting at a point p has the lever arm
      // (p - x0) - (x - x0).
      if (out && (!out->endLinear.isZero(0) || !out->endAngular.isZero(0))) {
        const RVec3 h_W = out->endAngular - (b.m_x_W - x0).cross(out->endLinear);
        b.m_v_W += LinearKick(b, out->endLinear);
        if (b.m_angularLocked) {
          b.m_w_W += InvInertia_W(b, b.m_q_WB.toRotationMatrix()) * h_W;
        } else {
          b.m_w_B += b.m_invI_B.cwiseProduct(b.m_q_WB.conjugate() * h_W);
        }
      }
      // Drag at the end: the impulses' velocity change decays through the step's second
      // half onto the flow's end velocity; the spin takes E/M.
      if (b.m_linearDamping != 0) b.m_v_W = b.m_v_W * Decay(b.m_linearDamping, halfDt) + vDragEnd;
      if (b.m_angularLocked) {
        if (b.m_angularDamping != 0) b.m_w_W *= spinEnd;
        b.m_w_B = b.m_q_WB.conjugate() * b.m_w_W;
      } else if (b.m_angularDamping != 0) {
        b.m_w_B *= spinEnd;
      }

      b.m_force_W.setZero(), b.m_torque_W.setZero();
      b.m_linearImpulse_W.setZero(), b.m_angularImpulse_W.setZero();

      // How long it has been at rest: its centre and the farthest point of its bounding
      // sphere slower than the sleep speed (SleepIslands).
      const RScalar speed = std::max(b.m_v_W.norm() + b.m_w_B.norm() * b.m_boundingRadius, pseudoSpeed);
      b.m_restTime = speed < in.settings.sleepSpeed ? b.m_restTime + dt : 0;

      if (!Kept(b)) {
        // Put back where it was, at rest: with the velocities that carried it out it would
        // leave again at every step, each one reported and each one paying for sweeps and
        // pair tests at 1e300 m.
        b.m_x_W = x0, b.m_q_WB = q0;
        b.m_v_W.setZero(), b.m_w_B.setZero(), b.m_w_W.setZero();
        b.m_restTime = 0;
        m_putBack[i] = 1;
      }
    }
  });
  // Each weld group as the one rigid body it forms (RWeldGroups.cpp): groups share no body.
  ParallelRanges(in.jobs, in.welds.GroupCount(), in.tasks, 16, [&](std::size_t g0, std::size_t g1, std::size_t) {
    for (std::size_t g = g0; g < g1; ++g) {
      in.welds.MoveWeld(bodies, g, dt, in.settings, solverBodies, in.inRows, in.solved, m_putBack);
    }
  });
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (!m_putBack[i]) continue;
    m_nonFiniteLast.push_back(RNonFiniteBody{i, bodies.handles[i], bodies[i].m_name, in.step});
    if (!m_nonFinite) m_nonFinite = m_nonFiniteLast.back();
  }
  // A body put back lost this step's impulses, and the contact memory of its pairs holds
  // what made it overflow: started warm from that, it would overflow again every step.
  if (!m_nonFiniteLast.empty()) {
    auto reverted = [this](std::uint32_t slot) {
      for (const RNonFiniteBody& nf : m_nonFiniteLast) {
        if (nf.handle.index == slot) return true;
      }
      return false;
    };
    warm.erase(std::remove_if(warm.begin(), warm.end(),
                              [&](const RWarmStart& w) {
                                return reverted(static_cast<std::uint32_t>(w.pair >> 32)) ||
                                       reverted(static_cast<std::uint32_t>(w.pair));
                              }),
               warm.end());
  }
}

}  // namespace REngine
