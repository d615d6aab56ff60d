// Private to REnginePhysics: a joint's rows and position errors at given poses of its
// bodies (RJointRows.cpp), for the joint solver (RJoints.cpp).
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RJoint.h>
#include <REnginePhysics/detail/RBodyCore.h>

#include "joints/RJointTypes.h"
#include "solver/RSolverRows.h"

#include <cstdint>

namespace REngine {

// A hinge's and a slider's motor row in the layout of BuildJointRows (RJointRows.cpp).
inline constexpr int kMotorRow = 7;

// The joint's kMaxRows rows at the poses (the layout: RJointRows.cpp), with effective
// masses from the bodies' inverse masses and inertias (sa, sb: the solver bodies, or the
// end bodies of the step's end, RJointEndBody), and each row's position error in C.
template <class Body>
void BuildJointRows(const RJoint& J, const RJointPoseIn& pa, const RJointPoseIn& pb, const Body& sa,
                    const Body& sb, std::uint32_t a, std::uint32_t b, RScalar dt, RJointRow* rows,
                    RScalar* C);
// A row's effective mass (dir.iA, dir.iB, dir.k) from its direction and arms (dir.d, rAxd,
// rBxd) and its bodies' inverse masses and inertias (anything with invM, invI, linMask,
// linLocked): a linear row's d is a unit vector, an angular row's zero.
template <class Body>
void SetJointMass(RDirection& dir, const Body& a, const Body& b) {
  dir.iA = a.invI * dir.rAxd;
  dir.iB = b.invI * dir.rBxd;
  const RScalar dd = dir.d.dot(dir.d);
  dir.k = solver::LinearCoupling(a, dir.d, dir.d, dd) + solver::LinearCoupling(b, dir.d, dir.d, dd) +
          dir.rAxd.dot(dir.iA) + dir.rBxd.dot(dir.iB);
}
// The position errors of those rows at other poses.
void JointErrors(const RJoint& J, const RJointPoseIn& pa, const RJointPoseIn& pb, const RJointRow* rows,
                 RScalar* C);
// What a joint's motor drives, at the poses: a hinge's angle (rad, in (-pi, pi]), a slider's
// travel (m); 0 for the other types.
RScalar JointMotorPosition(const RJoint& J, const RJointPoseIn& pa, const RJointPoseIn& pb);
// A static or kinematic body's pose at the start of the step, or at its end (end = true).
RJointPoseIn ImmovablePose(const RBodyCore& b, RScalar dt, bool end);

}  // namespace REngine
