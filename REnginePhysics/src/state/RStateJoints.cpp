// Save and load of an RBodies' joints (RWorldState.h): each joint's definition, the frames
// it keeps in its bodies, and the solver's memory of it (its last impulses: the next step's
// warm start), with the joints' slot table, so that joint handles a game keeps name the same
// joints after a load and a world with joints continues bit for bit.
#include "state/RStateAccess.h"

#include <REnginePhysics/RLimits.h>
#include "body/RBodyAccess.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace REngine {

using namespace state;

namespace {

void WriteDef(RWriter& w, const RJointDef& d) {
  w.U8(static_cast<std::uint8_t>(d.type));
  w.U32(d.a.index), w.U32(d.a.generation), w.U32(d.b.index), w.U32(d.b.generation);
  w.Vec3(d.anchor_W), w.Bool(d.hasAnchorB), w.Vec3(d.anchorB_W), w.Vec3(d.axis_W);
  w.Bool(d.hasLimits), w.F64(d.lower), w.F64(d.upper);
  w.F64(d.minDistance), w.F64(d.maxDistance);
  w.Bool(d.motor.enabled), w.F64(d.motor.speed), w.F64(d.motor.maxForce);
  w.Bool(d.collideConnected);
}

}  // namespace

void RStateAccess::WriteJoints(RWriter& w, const RBodies& bodies) {
  const RBodiesCore& c = Core(bodies);
  w.U64(c.m_jointSlots.generation.size());
  for (std::uint32_t g : c.m_jointSlots.generation) w.U32(g);
  w.U64(c.m_jointSlots.free.size());
  for (std::uint32_t slot : c.m_jointSlots.free) w.U32(slot);
  w.U64(c.m_jointSlots.items.size());
  for (std::size_t k = 0; k < c.m_jointSlots.items.size(); ++k) {
    const RJoint& j = c.m_jointSlots.items[k];
    w.U32(c.m_jointSlots.handles[k].index), w.U32(c.m_jointSlots.handles[k].generation);
    WriteDef(w, j.def);
    w.Vec3(j.anchorA_B), w.Vec3(j.anchorB_B), w.Vec3(j.axisA_B), w.Vec3(j.axisB_B);
    w.Vec3(j.perpA_B[0]), w.Vec3(j.perpA_B[1]), w.Quat(j.relative0);
    w.F64(j.minDistance), w.F64(j.maxDistance);
    for (int r = 0; r < RJoint::kMaxRows; ++r) w.F64(j.lambda[r]), w.F64(j.lambdaEnd[r]);
    w.Vec3(j.impulse_W), w.Vec3(j.angularImpulse_W);
  }
}

// Reads the joints' table and joints; checks that the table is one RBodies could have made
// and that every joint's bodies are live handles of the saved container.
void RStateAccess::ReadJoints(RReader& r, RSavedBodies& out) {
  r.SetRecord("joints");
  out.jointGeneration.resize(r.Count("slots", 4));
  for (std::uint32_t& g : out.jointGeneration) g = r.U32("generations");
  out.jointFree.resize(r.Count("free", 4));
  for (std::uint32_t& slot : out.jointFree) slot = r.U32("free");
  const std::size_t count = r.Count("joints", 400);
  out.jointDenseOfSlot.assign(out.jointGeneration.size(), RBodiesCore::kFree);
  out.joints.resize(count);
  out.jointHandles.resize(count);
  auto live = [&out](RBodyHandle h) {
    return h.index < out.generation.size() && out.generation[h.index] == h.generation &&
           out.denseOfSlot[h.index] != RBodiesCore::kFree;
  };
  for (std::size_t k = 0; k < count; ++k) {
    r.SetRecord(Indexed("joints", k));
    RJointHandle h;
    h.index = r.U32("handle"), h.generation = r.U32("handle");
    if (h.index >= out.jointGeneration.size() || out.jointGeneration[h.index] != h.generation ||
        out.jointDenseOfSlot[h.index] != RBodiesCore::kFree) {
      r.Fail("handle", "is not a live slot of the joints' table, or is named twice");
    }
    out.jointDenseOfSlot[h.index] = static_cast<std::uint32_t>(k);
    out.jointHandles[k] = h;
    RJoint& j = out.joints[k];
    RJointDef& d = j.def;
    const std::uint8_t type = r.U8("type");
    if (type > static_cast<std::uint8_t>(RJointType::kDistance)) r.Fail("type", "is not a joint type");
    d.type = static_cast<RJointType>(type);
    d.a.index = r.U32("a"), d.a.generation = r.U32("a");
    d.b.index = r.U32("b"), d.b.generation = r.U32("b");
    if (!live(d.a) || (d.b.IsValid() && !live(d.b)) || d.a == d.b) {
      r.Fail("a", "a joint's bodies must be live bodies of the container, and two");
    }
    // RBodies::AddJoint's checks (and SetJointMotor's): what a joint can be.
    const bool axial = d.type == RJointType::kHinge || d.type == RJointType::kSlider;
    d.anchor_W = r.WithinVec3("anchor", kMaxPosition);
    d.hasAnchorB = r.Bool("has_anchor_b");
    if (d.hasAnchorB && d.type != RJointType::kDistance) r.Fail("has_anchor_b", "only a distance joint has a second anchor");
    d.anchorB_W = r.WithinVec3("anchor_b", kMaxPosition);
    d.axis_W = r.UnitVec3("axis");  // kept unit length
    d.hasLimits = r.Bool("has_limits"), d.lower = r.Finite("lower"), d.upper = r.Finite("upper");
    if (d.hasLimits) {
      if (!axial) r.Fail("has_limits", "only a hinge or a slider has limits");
      if (!(d.lower <= d.upper)) r.Fail("lower", "must not exceed upper");
      if (d.type == RJointType::kHinge && !(d.lower >= -kPi)) r.Fail("lower", "a hinge's limits must lie within [-pi, pi]");
      if (d.type == RJointType::kHinge && !(d.upper <= kPi)) r.Fail("upper", "a hinge's limits must lie within [-pi, pi]");
    }
    d.minDistance = r.Finite("min_distance"), d.maxDistance = r.Finite("max_distance");
    d.motor.enabled = r.Bool("motor"), d.motor.speed = r.Finite("motor"), d.motor.maxForce = r.Finite("motor");
    if (!(d.motor.maxForce >= 0)) r.Fail("motor", "max force must be >= 0");
    if (d.motor.enabled && !axial) r.Fail("motor", "only a hinge or a slider has a motor");
    d.collideConnected = r.Bool("collide_connected");
    // The frames in the bodies: anchors from a body's centre (or world points for the
    // world), unit axes, a unit relative orientation.
    j.anchorA_B = r.WithinVec3("frames", kMaxSpan), j.anchorB_B = r.WithinVec3("frames", kMaxSpan);
    j.axisA_B = r.UnitVec3("frames"), j.axisB_B = r.UnitVec3("frames");
    j.perpA_B[0] = r.UnitVec3("frames"), j.perpA_B[1] = r.UnitVec3("frames");
    j.relative0 = r.UnitQuat("frames");
    // A distance joint's range (0 <= min <= max, max > 0); the other joints have none.
    j.minDistance = r.Finite("distances"), j.maxDistance = r.Finite("distances");
    if (d.type == RJointType::kDistance && !(j.minDistance >= 0 && j.minDistance <= j.maxDistance && j.maxDistance > 0)) {
      r.Fail("distances", "must be 0 <= min <= max, max > 0");
    }
    for (int row = 0; row < RJoint::kMaxRows; ++row) {
      j.lambda[row] = r.Within("impulses", kMaxImpulse), j.lambdaEnd[row] = r.Within("impulses", kMaxImpulse);
    }
    j.impulse_W = r.WithinVec3("impulses", kMaxImpulse), j.angularImpulse_W = r.WithinVec3("impulses", kMaxImpulse);
    // A joint moves a dynamic body: a joint between two static or kinematic bodies (or one
    // and the world) is refused by AddJoint.
    const RBodyCore& A = Core(out.bodies[out.denseOfSlot[d.a.index]]);
    const RBodyCore* B = d.b.IsValid() ? &Core(out.bodies[out.denseOfSlot[d.b.index]]) : nullptr;
    if (A.Immovable() && !(B && !B->Immovable())) {
      r.Fail("a", "a joint needs a dynamic body: a and b are both static or kinematic (or b is the world)");
    }
  }
  std::vector<char> freed(out.jointGeneration.size(), 0);
  r.SetRecord("joints");
  for (std::uint32_t slot : out.jointFree) {
    if (slot >= out.jointGeneration.size() || out.jointDenseOfSlot[slot] != RBodiesCore::kFree || freed[slot]) {
      r.Fail("free", "slot " + std::to_string(slot) + " is beyond the table, live, or free twice");
    }
    freed[slot] = 1;
  }
  r.SetRecord("");
}

// The loaded joints into the container, and what follows from them: the pairs they keep
// from colliding and their bodies' flags.
void RStateAccess::CommitJoints(RBodies& bodies, RSavedBodies& saved) {
  Core(bodies).m_jointSlots.items.swap(saved.joints);
  Core(bodies).m_jointSlots.handles.swap(saved.jointHandles);
  Core(bodies).m_jointSlots.generation.swap(saved.jointGeneration);
  Core(bodies).m_jointSlots.denseOfSlot.swap(saved.jointDenseOfSlot);
  Core(bodies).m_jointSlots.free.swap(saved.jointFree);
  Core(bodies).m_noCollide.clear();
  for (RRigidBody& b : Core(bodies).m_slots.items) Core(b).m_jointNoCollide = false;
  for (const RJoint& j : Core(bodies).m_jointSlots.items) {
    if (!j.def.b.IsValid() || j.def.collideConnected) continue;
    const std::uint32_t a = j.def.a.index, b = j.def.b.index;
    Core(bodies).m_noCollide.push_back(a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a);
    Core(bodies[j.def.a]).m_jointNoCollide = Core(bodies[j.def.b]).m_jointNoCollide = true;
  }
  std::sort(Core(bodies).m_noCollide.begin(), Core(bodies).m_noCollide.end());
}

}  // namespace REngine
