// The exact references of the narrow phase's cross-checks (support/CollisionOracles.h)
// checked themselves: the pruned separating axis test against the full enumeration and the
// brute-force distance against FCL's, on the random pairs (collision/RandomPairs.h); and the
// libccd oracle stopped by its support budget returning through its own clean-up.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RCollision.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "collision/RandomPairs.h"
#include "support/CollisionOracles.h"
#include "support/NarrowphaseTolerances.h"

using namespace REngine;
using namespace REngine::test;

// The references themselves: the pruned SAT (facet normals of the Minkowski difference
// only) equals the full enumeration over every edge pair for overlapping pairs, and for
// separated pairs both are positive lower bounds of the brute-force distance, which FCL's
// distance confirms independently.
TEST(CollisionCrosscheck, ReferencesAgreeWithEachOther) {
  std::mt19937_64 rng(0xC0FFEE'2024);
  int overlapping = 0, separated = 0;
  RScalar worstSat = 0, worstBrute = 0;
  for (int i = 0; i < 150; ++i) {
    Generated p = MakePair(rng, i);
    const RMat3 R_A = p.c.X_WA.q_WS.toRotationMatrix(), R_B = p.c.X_WB.q_WS.toRotationMatrix();
    const RConvexPolyhedron A = p.a->Polyhedron().Transformed(R_A, p.c.X_WA.position_W);
    const RConvexPolyhedron B = p.b->Polyhedron().Transformed(R_B, p.c.X_WB.position_W);
    const RScalar scale = p.a->Radius() + p.b->Radius();
    const SatResult pruned = SatSeparation(A, B, 0, kNormalTolerance, true);
    const SatResult full = SatSeparation(A, B, 0, kNormalTolerance, false);
    // Rounding of one support loop: ~1e-15 of the size.
    const RScalar tol = 1e-13 * scale;
    if (full.separation < 0) {
      ++overlapping;
      worstSat = std::max(worstSat, std::abs(pruned.separation - full.separation) / scale);
      EXPECT_NEAR(pruned.separation, full.separation, tol)
          << Reproduction(p.c, "Sat" + std::to_string(i));
    } else {
      ++separated;
      const BruteDistance d = BruteForceDistance(A, B);
      EXPECT_GT(pruned.separation, 0) << Reproduction(p.c, "Sat" + std::to_string(i));
      EXPECT_LE(pruned.separation, d.distance + tol);
      EXPECT_LE(full.separation, d.distance + tol);
      // The brute-force witnesses lie on the surfaces and realise the distance.
      EXPECT_NEAR(SurfaceOffset(A, d.pointA), 0, tol);
      EXPECT_NEAR(SurfaceOffset(B, d.pointB), 0, tol);
      EXPECT_NEAR((d.pointB - d.pointA).norm(), d.distance, tol);
      // FCL's GJK distance (GST_LIBCCD) stops when an iteration changes it by less than its
      // tolerance (1e-14 of the size here); it then matches to ~1e-15 of the size, which is
      // up to a few 1e-7 relative on the nearly touching pairs.
      const OracleDistance f =
          FclDistance(*p.a, p.c.X_WA, *p.b, p.c.X_WB, FclSolver::kLibccd, 1e-14 * scale);
      worstBrute = std::max(worstBrute, std::abs(f.distance - d.distance) / d.distance);
      EXPECT_NEAR(f.distance, d.distance, 1e-6 * d.distance + tol)
          << Reproduction(p.c, "Brute" + std::to_string(i));
    }
  }
  std::printf(
      "references: %d overlapping pairs, pruned SAT vs full enumeration max %.2e of "
      "size; %d separated, FCL distance vs brute force max rel %.2e\n",
      overlapping, worstSat, separated, worstBrute);
  EXPECT_GT(overlapping, 30);
  EXPECT_GT(separated, 30);
}

// The libccd oracle's guard: a query that runs out of its support budget is reported as
// failed and returns through libccd's own clean-up, so nothing leaks (under the sanitizer
// build LeakSanitizer fails this test otherwise: it used to longjmp out of libccd and leave
// the polytope allocated). With the budget restored, the same pair is answered.
TEST(CollisionCrosscheck, LibccdOracleStoppedByItsBudgetDoesNotLeak) {
  const OracleHull box(std::vector<RVec3>{RVec3(-1, -1, -1), RVec3(1, -1, -1), RVec3(-1, 1, -1),
                                          RVec3(1, 1, -1), RVec3(-1, -1, 1), RVec3(1, -1, 1),
                                          RVec3(-1, 1, 1), RVec3(1, 1, 1)});
  const OraclePose X_WA, X_WB{RVec3(0.3, 0.2, 1.5), RQuat(0.9, 0.1, 0.3, 0.2).normalized()};
  const CcdPosedHull a = PoseForCcd(box, X_WA), b = PoseForCcd(box, X_WB);
  const ccd_t config = MakeCcdConfig(2 * box.Radius());
  for (long budget : {3L, 6L, 12L}) {
    SetCcdSupportBudget(budget);
    EXPECT_FALSE(CcdGJKPenetration(a, b, config).ok) << budget;
  }
  SetCcdSupportBudget(0);
  const OraclePenetration p = CcdGJKPenetration(a, b, config);
  EXPECT_TRUE(p.ok && p.overlap);
}
