// Two boxes proven apart in closed form (RCollisionSolver::DistanceWithin's separating-axis
// proof for Box() polyhedra) against the exact references of support/CollisionOracles.h:
// the signed distance by enumeration (BruteForceDistance apart, SatSeparation overlapping).
// A proof must be true (the pair is farther apart than the cutoff, and the bound it returns
// is at most the distance), and a pair within the cutoff must get the full answer, the same
// verdict as the same boxes given as hulls (which take GJK alone).
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RConvexPolyhedron.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "support/CollisionOracles.h"

namespace REngine::test {
namespace {

RConvexShape ShapeOf(const RConvexPolyhedron& p) {
  RConvexShape s;
  s.polyhedron = &p;
  s.boundingRadius = p.MaxRadius();
  return s;
}

// The same box as a hull of its corners: no closed form, GJK alone.
RConvexPolyhedron HullOf(const RVec3& h) {
  std::vector<RVec3> corners;
  for (int i = 0; i < 8; ++i) corners.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
  return RConvexPolyhedron::Hull(corners);
}

RQuat RandomRotation(std::mt19937_64& rng) {
  std::normal_distribution<RScalar> n(0, 1);
  return RQuat(n(rng), n(rng), n(rng), n(rng)).normalized();
}

TEST(BoxPairs, ProvenApartOnlyBeyondTheCutoff) {
  std::mt19937_64 rng(0xB0C5'A9A7);
  std::uniform_real_distribution<RScalar> unit(0, 1);
  int proofs = 0, full = 0, compared = 0;
  for (int k = 0; k < 4000; ++k) {
    // Plates, rods and cubes from 2 cm to 2 m; a fifth of the pairs turned alike up to
    // quarter turns about one axis (parallel faces and edges, where edge axes vanish).
    auto extent = [&] { return 0.02 + 1.98 * unit(rng) * unit(rng); };
    const RVec3 ha(extent(), extent(), extent()), hb(extent(), extent(), extent());
    const RQuat qA = RandomRotation(rng);
    RQuat qB = RandomRotation(rng);
    if (k % 5 == 0) {
      const RScalar quarter = std::acos(RScalar(-1)) / 2 * static_cast<RScalar>(rng() % 4);
      qB = qA * RQuat(Eigen::AngleAxis<RScalar>(quarter, RVec3::Unit(static_cast<int>(rng() % 3))));
    }
    const RScalar reach = ha.norm() + hb.norm();
    const RVec3 direction = RandomRotation(rng) * RVec3::UnitX();
    const RVec3 xA(unit(rng), unit(rng), unit(rng));
    const RVec3 xB = xA + direction * (1.2 * reach * unit(rng));
    const RScalar cutoff = 0.3 * reach * unit(rng) * unit(rng);

    const RConvexPolyhedron boxA = RConvexPolyhedron::Box(ha), boxB = RConvexPolyhedron::Box(hb);
    ASSERT_NE(boxA.BoxHalfExtents(), nullptr);
    const RConvexPolyhedron hullA = HullOf(ha), hullB = HullOf(hb);
    ASSERT_EQ(hullA.BoxHalfExtents(), nullptr);
    RRelativePose X;
    X.R_AB = (qA.conjugate() * qB).toRotationMatrix();
    X.t_AB = qA.conjugate() * (xB - xA);
    const RDistanceResult ours = RCollisionSolver::DistanceWithin(ShapeOf(boxA), ShapeOf(boxB), X, cutoff);
    const RDistanceResult gjk = RCollisionSolver::DistanceWithin(ShapeOf(hullA), ShapeOf(hullB), X, cutoff);

    // The exact signed distance, both boxes in the world frame.
    const RConvexPolyhedron worldA = boxA.Transformed(qA.toRotationMatrix(), xA);
    const RConvexPolyhedron worldB = boxB.Transformed(qB.toRotationMatrix(), xB);
    const SatResult sat = SatSeparation(worldA, worldB, 0, 0);
    const RScalar exact = sat.separation < 0 ? sat.separation : BruteForceDistance(worldA, worldB).distance;
    // The references and the proof round at a few units in the last place of the pair's
    // size; 1e-10 of it is far above that and far below any margin the narrow phase uses.
    const RScalar tolerance = 1e-10 * reach;
    if (ours.separation > cutoff) {
      ++proofs;
      EXPECT_GT(exact, cutoff - tolerance) << "pair " << k << ": proven apart but within the cutoff";
      EXPECT_LE(ours.separation, exact + tolerance) << "pair " << k << ": the bound exceeds the distance";
      EXPECT_EQ(ours.status, RCollisionStatus::kSeparated) << "pair " << k;
    } else {
      ++full;
      EXPECT_NEAR(ours.separation, exact, 1e-9 * reach) << "pair " << k << ": within the cutoff, the full answer";
    }
    // Away from the cutoff by more than the rounding, both paths give the same verdict.
    if (std::abs(exact - cutoff) > tolerance) {
      ++compared;
      EXPECT_EQ(ours.separation > cutoff, gjk.separation > cutoff) << "pair " << k;
    }
  }
  std::printf("  %d pairs proven beyond the cutoff, %d answered in full, %d verdicts compared with GJK's\n",
              proofs, full, compared);
  // Both branches were taken many times: the suite is not all near or all far.
  EXPECT_GT(proofs, 1000);
  EXPECT_GT(full, 1000);
}

}  // namespace
}  // namespace REngine::test

namespace REngine::test {
namespace {

// What the proof assumes, checked rather than trusted: a box given negative half extents has
// the corners of the positive one, and a pose whose matrix is not a rotation (scaled) gets
// GJK's answer for the shape it describes, never a proof made for a rotation. The overlap
// below (R = 2I puts B's corners 20 m out: its x reaches from 12 - 20 to 12 + 20) is what
// GJK computes.
TEST(BoxPairs, ProofTrustsNoNegativeExtentsNorScaledPoses) {
  const RConvexPolyhedron unit = RConvexPolyhedron::Box(RVec3(1, 1, 1));
  const RConvexPolyhedron negative = RConvexPolyhedron::Box(RVec3(-1, -1, -1));
  ASSERT_NE(negative.BoxHalfExtents(), nullptr);
  EXPECT_EQ(*negative.BoxHalfExtents(), RVec3(1, 1, 1));
  RRelativePose X;
  X.t_AB = RVec3(1.5, 0, 0);  // overlapping unit boxes, 0.5 m deep
  const RDistanceResult a = RCollisionSolver::DistanceWithin(ShapeOf(negative), ShapeOf(negative), X, 0.1);
  const RDistanceResult b = RCollisionSolver::DistanceWithin(ShapeOf(unit), ShapeOf(unit), X, 0.1);
  EXPECT_NEAR(a.separation, -0.5, 1e-12);
  EXPECT_EQ(a.separation, b.separation);

  const RConvexPolyhedron small = RConvexPolyhedron::Box(RVec3(1, 1, 1)), large = RConvexPolyhedron::Box(RVec3(10, 10, 10));
  RRelativePose scaled;
  scaled.R_AB = 2 * RMat3::Identity();
  scaled.t_AB = RVec3(12, 0, 0);
  const RDistanceResult r = RCollisionSolver::DistanceWithin(ShapeOf(small), ShapeOf(large), scaled, 1);
  EXPECT_LE(r.separation, 1) << "proven apart through a matrix that is not a rotation";
}

}  // namespace
}  // namespace REngine::test
