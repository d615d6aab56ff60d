// Private to REnginePhysics: a joint's rows and position errors at given poses of its
// bodies (RJointRows.cpp), for the joint solver (RJoints.cpp).
#pragma once

#include "world/RWorldStep.h"

namespace REngine {

// The joint's kMaxRows rows at the poses (the layout: RJointRows.cpp), with effective
// masses from the bodies' inverse masses and inertias (sa, sb: anything with invM, invI,
// linMask, linLocked), and each row's position error in C.
template <class Body>
void BuildJointRows(const RJoint& J, const RJointPoseIn& pa, const RJointPoseIn& pb, const Body& sa,
                    const Body& sb, std::uint32_t a, std::uint32_t b, RScalar dt, RJointRow* rows,
                    RScalar* C);
// The position errors of those rows at other poses.
void JointErrors(const RJoint& J, const RJointPoseIn& pa, const RJointPoseIn& pb, const RJointRow* rows,
                 RScalar* C);
// A hinge's angle (rad) at the poses.
RScalar JointHingeAngle(const RJoint& J, const RJointPoseIn& pa, const RJointPoseIn& pb);
// A static or kinematic body's pose at the start of the step, or at its end (end = true).
RJointPoseIn ImmovablePose(const RBodyCore& b, RScalar dt, bool end);

}  // namespace REngine
