// Cylinders: mass properties against quadrature, the narrow phase against FCL and
// the cylinder's exact signed distance, the manifold's shape (an end standing on a face is
// a full manifold, a side lying on it a line), and rolling, resting and stacking against the
// closed forms of rigid-body motion.
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

RConvexShape Cylinder(RScalar r, RScalar h) { return CylinderShape(r, h); }
RConvexShape Capsule(RScalar r, RScalar h) { return CapsuleShape(r, h); }

// How far B must move along unit n (A's frame) to clear A: h_A(n) + h_B(-n), from the
// definitions of the support functions (a cylinder's by its rim, a polyhedron's by its
// vertices, a round core's plus its radius). Every direction's overlap is at least the
// depth, with equality along the true normal.
RScalar SupportOf(const RConvexShape& s, const RVec3& d) {
  if (s.cylinderRadius > 0) {
    return s.halfHeight * std::abs(d.y()) + s.cylinderRadius * std::hypot(d.x(), d.z());
  }
  if (s.polyhedron) {
    RScalar most = -std::numeric_limits<RScalar>::infinity();
    for (const RVec3& v : s.polyhedron->Vertices()) most = std::max(most, v.dot(d));
    return most;
  }
  return s.halfHeight * std::abs(d.y()) + s.radius * d.norm();
}
RScalar OverlapAlong(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X, const RVec3& n) {
  return SupportOf(a, n) + SupportOf(b, -(X.R_AB.transpose() * n)) - n.dot(X.t_AB);
}

}  // namespace

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

// Random pairs from a fixed seed: a cylinder against a box, a sphere, a capsule, a cylinder
// and a hull, posed near each other, the cylinder as A or as B. Every answer's witnesses lie
// on their surfaces (exact signed distances), apart along the normal by the separation.
// Apart: the distance against FCL's. Overlapping: the depth is the least overlap, no
// direction of 2000 (and none near the normal) needing less, and moving B by it along the
// normal leaves the pair touching. The verdict against FCL's collide away from touching.
// The hit rate must lie in a band, so easy cases alone cannot pass.
TEST(CylinderCrosscheck, RandomPairsAgreeWithFclAndTheDefinitions) {
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<RScalar> u(0, 1);
  const OracleHull hull(std::vector<RVec3>{{1, 0.2, 0}, {-0.7, 0.9, 0.3}, {0.1, -1, 0.5}, {0.3, 0.4, -1.1},
                                           {-0.5, -0.6, -0.4}, {0.8, 0.7, 0.9}, {-1, 0, -0.2}});
  std::vector<RVec3> directions;
  for (int i = 0; i < 2000; ++i) {
    std::normal_distribution<RScalar> g(0, 1);
    directions.push_back(RVec3(g(rng), g(rng), g(rng)).normalized());
  }
  int overlaps = 0, apart = 0, checked = 0;
  RScalar worstDistance = 0, worstDepth = 0, worstWitness = 0;
  RScalar worstAlong = 0, worstTouching = 0;
  int worstEpa = 0, worstGjk = 0, roughTouching = 0;
  for (int n = 0; n < 5000; ++n) {
    const int kind = n % 5;  // 0 box, 1 sphere, 2 capsule, 3 cylinder, 4 hull
    const RScalar r = 0.1 + u(rng), h = 0.05 + u(rng);
    const RConvexShape cyl = Cylinder(r, h);
    const Partner partner(static_cast<PartnerKind>(kind), rng, hull);
    const RConvexShape& other = partner.shape;
    const fcl::CollisionGeometryd* fclOther = partner.fcl;
    const PairPose pose(rng, cyl.boundingRadius + other.boundingRadius);
    const bool cylinderIsA = (n / 5) % 2 == 0;
    const RConvexShape& sa = cylinderIsA ? cyl : other;
    const RConvexShape& sb = cylinderIsA ? other : cyl;
    const RRelativePose X = pose.Relative();
    const RDistanceResult got = RCollisionSolver::Distance(sa, sb, X);
    const RScalar size = cyl.boundingRadius + other.boundingRadius;
    ASSERT_NEAR(got.normal.norm(), 1, 1e-12) << n;
    worstGjk = std::max(worstGjk, got.gjkIterations);
    const RScalar offA = SurfaceDistance(sa, got.witnessA), offB = SurfaceDistance(sb, X.R_AB.transpose() * (got.witnessB - X.t_AB));
    worstWitness = std::max({worstWitness, std::abs(offA) / size, std::abs(offB) / size});
    EXPECT_NEAR(offA, 0, 1e-9 * size) << "pair " << n << " kind " << kind;
    EXPECT_NEAR(offB, 0, 1e-9 * size) << "pair " << n << " kind " << kind;
    EXPECT_NEAR((got.witnessB - got.witnessA).dot(got.normal), got.separation, 1e-9 * size) << n;
    const fcl::Cylinderd fclCyl(r, 2 * h);
    const fcl::Transform3d tfCyl = FclPose(cylinderIsA ? pose.xA : pose.xB, cylinderIsA ? pose.qA : pose.qB, true);
    const fcl::Transform3d tfOther = FclPose(cylinderIsA ? pose.xB : pose.xA, cylinderIsA ? pose.qB : pose.qA, partner.alongZ);
    if (got.separation < 0) {
      ++overlaps;
      // Least overlap: no sampled direction, and none within a few degrees of the normal,
      // needs less than the depth (to the rounding of the support sums).
      const RScalar depth = -got.separation;
      worstEpa = std::max(worstEpa, got.epaIterations);
      // Where two curved surfaces touch at a point GJK stalls with its bounds apart (its
      // simplex's points cluster and resolve distances no finer than about 1e-7 of the size;
      // RCylinder.cpp): the overlap along the normal and the distance of a touching pair
      // are held to 1e-5 of the size there, 1e-9 elsewhere shown by the worst figures.
      constexpr RScalar kPointTouch = 1e-5;
      RScalar least = OverlapAlong(sa, sb, X, got.normal);
      worstAlong = std::max(worstAlong, std::abs(least - depth) / size);
      EXPECT_NEAR(least, depth, kPointTouch * size) << "pair " << n << " kind " << kind;
      RVec3 e1, e2;
      OrthonormalBasis(got.normal, e1, e2);
      for (const RVec3& d : directions) least = std::min(least, OverlapAlong(sa, sb, X, d));
      // Near the normal at every scale from 1e-7 rad (an overlap smooth there grows with
      // the square of the angle: a normal off by e shows as a lower overlap e away).
      for (RScalar a = 1e-7; a < 0.1; a *= 3) {
        for (int i = 0; i < 16; ++i) {
          const RScalar t = 2 * kPi * i / 16;
          least = std::min(least, OverlapAlong(sa, sb, X, (got.normal + a * (std::cos(t) * e1 + std::sin(t) * e2)).normalized()));
        }
      }
      worstDepth = std::max(worstDepth, (depth - least) / size);
      // EPA stops on a curved surface when its bounds meet to 1e-9 of the depth.
      EXPECT_GE(least, depth - 1e-9 * size) << "pair " << n << " kind " << kind << " depth " << depth;
      RRelativePose moved = X;
      moved.t_AB -= got.separation * got.normal;
      const RDistanceResult touching = RCollisionSolver::Distance(sa, sb, moved);
      worstTouching = std::max(worstTouching, std::abs(touching.separation) / size);
      if (std::abs(touching.separation) > 1e-9 * size) ++roughTouching;
      EXPECT_NEAR(touching.separation, 0, kPointTouch * size) << "pair " << n << " kind " << kind << " depth " << depth;
    } else {
      ++apart;
    }
    if (got.separation > 1e-6 * size) {
      fcl::DistanceRequestd request(true);
      request.gjk_solver_type = fcl::GST_INDEP;
      request.distance_tolerance = 1e-12;
      fcl::DistanceResultd result;
      if (cylinderIsA) {
        fcl::distance(&fclCyl, tfCyl, fclOther, tfOther, request, result);
      } else {
        fcl::distance(fclOther, tfOther, &fclCyl, tfCyl, request, result);
      }
      worstDistance = std::max(worstDistance, std::abs(result.min_distance - got.separation) / size);
      EXPECT_NEAR(got.separation, result.min_distance, 1e-6 * size) << "pair " << n << " kind " << kind;
      // Never farther than the points FCL found by more than GJK's certificate (its bounds
      // meet to 1e-9 of the distance; on curved surfaces it converges slowly, see RCylinder.h).
      EXPECT_LE(got.separation, result.min_distance + 1e-9 * size) << "pair " << n << " kind " << kind;
      ++checked;
    }
    if (std::abs(got.separation) > 1e-6 * size) {
      fcl::CollisionRequestd request;
      fcl::CollisionResultd result;
      fcl::collide(&fclCyl, tfCyl, fclOther, tfOther, request, result);
      EXPECT_EQ(result.isCollision(), got.separation < 0) << "pair " << n << " kind " << kind << " sep " << got.separation;
    }
  }
  std::printf("cylinder pairs: %d overlapping, %d apart; %d distances against FCL, worst |d - d_fcl| / size %.2e; "
              "worst depth above the least sampled overlap / size %.2e; worst |overlap along the normal - depth| / size "
              "%.2e; moved apart by the depth: worst |separation| / size %.2e, %d of them above 1e-9; worst witness off "
              "its surface / size %.2e; most GJK iterations %d, most EPA iterations %d\n",
              overlaps, apart, checked, worstDistance, worstDepth, worstAlong, worstTouching, roughTouching, worstWitness,
              worstGjk, worstEpa);
  EXPECT_LT(roughTouching, overlaps / 20);  // point touches of curved surfaces are the exception
  EXPECT_GT(overlaps, 1200);
  EXPECT_GT(apart, 1200);
}

namespace {

RConvexPolyhedron Slab() { return RConvexPolyhedron::Box(RVec3(3, 0.5, 3)); }

RContactManifold OnSlab(const RConvexPolyhedron& slab, const RConvexShape& c, const RQuat& q, const RVec3& t) {
  RConvexShape a;
  a.polyhedron = &slab, a.boundingRadius = slab.MaxRadius();
  RRelativePose X;
  X.R_AB = q.toRotationMatrix(), X.t_AB = t;
  return RCollisionSolver::Manifold(a, c, X, 1e-3);
}

}  // namespace

// An end standing on a face: a full manifold (four points on the rim, spread over it), each
// at the depth; tilted by 0.5 degrees (within the face-contact angle): the deepest point is
// the exact lowest rim point. A side lying on the face: a line, two points at the ends.
TEST(CylinderNarrowPhase, EndOnAFaceIsAFullManifoldAndSideALine) {
  const RConvexPolyhedron slab = Slab();
  const RConvexShape c = Cylinder(0.4, 0.6);
  const RContactManifold standing = OnSlab(slab, c, RQuat::Identity(), RVec3(0.1, 0.5 + 0.6 - 1e-3, 0.2));
  ASSERT_EQ(standing.pointCount, 4);
  EXPECT_NEAR(standing.normal.y(), 1, 1e-12);
  RScalar spread = 0;
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(standing.points[i].separation, -1e-3, 1e-12);
    EXPECT_NEAR(std::hypot(standing.points[i].position.x() - 0.1, standing.points[i].position.z() - 0.2), 0.4, 1e-12);
    spread = std::max(spread, (standing.points[i].position - standing.points[0].position).norm());
  }
  EXPECT_NEAR(spread, 0.8, 1e-12);  // opposite rim points among them

  const RScalar tilt = 0.5 * kPi / 180;
  const RQuat q(Eigen::AngleAxisd(tilt, RVec3(1, 0, 1).normalized()));
  const RVec3 t(0, 0.5 + 0.6 * std::cos(tilt) + 0.4 * std::sin(tilt) - 2e-4, 0);  // the low rim point 2e-4 deep
  const RContactManifold tilted = OnSlab(slab, c, q, t);
  ASSERT_GE(tilted.pointCount, 3);
  RScalar deepest = 0;
  for (int i = 0; i < tilted.pointCount; ++i) deepest = std::min(deepest, tilted.points[i].separation);
  EXPECT_NEAR(deepest, -2e-4, 1e-12);
  EXPECT_NEAR(tilted.query.separation, -2e-4, 1e-12);

  const RQuat lying(Eigen::AngleAxisd(kPi / 2, RVec3::UnitX()));
  const RContactManifold side = OnSlab(slab, c, lying, RVec3(0.3, 0.5 + 0.4 - 5e-4, 0));
  ASSERT_EQ(side.pointCount, 2);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(side.points[i].separation, -5e-4, 1e-12);
    EXPECT_NEAR(std::abs(side.points[i].position.z()), 0.6, 1e-12);
  }
}

// A cylinder against a sphere and a capsule touches at one exact point; two cylinders end
// on end make a full manifold; side by side (logs) a line.
TEST(CylinderNarrowPhase, RoundPartnersAndOtherCylinders) {
  const RConvexShape c = Cylinder(0.5, 0.5);
  RConvexShape ball;
  ball.radius = 0.25, ball.boundingRadius = 0.25;
  RRelativePose X;
  X.t_AB = RVec3(0.3, 0.5 + 0.25 + 0.01, 0);  // over the end
  RContactManifold m = RCollisionSolver::Manifold(c, ball, X, 0.1);
  ASSERT_EQ(m.pointCount, 1);
  EXPECT_NEAR(m.points[0].separation, 0.01, 1e-12);
  X.t_AB = RVec3(0.5 + 0.3 * std::cos(0.4), 0.5 + 0.3 * std::sin(0.4), 0);  // beside the rim
  m = RCollisionSolver::Manifold(c, ball, X, 0.1);
  EXPECT_NEAR(m.query.separation, 0.05, 1e-12);
  EXPECT_NEAR(m.query.normal.x(), std::cos(0.4), 1e-9);

  X.t_AB = RVec3(0.2, 1 - 2e-4, 0.1);
  m = RCollisionSolver::Manifold(c, c, X, 1e-3);
  EXPECT_EQ(m.pointCount, 4);
  for (int i = 0; i < m.pointCount; ++i) EXPECT_NEAR(m.points[i].separation, -2e-4, 1e-12);

  X.R_AB = RMat3::Identity();
  X.t_AB = RVec3(1 - 3e-4, 0.2, 0);  // side by side, B shifted along the axis by 0.2
  m = RCollisionSolver::Manifold(c, c, X, 1e-3);
  ASSERT_EQ(m.pointCount, 2);
  EXPECT_NEAR(m.normal.x(), 1, 1e-12);
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(m.points[i].separation, -3e-4, 1e-12);
  EXPECT_NEAR(std::abs(m.points[0].position.y() - m.points[1].position.y()), 0.8, 1e-12);

  const RConvexShape caps = Capsule(0.2, 0.7);
  X.R_AB = RMat3::Identity();
  X.t_AB = RVec3(0.7 - 1e-4, 0, 0);  // lying along the side
  m = RCollisionSolver::Manifold(c, caps, X, 1e-3);
  ASSERT_EQ(m.pointCount, 2);
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(m.points[i].separation, -1e-4, 1e-12);
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

RBodyDef CylinderDef(RScalar r, RScalar h) {
  RBodyDef c;
  c.shape = RShape::Cylinder(r, h);
  c.restitution = 0, c.friction = 0.6;
  return c;
}

}  // namespace

// On its side down a 20 degree incline with enough friction to roll: a = 2/3 g sin(theta)
// (I = m r^2 / 2 about its axis), within 1% over 1.5 s at 60 Hz, rolling without slipping.
TEST(CylinderPhysics, RollsDownAnInclineAtTwoThirdsGSinTheta) {
  const RScalar theta = 20 * kPi / 180, g = 9.81, T = 1.5, r = 0.5;
  std::vector<RRigidBody> bodies{Ground(-theta, 1.0)};
  RBodyDef c = CylinderDef(r, 0.8);
  c.mass = 1, c.friction = 1.0;
  const RQuat incline(Eigen::AngleAxisd(-theta, RVec3::UnitZ()));
  c.q_WS = incline * RQuat(Eigen::AngleAxisd(kPi / 2, RVec3::UnitX()));  // axis across the slope
  c.position_W = incline * RVec3(0, r, 0);
  bodies.emplace_back(c);
  RIntegrator integrator;
  integrator.Settings().gravity_W = RVec3(0, -g, 0);
  integrator.Settings().shortcuts.sleeping = false;
  const RVec3 down = incline * RVec3(1, 0, 0), x0 = bodies[1].Position_W();
  for (int k = 0; k < 90; ++k) integrator.Update(bodies, 1.0 / 60);
  const RScalar s = (bodies[1].Position_W() - x0).dot(down);
  const RScalar a = RScalar(2) / 3 * g * std::sin(theta);
  std::printf("cylinder rolling: s = %.6f m, closed form %.6f m\n", s, 0.5 * a * T * T);
  EXPECT_NEAR(s, 0.5 * a * T * T, 0.01 * 0.5 * a * T * T);
  EXPECT_NEAR(bodies[1].Velocity_W().norm(), bodies[1].AngularVelocity_B().norm() * r, g * std::sin(theta) / 60);
  // It stays on its side on the surface: no climb off the incline, no turn of its axis.
  EXPECT_NEAR((bodies[1].Position_W()).dot(incline * RVec3::UnitY()), r, 1e-3);
  EXPECT_NEAR(std::abs((bodies[1].Orientation_WB() * RVec3::UnitY()).dot(incline * RVec3::UnitZ())), 1, 1e-6);
}

// Standing on its end: it rests at its half height (within the slop) on a full manifold,
// without rocking or spinning.
TEST(CylinderPhysics, StandingOnItsEndRestsOnAFullManifold) {
  std::vector<RRigidBody> bodies{Ground(0, 0.5)};
  RBodyDef c = CylinderDef(0.3, 0.5);
  c.position_W = RVec3(0, 0.52, 0);
  bodies.emplace_back(c);
  RIntegrator integrator;
  integrator.Settings().gravity_W = RVec3(0, -9.81, 0);
  integrator.Settings().shortcuts.sleeping = false;
  for (int k = 0; k < 180; ++k) integrator.Update(bodies, 1.0 / 60);
  ASSERT_EQ(integrator.Contacts().size(), 1u);
  EXPECT_EQ(integrator.Contacts()[0].manifold.pointCount, 4);
  EXPECT_NEAR(bodies[1].Position_W().y(), 0.5, integrator.Settings().penetrationSlop);
  EXPECT_LT(bodies[1].AngularVelocity_B().norm(), 1e-9);
  EXPECT_LT(std::abs(bodies[1].Position_W().x()) + std::abs(bodies[1].Position_W().z()), 1e-9);
}

// A stack of eight cylinders, end on end, each turned about the axis from the one below and
// set 1 mm off centre: over 10 s it stands, every cylinder upright and within 1 mm of where
// it was put (Bullet's and Jolt's cylinder stacks wander).
TEST(CylinderPhysics, StackOfEightStands) {
  std::vector<RRigidBody> bodies{Ground(0, 0.6)};
  const RScalar r = 0.4, h = 0.25;
  for (int i = 0; i < 8; ++i) {
    RBodyDef c = CylinderDef(r, h);
    c.q_WS = RQuat(Eigen::AngleAxisd(0.3 * i, RVec3::UnitY()));
    c.position_W = RVec3(1e-3 * (i % 2), h + 2 * h * i + 1e-4 * i, 0);
    bodies.emplace_back(c);
  }
  std::vector<RVec3> start;
  for (const RRigidBody& b : bodies) start.push_back(b.Position_W());
  RIntegrator integrator;
  integrator.Settings().gravity_W = RVec3(0, -9.81, 0);
  for (int k = 0; k < 600; ++k) integrator.Update(bodies, 1.0 / 60);
  RScalar worstDrift = 0, worstTilt = 0;
  for (std::size_t i = 1; i < bodies.size(); ++i) {
    const RVec3 d = bodies[i].Position_W() - start[i];
    worstDrift = std::max(worstDrift, std::hypot(d.x(), d.z()));
    worstTilt = std::max(worstTilt, std::acos(std::min(RScalar(1), (bodies[i].Orientation_WB() * RVec3::UnitY()).y())));
    EXPECT_NEAR(bodies[i].Position_W().y(), h + 2 * h * static_cast<RScalar>(i - 1), 8 * integrator.Settings().penetrationSlop) << i;
  }
  std::printf("cylinder stack of 8: worst sideways drift %.3e m, worst tilt %.3e rad\n", worstDrift, worstTilt);
  EXPECT_LT(worstDrift, 1e-3);
  EXPECT_LT(worstTilt, 1e-3);
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

// Found by review (the inputs are its reproducers'): GJK's flat tetrahedron taken for an
// enclosure while a support plane had already set the shapes apart gave a box and a
// cylinder 4 mm apart a separation of 0, and a capsule and a cylinder different depths
// with A and B swapped.
TEST(CylinderNarrowPhase, AFlatTetrahedronDoesNotPassForAnOverlap) {
  const RConvexPolyhedron box = RConvexPolyhedron::Box(RVec3(0.7, 0.3, 0.5));
  RConvexShape a;
  a.polyhedron = &box, a.boundingRadius = box.MaxRadius();
  RRelativePose X;
  X.R_AB << -0.12858120141846707, 0.62915749615291316, 0.76656879644059406, 0.33016015686026134, 0.75604769163503049,
      -0.56514260040749853, -0.93512627247008284, 0.18042375954385551, -0.30493625813974612;
  X.t_AB = RVec3(1.0703994043788831, 0.48376362802643125, -0.1093644582171539);
  const RConvexShape c = Cylinder(0.90052342756342052, 0.25807575284682943);
  const RDistanceResult d = RCollisionSolver::Distance(a, c, X);
  // The exact distance: the least over the box's surface of the cylinder's signed distance
  // is what FCL gives; here its figure, 0.00395404928 m (to FCL's 1e-12).
  fcl::DistanceRequestd request(true);
  request.gjk_solver_type = fcl::GST_INDEP;
  request.distance_tolerance = 1e-12;
  fcl::DistanceResultd result;
  const fcl::Boxd fclBox(1.4, 0.6, 1.0);
  const fcl::Cylinderd fclCyl(0.90052342756342052, 2 * 0.25807575284682943);
  RQuat q(X.R_AB);
  fcl::distance(&fclBox, FclPose(RVec3::Zero(), RQuat::Identity(), false), &fclCyl, FclPose(X.t_AB, q, true), request,
                result);
  EXPECT_NEAR(d.separation, result.min_distance, 1e-9);
  EXPECT_GT(d.separation, 0.0039);

  RRelativePose Y;
  Y.R_AB << 0.045323371894233078, 0.29425466337186407, -0.95465176113808536, -0.96789592697537574, -0.22357050738232465,
      -0.11486384449985859, -0.24723120050797576, 0.92920956802689059, 0.27467492092046619;
  Y.t_AB = RVec3(-0.13893704837359677, 0.064326341000537968, 0.14088826029617196);
  const RConvexShape caps = Capsule(0.31432124739973188, 0.67711789165941705), cyl = Cylinder(0.16840902398264929, 0.77522201372715438);
  RRelativePose Yinv;
  Yinv.R_AB = Y.R_AB.transpose(), Yinv.t_AB = -(Y.R_AB.transpose() * Y.t_AB);
  const RScalar ab = RCollisionSolver::Distance(caps, cyl, Y).separation, ba = RCollisionSolver::Distance(cyl, caps, Yinv).separation;
  EXPECT_NEAR(ab, ba, 1e-9);
  EXPECT_NEAR(ab, -0.307742271, 1e-9);
}

// Found by review: a coin's end tilted beyond the face-contact angle was given its side's
// one spot; a coin dropped flat sank into the floor and rocked there. Tilted by 3 degrees with
// its lowest rim point 1 cm deep, the manifold holds that point at its depth and others on
// the rim around it; dropped, the coin rests at its half height and sleeps.
TEST(CylinderPhysics, ATiltedCoinKeepsItsRimAndRestsOnItsFace) {
  const RConvexPolyhedron slab = Slab();
  const RConvexShape coin = Cylinder(0.5, 0.02);
  for (const RScalar deg : {1.0, 1.2, 3.0, 10.0}) {
    const RScalar tilt = deg * kPi / 180;
    const RQuat q(Eigen::AngleAxisd(tilt, RVec3::UnitX()));
    const RVec3 t(0, 0.5 + 0.02 * std::cos(tilt) + 0.5 * std::sin(tilt) - 0.01, 0);
    const RContactManifold m = OnSlab(slab, coin, q, t);
    ASSERT_GE(m.pointCount, deg < 5 ? 2 : 1) << deg;  // (at 10 degrees the rest lie beyond the 1 mm margin)
    RScalar deepest = 1;
    for (int i = 0; i < m.pointCount; ++i) deepest = std::min(deepest, m.points[i].separation);
    EXPECT_NEAR(deepest, -0.01, 1e-12) << deg;
  }
  for (const RScalar deg : {0.5, 5.0}) {
    std::vector<RRigidBody> bodies{Ground(0, 0.5)};
    RBodyDef c = CylinderDef(0.5, 0.02);
    c.q_WS = RQuat(Eigen::AngleAxisd(deg * kPi / 180, RVec3(1, 0, 1).normalized()));
    c.position_W = RVec3(0, 1, 0);
    bodies.emplace_back(c);
    RIntegrator integrator;
    integrator.Settings().gravity_W = RVec3(0, -9.81, 0);
    for (int k = 0; k < 300; ++k) integrator.Update(bodies, 1.0 / 60);
    EXPECT_NEAR(bodies[1].Position_W().y(), 0.02, integrator.Settings().penetrationSlop) << deg;
    EXPECT_LT((bodies[1].Orientation_WB() * RVec3::UnitY() - RVec3::UnitY()).norm(), 1e-3) << deg;
    EXPECT_TRUE(bodies[1].IsSleeping()) << deg;
  }
}

// Found by review: two cylinders side by side, one leaning 0.5 degrees, had separations
// measured from a plane through one end of A's line, so an overlapping pair had no
// penetrating point. And a capsule lying across a cylinder's end with its low end between
// the end's octagon and its rim lost its deepest point to the octagon.
TEST(CylinderNarrowPhase, LinesAndEndsKeepTheirDeepestPoint) {
  const RConvexShape c = Cylinder(0.5, 1);
  for (const RScalar deg : {0.5, 1.0, -1.0}) {
    RRelativePose X;
    X.R_AB = Eigen::AngleAxisd(deg * kPi / 180, RVec3::UnitZ()).toRotationMatrix();
    X.t_AB = RVec3(1 - 1e-4, 0, 0);
    // Move B so the pair overlaps by 1e-4 exactly along the query's normal.
    X.t_AB -= (RCollisionSolver::Distance(c, c, X).separation + 1e-4) * RVec3::UnitX();
    const RContactManifold m = RCollisionSolver::Manifold(c, c, X, 0.05);
    RScalar deepest = 1;
    for (int i = 0; i < m.pointCount; ++i) deepest = std::min(deepest, m.points[i].separation);
    EXPECT_NEAR(deepest, m.query.separation, 1e-9) << deg;
  }
  const RConvexShape end = Cylinder(1, 0.5), caps = Capsule(0.1, 0.5);
  const RScalar phi = 22.5 * kPi / 180, tilt = 20 * kPi / 180;
  const RVec3 radial(std::cos(phi), 0, -std::sin(phi));
  const RVec3 up = -std::cos(tilt) * radial + std::sin(tilt) * RVec3::UnitY();
  RRelativePose X;
  X.R_AB = Eigen::Quaterniond::FromTwoVectors(RVec3::UnitY(), up).toRotationMatrix();
  X.t_AB = 0.96 * radial + RVec3(0, 0.5 + 0.1 - 1e-3, 0) + 0.5 * up;
  for (const RScalar margin : {0.0, 0.02}) {
    const RContactManifold m = RCollisionSolver::Manifold(end, caps, X, margin);
    ASSERT_GE(m.pointCount, 1);
    RScalar deepest = 1;
    for (int i = 0; i < m.pointCount; ++i) deepest = std::min(deepest, m.points[i].separation);
    EXPECT_NEAR(deepest, -1e-3, 1e-9) << margin;
  }
}
