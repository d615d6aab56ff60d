// A hinge motor at its torque limit turning a load whose centre of mass is off the hinge's
// axis, in zero gravity, against the closed form. About the fixed axis n through the anchor
// the body has the moment I_n = n . I_p n, I_p its inertia about the anchor (I_com plus
// m (|c|^2 - c c^T), c the centre's offset: the parallel axes); the motor's torque tau gives
// alpha = tau / I_n while it is below its target speed, theta = alpha t^2 / 2 and
// omega = alpha t, and the anchor stays where it is: the hinge's rows supply the centripetal
// force m omega^2 d, the tangential m alpha d and, where n is not a principal axis of the
// body, the torque that keeps it turning about n. At the target speed the motor holds it.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "joints/JointsFixtures.h"
#include "support/Joints.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

// The body's moment of inertia about the axis n (unit, world) through the point p, kg m^2.
RScalar MomentAbout(const RRigidBody& b, const RVec3& p, const RVec3& n) {
  const RMat3 R = b.Orientation_WB().toRotationMatrix();
  const RMat3 Ic = R * b.Inertia_B().asDiagonal() * R.transpose();
  const RVec3 c = b.Position_W() - p;
  const RMat3 Ip = Ic + b.Mass() * (c.squaredNorm() * RMat3::Identity() - c * c.transpose());
  return n.dot(Ip * n);
}

struct MotorFigures {
  int spinUp = 0;                 // steps below the target speed, checked against the closed form
  RScalar theta = 0, omega = 0;   // largest |theta - alpha t^2/2| (rad), |omega - alpha t| (rad/s)
  RScalar offAxis = 0;            // largest spin off the axis, rad/s
  RScalar anchor = 0;             // largest distance of the body's anchor from the pivot, m
  RScalar held = 0, heldTurn = 0; // then: |omega - target| (rad/s); each step's turn off target dt (rad)
};

// Body `def` hinged to the world at `pivot` about `axis` (unit), its motor driving it to
// `target` rad/s with at most tau N m, from rest: the spin-up checked step by step against the
// closed form, then 120 steps at the target speed.
MotorFigures SpinUp(const BodyDef& def, const RVec3& pivot, const RVec3& axis, RScalar tau, RScalar target) {
  RBodies bodies;
  const RBodyHandle body = bodies.Add(def);
  RJointDef d = Joint(RJointType::kHinge, body, RBodyHandle{}, pivot);
  d.axis_W = axis;
  d.motor = {true, target, tau};
  const RJointHandle h = bodies.AddJoint(d);
  RIntegrator integrator;  // zero gravity
  const RScalar alpha = tau / MomentAbout(bodies[body], pivot, axis);
  MotorFigures f;
  f.spinUp = static_cast<int>(target / alpha / kDt) - 1;  // whole steps below the target speed
  RScalar theta = 0, last = bodies.JointPosition(h);
  auto turn = [&] {  // the hinge's angle, unwrapped
    const RScalar now = bodies.JointPosition(h);
    const RScalar step = std::remainder(now - last, 2 * kPi);
    last = now;
    return theta += step, step;
  };
  for (int s = 1; s <= f.spinUp + 121; ++s) {
    integrator.Update(bodies, kDt);
    const RScalar step = turn();
    const RRigidBody& b = bodies[body];
    const RVec3 w = b.AngularVelocity_W();
    f.offAxis = std::max(f.offAxis, (w - w.dot(axis) * axis).norm());
    f.anchor = std::max(f.anchor, Gap(bodies, h));
    if (s <= f.spinUp) {
      const RScalar t = s * kDt;
      f.theta = std::max(f.theta, std::abs(theta - 0.5 * alpha * t * t));
      f.omega = std::max(f.omega, std::abs(w.dot(axis) - alpha * t));
    } else if (s > f.spinUp + 1) {  // (the step that reaches the speed within it aside)
      f.held = std::max(f.held, std::abs(w.dot(axis) - target));
      f.heldTurn = std::max(f.heldTurn, std::abs(step - target * kDt));
    }
  }
  return f;
}

void Report(const char* name, const MotorFigures& f) {
  std::printf("%s: %d steps of spin-up: theta off alpha t^2/2 by %.2e rad, omega off alpha t by %.2e rad/s, "
              "spin off the axis %.2e rad/s; anchor off the pivot %.2e m; held speed off by %.2e rad/s, "
              "its turn a step by %.2e rad\n",
              name, f.spinUp, f.theta, f.omega, f.offAxis, f.anchor, f.held, f.heldTurn);
}

// Asserted: the angle to 1e-12 rad over the spin-up (hundreds of steps), the spin to 1e-12
// of the target, the anchor to the joints' tolerance.
void ExpectClosedForm(const MotorFigures& f, RScalar target) {
  EXPECT_GT(f.spinUp, 200);
  EXPECT_LT(f.theta, 1e-12);
  EXPECT_LT(f.omega, 1e-12 * target);
  EXPECT_LT(f.offAxis, 1e-12 * target);
  EXPECT_LT(f.anchor, 1e-10);
  EXPECT_LT(f.held, 1e-12 * target);
  EXPECT_LT(f.heldTurn, 1e-12);
}

}  // namespace

// A 4 kg box (0.5 x 0.1 x 0.25 m half extents) hinged about y at 0.4 m from its centre, along
// its principal axis x: alpha = tau / (I_y + m d^2).
TEST(HingeMotor, OffAxisBoxFollowsAlphaTSquaredOverTwo) {
  const RVec3 centre(0, 1, 0), pivot(0.4, 1, 0);
  const MotorFigures f = SpinUp(BoxDef(RVec3(0.5, 0.1, 0.25)).Mass(4).At(centre), pivot, RVec3::UnitY(), 2, 10);
  Report("off-axis box", f);
  ExpectClosedForm(f, 10);
}

// The same box turned so that the hinge's axis is along none of its principal axes (and still
// off its centre): the product of inertia makes the hinge carry a torque as it turns.
TEST(HingeMotor, TiltedOffAxisBoxFollowsAlphaTSquaredOverTwo) {
  const RVec3 centre(0, 1, 0), pivot(0.3, 1.1, -0.2);
  const RQuat q = RQuat(Eigen::AngleAxisd(0.5, RVec3(1, 2, 3).normalized()));
  const MotorFigures f =
      SpinUp(BoxDef(RVec3(0.5, 0.1, 0.25)).Mass(4).At(centre).Oriented(q), pivot, RVec3::UnitY(), 2, 10);
  Report("tilted box", f);
  ExpectClosedForm(f, 10);
}

// A turret: a base (0.8 x 0.4 x 0.8 m) on a hinge about y through its centre and a barrel
// 1.2 m long, raised 15 degrees, off to one side: the centre of mass is off the axis and y is
// not a principal axis.
namespace {
BodyDef TurretDef(const RVec3& at) {
  std::vector<RCompoundChild> parts(2);
  parts[0].shape = RShape::Box(RVec3(0.4, 0.2, 0.4));
  parts[1].shape = RShape::Box(RVec3(0.6, 0.05, 0.05));
  parts[1].position_S = RVec3(0.6 * std::cos(0.26) + 0.3, 0.2 + 0.6 * std::sin(0.26), 0.1);
  parts[1].q_SC = RQuat(Eigen::AngleAxisd(0.26, RVec3::UnitZ()));
  parts[1].density = 8;
  BodyDef def;
  def.shape = RShape::Compound(std::move(parts));
  def.Mass(30).At(at);
  return def;
}
}  // namespace

TEST(HingeMotor, TurretWithARaisedBarrelFollowsAlphaTSquaredOverTwo) {
  const BodyDef def = TurretDef(RVec3(0, 1, 0));
  const MotorFigures f = SpinUp(def, RVec3(0, 1, 0), RVec3::UnitY(), 5, 6);
  Report("turret", f);
  ExpectClosedForm(f, 6);
}

// A door (its centre 0.5 m off the hinge) driven by a motor at its force into its hinge limit,
// in zero gravity: it reaches the limit and stays there, pressed by the motor.
TEST(HingeMotor, DrivesAnOffAxisDoorIntoItsLimitAndHoldsItThere) {
  RBodies bodies;
  const RVec3 hinge(1, 0, 0);
  const RBodyHandle door = bodies.Add(BoxDef(RVec3(0.5, 1, 0.05)).Mass(20).At(hinge + RVec3(0.5, 0, 0)));
  RJointDef d = Joint(RJointType::kHinge, door, RBodyHandle{}, hinge);
  d.axis_W = RVec3::UnitY();
  d.hasLimits = true, d.lower = -0.5, d.upper = 0.5;
  d.motor = {true, 3, 20};
  const RJointHandle h = bodies.AddJoint(d);
  RIntegrator integrator;
  RScalar largest = 0, gap = 0;
  for (int s = 0; s < 240; ++s) {
    integrator.Update(bodies, kDt);
    largest = std::max(largest, bodies.JointPosition(h));
    gap = std::max(gap, Gap(bodies, h));
  }
  std::printf("door driven into its limit: largest angle %.12f rad (limit 0.5), at %.12f rad, spin %.2e rad/s, "
              "anchor off by %.2e m\n",
              largest, bodies.JointPosition(h), bodies[door].AngularVelocity_W().norm(), gap);
  EXPECT_LT(largest, 0.5 + 1e-9);
  EXPECT_NEAR(bodies.JointPosition(h), 0.5, 1e-9);
  EXPECT_LT(bodies[door].AngularVelocity_W().norm(), 1e-9);
  EXPECT_LT(gap, 1e-10);
}

// A turret (the compound of the test above) on a hinge to a free 200 kg hull, in zero gravity,
// its motor at its force. Between two bodies that both move the motor keeps the plain split of
// its impulse (RJointMotors.cpp says why): what is asked here is that the motor's torque and
// the hinge's impulses stay internal (the pair's momentum and angular momentum stay zero,
// the latter to what the joints' tolerance of 1e-10 m leaves), the hinge holds, and 1 and 2
// threads agree bit for bit.
TEST(HingeMotor, TurretOnAFreeHullKeepsMomentumAndAngularMomentum) {
  auto run = [](int threads, RVec3& momentum, RVec3& angular, RScalar& gap, RScalar& turned) {
    const BodyDef turretDef = TurretDef(RVec3(0, 1.2, 0));
    RBodies bodies;
    const RBodyHandle hull = bodies.Add(BoxDef(RVec3(2, 0.5, 1)).Mass(200).At(RVec3(0.3, 0.5, -0.2)));
    const RBodyHandle turret = bodies.Add(turretDef);
    RJointDef d = Joint(RJointType::kHinge, hull, turret, RVec3(0, 1.2, 0));
    d.axis_W = RVec3(0, 1, 0.1);
    d.motor = {true, 4, 20};
    const RJointHandle h = bodies.AddJoint(d);
    RWorldSettings settings;
    settings.threads = threads;
    RIntegrator integrator(settings);
    RScalar last = bodies.JointPosition(h);
    turned = 0, gap = 0;
    for (int s = 0; s < 240; ++s) {
      integrator.Update(bodies, kDt);
      const RScalar now = bodies.JointPosition(h);
      turned += std::remainder(now - last, 2 * kPi), last = now;
      gap = std::max(gap, Gap(bodies, h));
    }
    momentum = RVec3::Zero(), angular = RVec3::Zero();
    for (const RBodyHandle b : {hull, turret}) {
      momentum += bodies[b].Mass() * bodies[b].Velocity_W();
      angular += bodies[b].AngularMomentum_W() + bodies[b].Position_W().cross(bodies[b].Mass() * bodies[b].Velocity_W());
    }
  };
  RVec3 p1, l1, p2, l2;
  RScalar gap1, gap2, turned1, turned2;
  run(1, p1, l1, gap1, turned1);
  run(2, p2, l2, gap2, turned2);
  std::printf("turret on a free hull: turned %.6f rad; momentum %.2e N s, angular momentum %.2e N m s; "
              "anchors apart %.2e m\n",
              turned1, p1.norm(), l1.norm(), gap1);
  EXPECT_GT(turned1, 1);
  EXPECT_LT(p1.norm(), 1e-12);
  EXPECT_LT(l1.norm(), 1e-9);
  EXPECT_LT(gap1, 1e-10);
  EXPECT_EQ(p1, p2);
  EXPECT_EQ(l1, l2);
  EXPECT_EQ(turned1, turned2);
}
