// Cylinders: mass properties against quadrature, the body's bounding radius and box, bad
// sizes refused by name, and rays against the cylinder's exact signed distance.
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RQueries.h>
#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RShape.h>

#include "shape/CylinderFixtures.h"
#include "support/RandomPartners.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

using namespace REngine;
using namespace REngine::test;

TEST(CylinderMass, MatchesQuadratureOfTheSolidOfRevolution) {
  // Slices across y: a disc of area pi r^2 has moment pi r^4 / 2 about the axis and
  // pi r^4 / 4 + pi r^2 y^2 across it at height y; 3-point Gauss-Legendre integrates these
  // (degree 2 in y) exactly.
  const RScalar x[3] = {-std::sqrt(RScalar(0.6)), 0, std::sqrt(RScalar(0.6))};
  const RScalar w[3] = {RScalar(5) / 9, RScalar(8) / 9, RScalar(5) / 9};
  for (const auto& [r, h] : std::vector<std::pair<RScalar, RScalar>>{{0.5, 1}, {1, 0.01}, {0.2, 30}, {3, 3}}) {
    RScalar V = 0, axial = 0, across = 0;
    for (int k = 0; k < 3; ++k) {
      const RScalar y = h * x[k], wk = w[k] * h;
      V += wk * kPi * r * r;
      axial += wk * kPi * r * r * r * r / 2;
      across += wk * (kPi * r * r * r * r / 4 + kPi * r * r * y * y);
    }
    RShape s;
    s = RShape::Cylinder(r, h);
    const RMassProperties got = ComputeMassProperties(s);
    EXPECT_NEAR(got.volume, V, 1e-13 * V) << r << " " << h;
    EXPECT_NEAR(got.principalMoments.y(), axial, 1e-13 * axial) << r << " " << h;
    EXPECT_NEAR(got.principalMoments.x(), across, 1e-13 * across) << r << " " << h;
    EXPECT_NEAR(got.principalMoments.z(), across, 1e-13 * across) << r << " " << h;
    EXPECT_TRUE(got.com_S.isZero(0));
  }
}

TEST(CylinderMass, BodyHasItsBoundingRadiusAndBox) {
  RBodyDef def;
  def.restitution = 0.5;
  def.shape = RShape::Cylinder(0.3, 0.4);
  def.mass = 2;
  def.q_WS = RQuat(Eigen::AngleAxisd(0.7, RVec3(1, 2, 3).normalized()));
  const RRigidBody b(def);
  EXPECT_NEAR(b.BoundingRadius(), 0.5, 1e-15);
  EXPECT_NEAR(b.Inertia_B().y(), 2 * 0.09 / 2, 1e-15);
  // The world box is the tight one: along each world axis, the rim's farthest point.
  const RWorldForm& wf = b.WorldForm(1);
  const RVec3 axis = def.q_WS * RVec3::UnitY();
  for (int k = 0; k < 3; ++k) {
    RScalar most = 0;
    for (int i = 0; i < 3600; ++i) {  // the rim, sampled: a lower bound within 0.3 (1 - cos(0.05 deg))
      const RScalar t = 2 * kPi * i / 3600;
      const RVec3 rim = def.q_WS * RVec3(0.3 * std::cos(t), 0.4, 0.3 * std::sin(t));
      most = std::max({most, std::abs(rim[k]), std::abs((rim - 0.8 * axis)[k])});
    }
    EXPECT_GE(wf.aabbMax_W[k], most - 1e-15);
    EXPECT_LE(wf.aabbMax_W[k], most + 1e-6);
    EXPECT_NEAR(wf.aabbMin_W[k], -wf.aabbMax_W[k], 1e-15);
  }
}

TEST(CylinderMass, BadSizesAreRefusedNamingTheField) {
  for (const auto& [r, h, field] : std::vector<std::tuple<RScalar, RScalar, std::string>>{
           {0.5, -1, "shape.half_height"}, {0.5, 0, "shape.half_height"}, {NAN, 1, "shape.radius"},
           {1e-9, 1, "shape.radius"}, {1, 1e-9, "shape.half_height"}, {0.5, INFINITY, "shape.half_height"}}) {
    RBodyDef def;
    def.restitution = 0.5;
    def.shape = RShape::Cylinder(r, h);
    try {
      RRigidBody b(def);
      ADD_FAILURE() << "accepted r=" << r << " h=" << h;
    } catch (const RBodyError& e) {
      EXPECT_EQ(e.Field(), field);
    }
  }
}

// Rays against a cylinder (r 0.5, half height 1): closed forms for the side, an end and a
// start inside, then random rays against sphere tracing of its exact signed distance.
TEST(CylinderRays, MeetTheSurfaceWhereItsSignedDistanceVanishes) {
  RConvexShape c = Cylinder(0.5, 1);
  RShapeRayHit hit;
  ASSERT_TRUE(RayCastShape(c, RVec3(3, 0.2, 0), RVec3(-1, 0, 0), 10, hit));
  EXPECT_NEAR(hit.distance, 2.5, 1e-15);
  EXPECT_NEAR(hit.normal.x(), 1, 1e-15);
  ASSERT_TRUE(RayCastShape(c, RVec3(0.3, 5, 0.1), RVec3(0, -1, 0), 10, hit));
  EXPECT_NEAR(hit.distance, 4, 1e-15);
  EXPECT_NEAR(hit.normal.y(), 1, 1e-15);
  EXPECT_FALSE(RayCastShape(c, RVec3(0.6, 5, 0), RVec3(0, -1, 0), 10, hit));
  ASSERT_TRUE(RayCastShape(c, RVec3(0.1, 0.5, 0), RVec3(1, 0, 0), 10, hit));
  EXPECT_EQ(hit.distance, 0);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<RScalar> u(-1, 1);
  int hits = 0;
  for (int n = 0; n < 3000; ++n) {
    const RVec3 o = 3 * RVec3(u(rng), u(rng), u(rng));
    if (CylinderSdf(0.5, 1, o) <= 0) continue;
    const RVec3 d = (RVec3(0.6 * u(rng), 1.2 * u(rng), 0.6 * u(rng)) - o).normalized();
    // Sphere tracing: step by the distance to the surface, which never crosses it.
    RScalar t = 0;
    bool traced = false;
    for (int k = 0; k < 10000 && t < 20; ++k) {
      const RScalar s = CylinderSdf(0.5, 1, o + t * d);
      if (s < 1e-12) {
        traced = true;
        break;
      }
      t += s;
    }
    const bool got = RayCastShape(c, o, d, 20, hit);
    // A ray that grazes the rim within the tracer's resolution may go either way.
    if (got != traced) {
      EXPECT_LT(std::abs(CylinderSdf(0.5, 1, o + (got ? hit.distance : t) * d)), 1e-6) << n;
      continue;
    }
    if (!got) continue;
    ++hits;
    EXPECT_NEAR(hit.distance, t, 1e-9) << n;
    EXPECT_NEAR(CylinderSdf(0.5, 1, o + hit.distance * d), 0, 1e-12) << n;
  }
  EXPECT_GT(hits, 1000);
}
