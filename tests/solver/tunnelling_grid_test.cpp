// No body ends on the far side of a plate it hits, whatever its shape, speed and angle: a
// grid of elongated bodies (box, capsule, cylinder, hull, compound), nose first and
// tilted, at 100 to 3000 m/s and 10 to 80 degrees from the plate's surface, against a
// static plate 5 cm thick. The body's centre must not cross the plate's mid-plane within
// the plate: a crossing is a body through it. The grid runs inelastic (e = 0) and elastic
// (e = 1), and no step may end with more kinetic energy than the body came in with (space:
// nothing else gives it any).
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

constexpr RScalar kDt = 1.0 / 60;
constexpr RScalar kHalfThickness = 0.025;
constexpr RScalar kHalfWidth = 240;  // (a box is at most 1e4 times as wide as thick)

struct Shot {
  const char* name;
  RShape shape;
};

std::vector<Shot> Shots() {
  std::vector<RVec3> prism;
  for (int k = 0; k < 6; ++k) {
    const RScalar a = k * kPi / 3;
    prism.emplace_back(0.1 * std::cos(a), -0.5, 0.1 * std::sin(a));
    prism.emplace_back(0.1 * std::cos(a), 0.5, 0.1 * std::sin(a));
  }
  return {{"box", RShape::Box(RVec3(0.1, 0.5, 0.1))},
          {"capsule", RShape::Capsule(0.1, 0.4)},
          {"cylinder", RShape::Cylinder(0.1, 0.5)},
          {"hull", RShape::Hull(prism)},
          {"compound", RShape::Compound({{RShape::Box(RVec3(0.1, 0.25, 0.1)), RVec3(0, -0.25, 0)},
                                         {RShape::Sphere(0.15), RVec3(0, 0.3, 0)}})}};
}

// The lowest height (world y) of a shape at pose (x, q) of its frame S.
RScalar Lowest(const RShape& shape, const RVec3& x, const RQuat& q) {
  const RMat3 R = q.toRotationMatrix();
  switch (shape.type) {
    case RShapeType::kBox:
      return x.y() - R.row(1).cwiseAbs().dot(shape.halfExtents);
    case RShapeType::kSphere:
      return x.y() - shape.radius;
    case RShapeType::kCapsule:
      return x.y() - std::abs(R(1, 1)) * shape.halfHeight - shape.radius;
    case RShapeType::kCylinder:
      return x.y() - std::abs(R(1, 1)) * shape.halfHeight - shape.radius * std::hypot(R(1, 0), R(1, 2));
    case RShapeType::kHull: {
      RScalar low = std::numeric_limits<RScalar>::infinity();
      for (const RVec3& p : shape.points) low = std::min(low, (x + R * p).y());
      return low;
    }
    default: {
      RScalar low = std::numeric_limits<RScalar>::infinity();
      for (const RCompoundChild& c : shape.children) low = std::min(low, Lowest(c.shape, x + R * c.position_S, q * c.q_SC));
      return low;
    }
  }
}

// One shot: whether the body went through the plate within 20 steps (its centre, or any of
// it: its lowest point under the plate's far face), and the most its kinetic energy ever
// exceeded what it came in with (relative).
struct ShotResult {
  bool crossed = false, pierced = false;
  RScalar gain = -1;
  RScalar y = 0, speed = 0;  // where it ended, how fast
};

ShotResult Fire(const RShape& shape, RScalar speed, RScalar degrees, RScalar tilt, RScalar restitution) {
  const RScalar angle = degrees * kPi / 180;
  const RVec3 dir(std::cos(angle), -std::sin(angle), 0);
  // Nose first: the shape's y axis along the velocity; tilted: turned a further `tilt`
  // degrees about z.
  const RQuat q = RQuat(Eigen::AngleAxis<RScalar>(tilt * kPi / 180, RVec3(RVec3::UnitZ()))) *
                  RQuat::FromTwoVectors(RVec3::UnitY(), dir);
  RBodies bodies;
  bodies.Add(BoxDef(RVec3(kHalfWidth, kHalfThickness, kHalfWidth)).Static().Restitution(restitution).Named("plate"));
  BodyDef d;
  d.shape = shape;
  // Half a step's flight above the plate: it hits in the middle of the first step.
  const RScalar height = kHalfThickness + 0.6 + 0.5 * speed * std::sin(angle) * kDt;
  const RBodyHandle body =
      bodies.Add(d.Mass(1).Restitution(restitution).Friction(0.5).Oriented(q).At(RVec3(-150, height, 0)).Moving(speed * dir));
  auto energy = [&] { return bodies[body].LinearKineticEnergy() + bodies[body].RotationalKineticEnergy(); };
  const RScalar energy0 = energy();
  RIntegrator integrator;
  ShotResult result;
  for (int s = 0; s < 20 && !result.crossed; ++s) {
    const RVec3 before = bodies[body].Position_W();
    integrator.Update(bodies, kDt);
    const RVec3 after = bodies[body].Position_W();
    result.gain = std::max(result.gain, energy() / energy0 - 1);
    // Through the plate: the centre's path crosses the mid-plane within the plate (past its
    // edge it may fall as it likes).
    if (before.y() >= 0 && after.y() < 0) {
      const RVec3 at = before + (after - before) * (before.y() / (before.y() - after.y()));
      result.crossed = std::abs(at.x()) < kHalfWidth && std::abs(at.z()) < kHalfWidth;
    }
    const RRigidBody& b = bodies[body];
    const bool over = std::abs(after.x()) < kHalfWidth - 1 && std::abs(after.z()) < kHalfWidth - 1;
    result.pierced = result.pierced || (over && Lowest(shape, b.ShapePosition_W(), b.ShapeOrientation_WS()) < -kHalfThickness);
  }
  result.y = bodies[body].Position_W().y(), result.speed = bodies[body].Velocity_W().norm();
  return result;
}

}  // namespace

TEST(Tunnelling, NoBodyEndsOnTheFarSideOfAThinPlateItHitsObliquely) {
  for (const RScalar restitution : {0.0, 1.0}) {
    int runs = 0, crossings = 0, piercings = 0, gains = 0;
    RScalar worstGain = -1;
    std::string failed;
    for (const Shot& shot : Shots()) {
      for (const RScalar speed : {100.0, 300.0, 1000.0, 1500.0, 2000.0, 2500.0, 3000.0}) {
        for (const RScalar degrees : {10.0, 30.0, 45.0, 60.0, 80.0}) {
          for (const RScalar tilt : {0.0, 45.0}) {
            const ShotResult r = Fire(shot.shape, speed, degrees, tilt, restitution);
            // No gain beyond rounding (a kinetic energy of 4.5e6 J rounds at 1e-9 J).
            const bool gained = r.gain > 1e-12;
            ++runs, crossings += r.crossed, piercings += r.pierced, gains += gained;
            worstGain = std::max(worstGain, r.gain);
            if (!r.crossed && !r.pierced && !gained) continue;
            char line[200];
            std::snprintf(line, sizeof line, "  %s at %.0f m/s, %.0f deg, tilt %.0f:%s%s%s centre at y %.3g, v %.4g m/s\n",
                          shot.name, speed, degrees, tilt, r.crossed ? " through," : "",
                          r.pierced ? " a part through," : "", gained ? " energy gained," : "", r.y, r.speed);
            failed += line;
          }
        }
      }
    }
    std::printf("oblique impacts on a 5 cm plate, e = %.0f: %d of %d runs end on the far side, %d end a step with "
                "a part beyond it, %d gain energy (kinetic energy after any step at most %.17g of the start's)\n%s",
                restitution, crossings, runs, piercings, gains, 1 + worstGain, failed.c_str());
    // A part of the body beyond the far face at the end of a step is counted, not asked
    // about: a body already turning fast when a step starts (its spin from the last step's
    // impacts) is swept only after an impact of this step, and its contact rows, built at the
    // start's geometry, can turn it on (1 run of 700: the capsule at 300 m/s and 10 degrees,
    // inelastic, ends its second step 3 cm beyond the plate, and is back above it after the
    // third).
    EXPECT_EQ(crossings, 0) << "e = " << restitution;
    EXPECT_EQ(gains, 0) << "e = " << restitution;
  }
}
