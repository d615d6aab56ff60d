// Joints: constraints between two bodies, or between a body and the world, solved with the
// contacts by the same solver (RIntegrator's FindImpulses; see RJoints.cpp for the method).
// They live in the RBodies container beside the bodies they join, named by handles:
//
//   RJointDef hinge;
//   hinge.type = RJointType::kHinge;
//   hinge.a = turret, hinge.b = ship;          // b invalid: the turret is hinged to the world
//   hinge.anchor_W = pivot, hinge.axis_W = up;  // as the bodies stand now
//   hinge.motor = {true, 1.0, 5e3};            // 1 rad/s with at most 5 kN m
//   RJointHandle h = bodies.AddJoint(hinge);
//   ...
//   bodies.RemoveJoint(h);                     // or removed with either body
//
// Frames and units: anchors and axes are given in the world frame as the bodies stand when
// the joint is added; the joint keeps them fixed in each body's frame from then on. Angles
// in rad, lengths in m, speeds in rad/s or m/s, forces in N or N m, impulses in N s or N m s.
#pragma once

#include <REnginePhysics/RAbi.h>
#include <REngineMath/RMath.h>
#include <REnginePhysics/RBodyHandle.h>
#include <REnginePhysics/RRigidBody.h>

#include <cstdint>
#include <limits>

namespace REngine {

enum class RJointType : std::uint8_t {
  kBall,      // the anchor points stay together; the bodies turn freely about them
  kHinge,     // the anchor points stay together and the bodies turn only about the axis
  kSlider,    // the bodies move only along the axis, without turning
  kFixed,     // no relative motion: a weld
  kDistance,  // the anchors stay between minDistance and maxDistance apart (a rope: min 0)
};

struct RJointTag;
// A joint's name in an RBodies: slot index and generation (RSlotHandle). Default-constructed:
// invalid.
using RJointHandle = RSlotHandle<RJointTag>;

// Drives a hinge's angle or a slider's travel towards a relative speed (b's relative to
// a's, about or along the axis: rad/s or m/s) with at most maxForce (N m or N), as Jolt's
// and Bullet's velocity motors do: maxForce dt of impulse a step, half at each end of it
// (so a motor at its force is a constant force, integrated as gravity is). speed must be
// finite and within 1e15, maxForce finite, >= 0 and at most 1e30: beyond them no game means
// it, and a step's motor impulse stays within what a saved state may hold.
struct RJointMotor {
  bool enabled = false;
  RScalar speed = 0;
  RScalar maxForce = 0;
};

struct RJointDef {
  RJointType type = RJointType::kBall;
  RBodyHandle a;  // required
  RBodyHandle b;  // invalid: the joint holds a to the world
  // World point where the joint acts, m, as the bodies stand when it is added. For a
  // distance joint, the anchor on a.
  RVec3 anchor_W = RVec3::Zero();
  // Distance joint: the anchor on b (world point, m); ignored when hasAnchorB is false
  // (then both anchors are anchor_W).
  bool hasAnchorB = false;
  RVec3 anchorB_W = RVec3::Zero();
  // Hinge and slider: the axis, world direction, any length but 0.
  RVec3 axis_W = RVec3::UnitX();
  // Hinge (angle, rad, in [-pi, pi]) and slider (travel along the axis, m): limits measured
  // from the pose the bodies have when the joint is added, lower <= 0 <= upper not required.
  // The angle, the travel and a motor's speed are b's relative to a (right-handed about the
  // axis), or for a joint to the world a's relative to the world.
  bool hasLimits = false;
  RScalar lower = 0, upper = 0;
  // Distance joint: the range of the anchors' distance, m, 0 <= min <= max; a negative value
  // takes the anchors' distance when the joint is added (the default: a rigid rod).
  RScalar minDistance = -1, maxDistance = -1;
  RJointMotor motor;  // hinge and slider
  // Whether the two joined bodies still collide with each other (Box2D's collideConnected).
  bool collideConnected = false;
};

// A joint definition that cannot make a joint: which field and why.
class RJointError : public RError {
 public:
  using RError::RError;
};

// A joint as RBodies holds it: its definition, the anchors and axes fixed in each body's
// frame (centre of mass, principal axes: the frame of RRigidBody's state), and the solver's
// memory of it.
struct RJoint {
  RJointDef def;
  // Anchor points from each body's centre of mass and the axis, in that body's frame; for
  // the world (no b), world points and directions. (For a joint to the world the axis is
  // kept reversed: see RJointDef::lower.)
  RVec3 anchorA_B = RVec3::Zero(), anchorB_B = RVec3::Zero();
  RVec3 axisA_B = RVec3::UnitX(), axisB_B = RVec3::UnitX();
  // Two directions perpendicular to the axis in a's frame (hinge: what turns about it;
  // slider: the directions it may not move along).
  RVec3 perpA_B[2] = {RVec3::UnitY(), RVec3::UnitZ()};
  // b's orientation relative to a's when the joint was added: q_A^-1 q_B (for the world,
  // q_B = identity).
  RQuat relative0 = RQuat::Identity();
  RScalar minDistance = 0, maxDistance = 0;  // distance joint, m
  // The solver's impulses of the last step, row by row (N s or N m s), at the start and at
  // the end of the step: the warm start of the next.
  static constexpr int kMaxRows = 8;
  RScalar lambda[kMaxRows] = {0, 0, 0, 0, 0, 0, 0, 0};
  RScalar lambdaEnd[kMaxRows] = {0, 0, 0, 0, 0, 0, 0, 0};
  // What the joint did to b in the last step (a gets the opposite), world, about the
  // anchor: linear impulse (N s) and angular impulse (N m s). Divided by dt: the force and
  // torque it held (a game breaks a joint past a threshold).
  RVec3 impulse_W = RVec3::Zero();
  RVec3 angularImpulse_W = RVec3::Zero();
};

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_JOINT(X) \
  X(RJointMotor) \
  X(RJointDef) \
  X(RJoint)
RENGINE_ABI_CHECK(kJoint, RENGINE_ABI_TYPES_JOINT)
