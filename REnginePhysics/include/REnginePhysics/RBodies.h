// RBodies: the container of rigid bodies a game passes to RIntegrator::Update. A body is
// added from its definition and named by a handle (slot index + generation, as in Box2D and
// Jolt) that stays valid until the body is removed, whatever else is added or removed.
//
//   RBodies bodies;
//   RBodyHandle ship = bodies.Add(shipDef);
//   integrator.Update(bodies, dt);
//   bodies[ship].AddForce_W(thrust);
//   bodies.Remove(ship);            // O(1); `ship` is stale from now on
//
// Storage is dense: the enabled bodies sit contiguously, in an order that depends only on
// the sequence of Add, Remove, Disable and Enable calls (a removed body's place is taken by
// the last one), and the integrator steps exactly that range. Disabled bodies (a pool of
// parked missiles) sit after it and cost nothing per step.
//
// Contact memory (warm starts) and sleeping islands are keyed by handle: adding a body wakes
// only what it touches (a dynamic one through the next step's pair sweep, a static or
// kinematic one the sleepers its box touches), removing or disabling one wakes only the
// sleeping island it belonged to (for a static or kinematic body, the sleepers whose boxes
// touched it), and every other pair keeps its warm start.
#pragma once

#include <REnginePhysics/RError.h>

#include <REnginePhysics/RAbi.h>
#include <REnginePhysics/RBodyHandle.h>
#include <REnginePhysics/RJoint.h>
#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RSlotMap.h>

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace REngine {

// A value from NextCacheStamp() (process-wide, never repeated), drawn afresh when the
// container changes and when it is copied or moved, so that a cache keyed by it can never
// take one container, or a copy of it, for another.
class RBodiesStamp {
 public:
  RBodiesStamp();
  RBodiesStamp(const RBodiesStamp&);
  RBodiesStamp& operator=(const RBodiesStamp&);
  void Bump();
  std::uint64_t Value() const { return m_value; }
  // A snapshot's restore (RSnapshot.h), which has just put back the container a value was
  // drawn for: the container holds that layout again.
  void Adopt(std::uint64_t value) { m_value = value; }

 private:
  std::uint64_t m_value;
};

// A handle that names no body or joint (never issued, or its body was removed). Field() is
// "handle"; what() says which handle and which call.
class RHandleError : public RError {
 public:
  explicit RHandleError(const std::string& what) : RError("handle", what, what) {}
};

// The container's state: RBodies holds it as a private base, so a game sees only RBodies'
// functions; the integrator and save/load reach it through the engine's private header
// body/RBodyAccess.h.
struct RBodiesCore {
  using RBodySlots = RSlotMap<RRigidBody, RBodyHandle>;
  using RJointSlots = RSlotMap<RJoint, RJointHandle>;
  static constexpr std::uint32_t kFree = RBodySlots::kFree;
  // The bodies, dense: enabled [0, m_enabled), then disabled.
  RBodySlots m_slots;
  std::size_t m_enabled = 0;
  // Read and cleared by the next Update: islands to wake (by island id), or all of them.
  std::vector<std::uint32_t> m_wakeIslands;
  bool m_wakeAll = false;
  // ... and the world boxes (min, max, min, max, ...) of the static and kinematic bodies that
  // left: the sleepers they touched wake.
  std::vector<RVec3> m_wakeBoxes;
  RBodiesStamp m_layoutStamp, m_poseStamp;
  // Joints: a slot map as the bodies', and the pairs of body slots a joint keeps from
  // colliding (lower << 32 | higher, sorted; a pair joined twice is there twice).
  RJointSlots m_jointSlots;
  std::vector<std::uint64_t> m_noCollide;
  // Changes with LayoutStamp and with every change of the joints' table or definitions: a
  // rollback snapshot (RSnapshot.h) shares the container's tables with earlier snapshots
  // while it is the value they were copied at.
  RBodiesStamp m_definitionStamp;
  void LayoutChanged() { m_layoutStamp.Bump(), m_poseStamp.Bump(), m_definitionStamp.Bump(); }
};

class RBodies : private RBodiesCore {
 public:
  // Most bodies one container holds (handles are 32-bit; RSceneLimits keeps scenes far
  // below).
  static constexpr std::size_t kMaxBodies = std::size_t(1) << 31;

  // Makes a body from its definition (RRigidBody's checks: throws RBodyError and adds
  // nothing) and returns its handle. A body made from a shared prepared shape
  // (RBodyDef::prepared) builds no hull. The body is enabled and awake.
  RBodyHandle Add(const RBodyDef& def);
  RBodyHandle Add(RRigidBody body);
  // Removes the body, O(1): the last enabled body takes its place. Its sleeping island wakes
  // (a removed body may have held a stack up); a removed static or kinematic body wakes the
  // sleepers whose boxes touched it (where it was at the last step, and where it is).
  // Throws RHandleError for a stale or invalid handle.
  void Remove(RBodyHandle h);
  // A disabled body stays in the container with its state, is not stepped, and touches
  // nothing: pooling. Disabling wakes what removing would; enabling is like adding. Both are
  // O(1) and do nothing when the body already is so. Throw RHandleError for a stale handle.
  void Disable(RBodyHandle h);
  void Enable(RBodyHandle h);
  bool IsEnabled(RBodyHandle h) const { return DenseIndex(h) < m_enabled; }

  bool Contains(RBodyHandle h) const { return m_slots.Contains(h); }
  // The body a handle names; throws RHandleError when stale. Find: nullptr instead.
  RRigidBody& operator[](RBodyHandle h) { return m_slots.items[DenseIndex(h)]; }
  const RRigidBody& operator[](RBodyHandle h) const { return m_slots.items[DenseIndex(h)]; }
  RRigidBody* Find(RBodyHandle h) { return Contains(h) ? &m_slots.items[m_slots.denseOfSlot[h.index]] : nullptr; }
  const RRigidBody* Find(RBodyHandle h) const {
    return Contains(h) ? &m_slots.items[m_slots.denseOfSlot[h.index]] : nullptr;
  }

  // Every body, enabled first: Size() of them, dense positions 0 .. Size() - 1.
  std::size_t Size() const { return m_slots.items.size(); }
  bool Empty() const { return m_slots.items.empty(); }
  std::size_t EnabledCount() const { return m_enabled; }
  RRigidBody& At(std::size_t dense) { return m_slots.items.at(dense); }
  const RRigidBody& At(std::size_t dense) const { return m_slots.items.at(dense); }
  RBodyHandle HandleAt(std::size_t dense) const { return m_slots.handles.at(dense); }

  // a and b never collide with each other from now on (a missile and its launcher), whatever
  // their ids: a body without an id (RBodyDef::id unset) is first given one unused in this
  // container (a search over the bodies, once per body), then a's ignore list takes b's id
  // (RRigidBody::IgnoreCollisionsWith). A body that shares its id with others on purpose
  // brings its group along. Wakes a as IgnoreCollisionsWith does. Throws RHandleError
  // for a stale handle, RBodyError ("ignore") when a and b are the same body, and RError
  // ("id") when every id is taken.
  void IgnoreCollisions(RBodyHandle a, RBodyHandle b);
  // The enabled bodies, as contiguous storage (what the integrator steps).
  RRigidBody* begin() { return m_slots.items.data(); }
  RRigidBody* end() { return m_slots.items.data() + m_enabled; }
  const RRigidBody* begin() const { return m_slots.items.data(); }
  const RRigidBody* end() const { return m_slots.items.data() + m_enabled; }
  const std::vector<RBodyHandle>& Handles() const { return m_slots.handles; }

  // Room for n bodies without reallocating (spawning then allocates only the body's own
  // name, ignore list and world-form arrays).
  void Reserve(std::size_t n);
  void Clear();

  // Joints (RJoint.h). AddJoint checks the definition, its type included (throws RJointError,
  // an RError, naming the field; RHandleError for a body that is not here; and
  // adds nothing), fixes the anchors and axes in the bodies' frames as they stand, and
  // wakes both bodies. A joint whose body is
  // disabled does nothing until it is enabled again; removing a body removes its joints.
  RJointHandle AddJoint(const RJointDef& def);
  // Throws RHandleError for a stale or invalid handle. Wakes the joint's bodies.
  void RemoveJoint(RJointHandle h);
  bool ContainsJoint(RJointHandle h) const { return m_jointSlots.Contains(h); }
  const RJoint& Joint(RJointHandle h) const { return m_jointSlots.items[JointDenseIndex(h)]; }
  // A motor's target speed and force (RJointMotor's checks: speed within 1e15, force in
  // [0, 1e30]; throws RJointError), for a hinge or slider; wakes the joint's bodies.
  void SetJointMotor(RJointHandle h, const RJointMotor& motor);
  // Every joint, in an order that depends only on the sequence of AddJoint and RemoveJoint
  // calls (a removed joint's place is taken by the last one).
  std::size_t JointCount() const { return m_jointSlots.items.size(); }
  const RJoint& JointAt(std::size_t dense) const { return m_jointSlots.items.at(dense); }
  RJointHandle JointHandleAt(std::size_t dense) const { return m_jointSlots.handles.at(dense); }
  // A hinge's angle (rad, b's turn about the axis relative to a since the joint was added)
  // and a slider's travel (m), at the bodies' present poses; 0 for other types.
  RScalar JointPosition(RJointHandle h) const;

  // For caches kept outside the step (RQueries' tree). LayoutStamp changes whenever the set or
  // order of the enabled bodies does (Add, Remove, Disable, Enable, a copy); PoseStamp
  // whenever LayoutStamp does and whenever RIntegrator::Update moves the bodies. Poses set
  // by game code (SetShapePose) are counted by BodyEditCount(). Values are unique in the
  // process.
  std::uint64_t LayoutStamp() const { return m_layoutStamp.Value(); }
  std::uint64_t PoseStamp() const { return m_poseStamp.Value(); }

 private:
  std::uint32_t DenseIndex(RBodyHandle h) const;
  // What leaving the step does to sleepers: a sleeping body's island wakes, a static or
  // kinematic body wakes the sleepers about it.
  void WakeForDeparture(RRigidBody& b);
  std::uint32_t JointDenseIndex(RJointHandle h) const;
  void RemoveJointAt(std::uint32_t dense);
  void RemoveJointsOf(RBodyHandle body);
  void SetNoCollideFlags(RBodyHandle body);
  void WakeJointPartners(RBodyHandle body);
};

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_BODIES(X) \
  X(RBodiesCore) \
  X(RBodies)
RENGINE_ABI_CHECK(kBodies, RENGINE_ABI_TYPES_BODIES)
