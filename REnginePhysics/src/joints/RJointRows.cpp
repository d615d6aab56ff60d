// A joint's rows (the joint solver's, RJointSolver.h): its geometry at given poses of its
// two bodies, the rows of its Jacobian with their effective masses, its position errors, and
// the poses the motion will give a body from the solver's velocities.
#include "joints/RJointRows.h"
#include <REngineMath/RFunctions.h>

#include "body/RBodyAccess.h"
#include "joints/RJointSolver.h"
#include "solver/RSolverRows.h"

#include <REngineMath/RQuaternion.h>

#include <cmath>
#include <limits>

namespace REngine {

using namespace solver;

namespace {


// Where the joint's frames are at the poses: world anchors and arms, the axis in each
// body, a's perpendiculars, and the rotation error q_B (q_A q_rel0)^-1 (world).
struct RJointGeometry {
  RVec3 pA, pB, rA, rB, axisA, axisB;
  RVec3 perp[2];
  RQuat error;
};

RJointGeometry Geometry(const RJoint& J, const RJointPoseIn& pa, const RJointPoseIn& pb) {
  RJointGeometry g;
  g.rA = pa.q * J.anchorA_B;
  g.rB = pb.q * J.anchorB_B;
  g.pA = pa.x + g.rA;
  g.pB = pb.x + g.rB;
  g.axisA = pa.q * J.axisA_B;
  g.axisB = pb.q * J.axisB_B;
  g.perp[0] = pa.q * J.perpA_B[0];
  g.perp[1] = pa.q * J.perpA_B[1];
  g.error = pb.q * (pa.q * J.relative0).conjugate();
  return g;
}

// The hinge's angle about a's axis: b's turn relative to a since the joint was added, in
// (-pi, pi].
RScalar HingeAngle(const RJointGeometry& g) {
  // q and -q are one rotation (a game may set either): the one with w >= 0, whose angle is
  // in (-pi, pi].
  const RScalar sign = g.error.w() < 0 ? RScalar(-1) : RScalar(1);
  const RVec3 v(g.error.x(), g.error.y(), g.error.z());
  return 2 * Atan2(sign * v.dot(g.axisA), sign * g.error.w());
}

void Linear(RDirection& dir, const RVec3& d, const RVec3& armA, const RVec3& armB) {
  dir.d = d, dir.rAxd = armA.cross(d), dir.rBxd = armB.cross(d);
}
void Angular(RDirection& dir, const RVec3& u) {
  dir.d.setZero(), dir.rAxd = u, dir.rBxd = u;
}

}  // namespace

// The rows of the joint at the poses, kMaxRows of them (unused ones kOff), each with its
// position error in C: an equality row's value, driven to 0; a limit row's distance into
// the allowed side (>= 0 allowed). Layout (the warm start's slots):
//   ball      0-2 anchors (world axes)
//   hinge     0-2 anchors, 3-4 the axes' alignment, 5 lower and 6 upper angle, 7 motor
//   slider    0-1 the anchors across the axis, 2-4 the rotation, 5 lower and 6 upper
//             travel, 7 motor
//   fixed     0-2 anchors, 3-5 the rotation
//   distance  0 min (equality when min = max), 1 max
template <class Body>
void BuildJointRows(const RJoint& J, const RJointPoseIn& pa, const RJointPoseIn& pb, const Body& sa,
                    const Body& sb, std::uint32_t a, std::uint32_t b, RScalar dt, RJointRow* rows,
                    RScalar* C) {
  using Kind = RJointRowKind;
  const RJointGeometry g = Geometry(J, pa, pb);
  for (int k = 0; k < RJoint::kMaxRows; ++k) {
    RJointRow& r = rows[k];
    r.a = a, r.b = b, r.kind = Kind::kOff, r.target = 0, r.lo = -kInf, r.hi = kInf, r.lambda = 0;
    r.dir.d.setZero(), r.dir.rAxd.setZero(), r.dir.rBxd.setZero(), r.dir.iA.setZero(), r.dir.iB.setZero();
    r.dir.k = 0;
    C[k] = 0;
  }
  const RVec3 u = g.pB - g.pA;
  // (The lambdas take the arms, not g: a lambda of this template holding a reference to a
  // type of this file's anonymous namespace is a -Wsubobject-linkage warning.)
  const RVec3& armA = g.rA;
  const RVec3& armB = g.rB;
  auto point = [&](int k, int axis) {
    Linear(rows[k].dir, RVec3::Unit(axis), armA, armB);
    rows[k].kind = Kind::kEquality;
  };
  auto across = [&](int k, const RVec3& d) {  // slider: a's arm reaches to b's anchor
    Linear(rows[k].dir, d, armA + u, armB);
    rows[k].kind = Kind::kEquality;
  };
  auto angular = [&](int k, const RVec3& axis) {
    Angular(rows[k].dir, axis);
    rows[k].kind = Kind::kEquality;
  };
  auto limit = [&](int k) { rows[k].kind = Kind::kLimit, rows[k].lo = 0, rows[k].hi = kInf; };
  auto motor = [&](int k) {
    rows[k].kind = Kind::kMotor;
    rows[k].target = J.def.motor.speed;
    // Half the step's impulse at each end (kick-drift-kick, as a force): exact for a
    // constant torque, and the end of the step reaches the motor's speed too.
    rows[k].hi = J.def.motor.maxForce * (RScalar(0.5) * dt), rows[k].lo = -rows[k].hi;
  };
  switch (J.def.type) {
    case RJointType::kBall:
      for (int k = 0; k < 3; ++k) point(k, k);
      break;
    case RJointType::kFixed:
      for (int k = 0; k < 3; ++k) point(k, k), angular(3 + k, RVec3::Unit(k));
      break;
    case RJointType::kHinge:
      for (int k = 0; k < 3; ++k) point(k, k);
      angular(3, g.perp[0]), angular(4, g.perp[1]);
      if (J.def.hasLimits) {
        Angular(rows[5].dir, g.axisA), limit(5);
        Angular(rows[6].dir, -g.axisA), limit(6);
      }
      if (J.def.motor.enabled) Angular(rows[kMotorRow].dir, g.axisA), motor(kMotorRow);
      break;
    case RJointType::kSlider:
      across(0, g.perp[0]), across(1, g.perp[1]);
      for (int k = 0; k < 3; ++k) angular(2 + k, RVec3::Unit(k));
      if (J.def.hasLimits) {
        Linear(rows[5].dir, g.axisA, g.rA + u, g.rB), limit(5);
        Linear(rows[6].dir, -g.axisA, g.rA + u, g.rB), limit(6);
      }
      if (J.def.motor.enabled) Linear(rows[kMotorRow].dir, g.axisA, g.rA + u, g.rB), motor(kMotorRow);
      break;
    case RJointType::kDistance: {
      const RScalar L = u.norm();
      // Anchors together (a rope's slack gathered at a point): any direction; the rows
      // are limits that do not act there unless min > 0.
      const RVec3 n = L > 0 ? RVec3(u / L) : g.axisA;
      if (J.minDistance == J.maxDistance) {
        Linear(rows[0].dir, n, g.rA, g.rB);
        rows[0].kind = Kind::kEquality;
      } else {
        if (J.minDistance > 0) Linear(rows[0].dir, n, g.rA, g.rB), limit(0);
        Linear(rows[1].dir, -n, g.rA, g.rB), limit(1);
      }
      break;
    }
  }
  for (int k = 0; k < RJoint::kMaxRows; ++k) {
    if (rows[k].kind != Kind::kOff) SetJointMass(rows[k].dir, sa, sb);
  }
  JointErrors(J, pa, pb, rows, C);
}

// The position errors of rows built by BuildJointRows (their directions) at other poses:
// what the step's end poses leave of each constraint.
void JointErrors(const RJoint& J, const RJointPoseIn& pa, const RJointPoseIn& pb, const RJointRow* rows,
                 RScalar* C) {
  using Kind = RJointRowKind;
  const RJointGeometry g = Geometry(J, pa, pb);
  const RVec3 u = g.pB - g.pA;
  for (int k = 0; k < RJoint::kMaxRows; ++k) C[k] = 0;
  switch (J.def.type) {
    case RJointType::kBall:
    case RJointType::kFixed:
    case RJointType::kHinge:
      for (int k = 0; k < 3; ++k) C[k] = u[k];
      break;
    case RJointType::kSlider:
      for (int k = 0; k < 2; ++k) C[k] = rows[k].dir.d.dot(u);
      break;
    case RJointType::kDistance:
      break;
  }
  if (J.def.type == RJointType::kFixed || J.def.type == RJointType::kSlider) {
    const int first = J.def.type == RJointType::kFixed ? 3 : 2;
    const RVec3 theta = QuatLog(g.error);
    for (int k = 0; k < 3; ++k) C[first + k] = theta[k];
  }
  if (J.def.type == RJointType::kHinge) {
    const RVec3 tilt = g.axisA.cross(g.axisB);
    C[3] = rows[3].dir.rBxd.dot(tilt), C[4] = rows[4].dir.rBxd.dot(tilt);
    if (rows[5].kind == Kind::kLimit) {
      const RScalar angle = HingeAngle(g);
      C[5] = angle - J.def.lower, C[6] = J.def.upper - angle;
    }
  }
  if (J.def.type == RJointType::kSlider && rows[5].kind == Kind::kLimit) {
    const RScalar travel = g.axisA.dot(u);
    C[5] = travel - J.def.lower, C[6] = J.def.upper - travel;
  }
  if (J.def.type == RJointType::kDistance) {
    const RScalar L = u.norm();
    if (rows[0].kind == Kind::kEquality) C[0] = L - J.maxDistance;
    if (rows[0].kind == Kind::kLimit) C[0] = L - J.minDistance;
    if (rows[1].kind == Kind::kLimit) C[1] = J.maxDistance - L;
  }
}

RScalar JointMotorPosition(const RJoint& J, const RJointPoseIn& pa, const RJointPoseIn& pb) {
  const RJointGeometry g = Geometry(J, pa, pb);
  if (J.def.type == RJointType::kHinge) return HingeAngle(g);
  return J.def.type == RJointType::kSlider ? g.axisA.dot(g.pB - g.pA) : 0;
}

template void BuildJointRows<RSolverBody>(const RJoint&, const RJointPoseIn&, const RJointPoseIn&, const RSolverBody&,
                                          const RSolverBody&, std::uint32_t, std::uint32_t, RScalar, RJointRow*,
                                          RScalar*);
template void BuildJointRows<RJointEndBody>(const RJoint&, const RJointPoseIn&, const RJointPoseIn&,
                                            const RJointEndBody&, const RJointEndBody&, std::uint32_t,
                                            std::uint32_t, RScalar, RJointRow*, RScalar*);

// The pose the motion (Integrate) will give a movable body from its solver state: its
// centre moved with the mid-step velocity and position correction's pseudo-velocity, its
// orientation by the same exact free flow (a copy of the body's, whose cache the motion
// keeps) and then position correction's turn; its spin at the end of the flow.
RJointPose RJointSolver::PredictPose(const RBodyCore& b, const RSolverBody& s, RScalar dt) {
  RJointPose p;
  p.vMid = s.v;
  // A body an impact hit this step moves with its piecewise path's velocity, deferV less than
  // the velocity after the impacts (ShiftArmsAfterImpacts), and gets deferV at the end.
  p.x = b.m_x_W + (s.deferV.isZero(0) ? s.v : RVec3(s.v - s.deferV)) * dt;
  if (!s.vp.isZero(0)) p.x += s.vp * dt;
  RQuat q = b.m_q_WB;
  RVec3 w_B;
  if (b.m_angularLocked) {
    if (!s.w.isZero(0)) q = QuatExp(s.w * dt) * q, q.normalize();
  } else {
    w_B = b.m_q_WB.conjugate() * s.w;
    RFreeRotation flow = b.m_rotation;
    flow.Advance(dt, w_B, q);
  }
  p.qFlow = q;
  if (!s.wp.isZero(0)) q = QuatExp(s.wp * dt) * q, q.normalize();
  p.q = q;
  p.wEnd_W = b.m_angularLocked ? s.w : RVec3(q * w_B);
  p.xPredicted = p.x, p.qPredicted = p.q;
  return p;
}

RJointPoseIn ImmovablePose(const RBodyCore& b, RScalar dt, bool end) {
  if (!end || !b.m_isKinematic) return {b.m_x_W, b.m_q_WB};
  // As RMotion::MoveKinematic moves it.
  RQuat q = b.m_q_WB;
  const RVec3 w = Body(b).AngularVelocity_W();
  if (!w.isZero(0)) q = QuatExp(w * dt) * q, q.normalize();
  return {b.m_x_W + b.m_v_W * dt, q};
}

}  // namespace REngine
