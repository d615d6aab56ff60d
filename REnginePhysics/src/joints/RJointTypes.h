// Private to REnginePhysics: the joint solver's types (RJoints.cpp, RJointRows.cpp and the
// rest of joints/): the step's joints, a joint's rows (scalar constraints along the contact
// solver's directions, solver/RSolverTypes.h), a joint body's poses, at the start of the
// step and at its end as the motion will make it, and a joint body as the end of the step's
// rows see it. The joint solver holds them (joints/RJointSolver.h); the welds and sleeping
// read the step's joints and poses.
#pragma once

#include <REngineMath/RMath.h>

#include "solver/RSolverTypes.h"

#include <cstdint>

namespace REngine {

// The step's joints (RJoints.cpp, RJointRows.cpp): those whose bodies are both stepped, one
// at least dynamic and awake, in the container's order; b is the world's solver body (index
// bodies.size()) for a joint to the world.
struct RStepJoint {
  std::uint32_t joint;  // index into RStepBodies::joints
  std::uint32_t a, b;   // dense indices
};
// One scalar constraint of a joint (a row of its Jacobian, RJoints.cpp): the relative
// velocity along it is Speed(dir, ...) as for a contact's normal; an angular row has
// dir.d = 0 and rAxd = rBxd = its world axis. Its impulse stays within [lo, hi].
enum class RJointRowKind : std::uint8_t { kOff, kEquality, kLimit, kMotor };
struct RJointRow {
  RDirection dir;
  std::uint32_t a, b;      // solver bodies (b: bodies.size() for the world)
  RJointRowKind kind;
  RScalar target;          // relative velocity to reach, m/s or rad/s
  RScalar lo, hi;          // impulse bounds, N s or N m s
  RScalar lambda;          // accumulated impulse
};
// A body's pose for its joints: centre of mass (world, m) and orientation q_WB.
struct RJointPoseIn {
  RVec3 x;
  RQuat q;
};
// A body's pose at the end of the step as the motion will make it from the solver's
// velocities (what the joints' position errors are predicted at), and its velocities
// then (before the end impulses).
struct RJointPose {
  RVec3 x;        // centre of mass, world, m
  RQuat q;        // q_WB
  RQuat qFlow;    // q_WB after the free flow, before position correction's turn
  RVec3 vMid;     // the velocity it moves with, m/s
  RVec3 wEnd_W;   // its spin at the end of the free flow, world, rad/s (before the end kick)
  RVec3 xPredicted;  // x and q as predicted, before ProjectJoints corrects them
  RQuat qPredicted;
};
// A joint body at the predicted end of the step (RJointEnd.cpp: the position projection and
// the end's velocity projection solve on these, as the rounds solve on the solver bodies):
// its velocities (world, m/s and rad/s; pseudo-velocities in the position projection), its
// inverse inertia at the end pose (world, 1/(kg m^2)), its inverse mass (1/kg, 0 for a
// static or kinematic body and the world) and linear locks (as RSolverBody's).
struct RJointEndBody {
  RVec3 v, w;
  RMat3 invI;
  RScalar invM;
  RVec3 linMask;
  bool linLocked;
};

}  // namespace REngine
