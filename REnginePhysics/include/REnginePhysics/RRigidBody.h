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
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RError.h>
#include <REnginePhysics/RFreeRotation.h>
#include <REnginePhysics/RShape.h>
#include <REnginePhysics/RTriangleMesh.h>

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <optional>
#include <string>
#include <vector>

namespace REngine {

struct RConvexShape;  // RCollision.h

// World-space form of a body's collision shape, computed lazily and cached against the
// integrator's stamp: at most once per body per step, however many pairs ask. It holds what
// the pair sweep reads (the narrow phase works in the bodies' own frames).
struct RWorldForm {
  std::uint64_t stamp = 0;           // stamp it was computed at; 0: never
  RVec3 aabbMin_W = RVec3::Zero();   // axis-aligned bounding box, world, m
  RVec3 aabbMax_W = RVec3::Zero();
  RVec3 sphereCenter_W = RVec3::Zero();  // bounding sphere about the centre of mass, m
  RScalar sphereRadius = 0;
};

// A body definition that cannot make a body: which field (e.g. "shape.radius") and why.
class RBodyError : public RError {
 public:
  using RError::RError;
};

// A collision shape prepared once and shared, immutable, by every body made from it: the
// hull built (Qhull), its mass properties at unit density, the body frame. Spawning a
// missile or a fragment from one (RBodyDef::prepared) copies a pointer, not a hull.
struct RPreparedShape {
  RShape shape;                 // as given, shape frame S
  RMassProperties unitMass;     // at 1 kg/m^3, S frame
  RVec3 p_BS = RVec3::Zero();   // origin of S in the body frame B, m
  RQuat q_BS = RQuat::Identity();  // rotation S -> B
  std::shared_ptr<const RConvexPolyhedron> polyhedron_B;  // body frame; null but for a box or hull
  RScalar boundingRadius = 0;   // largest distance of the surface from the centre of mass, m
  // A compound: its children prepared (each its own shape, body frame and polyhedron), and
  // as the narrow phase sees them, posed in this body frame B (pointing into childShapes).
  std::vector<std::shared_ptr<const RPreparedShape>> childShapes;
  std::vector<RShapeChild> children;
  RVec3 boxCenter_B = RVec3::Zero(), boxHalf_B = RVec3::Zero();  // a compound's or mesh's box in B, m
  // A mesh: its triangles in B (B is S moved to the centre of the mesh's box; no rotation).
  std::shared_ptr<const RTriangleMesh> mesh_B;
};

// Checks a shape as RRigidBody does (sizes finite, > 0 and at most 1e12 m, a box no thinner
// than 1e-4 of its size, hull points that span a solid, every field its type does not read
// left at 0 or empty) and prepares it. Throws RBodyError naming the field ("shape.radius",
// "shape.half_extents", "shape.points"; "shape.radius" too for a radius set on a box).
std::shared_ptr<const RPreparedShape> PrepareShape(const RShape& shape);

// How a body moves. Dynamic: by forces, gravity and collisions. Static: never (infinite mass,
// zero velocity). Kinematic: by its own velocity and angular velocity alone, which the game
// sets; infinitely heavy to everything else (inverse mass and inertia 0 in the solver), it
// pushes and carries dynamic bodies with the velocity of its surface at the contact point,
// and collisions, forces, impulses and gravity never change its motion.
enum class RBodyKind : std::uint8_t { kDynamic, kStatic, kKinematic };

// Axes along which a body can neither move nor turn, world axes x, y, z. A collision treats
// a locked axis as infinitely heavy for that body: its inverse mass is 0 along a locked
// linear axis, and its world inverse inertia is that of the inertia restricted to the free
// angular axes (zero rows and columns on the locked ones). All six locked is the same as
// kinematic (its velocities along locked axes being 0, it never moves).
struct RBodyLocks {
  std::array<bool, 3> linear{false, false, false};
  std::array<bool, 3> angular{false, false, false};
};

// What a game or a scene file says about a body; RRigidBody copies it.
struct RBodyDef {
  std::string name;
  // Made by RShape's factories (RShape::Box(halfExtents), ...). Left as it is, it is a
  // sphere of radius 0, refused: no body gets a size nobody gave.
  RShape shape;
  // When set, the body is made from this shape and `shape` is not read: no hull is built.
  std::shared_ptr<const RPreparedShape> prepared;
  // How the body moves (RBodyKind). The scene format's `"static": true` is kind kStatic.
  RBodyKind kind = RBodyKind::kDynamic;
  std::optional<RScalar> mass;  // kg; when unset, density * volume
  RScalar density = 1;          // kg/m^3, used when mass is unset
  RVec3 position_W = RVec3::Zero();           // origin of S in the world, m (|x_i| <= 1e15)
  RQuat q_WS = RQuat::Identity();             // orientation of S in the world
  RVec3 velocity_W = RVec3::Zero();           // centre-of-mass velocity, world, m/s
  RVec3 angularVelocity_W = RVec3::Zero();    // world frame, rad/s
  // Coefficient of restitution, [0, 1]: the fraction of the approach speed a collision gives
  // back (RWorldSettings::restitutionCombine makes a pair's from the two bodies'). 0 by
  // default, as in Jolt and Box2D: a body bounces only where the game says so. (A scene file
  // body without "restitution" has 0.5: RScene::kDefaultRestitution.)
  RScalar restitution = 0;
  RScalar friction = RScalar(0.5);            // Coulomb coefficient, >= 0
  bool responds = true;  // false: collisions are reported, not resolved (missiles, sensors)
  // Drag rates c, 1/s, finite and >= 0 ("linear_damping", "angular_damping"): with no other
  // force or torque a dynamic body's speed decays exactly as v0 e^(-c t) and its angular
  // velocity (world frame) as w0 e^(-c t). 0: no drag, and no arithmetic.
  RScalar linearDamping = 0;
  RScalar angularDamping = 0;
  // Multiplies the world's gravity for this body, finite ("gravity_scale"); 1: the world's.
  RScalar gravityScale = 1;
  // World axes the body can neither move along nor turn about (see RBodyLocks).
  RBodyLocks locks;
  // The body's name in ignore lists, 0 to 2^32 - 2 (a scene gives each body its index in
  // its list). Unset by default: the body has no id, and no ignore list names it, so an
  // ignore list never matches bodies the game did not mean (ids that all default to one
  // value would make `ignore = {launcherId}` ignore everything). Several bodies may share
  // an id on purpose (a group ignored as one). In an RBodies, RBodies::IgnoreCollisions
  // takes handles instead and gives a body without an id one of its own.
  std::optional<std::uint32_t> id;
  // Ids of bodies this one never collides with (a missile and its launcher), each 0 to
  // 2^32 - 2.
  std::vector<std::uint32_t> ignore;
  // Collision filter bits, Box2D's rule: two bodies are tested against each other only if
  // (a.category & b.mask) != 0 and (b.category & a.mask) != 0 (both directions agree), and
  // neither ignores the other. Queries (RQueries.h) test their own mask against `category`.
  // The defaults let everything collide with everything.
  std::uint32_t category = 1;
  std::uint32_t mask = 0xFFFFFFFFu;
  // The game's own value (a pointer or an index, as std::uintptr_t); the engine never reads
  // it, copies it with the body and hands it back.
  std::uintptr_t userData = 0;
};

class alignas(64) RRigidBody {
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
  // Collision filter bits (RBodyDef::category, mask). Setting them wakes the body, and a
  // static or kinematic body wakes the sleepers whose boxes touch it, as IgnoreCollisionsWith
  // does: a sleeping pair is not looked at, so it would never learn that it may now touch.
  std::uint32_t Category() const { return m_category; }
  std::uint32_t Mask() const { return m_mask; }
  void SetCollisionFilter(std::uint32_t category, std::uint32_t mask);
  // The game's value (RBodyDef::userData); never read by the engine.
  std::uintptr_t UserData() const { return m_userData; }
  void SetUserData(std::uintptr_t value) { m_userData = value; }

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
  void Wake() {
    if (!m_isStatic) m_sleeping = false, m_restTime = 0;
  }

 private:
  friend class RIntegrator;
  friend class RWorldStep;
  friend class RBodies;
  friend struct RStateAccess;  // save and load (RWorldState.h)
  friend RConvexShape ShapeOf(const RRigidBody& body);  // reads m_polyhedron_B (line 0)

  // The fields are grouped by who reads them, hot first, and the body starts on a cache
  // line: a step's passes over every body (the sweep's set-up, the broad phase's boxes,
  // waking and sleeping, the motion) and the pair loop, which reaches a pair's second body
  // at random, each touch one to three lines of a 1.2 KB body instead of the seven to nine
  // that the definition's order spread them over. Only speed depends on the order.

  // Line 0: what every pass asks first. Kind and response; sleeping: whether the body
  // sleeps, how long (s) it has been slower than the sleep speed, and the island it fell
  // asleep with (the integrator's index of the island's first body; kNoIsland when awake
  // and not yet woken by the integrator); where it was at the end of its last step (which
  // integrator stepped it, at which slot: a body found at another slot of a plain vector, or
  // stepped by another integrator, means island ids no longer mean what they did, and
  // everything wakes; a body an RBodies has just added has not been stepped and wakes
  // nothing by itself); the filter bits; the shape's pointer and bounding radius.
  static constexpr std::uint32_t kNoIsland = 0xffffffffu;
  bool m_isStatic = false;
  bool m_isKinematic = false;
  bool m_responds = true;
  bool m_sleeping = false;
  // A static or kinematic body the game added, enabled, moved or refiltered since the last step.
  bool m_staticMoved = false;
  // Where a static or kinematic body the game moved (or refiltered) was at the last step,
  // world box (valid when m_wakeFromSet): the sleepers that touched it there wake, and those
  // that touch it where it is now, not the world.
  bool m_wakeFromSet = false;
  // Locks as the motion uses them: whether any linear (angular) axis is locked, and the
  // masks (below), 1 on a free world axis and 0 on a locked one (so a masked unlocked value
  // is the value bit for bit; unlocked bodies skip the multiply anyway).
  bool m_linearLocked = false, m_angularLocked = false;
  // Kinematic or angular locks: the world angular velocity m_w_W is the state, and m_w_B is
  // kept equal to it turned into the body frame.
  bool m_worldSpin = false;
  // Whether m_ignore (a cold line) holds anything: the pair loop asks only then.
  bool m_ignores = false;
  // Whether a joint keeps it from colliding with the body it joins (RBodies' m_noCollide).
  bool m_jointNoCollide = false;
  std::uint32_t m_sleepIsland = kNoIsland;
  std::uint32_t m_slot = kNoIsland;
  std::uint32_t m_category = 1, m_mask = 0xFFFFFFFFu;
  std::uint64_t m_slotWorld = 0;
  RScalar m_restTime = 0;
  RScalar m_boundingRadius = 0;
  const RConvexPolyhedron* m_polyhedron_B = nullptr;  // m_prepared's, null for a sphere, capsule or cylinder

  // Lines 1 and 2: the state and what the step's velocities are made of.
  RVec3 m_x_W = RVec3::Zero();
  RScalar m_invMass = 0;  // here: the quaternion's 16-byte alignment leaves this room
  RQuat m_q_WB = RQuat::Identity();
  RVec3 m_v_W = RVec3::Zero();
  RVec3 m_w_B = RVec3::Zero();
  // Which construction this body's shape and mass came from: a number drawn from a
  // process-wide counter by every constructor, kept by copies, so that state kept about a
  // body between steps (the contact memory of a pair, the queries' proxies) can tell a body
  // the game replaced in its place (`bodies[k] = RRigidBody(def)`) from the one it knew.
  // Assigning a body also counts as an edit (BodyEditCount): the queries look again.
  struct RSerial {
    std::uint64_t value = 0;
    RSerial();
    RSerial(const RSerial&) = default;
    RSerial& operator=(const RSerial& other);
  };
  RSerial m_serial;
  RScalar m_gravityScale = 1;

  // Lines 3 and 4: what the game and the solver accumulate, and the inverse inertia.
  RVec3 m_force_W = RVec3::Zero();
  RVec3 m_torque_W = RVec3::Zero();
  RVec3 m_linearImpulse_W = RVec3::Zero();
  RVec3 m_angularImpulse_W = RVec3::Zero();
  RVec3 m_invI_B = RVec3::Zero();
  RScalar m_linearDamping = 0;  // 1/s

  // Then what fewer passes read: drag, world spin, lock masks, the body-frame box (the
  // shape's axis-aligned box about the centre of mass, m: turned with the body it bounds
  // the world box without visiting vertices, the broad phase's boxes; a sphere's is its
  // bounding cube), and the world form (only pairs near each other).
  RScalar m_angularDamping = 0;  // 1/s
  RVec3 m_w_W = RVec3::Zero();  // world, rad/s; the state when m_worldSpin
  RVec3 m_linearMask = RVec3::Ones(), m_angularMask = RVec3::Ones();
  RVec3 m_boxCenter_B = RVec3::Zero(), m_boxHalf_B = RVec3::Zero();
  // A shape without a polyhedron, as the narrow phase sees it (RConvexShape): a core
  // segment from (0, -h, 0) to (0, h, 0) in B (h = 0: a point, a sphere), swept by a
  // sphere of the radius, m; or a cylinder of m_cylinderRadius about that segment (its
  // core radius 0). All 0 for a polyhedron.
  RScalar m_coreHalfHeight = 0, m_coreRadius = 0, m_cylinderRadius = 0;
  // A compound's children (m_prepared's; null and 0 for any other shape).
  const RShapeChild* m_children = nullptr;
  std::uint32_t m_childCount = 0;
  const RTriangleMesh* m_mesh = nullptr;  // a mesh's triangles in B (m_prepared's), else null
  mutable RWorldForm m_worldForm;
  // Beside the form it counts: on a cold line, each pair that computed a form waited for
  // memory to count it (a 30000-body cloud: 2 ms a step).
  mutable std::uint64_t m_worldFormComputations = 0;

  // Last, what the step reads only at a contact or never: material, mass properties, the
  // shape's frame, the definition, and the rotation's cached elliptic constants (only the
  // motion reads them, after everything above).
  RScalar m_restitution = 0;
  RScalar m_friction = 0;
  RScalar m_mass = 0;
  RVec3 m_I_B = RVec3::Zero();
  RVec3 m_p_BS = RVec3::Zero();
  RQuat m_q_BS = RQuat::Identity();
  RBodyLocks m_locks;
  RVec3 m_wakeFromMin_W = RVec3::Zero(), m_wakeFromMax_W = RVec3::Zero();
  std::string m_name;
  // kNoId: no id (RBodyDef::id unset). No ignore list holds it, so the pair loop's search
  // needs no test of its own; saved states store it as it is.
  static constexpr std::uint32_t kNoId = 0xFFFFFFFFu;
  std::uint32_t m_id = kNoId;
  std::vector<std::uint32_t> m_ignore;  // sorted
  std::uintptr_t m_userData = 0;
  std::shared_ptr<const RPreparedShape> m_prepared;  // never null
  RFreeRotation m_rotation;

  // An edit of a static or kinematic body: notes its box before the edit (a body never
  // stepped held no sleeper) and marks it moved.
  void NoteImmovableEdit();
  // A box about the body at its pose, world (its body-frame box turned: |R| h about R c).
  void WorldBox(RVec3& min_W, RVec3& max_W) const;
  // Static or kinematic: not moved by anything the solver or the game's forces do, in no
  // island; moving it (SetShapePose), adding or removing it is what a static body's is.
  bool Immovable() const { return m_isStatic || m_isKinematic; }
  void WakeIfNonZero(const RVec3& x) {
    if (!x.isZero(0)) Wake();
  }
  void ComputeWorldForm(std::uint64_t stamp) const;
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
  X(RRigidBody)
RENGINE_ABI_CHECK(kRigidBody, RENGINE_ABI_TYPES_RIGID_BODY)
