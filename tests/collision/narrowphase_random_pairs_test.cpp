// The narrow phase (RCollisionSolver) against independent references, on random hull pairs.
//
//  * Exact references (tests/support/CollisionOracles): the separating axis test over every
//    facet normal of the Minkowski difference gives the minimum penetration depth and its
//    axis; enumeration of vertex-face and edge-edge pairs gives the distance of separated
//    shapes. Both are iteration-free and share nothing with GJK/EPA. Our answers are
//    asserted against them.
//  * libccd 2.1 (GJK, GJK+EPA, MPR) and FCL 0.7 (collide, distance): their accuracy against
//    the exact references is measured and printed; only our agreement with FCL's distance,
//    where FCL is accurate, is asserted.
//
// Every failure of a random pair prints it as a TEST that pastes, as a regression test, into
// a file that includes collision/RandomPairs.h (the pairs, their references and checks).
//
// The tolerances: support/NarrowphaseTolerances.h. The references checked against each other
// and the libccd oracle's budget: narrowphase_references_test.cpp. The adversarial pairs, each
// at three offsets from the origin: narrowphase_adversarial_test.cpp and
// narrowphase_hard_pairs_test.cpp.
#include <REnginePhysics/RCollision.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
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

namespace {

// Error statistics: count, median, 99th percentile, maximum, and how many exceed 1e-6
// (the relative tolerance ours is held to).
struct Stats {
  std::vector<RScalar> v;
  void Add(RScalar x) { v.push_back(x); }
  RScalar Quantile(RScalar q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(q * static_cast<RScalar>(v.size() - 1))];
  }
  void Print(const char* name) {
    const auto over = std::count_if(v.begin(), v.end(), [](RScalar x) { return x > 1e-6; });
    std::printf("  %-44s n=%5zu  median %9.2e  p99 %9.2e  max %9.2e  >1e-6: %4td\n", name, v.size(),
                Quantile(0.5), Quantile(0.99), Quantile(1.0), over);
  }
};

// Verdict agreement with the exact reference; for the disagreements, the largest
// |reference separation| / size, which tells near-contact misses from gross ones.
struct Agreement {
  int compared = 0, agreed = 0, failed = 0;
  RScalar worstMiss = 0;
  void Add(bool ok, RScalar relativeSeparation) {
    ++compared;
    agreed += ok;
    if (!ok) worstMiss = std::max(worstMiss, std::abs(relativeSeparation));
  }
  void Print(const char* name) const {
    std::printf("  %-44s %5d / %5d agree (%7.3f%%)", name, agreed, compared,
                compared ? 100.0 * agreed / compared : 100.0);
    if (agreed < compared) std::printf(", misses up to |separation| = %.2g of size", worstMiss);
    if (failed) std::printf(", %d oracle failures", failed);
    std::printf("\n");
  }
};

}  // namespace

// ---------------------------------------------------------------------------------------

// 10 000 random pairs: ours against the exact references (asserted), libccd and FCL against
// the same references (measured and printed).
TEST(CollisionCrosscheck, RandomHullPairs) {
  constexpr int kPairs = 10000;
  constexpr int kMaxPrinted = 5;
  std::mt19937_64 rng(0x5EED'0C01'1DE5);
  int penetrating = 0, withinTwoBands = 0, nearContact = 0, insideHalfBand = 0, failures = 0,
      tiedNormals = 0;
  Stats oursDepth, oursDepthAbs, oursDist, oursDistAbs, oursNormalPen, oursNormalSep;
  Stats ccdEpaDepth, ccdEpaNormal, fclIndepDepth, fclIndepNormal;
  Stats fclDistLibccd, fclDistIndep, fclDistLibccdAbs, fclDistIndepAbs, oursVsFcl;
  Agreement vOurs, vIntersect, vCcdGjk, vCcdEpa, vCcdMpr, vFclLibccd, vFclIndep;
  double oursSeconds = 0;

  for (int i = 0; i < kPairs; ++i) {
    Generated p = MakePair(rng, i);
    PairEval e = EvaluateReference(*p.a, p.c.X_WA, *p.b, p.c.X_WB);
    const auto t0 = std::chrono::steady_clock::now();
    EvaluateOurs(*p.a, p.c.X_WA, *p.b, p.c.X_WB, e);
    oursSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const RScalar ref = e.refSeparation;
    const bool decided = std::abs(ref) > 2 * e.band;  // verdicts compared only there
    if (ref < 0) ++penetrating;
    if (!decided) ++withinTwoBands;
    if (std::abs(ref) < 0.5 * e.band) ++insideHalfBand;
    if (std::abs(ref) <= 1e-4 * e.scale) ++nearContact;
    if (!e.sat.unique) ++tiedNormals;

    // FCL's distance for separated pairs. Its GJK stops when the distance changes by less
    // than distance_tolerance between iterations; 1e-14 of the size is near rounding, and
    // GST_LIBCCD then matches brute force to ~1e-15 of the size (printed below), far inside
    // the band: so ours must match it as it must match brute force. GST_INDEP is measured
    // only (it fails outright on some pairs).
    OracleDistance fclDist;
    fclDist.ok = false;
    std::vector<std::string> bad = CheckOurs(e);
    if (ref > 2 * e.band) {
      fclDist = FclDistance(*p.a, p.c.X_WA, *p.b, p.c.X_WB, FclSolver::kLibccd, 1e-14 * e.scale);
      const OracleDistance di =
          FclDistance(*p.a, p.c.X_WA, *p.b, p.c.X_WB, FclSolver::kIndep, 1e-14 * e.scale);
      if (fclDist.ok) {
        fclDistLibccd.Add(std::abs(fclDist.distance - ref) / ref);
        fclDistLibccdAbs.Add(std::abs(fclDist.distance - ref) / e.scale);
        const RScalar diff = std::abs(e.ours.separation - fclDist.distance);
        oursVsFcl.Add(diff / ref);
        if (!(diff <= kRelativeTolerance * ref + e.band)) {
          char buf[160];
          std::snprintf(buf, sizeof buf, "distance differs from FCL's %.17g", fclDist.distance);
          bad.emplace_back(buf);
        }
      }
      if (di.ok) {
        fclDistIndep.Add(std::abs(di.distance - ref) / ref);
        fclDistIndepAbs.Add(std::abs(di.distance - ref) / e.scale);
      }
    }
    if (!bad.empty()) {
      ++failures;
      if (failures <= kMaxPrinted) {
        std::string msg = "pair " + std::to_string(i) + ":";
        for (const std::string& b : bad) msg += "\n  " + b;
        ADD_FAILURE() << msg << "\n" << Reproduction(p.c, "RandomPair" + std::to_string(i));
      }
    }
    if (decided) {
      vOurs.Add((e.ours.separation < 0) == (ref < 0), ref / e.scale);
      vIntersect.Add(e.intersect == (ref < 0), ref / e.scale);
    }
    if (ref < 0) {
      oursDepth.Add(std::abs(e.ours.separation - ref) / -ref);
      oursDepthAbs.Add(std::abs(e.ours.separation - ref) / e.scale);
      if (decided) {
        RScalar angle = Angle(e.normal_W, e.sat.axis);
        for (const RVec3& n : e.sat.nearOptimalAxes) angle = std::min(angle, Angle(e.normal_W, n));
        oursNormalPen.Add(angle);
      }
    } else {
      oursDist.Add(std::abs(e.ours.separation - ref) / ref);
      oursDistAbs.Add(std::abs(e.ours.separation - ref) / e.scale);
      if (decided) oursNormalSep.Add(Angle(e.normal_W, e.refNormal_W));
    }

    // libccd, in the world frame, tolerances relative to the pair's size.
    const CcdPosedHull ca = PoseForCcd(*p.a, p.c.X_WA), cb = PoseForCcd(*p.b, p.c.X_WB);
    const ccd_t config = MakeCcdConfig(e.scale);
    const int gjk = CcdGJKIntersect(ca, cb, config);
    const OraclePenetration epa = CcdGJKPenetration(ca, cb, config);
    // MPR's depth is measured along the line between the two interior points, not the
    // minimum translation: only its verdict is compared.
    const OraclePenetration mpr = CcdMPRPenetration(ca, cb, config);
    const RScalar tol = 1e-12 * e.scale;
    const OraclePenetration fl =
        FclCollide(*p.a, p.c.X_WA, *p.b, p.c.X_WB, FclSolver::kLibccd, tol);
    const OraclePenetration fi = FclCollide(*p.a, p.c.X_WA, *p.b, p.c.X_WB, FclSolver::kIndep, tol);
    if (gjk < 0) ++vCcdGjk.failed;
    if (!epa.ok) ++vCcdEpa.failed;
    if (!mpr.ok) ++vCcdMpr.failed;
    if (!fl.ok) ++vFclLibccd.failed;
    if (!fi.ok) ++vFclIndep.failed;
    if (decided) {
      const RScalar rel = ref / e.scale;
      if (gjk >= 0) vCcdGjk.Add((gjk == 1) == (ref < 0), rel);
      if (epa.ok) vCcdEpa.Add(epa.overlap == (ref < 0), rel);
      if (mpr.ok) vCcdMpr.Add(mpr.overlap == (ref < 0), rel);
      if (fl.ok) vFclLibccd.Add(fl.overlap == (ref < 0), rel);
      if (fi.ok) vFclIndep.Add(fi.overlap == (ref < 0), rel);
    }
    if (ref < -2 * e.band) {
      auto normalErr = [&](const RVec3& n) {
        RScalar angle = Angle(n, e.sat.axis);
        for (const RVec3& m : e.sat.nearOptimalAxes) angle = std::min(angle, Angle(n, m));
        return angle;
      };
      if (epa.ok && epa.overlap) {
        ccdEpaDepth.Add(std::abs(epa.depth + ref) / -ref);
        ccdEpaNormal.Add(normalErr(epa.normal_W));
      }
      if (fi.ok && fi.overlap) {
        fclIndepDepth.Add(std::abs(fi.depth + ref) / -ref);
        fclIndepNormal.Add(normalErr(fi.normal_W));
      }
    }
  }

  std::printf(
      "random hull pairs: %d, penetrating %d (%.1f%%); |separation| <= 1e-4 of the "
      "size: %d, within two bands: %d, within half a band: %d; tied SAT minima: %d; "
      "our Distance + Intersect: %.3f s in total\n",
      kPairs, penetrating, 100.0 * penetrating / kPairs, nearContact, withinTwoBands,
      insideHalfBand, tiedNormals, oursSeconds);
  std::printf("accuracy against the exact references (depth: SAT; distance: brute force):\n");
  oursDepth.Print("ours depth, relative");
  oursDepthAbs.Print("ours depth, absolute / size");
  oursNormalPen.Print("ours penetration normal, rad");
  oursDist.Print("ours distance, relative");
  oursDistAbs.Print("ours distance, absolute / size");
  oursNormalSep.Print("ours separation normal, rad");
  ccdEpaDepth.Print("libccd GJK+EPA depth, relative");
  ccdEpaNormal.Print("libccd GJK+EPA normal, rad");
  fclIndepDepth.Print("FCL collide GST_INDEP (EPA) depth, relative");
  fclIndepNormal.Print("FCL collide GST_INDEP (EPA) normal, rad");
  fclDistLibccd.Print("FCL distance GST_LIBCCD, relative");
  fclDistLibccdAbs.Print("FCL distance GST_LIBCCD, absolute / size");
  fclDistIndep.Print("FCL distance GST_INDEP, relative");
  fclDistIndepAbs.Print("FCL distance GST_INDEP, absolute / size");
  oursVsFcl.Print("ours vs FCL distance GST_LIBCCD, relative");
  std::printf("verdicts outside two bands of contact (exact reference: SAT):\n");
  vOurs.Print("ours Distance()");
  vIntersect.Print("ours Intersect()");
  vCcdGjk.Print("libccd ccdGJKIntersect");
  vCcdEpa.Print("libccd ccdGJKPenetration");
  vCcdMpr.Print("libccd ccdMPRPenetration");
  vFclLibccd.Print("FCL collide GST_LIBCCD (MPR)");
  vFclIndep.Print("FCL collide GST_INDEP (GJK+EPA)");

  EXPECT_EQ(failures, 0) << "pairs where ours disagrees with the exact reference (first "
                         << kMaxPrinted << " printed)";
  // The suite must not pass on easy cases: about half the pairs overlap.
  EXPECT_GE(penetrating, kPairs / 4);
  EXPECT_LE(penetrating, 3 * kPairs / 4);
  // Near contact is represented: every 8th pair is slid to 10^[-10, -4] of its size, so
  // ~1250 pairs, of which ~22% (log10(20) of 6 decades) within two bands, ~8% within half.
  EXPECT_GE(nearContact, kPairs / 10);
  EXPECT_GE(withinTwoBands, kPairs / 50);
  EXPECT_GE(insideHalfBand, kPairs / 200);
}

