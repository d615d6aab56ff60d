// The API refuses invalid values at the door, and a body that overflows anyway is put back
// and started afresh. Each test reproduces an input that must not get through: a negative or
// zero dt, a zero quaternion kept forever, a NaN pose, and one infinite force that would
// freeze a stack for good.
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "support/Joints.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kNaN = std::numeric_limits<RScalar>::quiet_NaN();


}  // namespace

TEST(ApiInput, UpdateRefusesAStepThatIsNotFiniteAndPositive) {
  std::vector<RRigidBody> bodies{RRigidBody(UnitBoxDef(RVec3::Zero()))};
  bodies[0].SetVelocity_W(RVec3(1, 0, 0));
  RIntegrator integrator;
  for (RScalar dt : {RScalar(0), RScalar(-1) / 60, kNaN, kInf, -kInf, std::nextafter(RIntegrator::kMaxDt, RScalar(2)),
                     RScalar(1e300)}) {
    EXPECT_THROW(integrator.Update(bodies, dt), RError) << dt;
  }
  // Nothing moved, and the integrator still steps: x = v t exactly.
  EXPECT_EQ(integrator.StepCount(), 0u);
  EXPECT_EQ(bodies[0].Position_W(), RVec3::Zero());
  integrator.Update(bodies, 0.5);
  EXPECT_EQ(bodies[0].Position_W(), RVec3(0.5, 0, 0));
}

// Settings no step can run: solver iterations outside 1 to kMaxSolverIterations (2^31 - 1 of
// them was a step that never ended), a combine mode no enumerator names. Refused before
// anything moves; the world steps again once they are right.
TEST(ApiInput, UpdateRefusesSettingsOutsideTheirRanges) {
  std::vector<RRigidBody> bodies{RRigidBody(UnitBoxDef(RVec3::Zero()))};
  bodies[0].SetVelocity_W(RVec3(1, 0, 0));
  RIntegrator integrator;
  for (int iterations : {0, -1, RWorldSettings::kMaxSolverIterations + 1, 2147483647}) {
    integrator.Settings().solverIterations = iterations;
    EXPECT_THROW(integrator.Update(bodies, 0.5), RError) << iterations;
  }
  integrator.Settings().solverIterations = RWorldSettings::kMaxSolverIterations;
  integrator.Settings().frictionCombine = static_cast<RCombineMode>(99);
  EXPECT_THROW(integrator.Update(bodies, 0.5), RError);
  integrator.Settings().frictionCombine = RCombineMode::kGeometric;
  integrator.Settings().restitutionCombine = static_cast<RCombineMode>(5);
  EXPECT_THROW(integrator.Update(bodies, 0.5), RError);
  integrator.Settings().restitutionCombine = RCombineMode::kMin;
  EXPECT_EQ(integrator.StepCount(), 0u);
  EXPECT_EQ(bodies[0].Position_W(), RVec3::Zero());
  integrator.Update(bodies, 0.5);
  EXPECT_EQ(bodies[0].Position_W(), RVec3(0.5, 0, 0));
}

// A body the game sets moving at 1e17 m/s (finite: accepted) would leave the world, 1e15 m
// of the origin, in its first step of 1/60 s: it is put back where it was, at rest, and
// reported in that step only; the other body moves on untouched, and the steps after report
// nothing (put back with its velocity, it would leave again at every step, each reported).
TEST(ApiInput, ABodyThatRunsAwayIsPutBackAtRestAndReportedOnce) {
  std::vector<RRigidBody> bodies{RRigidBody(UnitBoxDef(RVec3(0, 0, 0))), RRigidBody(UnitBoxDef(RVec3(0, 5, 0)))};
  bodies[0].SetVelocity_W(RVec3(1e17, 0, 0));
  bodies[0].SetAngularVelocity_W(RVec3(0, 0, 3));
  bodies[1].SetVelocity_W(RVec3(0, 1, 0));
  RIntegrator integrator;
  const RScalar dt = RScalar(1) / 60;
  integrator.Update(bodies, dt);
  ASSERT_EQ(integrator.NonFiniteInLastStep().size(), 1u);
  EXPECT_EQ(integrator.NonFiniteInLastStep()[0].bodyIndex, 0u);
  EXPECT_EQ(bodies[0].Position_W(), RVec3::Zero());
  EXPECT_EQ(bodies[0].Velocity_W(), RVec3::Zero());
  EXPECT_EQ(bodies[0].AngularVelocity_W(), RVec3::Zero());
  EXPECT_EQ(bodies[1].Position_W(), RVec3(0, 5 + dt, 0));
  for (int i = 0; i < 10; ++i) {
    integrator.Update(bodies, dt);
    EXPECT_TRUE(integrator.NonFiniteInLastStep().empty()) << "step " << i + 2;
  }
  EXPECT_EQ(bodies[0].Position_W(), RVec3::Zero());
  EXPECT_EQ(integrator.NonFinite()->step, 1u);
}

TEST(ApiInput, SetShapePoseRefusesZeroAndNonFiniteValues) {
  RRigidBody body(UnitBoxDef(RVec3(1, 2, 3)));
  const RQuat q = RQuat(1, 2, 3, 4).normalized();
  body.SetShapePose(RVec3(4, 5, 6), RQuat(2, 4, 6, 8));  // any non-zero length is normalised
  EXPECT_NEAR(body.ShapeOrientation_WS().angularDistance(q), 0, 1e-15);
  const struct {
    RVec3 position;
    RQuat q;
    const char* field;
  } bad[] = {{RVec3(4, 5, 6), RQuat(0, 0, 0, 0), "orientation"},
             {RVec3(4, 5, 6), RQuat(kNaN, 0, 0, 1), "orientation"},
             {RVec3(4, 5, 6), RQuat(kInf, 0, 0, 0), "orientation"},
             {RVec3(kNaN, 5, 6), q, "position"},
             {RVec3(4, -kInf, 6), q, "position"}};
  for (const auto& c : bad) {
    try {
      body.SetShapePose(c.position, c.q);
      ADD_FAILURE() << "accepted " << c.field;
    } catch (const RBodyError& e) {
      EXPECT_EQ(e.Field(), c.field);
    }
    // The body keeps its last valid pose.
    EXPECT_EQ(body.ShapePosition_W(), RVec3(4, 5, 6));
    EXPECT_NEAR(body.ShapeOrientation_WS().angularDistance(q), 0, 1e-15);
  }
}

TEST(ApiInput, VelocitiesForcesAndImpulsesMustBeFinite) {
  RRigidBody body(UnitBoxDef(RVec3::Zero()));
  const RVec3 nan(kNaN, 0, 0), inf(0, kInf, 0), big(0, 0, 1e308);
  for (const RVec3& v : {nan, inf}) {
    EXPECT_THROW(body.SetVelocity_W(v), RBodyError);
    EXPECT_THROW(body.SetAngularVelocity_W(v), RBodyError);
    EXPECT_THROW(body.AddForce_W(v), RBodyError);
    EXPECT_THROW(body.AddTorque_W(v), RBodyError);
    EXPECT_THROW(body.AddImpulse_W(v), RBodyError);
    EXPECT_THROW(body.AddAngularImpulse_W(v), RBodyError);
    EXPECT_THROW(body.AddForceAtPoint_W(v, RVec3::Zero()), RBodyError);
    EXPECT_THROW(body.AddForceAtPoint_W(RVec3::UnitX(), v), RBodyError);
    EXPECT_THROW(body.AddImpulseAtPoint_W(v, RVec3::Zero()), RBodyError);
    EXPECT_THROW(body.AddImpulseAtPoint_W(RVec3::UnitX(), v), RBodyError);
  }
  // A finite angular velocity that overflows when turned into the body frame (found by
  // fuzz_world: the body's spin became NaN before any step) is refused too.
  body.SetShapePose(RVec3::Zero(), RQuat(1, 2, 3, 4));
  EXPECT_THROW(body.SetAngularVelocity_W(RVec3(1.7e308, -1.7e308, 1.7e308)), RBodyError);
  EXPECT_TRUE(AllFinite(body.AngularVelocity_B()));
  body.SetShapePose(RVec3::Zero(), RQuat::Identity());
  // Finite arguments whose sum overflows are refused too, and leave the sum as it was.
  body.AddForce_W(big);
  EXPECT_THROW(body.AddForce_W(big), RBodyError);
  EXPECT_THROW(body.AddForceAtPoint_W(RVec3(1e308, 0, 0), RVec3(0, 1e308, 0)), RBodyError);
  // In zero g the accepted force alone acts for the step: v = F dt / m.
  std::vector<RRigidBody> bodies{body};
  RIntegrator integrator;
  integrator.Update(bodies, 1e-300);
  EXPECT_EQ(bodies[0].Velocity_W(), big * 1e-300);
  EXPECT_EQ(bodies[0].AngularVelocity_W(), RVec3::Zero());
}

// A light box on a heavy one on the ground. A finite force too large for the light box's
// mass overflows its step; the pair's impulses that step are non-finite. Both bodies are
// put back and reported in that step only, the contact memory of their pairs is dropped,
// and the next steps are normal: the stack stands and the game's velocity takes effect.
// (Before: the non-finite impulses were remembered as warm starts, the bodies were put back
// every step after, only the first step was reported, and SetVelocity_W did nothing.)
TEST(ApiInput, AnOverflowingBodyIsPutBackAndStartsAfresh) {
  std::vector<RRigidBody> bodies{
      RRigidBody(BoxDef(RVec3(5, 0.5, 5)).Static().At(RVec3(0, -0.5, 0))),
      RRigidBody(UnitBoxDef(RVec3(0, 0.5, 0))),
      RRigidBody(UnitBoxDef(RVec3(0, 1.5, 0)).Mass(1e-20))};
  RWorldSettings settings;
  settings.gravity_W = RVec3(0, -9.81, 0);
  settings.shortcuts.sleeping = false;
  RIntegrator integrator(settings);
  const RScalar dt = RScalar(1) / 60;
  for (int i = 0; i < 30; ++i) integrator.Update(bodies, dt);
  ASSERT_TRUE(integrator.NonFiniteInLastStep().empty());
  const RVec3 light0 = bodies[2].Position_W(), heavy0 = bodies[1].Position_W();

  bodies[2].AddForce_W(RVec3(0, -1e300, 0));  // 1e320 m/s^2: overflows
  integrator.Update(bodies, dt);
  ASSERT_FALSE(integrator.NonFiniteInLastStep().empty());
  EXPECT_EQ(integrator.NonFiniteInLastStep().back().bodyIndex, 2u);
  EXPECT_EQ(bodies[2].Position_W(), light0);  // put back where it was

  for (int i = 0; i < 10; ++i) {
    integrator.Update(bodies, dt);
    EXPECT_TRUE(integrator.NonFiniteInLastStep().empty()) << "step " << i;
  }
  EXPECT_EQ(integrator.NonFinite()->step, 31u);  // the first one, still reported
  for (const RRigidBody& b : bodies) EXPECT_TRUE(AllFinite(b.Position_W()) && AllFinite(b.Velocity_W()));
  EXPECT_LT((bodies[1].Position_W() - heavy0).norm(), 1e-3);
  EXPECT_LT((bodies[2].Position_W() - light0).norm(), 1e-3);
  // Thrown upwards at 5 m/s, it leaves the stack: after one step its centre has risen by
  // the kick-drift-kick closed form v dt - g dt^2 / 2.
  bodies[2].SetVelocity_W(RVec3(0, 5, 0));
  const RScalar y0 = bodies[2].Position_W().y();
  integrator.Update(bodies, dt);
  EXPECT_NEAR(bodies[2].Position_W().y() - y0, 5 * dt - 0.5 * 9.81 * dt * dt, 1e-12);
}

// Positions beyond 1e15 m are refused (at 1e185 m a sphere pair's distance overflowed to
// infinity: found by fuzz_narrowphase); 1e15 m itself is a body.
TEST(ApiInput, PositionsBeyondTheRangeAreRefused) {
  for (RScalar x : {1.0000001e15, -1e185, 1e308, kNaN, -kInf}) {
    EXPECT_THROW(RRigidBody(UnitBoxDef(RVec3(0, x, 0))), RBodyError) << x;
    RRigidBody body(UnitBoxDef(RVec3::Zero()));
    EXPECT_THROW(body.SetShapePose(RVec3(x, 0, 0), RQuat::Identity()), RBodyError) << x;
    EXPECT_EQ(body.ShapePosition_W(), RVec3::Zero());
  }
  EXPECT_NO_THROW(RRigidBody(UnitBoxDef(RVec3(1e15, -1e15, 1e15))));
}

// Extreme but finite values found by fuzz_world and fuzz_narrowphase: a body so small that
// its moments underflow is refused without dividing by zero; bodies flung at each other at
// up to 1e300 m/s end every step finite (or put back and reported), never with a manifold of
// non-numbers turned into an impact (0 / 0 in the impact's centre).
TEST(ApiInput, ExtremeFiniteValuesNeverMakeNonNumbers) {
  RBodyDef tiny = UnitBoxDef(RVec3::Zero()).Mass(1e-300);
  tiny.shape.halfExtents = RVec3::Constant(1e-20);
  EXPECT_THROW(RRigidBody{tiny}, RBodyError);
  for (RScalar speed : {1e100, 1e150, 1e200, 1e300}) {
    std::vector<RRigidBody> bodies{RRigidBody(UnitBoxDef(RVec3::Zero())),
                                   RRigidBody(UnitBoxDef(RVec3(2, 0.3, 0)))};
    bodies[0].SetVelocity_W(RVec3(speed, 0, 0));
    bodies[1].SetVelocity_W(RVec3(-speed, 0, 0));
    RIntegrator integrator;
    for (int step = 0; step < 3; ++step) {
      integrator.Update(bodies, 1.0 / 60);
      for (const RRigidBody& b : bodies) {
        EXPECT_TRUE(AllFinite(b.Position_W()) && AllFinite(b.Velocity_W()) &&
                    AllFinite(b.Orientation_WB()) && AllFinite(b.AngularVelocity_B()))
            << speed << " step " << step;
      }
    }
  }
}

// Sizes the narrow phase cannot square are refused (a box 1e134 m wide and 1e-237 m thick
// had a finite mass and a sane inertia ratio: found by fuzz_narrowphase), and so is a box
// thinner than 1e-4 of its size, the rule hulls follow.
TEST(ApiInput, ShapeSizesOutsideTheRangeAreRefused) {
  RBodyDef d = UnitBoxDef(RVec3::Zero());
  for (const RVec3& e : {RVec3(1e-237, 7e133, 1.7e133), RVec3(2e12, 1e12, 1e12),
                         RVec3(1, 1, 0.99e-4)}) {
    d.shape.halfExtents = e;
    try {
      RRigidBody body(d);
      ADD_FAILURE() << e.transpose();
    } catch (const RBodyError& error) {
      EXPECT_EQ(error.Field(), "shape.half_extents");
    }
  }
  d.shape.halfExtents = RVec3(1, 1, 1e-4);  // the thinnest box accepted
  EXPECT_NO_THROW(RRigidBody{d});
  d.shape = RShape::Sphere(1.1e12);
  EXPECT_THROW(RRigidBody{d}, RBodyError);
}

// An enum value no enumerator names (a cast, a header newer than the library) is refused
// naming its field, never taken for one of the others: a joint type of 99 made a ball joint.
TEST(ApiInput, EnumsOutsideTheirEnumeratorsAreRefused) {
  RBodies bodies;
  const RBodyHandle a = bodies.Add(SphereDef(0.5).Mass(1));
  RJointDef def = Joint(RJointType(99), a, RBodyHandle{}, RVec3::Zero());
  try {
    bodies.AddJoint(def);
    ADD_FAILURE() << "joint type 99 accepted";
  } catch (const RError& e) {
    const auto* field = dynamic_cast<const RJointError*>(&e);
    ASSERT_NE(field, nullptr) << e.what();
    EXPECT_EQ(field->Field(), "type");
  }
  EXPECT_EQ(bodies.JointCount(), 0u);
  def.type = RJointType::kDistance;  // the last enumerator
  def.hasAnchorB = true, def.anchorB_W = RVec3(0, 1, 0);
  EXPECT_NO_THROW(bodies.AddJoint(def));

  RBodyDef body = SphereDef(0.5).Mass(1);
  body.shape.type = RShapeType(99);
  try {
    RRigidBody{body};
    ADD_FAILURE() << "shape type 99 accepted";
  } catch (const RBodyError& e) {
    EXPECT_EQ(e.Field(), "shape.type");
  }
  RBodyDef compound = SphereDef(0.5).Mass(1);
  compound.shape = RShape::Compound({RCompoundChild{}});
  compound.shape.children[0].shape = RShape::Sphere(0.5);
  compound.shape.children[0].shape.type = RShapeType(7);  // one past kMesh
  try {
    RRigidBody{compound};
    ADD_FAILURE() << "child shape type 7 accepted";
  } catch (const RBodyError& e) {
    EXPECT_EQ(e.Field(), "shape.children[0].shape.type");
  }
  RBodyDef kind = SphereDef(0.5).Mass(1);
  kind.kind = RBodyKind(3);
  try {
    RRigidBody{kind};
    ADD_FAILURE() << "body kind 3 accepted";
  } catch (const RBodyError& e) {
    EXPECT_EQ(e.Field(), "kind");
  }
}

// Impulses are held to 1e30 (N s, N m s) in each component, as a saved state's are: one of
// 1e300 flung a body to 1e299 m in a step. 1e30 itself is accepted; the next double above
// it is refused, and the body keeps what it had.
TEST(ApiInput, ImpulsesBeyondTheLimitAreRefused) {
  const RScalar limit = 1e30, beyond = std::nextafter(limit, kInf);
  RRigidBody body(SphereDef(0.5).Mass(2));
  body.AddImpulse_W(RVec3(0, -limit, 0));
  body.AddAngularImpulse_W(RVec3(limit, 0, 0));
  body.AddImpulseAtPoint_W(RVec3(0, 0, limit), RVec3(0, 1, 0));
  const struct {
    const char* field;
    void (*add)(RRigidBody&, const RVec3&);
  } adds[] = {{"impulse", [](RRigidBody& b, const RVec3& j) { b.AddImpulse_W(j); }},
              {"angular_impulse", [](RRigidBody& b, const RVec3& j) { b.AddAngularImpulse_W(j); }},
              {"impulse", [](RRigidBody& b, const RVec3& j) { b.AddImpulseAtPoint_W(j, RVec3::Zero()); }}};
  for (const auto& add : adds) {
    for (const RVec3& j : {RVec3(beyond, 0, 0), RVec3(0, -beyond, 0), RVec3(0, 0, 1e300)}) {
      RRigidBody copy = body;
      try {
        add.add(copy, j);
        ADD_FAILURE() << add.field << " " << j.transpose() << " accepted";
      } catch (const RBodyError& e) {
        EXPECT_EQ(e.Field(), add.field);
        EXPECT_NE(std::string(e.what()).find("1e30"), std::string::npos) << e.what();
      }
      std::vector<RRigidBody> one{copy}, reference{body};
      RIntegrator a, b;
      a.Update(one, 0.01), b.Update(reference, 0.01);
      EXPECT_EQ(one[0].Velocity_W(), reference[0].Velocity_W()) << "the refused impulse was kept";
      EXPECT_EQ(one[0].AngularVelocity_W(), reference[0].AngularVelocity_W());
    }
  }
}

// A motor's speed is held within 1e15 (m/s, rad/s) and its force to [0, 1e30] (N, N m), by
// AddJoint and SetJointMotor alike; the limits themselves are accepted.
TEST(ApiInput, MotorsBeyondTheLimitsAreRefused) {
  RBodies bodies;
  const RBodyHandle a = bodies.Add(SphereDef(0.5).Mass(1));
  RJointDef def = Joint(RJointType::kHinge, a, RBodyHandle{}, RVec3::Zero());
  def.axis_W = RVec3::UnitY();
  def.motor = {true, -1e15, 1e30};
  const RJointHandle h = bodies.AddJoint(def);
  const struct {
    RJointMotor motor;
    const char* field;
  } bad[] = {{{true, std::nextafter(1e15, kInf), 1}, "motor.speed"},
             {{true, -1e300, 1}, "motor.speed"},
             {{true, 1, std::nextafter(1e30, kInf)}, "motor.max_force"},
             {{true, 1, 1e300}, "motor.max_force"}};
  for (const auto& c : bad) {
    def.motor = c.motor;
    try {
      bodies.AddJoint(def);
      ADD_FAILURE() << c.field << " accepted by AddJoint";
    } catch (const RJointError& e) {
      EXPECT_EQ(e.Field(), c.field);
    }
    try {
      bodies.SetJointMotor(h, c.motor);
      ADD_FAILURE() << c.field << " accepted by SetJointMotor";
    } catch (const RJointError& e) {
      EXPECT_EQ(e.Field(), c.field);
    }
  }
  EXPECT_EQ(bodies.JointCount(), 1u);
  EXPECT_EQ(bodies.Joint(h).def.motor.speed, -1e15);
  EXPECT_EQ(bodies.Joint(h).def.motor.maxForce, 1e30);
}
