// Drag, checked against the exact flow of dv/dt = a - c v and of the damped free rotation:
// velocity, position and orientation after many steps, with and without gravity, and a
// body without drag left bit for bit as it was.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;
constexpr RScalar kG = 9.81;

RWorldSettings ZeroGravity() { return RWorldSettings{}; }

}  // namespace

// ---- drag ---------------------------------------------------------------------------------

// With no other force a damped body's velocity is v0 e^(-c t), and with the torque -c L of
// angular drag its world angular momentum is L0 e^(-c t) (the free flow keeps L; the drag
// scales it without turning it), for any body, here a box of three distinct moments spun
// near its intermediate axis. Each step multiplies by e^(-c dt/2) twice, a few roundings a
// step: after 600 steps the relative error is a few hundred ulp, asked below 1e-12.
TEST(Drag, SpeedAndAngularMomentumDecayExactlyAsExponentials) {
  const RScalar cv = 0.7, cw = 0.3;
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
      BoxDef(RVec3(0.5, 0.3, 0.1)).Mass(2).Moving(RVec3(3, -1, 2)).Spinning(RVec3(0.05, 4, 0.1))
          .Damping(cv, cw).Named("box")});
  RIntegrator integrator(ZeroGravity());
  const RVec3 v0 = bodies[0].Velocity_W(), L0 = bodies[0].AngularMomentum_W();
  const RScalar E0 = bodies[0].RotationalKineticEnergy();
  RScalar worstV = 0, worstL = 0;
  for (int n = 1; n <= 600; ++n) {
    integrator.Update(bodies, kDt);
    const RScalar t = n * kDt;
    worstV = std::max(worstV, (bodies[0].Velocity_W() - v0 * std::exp(-cv * t)).norm() /
                                  (v0.norm() * std::exp(-cv * t)));
    worstL = std::max(worstL, (bodies[0].AngularMomentum_W() - L0 * std::exp(-cw * t)).norm() /
                                  (L0.norm() * std::exp(-cw * t)));
  }
  std::printf("drag, 600 steps: worst relative error of v %.2g, of L %.2g\n", worstV, worstL);
  EXPECT_LT(worstV, 1e-12);
  EXPECT_LT(worstL, 1e-12);
  // The rotational energy of the free flow at angular momentum L e^(-ct): E0 e^(-2ct).
  EXPECT_NEAR(bodies[0].RotationalKineticEnergy() / (E0 * std::exp(-2 * cw * 10.0)), 1, 1e-12);
}

// Without drag the velocity passes through untouched: no factor 1 multiplied in.
TEST(Drag, ZeroDragLeavesTheMotionBitForBit) {
  const BodyDef d = BoxDef(RVec3(0.5, 0.3, 0.1)).Mass(2).Moving(RVec3(3, -1, 2))
                        .Spinning(RVec3(0.05, 4, 0.1)).Named("box");
  std::vector<RRigidBody> plain = MakeBodies(std::vector<BodyDef>{d});
  BodyDef scaled = d;
  scaled.GravityScale(1).Damping(0, 0);
  std::vector<RRigidBody> explicitDefaults = MakeBodies(std::vector<BodyDef>{scaled});
  RIntegrator a(EarthGravity()), b(EarthGravity());
  Step(a, plain, 100), Step(b, explicitDefaults, 100);
  EXPECT_EQ(plain[0].Position_W(), explicitDefaults[0].Position_W());
  EXPECT_EQ(plain[0].AngularVelocity_B(), explicitDefaults[0].AngularVelocity_B());
}

// The exact flow of dv/dt = g - c v: v(t) = g/c + (v0 - g/c) e^(-ct) and
// x(t) = x0 + g t/c + (v0 - g/c)(1 - e^(-ct))/c. Each step follows it exactly but for a few
// roundings of the position (relative 1e-16 of the distance travelled): 600 steps leave some
// 1e-14 of the distance, asked below 1e-12, with and without gravity, for slow drag
// (c dt = 0.002, the series branch of the flow's factors) and fast (c dt = 0.5).
TEST(Drag, PositionFollowsTheExactFlowWithAndWithoutGravity) {
  for (const RScalar gy : {0.0, -kG}) {
    for (const RScalar c : {0.12, 30.0}) {
      const RVec3 x0(1, 2, 3), v0(40, -7, 12), g(0, gy, 0);
      std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
          SphereDef(0.5).Mass(2).At(x0).Moving(v0).Damping(c, 0).Named("ball")});
      RWorldSettings settings;
      settings.gravity_W = g;
      RIntegrator integrator(settings);
      RScalar worstX = 0, worstV = 0;
      for (int n = 1; n <= 600; ++n) {
        integrator.Update(bodies, kDt);
        const RScalar t = n * kDt, decay = std::exp(-c * t);
        const RVec3 v = g / c + (v0 - g / c) * decay;
        const RVec3 x = x0 + g * (t / c) + (v0 - g / c) * (-std::expm1(-c * t) / c);
        worstX = std::max(worstX, (bodies[0].Position_W() - x).norm() / (1 + (x - x0).norm()));
        worstV = std::max(worstV, (bodies[0].Velocity_W() - v).norm() / (1 + v.norm()));
      }
      std::printf("drag c %g, g %g, 600 steps: position %.2g, velocity %.2g\n", c, gy, worstX, worstV);
      EXPECT_LT(worstX, 1e-12) << "c " << c << " g " << gy;
      EXPECT_LT(worstV, 1e-12) << "c " << c << " g " << gy;
    }
  }
}

// Angular drag scales the spin by e^(-ct) and the damped free flow is the free flow along
// the time tau = (1 - e^(-ct))/c (Euler's equations with a scalar factor on both sides). A
// spin about a principal axis turns through w0 tau; a box of three distinct moments spun
// near its intermediate axis stands, at t, where an undamped copy stands after exact steps
// adding up to tau (the free flow is exact at any step), with spin e^(-ct) the copy's.
TEST(Drag, OrientationFollowsTheDampedFreeFlow) {
  const RScalar c = 0.3;
  {
    std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{
        BoxDef(RVec3(0.5, 0.3, 0.1)).Mass(2).Spinning(RVec3(0, 4, 0)).Damping(0, c).Named("box")});
    RIntegrator integrator(ZeroGravity());
    RScalar worst = 0;
    for (int n = 1; n <= 600; ++n) {
      integrator.Update(bodies, kDt);
      const RScalar t = n * kDt, angle = 4 * -std::expm1(-c * t) / c;
      const RQuat q(Eigen::AngleAxis<RScalar>(angle, RVec3::UnitY()));
      const RQuat& got = bodies[0].Orientation_WB();
      worst = std::max(worst, std::min((got.coeffs() - q.coeffs()).norm(), (got.coeffs() + q.coeffs()).norm()));
    }
    std::printf("angular drag about a principal axis, 600 steps: orientation %.2g\n", worst);
    EXPECT_LT(worst, 1e-12);
  }
  const BodyDef box = BoxDef(RVec3(0.5, 0.3, 0.1)).Mass(2).Spinning(RVec3(0.05, 4, 0.1)).Named("box");
  BodyDef damped = box;
  damped.Damping(0, c);
  std::vector<RRigidBody> bodies = MakeBodies(std::vector<BodyDef>{damped});
  RIntegrator integrator(ZeroGravity());
  const int steps = 600;
  Step(integrator, bodies, steps);
  const RScalar t = steps * kDt, tau = -std::expm1(-c * t) / c;
  std::vector<RRigidBody> free = MakeBodies(std::vector<BodyDef>{box});
  RIntegrator exact(ZeroGravity());
  const int pieces = static_cast<int>(std::ceil(tau));  // (a step is at most 1 s)
  for (int k = 0; k < pieces; ++k) exact.Update(free, tau / pieces);
  const RQuat &got = bodies[0].Orientation_WB(), &want = free[0].Orientation_WB();
  const RScalar dq = std::min((got.coeffs() - want.coeffs()).norm(), (got.coeffs() + want.coeffs()).norm());
  const RVec3 w = free[0].AngularVelocity_B() * std::exp(-c * t);
  const RScalar dw = (bodies[0].AngularVelocity_B() - w).norm() / w.norm();
  std::printf("angular drag near the intermediate axis, %d steps: orientation %.2g, spin %.2g\n", steps, dq, dw);
  EXPECT_LT(dq, 1e-10);
  EXPECT_LT(dw, 1e-10);
}
