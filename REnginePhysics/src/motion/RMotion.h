// Private to REnginePhysics: the motion, UpdateObjects' half of the step. It defines the
// step's velocities once for every subsystem (the static functions below: the pair sweep
// grows its bounds by them, the contact and joint solvers solve for them, the welds move
// with them) and moves the bodies with them (Integrate: kick-drift-kick for the centre of
// mass, the exact free flow between half torque kicks for the rotation, the contact
// solver's outputs applied). It owns the bodies put back this step, those whose new state
// the world cannot hold, and the first body ever put back, which RIntegrator reports.
// What Integrate reads of the other subsystems (the contact solver's outputs, the weld
// groups, the settings, the job system) comes in as parameters. Definitions:
// RIntegration.cpp (Integrate, Kept) and RBodyMotion.cpp (kinematic bodies, angular locks,
// drag, gravity scales).
#pragma once

#include "state/RLoadKey.h"
#include <REngineMath/RFunctions.h>

#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/detail/RBodyCore.h>

#include "solver/RSolverTypes.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace REngine {

class RJobSystem;
class RWeldGroups;
struct RStepBodies;

class RMotion {
 public:
  // The step's velocities, one definition for every subsystem (kick-drift-kick): a body moves
  // through the step with its mid-step velocity v + J/m + a dt/2, a = F/m + s g (exact for a
  // constant a; s the body's gravity scale), and ends it with another a dt/2. Its angular
  // kick at the start is the angular impulse plus half the torque's impulse, and at the end
  // the other half (world, N m s). The contact solver solves for the mid-step velocities,
  // the pair sweep grows the bounds by them, Integrate moves the bodies with them.
  // Drag (DragFlow) follows the exact flow of dv/dt = a - c v through the step, in velocity
  // and position, and scales the spin as the exact damped free flow does; an impulse's
  // velocity change decays from mid-step on. Locks zero what a kick gives along a locked
  // axis; a kinematic body moves with its own v, nothing else.
  // The body's gravity, s g (world, m/s^2).
  static RVec3 Gravity(const RBodyCore& b, const RVec3& gravity_W) {
    // Scale 1 is not multiplied: the arithmetic of a scene without scales is unchanged.
    return b.m_gravityScale == 1 ? gravity_W : RVec3(gravity_W * b.m_gravityScale);
  }
  // Its acceleration through the step, F/m + s g, zero along locked axes (world, m/s^2).
  static RVec3 Acceleration(const RBodyCore& b, const RVec3& gravity_W) {
    if (b.m_isKinematic) return RVec3::Zero();
    const RVec3 a = b.m_force_W * b.m_invMass + Gravity(b, gravity_W);
    return b.m_linearLocked ? RVec3(a.cwiseProduct(b.m_linearMask)) : a;
  }
  // The velocity change of a linear impulse J (N s, world), zero along locked axes.
  static RVec3 LinearKick(const RBodyCore& b, const RVec3& J) {
    const RVec3 dv = J * b.m_invMass;
    return b.m_linearLocked ? RVec3(dv.cwiseProduct(b.m_linearMask)) : dv;
  }
  // e^(-c t): a drag rate's factor over time t (1/s, s).
  static RScalar Decay(RScalar c, RScalar t) { return Exp(-c * t); }
  // Drag at rate c over a step dt: the exact flow of dv/dt = a - c v from u (a constant) is
  // v(dt) = E u + M dt a and x(dt) = x(0) + dt (M u + G dt a), with E = e^(-c dt), M the
  // mean of e^(-c t) over the step, (1 - E)/(c dt), and G = (c dt - 1 + E)/(c dt)^2 (1/2
  // without drag). A step with the mean velocity M u + G dt a then lands where the flow
  // does, and a body's spin scaled by M turns through the flow's angle (RIntegration.cpp).
  struct RDragFlow {
    RScalar E, M, G;
  };
  static RDragFlow DragFlow(RScalar c, RScalar dt);
  // The velocity the body moves with through the step (world, m/s): with drag, its mean
  // velocity over the step, the impulse's velocity change undamped.
  static RVec3 MidStepVelocity(const RBodyCore& b, const RVec3& gravity_W, RScalar halfDt) {
    if (b.m_isKinematic) return b.m_v_W;
    if (b.m_linearDamping != 0) {
      const RScalar dt = 2 * halfDt;
      const RDragFlow d = DragFlow(b.m_linearDamping, dt);
      return b.m_v_W * d.M + LinearKick(b, b.m_linearImpulse_W) + Acceleration(b, gravity_W) * (d.G * dt);
    }
    return b.m_v_W + LinearKick(b, b.m_linearImpulse_W) + Acceleration(b, gravity_W) * halfDt;
  }
  static RVec3 StartAngularKick_W(const RBodyCore& b, RScalar halfDt) {
    return b.m_angularImpulse_W + b.m_torque_W * halfDt;
  }
  static RVec3 EndAngularKick_W(const RBodyCore& b, RScalar halfDt) { return b.m_torque_W * halfDt; }
  // RBodyMotion.cpp: the motion's new concerns. The world inverse inertia (1/(kg m^2)) at
  // orientation R_WB: R diag(1/I) R^T, or with angular locks the inverse of the inertia
  // restricted to the free axes (zero rows and columns on the locked ones); zero for a
  // static or kinematic body.
  static RMat3 InvInertia_W(const RBodyCore& b, const RMat3& R_WB);
  // The angular velocity the body turns with this step after its start kick (world, rad/s),
  // drag included; the solver's and the pair sweep's.
  static RVec3 MidStepSpin_W(const RBodyCore& b, const RMat3& R_WB, const RMat3& invI_W, RScalar halfDt);
  // A body's contact solver state at the start of its solve (RContactSolver::FindImpulses),
  // from these definitions: vMove its mid-step velocity (world, m/s).
  static void InitSolverBody(RSolverBody& s, const RBodyCore& b, const RVec3& vMove, RScalar halfDt,
                             const RVec3& gravity_W);
  // What sticking to a spinning kinematic body means for a point at arm r_W from its centre
  // (world, m/s), beyond its surface velocity v + w x r there: at the start of the step
  // (end = false) the chord's velocity, (exp(w dt) r - r) / dt - w x r, which a body moving
  // in a straight line through the step must have to land on the same point of the surface
  // (without it a crate on a turntable spirals outwards by r w^2 dt^2 / 2 a step); at the
  // end, the surface velocity where the point is then, w x (exp(w dt) r - r). Zero for
  // every other body.
  static RVec3 KinematicDrift_W(const RBodyCore& b, const RVec3& r_W, RScalar dt, bool end);
  // The same for a surface turning at w_W (rad/s, world), whatever the body.
  static RVec3 SurfaceDrift_W(const RVec3& w_W, const RVec3& r_W, RScalar dt, bool end);
  // A contact at arms rA, rB (world, m) against a spinning kinematic body: A's drift less
  // B's, both arms turning with the kinematic body's spin w_W (a body at rest on it turns
  // with it: its centre then keeps to its own circle, not to the contact point's). Zero
  // when w_W is.
  static RVec3 ContactDrift_W(const RVec3& w_W, const RVec3& rA, const RVec3& rB, RScalar dt, bool end) {
    return SurfaceDrift_W(w_W, rA, dt, end) - SurfaceDrift_W(w_W, rB, dt, end);
  }
  // A kinematic body's step: x += v dt, q = exp(w dt) q, exact for constant velocities.
  static void MoveKinematic(RBodyCore& b, RScalar dt);
  // Whether a body's state after its motion is finite and within kMaxPosition (Integrate).
  static bool Kept(const RBodyCore& b);
  // A body with angular locks: its world spin, drag and kicks, turned about the world axis
  // of its spin (exact with one free axis). Integrate's angular part for such bodies.
  static void TurnLocked(RBodyCore& b, RScalar dt);
  // How far gravity can pull two bodies apart in a step, in units of |g|: max(0, s) -
  // min(0, s) over the dynamic bodies' scales (1 when every scale is 1).
  static RScalar GravitySpread(const RStepBodies& bodies);

  // What Integrate reads of the step's other subsystems, this step.
  struct RStepInputs {
    const RWorldSettings& settings;  // gravity_W, sleepSpeed
    // Bodies welded together move as the one rigid body each group forms (MoveWeld).
    const RWeldGroups& welds;
    // Whether the contact solver solved this step, and per body (dense index) whether it
    // is in some resolved contact's rows: only those have solver outputs.
    bool solved;
    const std::vector<char>& inRows;
    std::uint64_t step;  // the step's count, reported with a body put back
    RJobSystem* jobs;    // null: one thread
    std::size_t tasks;   // how many tasks a parallel stage is cut into
  };
  // UpdateObjects' motion: applies the accumulated impulses, then kick-drift-kick for the
  // centre of mass and the exact free flow between half torque kicks for the rotation. A
  // body whose new state the world cannot hold (Kept) is put back and reported
  // (NonFiniteInLastStep, NonFinite), and its pairs' warm starts dropped from warm. The
  // solver bodies (per dense index; read for the bodies in.inRows marks, when in.solved)
  // and the warm-start memory are the contact solver's (solver/RSolverTypes.h).
  void Integrate(const RStepBodies& bodies, RScalar dt, const RStepInputs& in,
                 const std::vector<RSolverBody>& solverBodies, std::vector<RWarmStart>& warm);

  // The first body put back since the world began (or was loaded), if any; the bodies put
  // back by the last step, in index order.
  const std::optional<RNonFiniteBody>& NonFinite() const { return m_nonFinite; }
  const std::vector<RNonFiniteBody>& NonFiniteInLastStep() const { return m_nonFiniteLast; }
  // Save/load's (state/RWorldState.cpp; RStateStep.cpp writes NonFinite()): a load restores
  // the first body put back and forgets the last step's, which are not saved.
  // A rollback snapshot's (RSnapshot.h): copied (NonFinite is empty in a healthy world).
  void RestoreForSnapshot(RLoadKey, const std::optional<RNonFiniteBody>& nonFinite) {
    if (nonFinite || m_nonFinite) m_nonFinite = nonFinite;
    m_nonFiniteLast.clear();
  }
  void RestoreForLoad(RLoadKey, std::optional<RNonFiniteBody> nonFinite) {
    m_nonFinite = std::move(nonFinite);
    m_nonFiniteLast.clear();
  }

 private:
  std::optional<RNonFiniteBody> m_nonFinite;
  std::vector<RNonFiniteBody> m_nonFiniteLast;
  std::vector<char> m_putBack;  // Integrate: bodies whose new state was not finite
};

}  // namespace REngine
