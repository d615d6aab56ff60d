// The engine's state of a rigid body: what RRigidBody's functions read and set, and what
// the step reads and writes in its passes over the bodies (the pair sweep, the broad phase,
// sleeping, the motion). RRigidBody holds it as a private base: a game sees the body through
// RRigidBody's functions alone, and the engine reaches these fields through its private
// header body/RBodyAccess.h. Units and frames as RRigidBody.h states them.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RBodyDef.h>
#include <REnginePhysics/RFreeRotation.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace REngine {

struct alignas(64) RBodyCore {
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
  bool m_oneWay = false;  // RBodyDef::oneWay
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
  // Which version of the fields a step never changes (the definition, filter bits, drag,
  // user data, an immovable body's pose): a number drawn from a process-wide counter by every
  // constructor and by every edit of them between steps, kept by copies. A rollback snapshot
  // (RSnapshot.h) shares those fields with earlier snapshots while the number is the one
  // they were copied at, and saves only what a step changes.
  struct RDefinitionStamp {
    std::uint64_t value = 0;
    RDefinitionStamp();
    void Bump();
  };
  RDefinitionStamp m_definition;

  // An edit of a static or kinematic body: notes its box before the edit (a body never
  // stepped held no sleeper) and marks it moved.
  // (Also a definition edit: see m_definition.)
  void NoteImmovableEdit();
  // A box about the body at its pose, world (its body-frame box turned: |R| h about R c).
  void WorldBox(RVec3& min_W, RVec3& max_W) const;
  // Static or kinematic: not moved by anything the solver or the game's forces do, in no
  // island; moving it (SetShapePose), adding or removing it is what a static body's is.
  bool Immovable() const { return m_isStatic || m_isKinematic; }
  // RRigidBody::Wake.
  void Wake() {
    if (!m_isStatic) m_sleeping = false, m_restTime = 0;
  }
  void WakeIfNonZero(const RVec3& x) {
    if (!x.isZero(0)) Wake();
  }
  void ComputeWorldForm(std::uint64_t stamp) const;
};

}  // namespace REngine
