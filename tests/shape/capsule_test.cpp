// Capsules: mass properties against quadrature, the narrow phase against FCL and
// closed forms, and a capsule resting and rolling against the closed forms of rigid-body
// motion.
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RQueries.h>
#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RShape.h>

#include "support/CollisionOracles.h"
#include "support/RandomPartners.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using namespace REngine;
using namespace REngine::test;

namespace {

// Distance of two segments by a ternary search over the first one's parameter: the
// distance from a point moving along a segment to a segment is convex in its parameter.
// Independent of the closed form the engine uses.
RScalar SegmentDistance(const RVec3& a0, const RVec3& a1, const RVec3& b0, const RVec3& b1) {
  auto toB = [&](const RVec3& p) {
    const RVec3 d = b1 - b0;
    const RScalar t = std::clamp((p - b0).dot(d) / d.squaredNorm(), RScalar(0), RScalar(1));
    return (b0 + t * d - p).norm();
  };
  RScalar lo = 0, hi = 1;
  for (int k = 0; k < 200; ++k) {
    const RScalar m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (toB(a0 + m1 * (a1 - a0)) < toB(a0 + m2 * (a1 - a0))) hi = m2; else lo = m1;
  }
  return toB(a0 + (lo + hi) / 2 * (a1 - a0));
}

// The capsule as a solid of revolution about y: its radius at height y is rho(y). Volume
// and moments are integrals of polynomials in y over three pieces (a cap, the cylinder, a
// cap), each exact to rounding with 3-point Gauss-Legendre (exact to degree 5; rho^4 and
// rho^2 y^2 are of degree 4). Independent of the closed form's parallel-axis algebra.
RMassProperties CapsuleByQuadrature(RScalar r, RScalar h) {
  const RScalar x[3] = {-std::sqrt(RScalar(0.6)), 0, std::sqrt(RScalar(0.6))};
  const RScalar w[3] = {RScalar(5) / 9, RScalar(8) / 9, RScalar(5) / 9};
  auto rho2 = [&](RScalar y) {
    const RScalar over = std::max(std::abs(y) - h, RScalar(0));
    return r * r - over * over;
  };
  RScalar V = 0, axial = 0, across = 0;
  const RScalar pieces[4] = {-h - r, -h, h, h + r};
  for (int p = 0; p < 3; ++p) {
    const RScalar a = pieces[p], b = pieces[p + 1];
    for (int k = 0; k < 3; ++k) {
      const RScalar y = (a + b) / 2 + (b - a) / 2 * x[k], wk = w[k] * (b - a) / 2;
      const RScalar q = rho2(y);
      V += wk * kPi * q;
      axial += wk * kPi / 2 * q * q;               // a disc's m r^2 / 2
      across += wk * (kPi / 4 * q * q + kPi * q * y * y);  // a disc's m r^2 / 4, moved by y
    }
  }
  RMassProperties mp;
  mp.volume = V;
  mp.principalMoments = RVec3(across, axial, across);
  return mp;
}

RConvexShape Capsule(RScalar r, RScalar h) { return CapsuleShape(r, h); }

}  // namespace

TEST(CapsuleMass, MatchesQuadratureOfTheSolidOfRevolution) {
  for (const auto& [r, h] : std::vector<std::pair<RScalar, RScalar>>{{0.5, 1}, {1, 0.01}, {0.2, 30}, {3, 3}}) {
    RShape s;
    s = RShape::Capsule(r, h);
    const RMassProperties got = ComputeMassProperties(s), want = CapsuleByQuadrature(r, h);
    EXPECT_NEAR(got.volume, want.volume, 1e-13 * want.volume) << r << " " << h;
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(got.principalMoments[a], want.principalMoments[a], 1e-13 * want.principalMoments.maxCoeff()) << r << " " << h;
    }
    EXPECT_TRUE(got.com_S.isZero(0));
  }
}

TEST(CapsuleMass, BodyReportsItsAxisAsAPrincipalAxis) {
  RBodyDef def;
  def.restitution = 0.5;
  def.shape = RShape::Capsule(0.5, 1);
  def.mass = 2;
  const RRigidBody b(def);
  const RMassProperties want = CapsuleByQuadrature(0.5, 1);
  EXPECT_NEAR(b.Inertia_B().y(), want.principalMoments.y() * 2 / want.volume, 1e-14);
  EXPECT_NEAR(b.BoundingRadius(), 1.5, 1e-15);
}

TEST(CapsuleMass, BadSizesAreRefusedNamingTheField) {
  for (const auto& [r, h, field] : std::vector<std::tuple<RScalar, RScalar, std::string>>{
           {0.5, -1, "shape.half_height"}, {0.5, 0, "shape.half_height"}, {NAN, 1, "shape.radius"},
           {1e-9, 1, "shape.radius"}, {0.5, INFINITY, "shape.half_height"}}) {
    RBodyDef def;
    def.restitution = 0.5;
    def.shape = RShape::Capsule(r, h);
    try {
      RRigidBody b(def);
      ADD_FAILURE() << "accepted r=" << r << " h=" << h;
    } catch (const RBodyError& e) {
      EXPECT_EQ(e.Field(), field);
    }
  }
}

// Random pairs from a fixed seed: a capsule against a box, a sphere, a capsule and a hull,
// posed near each other. Every answer's witnesses on their surfaces, and a penetrating pair
// moved apart by its depth along its normal touching. Apart: the distance against FCL's
// (asked for to 1e-12; ours is exact to rounding). Overlapping or apart: the verdict against
// FCL's collide, away from a band about touching; the depth of two capsules against its
// closed form. The hit rate must lie in a band, so easy cases alone cannot pass.
TEST(CapsuleCrosscheck, RandomPairsAgreeWithFcl) {
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<RScalar> u(0, 1);
  const OracleHull hull(std::vector<RVec3>{{1, 0.2, 0}, {-0.7, 0.9, 0.3}, {0.1, -1, 0.5}, {0.3, 0.4, -1.1},
                                           {-0.5, -0.6, -0.4}, {0.8, 0.7, 0.9}, {-1, 0, -0.2}});
  int overlaps = 0, apart = 0, checked = 0;
  RScalar worstDistance = 0;
  for (int n = 0; n < 4000; ++n) {
    const int kind = n % 4;  // 0 box, 1 sphere, 2 capsule, 3 hull
    const RScalar r = 0.1 + u(rng), h = 0.05 + 2 * u(rng);
    const RConvexShape caps = Capsule(r, h);
    static constexpr PartnerKind kKinds[4] = {PartnerKind::kBox, PartnerKind::kSphere, PartnerKind::kCapsule,
                                              PartnerKind::kHull};
    const Partner partner(kKinds[kind], rng, hull);
    const RConvexShape& other = partner.shape;
    const fcl::CollisionGeometryd* fclOther = partner.fcl;
    const PairPose pose(rng, caps.boundingRadius + other.boundingRadius);
    const RQuat &qA = pose.qA, &qB = pose.qB;
    const RVec3 &xA = pose.xA, &xB = pose.xB;
    // The capsule as A half of the time, as B the other half.
    const bool capsuleIsA = (n / 4) % 2 == 0;
    const RConvexShape& sa = capsuleIsA ? caps : other;
    const RConvexShape& sb = capsuleIsA ? other : caps;
    const RRelativePose X = pose.Relative();
    const RDistanceResult got = RCollisionSolver::Distance(sa, sb, X);
    const RScalar size = caps.boundingRadius + other.boundingRadius;
    // The witnesses lie on their surfaces (B's in B's frame), the separation apart along the
    // normal; a penetrating pair moved apart by its depth along its normal touches.
    ASSERT_NEAR(got.normal.norm(), 1, 1e-12) << n;
    EXPECT_NEAR(SurfaceDistance(sa, got.witnessA), 0, 1e-9 * size) << "pair " << n << " kind " << kind;
    EXPECT_NEAR(SurfaceDistance(sb, X.R_AB.transpose() * (got.witnessB - X.t_AB)), 0, 1e-9 * size)
        << "pair " << n << " kind " << kind;
    EXPECT_NEAR((got.witnessB - got.witnessA).dot(got.normal), got.separation, 1e-9 * size) << n;
    if (got.separation < 0) {
      RRelativePose moved = X;
      moved.t_AB -= got.separation * got.normal;
      EXPECT_NEAR(RCollisionSolver::Distance(sa, sb, moved).separation, 0, 1e-8 * size)
          << "pair " << n << " kind " << kind << " depth " << -got.separation;
    }
    got.separation > 0 ? ++apart : ++overlaps;
    fcl::Capsuled fclCaps(r, 2 * h);
    const fcl::Transform3d tfCaps = FclPose(capsuleIsA ? xA : xB, capsuleIsA ? qA : qB, true);
    const fcl::Transform3d tfOther = FclPose(capsuleIsA ? xB : xA, capsuleIsA ? qB : qA, kind == 2);
    if (got.separation > 1e-6 * size) {
      fcl::DistanceRequestd request(true);
      request.gjk_solver_type = fcl::GST_INDEP;
      request.distance_tolerance = 1e-12;
      fcl::DistanceResultd result;
      fcl::distance(&fclCaps, tfCaps, fclOther, tfOther, request, result);
      worstDistance = std::max(worstDistance, std::abs(result.min_distance - got.separation) / size);
      EXPECT_NEAR(got.separation, result.min_distance, 1e-6 * size) << "pair " << n << " kind " << kind;
      ++checked;
    }
    if (std::abs(got.separation) > 1e-6 * size) {
      fcl::CollisionRequestd request;
      fcl::CollisionResultd result;
      fcl::collide(&fclCaps, tfCaps, fclOther, tfOther, request, result);
      EXPECT_EQ(result.isCollision(), got.separation < 0) << "pair " << n << " kind " << kind << " sep " << got.separation;
    }
    if (kind == 2 && got.separation < 0) {
      // Two capsules: the depth is r_a + r_b less the distance of their cores, exactly.
      const RVec3 a0(0, -sa.halfHeight, 0), a1(0, sa.halfHeight, 0);
      const RVec3 b0 = X.R_AB * RVec3(0, -sb.halfHeight, 0) + X.t_AB, b1 = X.R_AB * RVec3(0, sb.halfHeight, 0) + X.t_AB;
      EXPECT_NEAR(got.separation, SegmentDistance(a0, a1, b0, b1) - r - other.radius, 1e-12 * size) << n;
    }
  }
  std::printf("capsule pairs: %d overlapping, %d apart; %d distances against FCL, worst |d - d_fcl| / size %.2e\n",
              overlaps, apart, checked, worstDistance);
  EXPECT_GT(overlaps, 1000);
  EXPECT_GT(apart, 1000);
}

// A capsule against a box's face with its core inside the box: the depth is the core's
// deepest end below the face plus the radius (the exact answer the enumeration gives).
TEST(CapsuleNarrowPhase, CoreInsideABoxGivesTheDepthOfItsDeepestEndPlusTheRadius) {
  const RConvexPolyhedron box = RConvexPolyhedron::Box(RVec3(2, 1, 2));
  RConvexShape a;
  a.polyhedron = &box, a.boundingRadius = box.MaxRadius();
  const RConvexShape c = Capsule(0.3, 0.5);
  RRelativePose X;
  // Tilted 10 degrees about z, its centre 0.1 below the top face.
  X.R_AB = Eigen::AngleAxisd(10 * kPi / 180, RVec3::UnitZ()).toRotationMatrix();
  X.t_AB = RVec3(0.2, 0.9, 0);
  const RDistanceResult d = RCollisionSolver::Distance(a, c, X);
  const RScalar lowestEnd = 0.9 - 0.5 * std::cos(10 * kPi / 180);
  EXPECT_NEAR(d.separation, lowestEnd - 1 - 0.3, 1e-14);
  EXPECT_NEAR(d.normal.y(), 1, 1e-14);
}

namespace {

RRigidBody Ground(RScalar angle, RScalar friction) {
  RBodyDef g;
  g.name = "ground";
  g.kind = RBodyKind::kStatic;
  g.shape = RShape::Box(RVec3(200, 0.5, 5));
  g.q_WS = RQuat(Eigen::AngleAxisd(angle, RVec3::UnitZ()));
  g.position_W = g.q_WS * RVec3(0, -0.5, 0);
  g.friction = friction, g.restitution = 0;
  return RRigidBody(g);
}

}  // namespace

// Lying on a floor: two contact points, one under each end of the core, and it rests at
// its radius exactly (to the slop), with no spin.
TEST(CapsulePhysics, LyingCapsuleRestsOnTwoPointsAtItsRadius) {
  std::vector<RRigidBody> bodies{Ground(0, 0.5)};
  RBodyDef c;
  c.shape = RShape::Capsule(0.5, 1);
  c.q_WS = RQuat(Eigen::AngleAxisd(kPi / 2, RVec3::UnitZ()));
  c.position_W = RVec3(0, 0.8, 0);
  c.restitution = 0;
  bodies.emplace_back(c);
  RIntegrator integrator;
  integrator.Settings().gravity_W = RVec3(0, -9.81, 0);
  integrator.Settings().shortcuts.sleeping = false;  // (a sleeping pair reports no contact)
  for (int k = 0; k < 120; ++k) integrator.Update(bodies, 1.0 / 60);
  ASSERT_EQ(integrator.Contacts().size(), 1u);
  EXPECT_EQ(integrator.Contacts()[0].manifold.pointCount, 2);
  EXPECT_NEAR(bodies[1].Position_W().y(), 0.5, integrator.Settings().penetrationSlop);
  EXPECT_LT(bodies[1].AngularVelocity_B().norm(), 1e-9);
}

// On its side down a 20 degree incline with enough friction to roll: a = g sin(theta) /
// (1 + I / (m r^2)), I the moment about its axis (closed form above), within 1%.
// A round body (its axis, if any, across the slope) let go on a 20 degree incline with
// enough friction to roll, for 1.5 s at 60 Hz; returns it after the run and the distance
// it went down the slope.
constexpr RScalar kInclineTheta = 20 * kPi / 180, kInclineG = 9.81, kInclineT = 1.5;
RScalar RollDownIncline(RBodyDef c, RScalar r, RRigidBody& out) {
  std::vector<RRigidBody> bodies{Ground(-kInclineTheta, 1.0)};
  c.mass = 1, c.friction = 1.0, c.restitution = 0;
  const RQuat incline(Eigen::AngleAxisd(-kInclineTheta, RVec3::UnitZ()));
  c.position_W = incline * RVec3(0, r, 0);  // resting on the incline's surface
  bodies.emplace_back(c);
  RIntegrator integrator;
  integrator.Settings().gravity_W = RVec3(0, -kInclineG, 0);
  integrator.Settings().shortcuts.sleeping = false;
  const RVec3 down = incline * RVec3(1, 0, 0), x0 = bodies[1].Position_W();
  for (int k = 0; k < static_cast<int>(std::lround(kInclineT * 60)); ++k) integrator.Update(bodies, 1.0 / 60);
  out = bodies[1];
  return (bodies[1].Position_W() - x0).dot(down);
}

// On its side down a 20 degree incline with enough friction to roll: a = g sin(theta) /
// (1 + I / (m r^2)), I the moment about its axis (closed form above), within 1%.
TEST(CapsulePhysics, RollsDownAnInclineAtTheRollingAcceleration) {
  const RScalar theta = kInclineTheta, g = kInclineG, T = kInclineT, r = 0.5;
  RBodyDef c;
  c.restitution = 0.5;
  c.shape = RShape::Capsule(r, 1);
  c.q_WS = RQuat(Eigen::AngleAxisd(kPi / 2, RVec3::UnitX()));  // axis along z, across the slope
  RRigidBody body(c);
  const RScalar s = RollDownIncline(c, r, body);
  const RScalar I = body.Inertia_B().y();
  const RScalar a = g * std::sin(theta) / (1 + I / (1 * r * r));
  std::printf("capsule rolling: s = %.6f m, closed form %.6f m\n", s, 0.5 * a * T * T);
  EXPECT_NEAR(s, 0.5 * a * T * T, 0.01 * 0.5 * a * T * T);
  // Rolling, not sliding: the contact point is at rest, v = w r, but for the end of the
  // step's kicks (gravity's last half kick along the slope and the friction's answer to it
  // come at the end and the start of steps): within one step's kick, g sin(theta) dt, where
  // sliding for the 1.5 s would leave v - w r at a T (I / (m r^2)) / (1 + ...) = 1.4 m/s.
  EXPECT_NEAR(body.Velocity_W().norm(), body.AngularVelocity_B().norm() * r, g * std::sin(theta) / 60);
}

// Rays against a capsule (r 0.5, core half length 1 along y): closed forms for the side, a
// cap, a ray along the axis off centre and a start inside; then random rays against sphere
// tracing of the capsule's exact signed distance (|p - nearest core point| - r), which steps
// the distance to the surface and never passes it.
TEST(CapsuleRays, MeetTheSurfaceWhereItsSignedDistanceVanishes) {
  const RConvexShape c = Capsule(0.5, 1);
  RShapeRayHit hit;
  ASSERT_TRUE(RayCastShape(c, RVec3(5, 0.3, 0), RVec3(-1, 0, 0), 100, hit));
  EXPECT_NEAR(hit.distance, 4.5, 1e-15);
  EXPECT_TRUE(hit.normal.isApprox(RVec3(1, 0, 0), 1e-15));
  ASSERT_TRUE(RayCastShape(c, RVec3(0, 5, 0), RVec3(0, -1, 0), 100, hit));
  EXPECT_NEAR(hit.distance, 3.5, 1e-15);
  ASSERT_TRUE(RayCastShape(c, RVec3(0.4, 5, 0), RVec3(0, -1, 0), 100, hit));
  EXPECT_NEAR(hit.distance, 5 - (1 + std::sqrt(0.25 - 0.16)), 1e-14);
  EXPECT_FALSE(RayCastShape(c, RVec3(0.6, 5, 0), RVec3(0, -1, 0), 100, hit));
  EXPECT_FALSE(RayCastShape(c, RVec3(5, 0.3, 0), RVec3(-1, 0, 0), 4.4, hit));  // too short
  ASSERT_TRUE(RayCastShape(c, RVec3(0.1, 1.2, 0), RVec3(1, 0, 0), 100, hit));
  EXPECT_EQ(hit.distance, 0);

  auto sdf = [](const RVec3& p) { return (p - RVec3(0, std::clamp(p.y(), -1.0, 1.0), 0)).norm() - 0.5; };
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<RScalar> u(-1, 1);
  int hits = 0, misses = 0;
  for (int n = 0; n < 3000; ++n) {
    const RVec3 o = RVec3(u(rng), u(rng), u(rng)).normalized() * 4;
    const RVec3 target(0.8 * u(rng), 1.7 * u(rng), 0.8 * u(rng));
    const RVec3 d = (target - o).normalized();
    // Sphere tracing: t advances by the distance to the surface; it reaches the first hit
    // from outside or passes the shape (the distance grows again).
    RScalar t = 0, best = std::numeric_limits<RScalar>::infinity();
    bool traced = false;
    for (int k = 0; k < 100000 && t < 10; ++k) {
      const RScalar s = sdf(o + t * d);
      best = std::min(best, s);
      if (s < 1e-13) {
        traced = true;
        break;
      }
      t += s;
    }
    const bool got = RayCastShape(c, o, d, 10, hit);
    if (!traced && best < 1e-6) continue;  // grazing: tracing cannot tell in its budget
    ASSERT_EQ(got, traced) << n;
    if (got) {
      ++hits;
      EXPECT_NEAR(hit.distance, t, 1e-11) << n;
      EXPECT_NEAR(sdf(o + hit.distance * d), 0, 1e-12) << n;
      // The normal is the gradient of the distance there.
      const RVec3 p = o + hit.distance * d;
      const RVec3 core(0, std::clamp(p.y(), -1.0, 1.0), 0);
      EXPECT_TRUE(hit.normal.isApprox((p - core).normalized(), 1e-9)) << n;
    } else {
      ++misses;
    }
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 300);
}

// A capsule missile at 2 km/s, nose first, at a plate 5 cm thick: 33 m a step, 660 times the
// plate. It does not pass through: the speculative contact stops it at the plate's face
// (restitution 0), within the slop, in the step it arrives.
TEST(CapsulePhysics, FastMissileDoesNotTunnelThroughAThinPlate) {
  RBodyDef plate;
  plate.kind = RBodyKind::kStatic;
  plate.shape = RShape::Box(RVec3(0.025, 5, 5));
  plate.position_W = RVec3(1e6 + 100, 0, 0);  // far out, where space games are
  plate.restitution = 0;
  RBodyDef missile;
  missile.shape = RShape::Capsule(0.2, 1);
  missile.q_WS = RQuat(Eigen::AngleAxisd(-kPi / 2, RVec3::UnitZ()));  // its axis along x
  missile.position_W = RVec3(1e6, 0.3, 0);
  missile.velocity_W = RVec3(2000, 0, 0);
  missile.restitution = 0;
  std::vector<RRigidBody> bodies{RRigidBody(plate), RRigidBody(missile)};
  RIntegrator integrator;
  for (int k = 0; k < 10; ++k) integrator.Update(bodies, 1.0 / 60);
  const RScalar face = 1e6 + 100 - 0.025, nose = bodies[1].Position_W().x() + 1.2;
  EXPECT_NEAR(nose, face, integrator.Settings().penetrationSlop + 1e-9 * 1e6);
  EXPECT_NEAR(bodies[1].Velocity_W().x(), 0, 1e-9);
}

// The reference for the capsule's rolling: a ball rolls down the same incline at
// a = 5/7 g sin(theta) (I = 2/5 m r^2), within 1%.
TEST(CapsulePhysics, BallRollsDownTheSameInclineAtFiveSeventhsOfGSinTheta) {
  const RScalar r = 0.5;
  RBodyDef c;
  c.restitution = 0.5;
  c.shape = RShape::Sphere(r);
  RRigidBody body(c);
  const RScalar s = RollDownIncline(c, r, body);
  const RScalar want = 0.5 * (5.0 / 7 * kInclineG * std::sin(kInclineTheta)) * kInclineT * kInclineT;
  std::printf("ball rolling: s = %.6f m, closed form %.6f m\n", s, want);
  EXPECT_NEAR(s, want, 0.01 * want);
}

// A thin capsule deep across a box's top edge: the deepest axis is the edge crossed with the
// core, across the core, so both ends are equally deep along it; the witnesses must still be
// where the shapes meet, at the edge, not at an end metres away (a wrong lever arm spins
// the body). The depth against the box's SAT over its faces and the edge axis.
TEST(CapsuleNarrowPhase, DeepAcrossAnEdgeTheWitnessesAreAtTheEdge) {
  const RConvexPolyhedron box = RConvexPolyhedron::Box(RVec3(1, 1, 1));
  RConvexShape a;
  a.polyhedron = &box, a.boundingRadius = box.MaxRadius();
  const RVec3 p0(0.5, 0.99, 0), p1(3, 0.5, 0);
  const RConvexShape c = Capsule(0.05, 0.5 * (p1 - p0).norm());
  RRelativePose X;
  X.t_AB = 0.5 * (p0 + p1);
  X.R_AB = RQuat::FromTwoVectors(RVec3::UnitY(), (p1 - p0).normalized()).toRotationMatrix();
  for (const bool swapped : {false, true}) {
    RDistanceResult d;
    RVec3 onBox, onCapsule;
    if (!swapped) {
      d = RCollisionSolver::Distance(a, c, X);
      onBox = d.witnessA, onCapsule = d.witnessB;
    } else {
      RRelativePose Xi;
      Xi.R_AB = X.R_AB.transpose(), Xi.t_AB = -(Xi.R_AB * X.t_AB);
      d = RCollisionSolver::Distance(c, a, Xi);
      onCapsule = X.R_AB * d.witnessA + X.t_AB, onBox = X.R_AB * d.witnessB + X.t_AB;
    }
    // The core crosses the edge x = 1, y = 1 at y = 0.99 - 0.49 (0.5 / 2.5) = 0.892: the
    // least overlap is across the edge, along the normal of the core's line (0.49, 2.5)/|.|.
    const RVec3 n = RVec3(0.49, 2.5, 0).normalized();
    const RScalar depth = n.dot(RVec3(1, 1, 0) - RVec3(1, 0.892, 0)) + 0.05;
    EXPECT_NEAR(d.separation, -depth, 1e-12) << swapped;
    EXPECT_LT((onBox - RVec3(1, 1, 0)).norm(), 0.1) << swapped << " " << onBox.transpose();
    EXPECT_LT((onCapsule - RVec3(1, 0.892, 0)).norm(), 0.1) << swapped << " " << onCapsule.transpose();
  }
}

// Line contacts in both roles: a capsule lying on a box (the box as B, the capsule as A)
// and one capsule lying on another along it: two points each, under the two ends of the
// shorter core, with the normal from A to B.
TEST(CapsuleNarrowPhase, LyingAlongAFaceOrACapsuleGivesTwoPoints) {
  const RConvexPolyhedron box = RConvexPolyhedron::Box(RVec3(3, 0.5, 3));
  RConvexShape floor;
  floor.polyhedron = &box, floor.boundingRadius = box.MaxRadius();
  const RConvexShape c = Capsule(0.5, 1);
  // The capsule (A) lies along x, its core 0.499 above the box's top (B below it).
  RRelativePose X;
  X.R_AB = RMat3::Identity();
  X.t_AB = RVec3(0, -0.5 - 0.4999, 0);
  const RMat3 turn = Eigen::AngleAxisd(kPi / 2, RVec3::UnitZ()).toRotationMatrix();  // core along x in the world
  RRelativePose Xc;  // box in the capsule's frame: the capsule turned, the box not
  Xc.R_AB = turn.transpose();
  Xc.t_AB = turn.transpose() * X.t_AB;
  const RContactManifold m = RCollisionSolver::Manifold(c, floor, Xc, 0.01);
  ASSERT_EQ(m.pointCount, 2);
  EXPECT_TRUE((turn * m.normal).isApprox(RVec3(0, -1, 0), 1e-12)) << (turn * m.normal).transpose();
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(m.points[k].separation, -0.0001, 1e-12);
    EXPECT_NEAR(std::abs((turn * m.points[k].position).x()), 1, 1e-12);
  }
  EXPECT_NE(m.points[0].featureId, m.points[1].featureId);

  // A capsule beside a longer one, both along y, 0.99 apart between cores (radii 0.5 and 0.5).
  const RConvexShape longer = Capsule(0.5, 3);
  RRelativePose Xl;
  Xl.R_AB = RMat3::Identity();
  Xl.t_AB = RVec3(0.99, 0.5, 0);  // B's core beside A's, shifted along it
  const RContactManifold m2 = RCollisionSolver::Manifold(c, longer, Xl, 0.01);
  ASSERT_EQ(m2.pointCount, 2);
  EXPECT_TRUE(m2.normal.isApprox(RVec3(1, 0, 0), 1e-12));
  EXPECT_NEAR(m2.points[0].separation, -0.01, 1e-12);
  EXPECT_NEAR(m2.points[1].separation, -0.01, 1e-12);
  // The stretch of A's core that B's faces: all of A's, y in [-1, 1].
  EXPECT_NEAR(std::min(m2.points[0].position.y(), m2.points[1].position.y()), -1, 1e-12);
  EXPECT_NEAR(std::max(m2.points[0].position.y(), m2.points[1].position.y()), 1, 1e-12);
}

// Cores that cross (or a sphere's centre on a capsule's core) are a rounding error apart in
// no direction: the depth r_a + r_b is across both cores (their common perpendicular), or
// across the core for a centre on it, never along it.
TEST(CapsuleNarrowPhase, CrossingCoresPushApartAcrossBoth) {
  const RConvexShape a = Capsule(0.25, 1), b = Capsule(0.2, 1);
  RRelativePose X;
  X.R_AB = Eigen::AngleAxisd(kPi / 2, RVec3::UnitX()).toRotationMatrix();  // B's core along z
  X.t_AB = RVec3(0, 0.3, 0.37);                                          // crossing A's at y = 0.3
  RDistanceResult d = RCollisionSolver::Distance(a, b, X);
  EXPECT_NEAR(d.separation, -0.45, 1e-15);
  EXPECT_NEAR(std::abs(d.normal.x()), 1, 1e-12) << d.normal.transpose();
  X.R_AB = Eigen::AngleAxisd(40 * kPi / 180, RVec3::UnitX()).toRotationMatrix();  // tilted, still crossing
  X.t_AB = RVec3(0, 0.3, 0) + X.R_AB.col(1) * 0.37;
  d = RCollisionSolver::Distance(a, b, X);
  EXPECT_NEAR(d.separation, -0.45, 1e-15);
  EXPECT_NEAR(std::abs(d.normal.x()), 1, 1e-12) << d.normal.transpose();
  RConvexShape ball;
  ball.radius = 0.1, ball.boundingRadius = 0.1;
  for (const RScalar y : {0.1, 0.2, 0.3}) {
    X.R_AB = RMat3::Identity(), X.t_AB = RVec3(0, y, 0);
    d = RCollisionSolver::Distance(a, ball, X);
    EXPECT_NEAR(d.separation, -0.35, 1e-15);
    EXPECT_NEAR(d.normal.y(), 0, 1e-12) << y << ": " << d.normal.transpose();
  }
}
