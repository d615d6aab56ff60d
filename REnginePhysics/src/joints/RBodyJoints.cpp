// RBodies' joints: a slot map beside the bodies' (see RBodies.h, RJoint.h); the checks at
// the door and the frames a joint keeps in each body.
#include <REnginePhysics/RBodies.h>

#include "joints/RJointRows.h"
#include <REnginePhysics/RLimits.h>

#include <REngineMath/RQuaternion.h>

#include <algorithm>
#include <cmath>
#include <string>
#include "body/RBodyAccess.h"

namespace REngine {

namespace {

void Require(bool ok, const char* field, const std::string& problem) {
  if (!ok) throw RJointError(field, problem);
}

// Coordinates beyond this (m) are not a place: bodies are limited to 1e12 m in size.
constexpr RScalar kMostCoordinate = 1e15;

bool Finite(const RVec3& v) { return v.allFinite() && v.cwiseAbs().maxCoeff() <= kMostCoordinate; }

std::uint64_t SlotPair(std::uint32_t a, std::uint32_t b) {
  return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
}

void CheckMotor(const RJointMotor& m) {
  Require(std::isfinite(m.speed) && std::abs(m.speed) <= kMaxMotorSpeed, "motor.speed",
          "must be finite and within 1e15 (m/s or rad/s)");
  Require(std::isfinite(m.maxForce) && m.maxForce >= 0 && m.maxForce <= kMaxMotorForce, "motor.max_force",
          "must be finite, >= 0 and at most 1e30 (N or N m)");
}

}  // namespace

std::uint32_t RBodies::JointDenseIndex(RJointHandle h) const {
  if (!ContainsJoint(h)) {
    throw RHandleError("RBodies: joint handle (index " + std::to_string(h.index) + ", generation " +
                       std::to_string(h.generation) + ") names no joint: " +
                       (h.IsValid() ? "it was removed" : "it was never issued"));
  }
  return m_jointSlots.denseOfSlot[h.index];
}

RJointHandle RBodies::AddJoint(const RJointDef& def) {
  // A type from a cast or a newer header: every branch below would take it for a ball.
  Require(def.type == RJointType::kBall || def.type == RJointType::kHinge || def.type == RJointType::kSlider ||
              def.type == RJointType::kFixed || def.type == RJointType::kDistance,
          "type", "must be ball, hinge, slider, fixed or distance (got " + std::to_string(int(def.type)) + ")");
  // The bodies: a here (RHandleError otherwise), b here or the world, not a itself, and
  // something a joint can move.
  RRigidBody& A = (*this)[def.a];
  RRigidBody* B = def.b.IsValid() ? &(*this)[def.b] : nullptr;
  Require(def.a != def.b, "b", "must be another body than a");
  Require(!Core(A).Immovable() || (B && !Core(*B).Immovable()), "a",
          "a joint needs a dynamic body: a and b are both static or kinematic (or b is the world)");
  Require(Finite(def.anchor_W), "anchor", "must be finite (and within 1e15 m)");
  const bool axial = def.type == RJointType::kHinge || def.type == RJointType::kSlider;
  RVec3 axis = RVec3::UnitX();
  if (axial) {
    const RScalar largest = def.axis_W.cwiseAbs().maxCoeff();
    Require(def.axis_W.allFinite() && largest > 0, "axis", "must be finite and not zero");
    // Scaled by its largest component first: the norm of [1e200, 0, 0] overflows, and of
    // [1e-320, 0, 0] underflows.
    axis = (def.axis_W / largest).normalized();
  }
  if (def.hasLimits) {
    Require(axial, "limits", "only a hinge or a slider has limits");
    Require(std::isfinite(def.lower) && std::isfinite(def.upper) && def.lower <= def.upper, "limits",
            "must be finite with lower <= upper");
    if (def.type == RJointType::kHinge) {
      Require(def.lower >= -kPi && def.upper <= kPi, "limits", "a hinge's limits must lie within [-pi, pi]");
    }
  }
  if (def.motor.enabled) {
    Require(axial, "motor", "only a hinge or a slider has a motor");
    CheckMotor(def.motor);
  }
  const RVec3 anchorB = def.type == RJointType::kDistance && def.hasAnchorB ? def.anchorB_W : def.anchor_W;
  if (def.hasAnchorB) {
    Require(def.type == RJointType::kDistance, "anchor_b", "only a distance joint has a second anchor");
    Require(Finite(def.anchorB_W), "anchor_b", "must be finite (and within 1e15 m)");
  }
  RJoint j;
  j.def = def;
  j.def.axis_W = axis;
  if (def.type == RJointType::kDistance) {
    const RScalar now = (anchorB - def.anchor_W).norm();
    const RScalar lo = def.minDistance < 0 ? now : def.minDistance;
    const RScalar hi = def.maxDistance < 0 ? now : def.maxDistance;
    Require(std::isfinite(def.minDistance) && std::isfinite(def.maxDistance), "min_distance",
            "min_distance and max_distance must be finite");
    Require(lo <= hi, "min_distance", "must not exceed max_distance");
    Require(hi > 0, "max_distance", "must be > 0 (anchors that stay together are a ball joint)");
    j.minDistance = lo, j.maxDistance = hi;
  }
  // The frames, as the bodies stand.
  const RQuat qA = A.Orientation_WB();
  const RQuat qB = B ? B->Orientation_WB() : RQuat::Identity();
  const RVec3 xB = B ? B->Position_W() : RVec3::Zero();
  j.anchorA_B = qA.conjugate() * (def.anchor_W - A.Position_W());
  j.anchorB_B = qB.conjugate() * (anchorB - xB);
  // A hinge's angle, a slider's travel and a motor's speed are b's relative to a; for a
  // joint to the world, a's relative to the world: the axis is kept reversed, which turns
  // "b relative to a about -axis" into "a relative to the world about axis".
  const RVec3 kept = B ? axis : RVec3(-axis);
  j.axisA_B = qA.conjugate() * kept;
  j.axisB_B = qB.conjugate() * kept;
  // Two directions across the axis: the axis' least component's unit vector, made
  // perpendicular (a stable choice whatever the axis).
  int least = 0;
  for (int k = 1; k < 3; ++k) least = std::abs(axis[k]) < std::abs(axis[least]) ? k : least;
  const RVec3 p0 = (RVec3::Unit(least) - axis[least] * axis).normalized();
  const RVec3 p1 = axis.cross(p0);
  j.perpA_B[0] = qA.conjugate() * p0;
  j.perpA_B[1] = qA.conjugate() * p1;
  j.relative0 = qA.conjugate() * qB;

  const RJointHandle h = m_jointSlots.Insert(j);
  m_definitionStamp.Bump();
  if (B && !def.collideConnected) {
    const std::uint64_t key = SlotPair(def.a.index, def.b.index);
    m_noCollide.insert(std::upper_bound(m_noCollide.begin(), m_noCollide.end(), key), key);
    Core(A).m_jointNoCollide = Core(*B).m_jointNoCollide = true;
  }
  // The bodies join one island: a sleeping one wakes (its island with it).
  A.Wake();
  if (B) B->Wake();
  return h;
}

void RBodies::RemoveJointAt(std::uint32_t dense) {
  const RJointDef def = m_jointSlots.items[dense].def;
  // The last joint takes its place.
  m_jointSlots.SwapDense(dense, static_cast<std::uint32_t>(m_jointSlots.items.size() - 1));
  m_jointSlots.PopBack();
  m_definitionStamp.Bump();
  if (def.b.IsValid() && !def.collideConnected) {
    const auto it = std::lower_bound(m_noCollide.begin(), m_noCollide.end(), SlotPair(def.a.index, def.b.index));
    if (it != m_noCollide.end()) m_noCollide.erase(it);
    SetNoCollideFlags(def.a), SetNoCollideFlags(def.b);
  }
  // What the joint held is free now: its bodies wake (a removed body's wake on its own).
  if (RRigidBody* A = Find(def.a)) A->Wake();
  if (RRigidBody* B = Find(def.b)) B->Wake();
}

void RBodies::RemoveJoint(RJointHandle h) { RemoveJointAt(JointDenseIndex(h)); }

void RBodies::RemoveJointsOf(RBodyHandle body) {
  for (std::size_t k = m_jointSlots.items.size(); k-- > 0;) {
    if (m_jointSlots.items[k].def.a == body || m_jointSlots.items[k].def.b == body) RemoveJointAt(static_cast<std::uint32_t>(k));
  }
}

// The bodies joined to this one: a sleeper hung from it (a hook far above, which no box
// sweep finds) lets go or is held again.
void RBodies::WakeJointPartners(RBodyHandle body) {
  for (const RJoint& j : m_jointSlots.items) {
    const RBodyHandle other = j.def.a == body ? j.def.b : j.def.b == body ? j.def.a : RBodyHandle{};
    if (RRigidBody* b = Find(other)) b->Wake();
  }
}

void RBodies::SetNoCollideFlags(RBodyHandle body) {
  RRigidBody* b = Find(body);
  if (!b) return;
  bool any = false;
  for (std::uint64_t key : m_noCollide) {
    any = any || static_cast<std::uint32_t>(key >> 32) == body.index || static_cast<std::uint32_t>(key) == body.index;
  }
  Core(*b).m_jointNoCollide = any;
  m_definitionStamp.Bump();
}

void RBodies::SetJointMotor(RJointHandle h, const RJointMotor& motor) {
  RJoint& j = m_jointSlots.items[JointDenseIndex(h)];
  Require(j.def.type == RJointType::kHinge || j.def.type == RJointType::kSlider, "motor",
          "only a hinge or a slider has a motor");
  if (motor.enabled) CheckMotor(motor);
  j.def.motor = motor;
  m_definitionStamp.Bump();
  if (RRigidBody* A = Find(j.def.a)) A->Wake();
  if (RRigidBody* B = Find(j.def.b)) B->Wake();
}

RScalar RBodies::JointPosition(RJointHandle h) const {
  const RJoint& j = m_jointSlots.items[JointDenseIndex(h)];
  const RRigidBody& A = (*this)[j.def.a];
  const RRigidBody* B = Find(j.def.b);
  const RJointPoseIn pa{A.Position_W(), A.Orientation_WB()};
  const RJointPoseIn pb = B ? RJointPoseIn{B->Position_W(), B->Orientation_WB()}
                            : RJointPoseIn{RVec3::Zero(), RQuat::Identity()};
  return JointMotorPosition(j, pa, pb);
}

}  // namespace REngine
