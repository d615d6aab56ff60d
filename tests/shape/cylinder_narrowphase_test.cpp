// Cylinders in the narrow phase: random pairs against FCL and the cylinder's exact signed
// distance, the manifold's shape (an end standing on a face is a full manifold, a side lying
// on it a line), and the pairs review found where a flat tetrahedron passed for an overlap
// or a line or an end lost its deepest point.
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RRigidBody.h>
#include <REnginePhysics/RShape.h>

#include "shape/CylinderFixtures.h"
#include "support/CollisionOracles.h"
#include "support/RandomPartners.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

using namespace REngine;
using namespace REngine::test;

namespace {

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
