// A rigid body: mass properties, pose, velocities and the accumulators that collision
// response and game code fill during a step.
//
// Frames. W: world. S: the shape's own frame, in which the scene gives sizes, points and
// the body's pose. B: the body frame, origin at the centre of mass, axes along the principal
// axes, so the inertia tensor is diagonal in B. The offset X_BS between B and S is fixed at
// creation; the body stores the pose of B (the physics state) and converts S poses in and
// out, so a scene's pose goes in and comes out unchanged.
#pragma once

#include <REnginePhysics/RAbi.h>
#include <REngineMath/RMath.h>
#include <REnginePhysics/RBodyDef.h>
#include <REnginePhysics/RError.h>
#include <REnginePhysics/detail/RBodyCore.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace REngine {
class alignas(64) RRigidBody : private RBodyCore {
 public:
  // Computes the mass properties. Throws RBodyError on a definition that would give a
  // non-finite or non-positive size, mass or inertia (or non-finite inverses), a size beyond
  // 1e12 m, a box thinner than 1e-4 of its largest half extent, a dynamic
  // body whose largest principal moment exceeds 1e9 times its smallest (a needle), or whose
  // hull points do not span a solid (RConvexPolyhedron::Hull), naming the field.
  explicit RRigidBody(const RBodyDef& def);

  const std::string& Name() const { return m_name; }
  const RShape& Shape() const { return m_prepared->shape; }
  // The prepared shape, shared: a body made from it (RBodyDef::prepared) builds no hull.
  const std::shared_ptr<const RPreparedShape>& PreparedShape() const { return m_prepared; }
  bool IsStatic() const { return m_isStatic; }
  bool IsKinematic() const { return m_isKinematic; }
  // kDynamic, kStatic or kKinematic; a dynamic body defined with all six axes locked is
  // kinematic.
  RBodyKind Kind() const {
    return m_isStatic ? RBodyKind::kStatic : m_isKinematic ? RBodyKind::kKinematic : RBodyKind::kDynamic;
  }
  // Drag rates, 1/s, and the gravity scale (see RBodyDef). Dynamic bodies only: a
  // kinematic body moves by its velocities alone.
  RScalar LinearDamping() const { return m_linearDamping; }
  RScalar AngularDamping() const { return m_angularDamping; }
  RScalar GravityScale() const { return m_gravityScale; }
  const RBodyLocks& Locks() const { return m_locks; }
  bool Responds() const { return m_responds; }
  bool OneWay() const { return m_oneWay; }
  RScalar Restitution() const { return m_restitution; }
  RScalar Friction() const { return m_friction; }

  // RBodyDef::id; unset for a body without one.
  std::optional<std::uint32_t> Id() const {
    return m_id == kNoId ? std::nullopt : std::optional<std::uint32_t>(m_id);
  }
  // False when this body must never be tested against `other`: their category and mask bits
  // disagree in either direction (RBodyDef::category), or other's id is in this body's
  // ignore list or this one's in other's. Static pairs are rejected by the integrator before
  // this is asked.
  bool ShouldCheckCollision(const RRigidBody& other) const;
  // Never collide with the bodies whose id is otherId (0 to 2^32 - 2; RBodyError "ignore"
  // otherwise). In an RBodies, RBodies::IgnoreCollisions(a, b) does this by handle.
  void IgnoreCollisionsWith(std::uint32_t otherId);
  // The ids this body never collides with, sorted.
  const std::vector<std::uint32_t>& IgnoredIds() const { return m_ignore; }
  // Collision filter bits (RBodyDef::category, mask). Setting them wakes the body, and a
  // static or kinematic body wakes the sleepers whose boxes touch it, as IgnoreCollisionsWith
  // does: a sleeping pair is not looked at, so it would never learn that it may now touch.
  std::uint32_t Category() const { return m_category; }
  std::uint32_t Mask() const { return m_mask; }
  void SetCollisionFilter(std::uint32_t category, std::uint32_t mask);
  // The game's value (RBodyDef::userData); never read by the engine.
  std::uintptr_t UserData() const { return m_userData; }
  void SetUserData(std::uintptr_t value) { m_userData = value, m_definition.Bump(); }

  // Mass, kg (0 for a static or kinematic body), and its inverse, 1/kg (0 for a static or
  // kinematic body). A body with locked axes keeps its mass; the solver zeroes its inverse
  // along the locked axes.
  RScalar Mass() const { return m_mass; }
  RScalar InvMass() const { return m_invMass; }
  // Principal moments about the centre of mass, body frame, kg m^2 (0 when static or
  // kinematic), and their inverses, 1/(kg m^2) (0 then: never infinity arithmetic).
  const RVec3& Inertia_B() const { return m_I_B; }
  const RVec3& InvInertia_B() const { return m_invI_B; }
  RInertiaSymmetry Symmetry() const { return m_rotation.Symmetry(); }

  // Physics state: centre of mass (world, m), orientation of B, velocity of the centre of
  // mass (world, m/s), angular velocity (body frame, rad/s). Velocities are those at the end
  // of the last step, contact impulses at its end included: a body resting under gravity
  // reports zero.
  const RVec3& Position_W() const { return m_x_W; }
  const RQuat& Orientation_WB() const { return m_q_WB; }
  const RVec3& Velocity_W() const { return m_v_W; }
  const RVec3& AngularVelocity_B() const { return m_w_B; }
  // A kinematic body, or one with angular locks, keeps its angular velocity in the world
  // frame (exactly as set: a turntable's axis does not drift by rounding); others in B.
  RVec3 AngularVelocity_W() const { return m_worldSpin ? m_w_W : RVec3(m_q_WB * m_w_B); }
  // Angular momentum about the centre of mass, world frame, kg m^2/s.
  RVec3 AngularMomentum_W() const { return m_q_WB * m_I_B.cwiseProduct(m_w_B); }
  // Kinetic energy, J: translational and rotational.
  RScalar LinearKineticEnergy() const { return RScalar(0.5) * m_mass * m_v_W.squaredNorm(); }
  RScalar RotationalKineticEnergy() const {
    return RScalar(0.5) * m_w_B.dot(m_I_B.cwiseProduct(m_w_B));
  }

  // Pose of the shape frame S: the scene's position and orientation.
  RVec3 ShapePosition_W() const { return m_x_W + m_q_WB * m_p_BS; }
  RQuat ShapeOrientation_WS() const { return m_q_WB * m_q_BS; }
  // Fixed offset of S in B: origin of S (body frame, m) and rotation S -> B.
  const RVec3& ShapeOffset_B() const { return m_p_BS; }
  const RQuat& ShapeRotation_BS() const { return m_q_BS; }

  // The collision polyhedron in the body frame B (null for a sphere or a capsule: see
  // Shape()). Shared, immutable.
  const std::shared_ptr<const RConvexPolyhedron>& Polyhedron_B() const {
    return m_prepared->polyhedron_B;
  }
  // The bounding sphere's radius about the centre of mass, m: a sphere's radius, a capsule's
  // half height plus radius, a polyhedron's largest vertex distance.
  RScalar BoundingRadius() const { return m_boundingRadius; }

  // The world form at `stamp` (RIntegrator::CacheStamp()): recomputed only if the cached one
  // carries another stamp. A static body's is kept from any earlier stamp until the game
  // moves it (RWorldSettings::RShortcuts::staticForms). Not thread-safe: one thread steps a
  // world.
  const RWorldForm& WorldForm(std::uint64_t stamp) const {
    if (m_worldForm.stamp != stamp && !(m_isStatic && m_worldForm.stamp != 0)) {
      ComputeWorldForm(stamp);
    }
    return m_worldForm;
  }
  // The body's construction (see m_serial): equal for a body and its copies, different for
  // any other body constructed in this process.
  std::uint64_t Serial() const { return m_serial.value; }
  // How many times the world form has been computed (for tests and profiling).
  std::uint64_t WorldFormComputations() const { return m_worldFormComputations; }

  // Setters for game code between steps. Velocities are ignored on static bodies; on a
  // kinematic body they are its motion; components along locked axes are set to 0. Each
  // wakes the body, and with it its island (RWorldSettings::RShortcuts::sleeping); moving a
  // static or kinematic body with SetShapePose wakes the sleepers whose boxes touch where it
  // was at the last step or where it is now (a kinematic body moved by its velocity wakes
  // only what it touches). A body with angular locks or a
  // kinematic one keeps its world angular velocity through SetShapePose; others keep their
  // body-frame one. Invalid values are refused at the door: a
  // non-finite velocity or quaternion, a quaternion of zero length (q_WS is normalised), or
  // a position not finite or beyond 1e15 m of the origin, throws RBodyError naming the
  // argument and leaves the body as it was.
  void SetShapePose(const RVec3& position_W, const RQuat& q_WS);
  void SetVelocity_W(const RVec3& v_W);
  void SetAngularVelocity_W(const RVec3& w_W);
  // Drag rates (1/s, finite, >= 0) and gravity scale (finite); RBodyError names the field
  // ("linear_damping", "angular_damping", "gravity_scale"). Each wakes the body.
  void SetLinearDamping(RScalar c);
  void SetAngularDamping(RScalar c);
  void SetGravityScale(RScalar s);

  // Accumulators, cleared by each step after use (a kinematic or static body ignores them).
  // Forces and torques act over the whole
  // next step (N, N m, world frame); impulses act at its start (N s, N m s, world frame).
  // A non-zero one wakes the body and its island. A non-finite argument, an impulse beyond
  // 1e30 (N s, N m s) in a component, or one that makes the accumulated sum overflow,
  // throws RBodyError and changes nothing.
  void AddForce_W(const RVec3& f_W);
  void AddTorque_W(const RVec3& t_W);
  // Force at a world point: the force plus its torque about the centre of mass.
  void AddForceAtPoint_W(const RVec3& f_W, const RVec3& p_W);
  void AddImpulse_W(const RVec3& j_W);
  void AddAngularImpulse_W(const RVec3& h_W);
  void AddImpulseAtPoint_W(const RVec3& j_W, const RVec3& p_W);

  // Sleeping (RWorldSettings::RShortcuts::sleeping): a sleeping body is not moved, and its
  // velocities are zero. Wake() wakes it, and the next step wakes the rest of its island
  // (on a static body it does nothing).
  bool IsSleeping() const { return m_sleeping; }
  using RBodyCore::Wake;
};

// How many times game code has, anywhere in the process, moved a body, changed its filter
// bits or assigned one body over another between steps (SetShapePose, SetCollisionFilter,
// operator=). Caches of bodies' poses outside the
// step (RQueries' tree) compare it, with RBodies' stamps, to know they are current: a body
// does not know its container, so the count is process-wide (a teleport in one world makes
// another world's queries refresh once, which costs time, never an answer).
std::uint64_t BodyEditCount();

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_RIGID_BODY(X) \
  X(RWorldForm) \
  X(RPreparedShape) \
  X(RBodyLocks) \
  X(RBodyDef) \
  X(RBodyCore) \
  X(RRigidBody)
RENGINE_ABI_CHECK(kRigidBody, RENGINE_ABI_TYPES_RIGID_BODY)
