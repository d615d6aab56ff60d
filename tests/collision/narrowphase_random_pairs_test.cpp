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
// Every failure of a random pair prints it as a TEST that pastes into this file (after the
// helpers) as a regression test.
//
// The tolerances: support/NarrowphaseTolerances.h. The adversarial pairs, each at three
// offsets from the origin: narrowphase_adversarial_test.cpp.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RCollision.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "support/CollisionOracles.h"
#include "support/NarrowphaseTolerances.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

// ---------------------------------------------------------------------------------------
// Pasteable reproduction.

std::string Cpp(const RVec3& v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "RVec3(%.17g, %.17g, %.17g)", v.x(), v.y(), v.z());
  return buf;
}
std::string Cpp(const RQuat& q) {  // RQuat's constructor takes (w, x, y, z)
  char buf[160];
  std::snprintf(buf, sizeof buf, "RQuat(%.17g, %.17g, %.17g, %.17g)", q.w(), q.x(), q.y(), q.z());
  return buf;
}
std::string Cpp(const std::vector<RVec3>& points) {
  std::string s = "{";
  for (std::size_t i = 0; i < points.size(); ++i) s += (i ? ",\n       " : "") + Cpp(points[i]);
  return s + "}";
}

// A pair as the random suite makes it: hull input points in each shape's own frame, and the
// world poses of those frames.
struct PairCase {
  std::vector<RVec3> pointsA, pointsB;  // m
  OraclePose X_WA, X_WB;
};

std::string Reproduction(const PairCase& c, const std::string& name) {
  return "TEST(CollisionRegression, " + name + ") {\n  const PairCase c{\n      " + Cpp(c.pointsA) +
         ",\n      " + Cpp(c.pointsB) + ",\n      {" + Cpp(c.X_WA.position_W) + ", " +
         Cpp(c.X_WA.q_WS) + "},\n      {" + Cpp(c.X_WB.position_W) + ", " + Cpp(c.X_WB.q_WS) +
         "}};\n  ExpectPairMatchesReference(c);\n}\n";
}

// ---------------------------------------------------------------------------------------
// One pair: the exact reference, our answer, and the checks.

struct PairEval {
  RScalar scale = 0;  // rA + rB, m
  RScalar band = 0;   // touching band, m
  // Reference, world frame.
  RConvexPolyhedron posedA, posedB;
  SatResult sat;
  BruteDistance brute;  // only for separated pairs
  RScalar refSeparation = 0;
  RVec3 refNormal_W = RVec3::UnitX();  // separated: direction of the closest points
  // Ours, converted to the world frame.
  RDistanceResult ours;
  RVec3 normal_W, witnessA_W, witnessB_W;
  bool intersect = false;
};

RConvexShape ShapeFor(const OracleHull& h) {
  RConvexShape s;
  s.polyhedron = &h.Polyhedron();
  s.boundingRadius = h.Radius();
  return s;
}

// X_AB from the world poses: p_A = R_A^T (p_W - x_A).
RRelativePose RelativeFromWorld(const OraclePose& X_WA, const OraclePose& X_WB) {
  const RMat3 R_WA = X_WA.q_WS.toRotationMatrix(), R_WB = X_WB.q_WS.toRotationMatrix();
  RRelativePose X;
  X.R_AB = R_WA.transpose() * R_WB;
  X.t_AB = R_WA.transpose() * (X_WB.position_W - X_WA.position_W);
  return X;
}

// The exact reference for a pair (fills scale, band, the posed polyhedra and the reference
// fields of `e`).
PairEval EvaluateReference(const OracleHull& a, const OraclePose& X_WA, const OracleHull& b,
                           const OraclePose& X_WB) {
  PairEval e;
  e.scale = a.Radius() + b.Radius();
  e.band = RCollisionSolver::kTouchingTolerance * e.scale;
  e.posedA = a.Polyhedron().Transformed(X_WA.q_WS.toRotationMatrix(), X_WA.position_W);
  e.posedB = b.Polyhedron().Transformed(X_WB.q_WS.toRotationMatrix(), X_WB.position_W);
  // Ties: facets whose depths differ by less than the band are equally right answers.
  e.sat = SatSeparation(e.posedA, e.posedB, e.band, kNormalTolerance);
  if (e.sat.separation > 0) {
    e.brute = BruteForceDistance(e.posedA, e.posedB);
    e.refSeparation = e.brute.distance;
    e.refNormal_W = (e.brute.pointB - e.brute.pointA).normalized();
  } else {
    e.refSeparation = e.sat.separation;
    e.refNormal_W = e.sat.axis;
  }
  return e;
}

// Our Distance and Intersect for the pair, in the frame of A as the engine poses them, with
// the results taken back to the world.
void EvaluateOurs(const OracleHull& a, const OraclePose& X_WA, const OracleHull& b,
                  const OraclePose& X_WB, PairEval& e) {
  const RConvexShape sa = ShapeFor(a), sb = ShapeFor(b);
  const RRelativePose X_AB = RelativeFromWorld(X_WA, X_WB);
  e.ours = RCollisionSolver::Distance(sa, sb, X_AB);
  e.intersect = RCollisionSolver::Intersect(sa, sb, X_AB);
  const RMat3 R_WA = X_WA.q_WS.toRotationMatrix();
  e.normal_W = R_WA * e.ours.normal;
  e.witnessA_W = R_WA * e.ours.witnessA + X_WA.position_W;
  e.witnessB_W = R_WA * e.ours.witnessB + X_WA.position_W;
}

PairEval Evaluate(const OracleHull& a, const OraclePose& X_WA, const OracleHull& b,
                  const OraclePose& X_WB) {
  PairEval e = EvaluateReference(a, X_WA, b, X_WB);
  EvaluateOurs(a, X_WA, b, X_WB, e);
  return e;
}

// What is wrong with our answer, or an empty list.
std::vector<std::string> CheckOurs(const PairEval& e) {
  std::vector<std::string> bad;
  char buf[512];
  auto fail = [&](const char* what) { bad.emplace_back(what); };
  const RDistanceResult& r = e.ours;
  std::snprintf(buf, sizeof buf,
                "ours: %s separation %.17g normal_W (%.17g, %.17g, %.17g), gjk %d epa %d "
                "iterations; reference separation %.17g axis (%.17g, %.17g, %.17g) "
                "(%zu near-optimal axes); band %.3g",
                StatusName(r.status), r.separation, e.normal_W.x(), e.normal_W.y(), e.normal_W.z(),
                r.gjkIterations, r.epaIterations, e.refSeparation, e.refNormal_W.x(),
                e.refNormal_W.y(), e.refNormal_W.z(), e.sat.nearOptimalAxes.size(), e.band);
  const std::string summary = buf;
  if (!std::isfinite(r.separation) || !AllFinite(r.normal) || !AllFinite(r.witnessA) ||
      !AllFinite(r.witnessB))
    fail("non-finite result");
  if (r.status == RCollisionStatus::kIterationCap) fail("iteration cap on a valid pair");
  if (r.gjkIterations > RCollisionSolver::kMaxGjkIterations ||
      r.epaIterations > RCollisionSolver::kMaxEpaIterations)
    fail("iterations beyond the documented caps");
  if (std::abs(r.normal.norm() - 1) > 1e-12) fail("normal not unit");

  // The status must classify our own separation as the header says.
  const RScalar s = r.separation;
  if (r.status != RCollisionStatus::kIterationCap) {
    const RCollisionStatus expect = s > e.band    ? RCollisionStatus::kSeparated
                                    : s < -e.band ? RCollisionStatus::kPenetrating
                                                  : RCollisionStatus::kTouching;
    if (r.status != expect && std::abs(std::abs(s) - e.band) > 1e-6 * e.band)
      fail("status does not match our own separation and the band");
  }
  // Verdict against the exact reference, two bands away from contact; inside half a band,
  // touching (our error is far below half a band).
  const RScalar ref = e.refSeparation;
  if (ref > 2 * e.band && r.status != RCollisionStatus::kSeparated) fail("verdict: not separated");
  if (ref < -2 * e.band && r.status != RCollisionStatus::kPenetrating)
    fail("verdict: not penetrating");
  if (std::abs(ref) < 0.5 * e.band && r.status != RCollisionStatus::kTouching)
    fail("verdict: not touching inside the band");
  if (std::abs(ref) > 2 * e.band && e.intersect != (ref < 0)) fail("Intersect() verdict");
  // Value.
  if (!(std::abs(s - ref) <= kRelativeTolerance * std::abs(ref) + e.band))
    fail(ref < 0 ? "depth differs from the SAT minimum" : "distance differs from brute force");
  // Normal: for penetration, any of the near-optimal SAT axes; for separation, the (unique)
  // direction of the closest points.
  if (std::abs(ref) > 2 * e.band) {
    RScalar angle = Angle(e.normal_W, e.refNormal_W);
    if (ref < 0)
      for (const RVec3& n : e.sat.nearOptimalAxes) angle = std::min(angle, Angle(e.normal_W, n));
    if (!(angle <= kNormalTolerance)) fail("normal differs from the reference");
  }
  // Witnesses: on the surfaces, and witnessB - witnessA = separation * normal.
  if (!(std::abs(SurfaceOffset(e.posedA, e.witnessA_W)) <= e.band))
    fail("witnessA off A's surface");
  if (!(std::abs(SurfaceOffset(e.posedB, e.witnessB_W)) <= e.band))
    fail("witnessB off B's surface");
  if (!((e.witnessB_W - e.witnessA_W - s * e.normal_W).norm() <=
        kRelativeTolerance * std::abs(s) + e.band))
    fail("witnessB - witnessA != separation * normal");
  for (std::string& b : bad) b += "\n    " + summary;
  return bad;
}

[[maybe_unused]] void ExpectPairMatchesReference(const PairCase& c) {
  const OracleHull a(c.pointsA), b(c.pointsB);
  for (const std::string& f : CheckOurs(Evaluate(a, c.X_WA, b, c.X_WB))) ADD_FAILURE() << f;
}

// ---------------------------------------------------------------------------------------
// Random pairs.

RScalar LogUniform(std::mt19937_64& rng, RScalar lo, RScalar hi) {
  std::uniform_real_distribution<RScalar> u(std::log(lo), std::log(hi));
  return std::exp(u(rng));
}


// A hull's input points in its own frame, centred on their mean: a box (a quarter of the
// shapes) or a cloud of 4 to 64 points in or on a ball; size 1 cm to 100 m log-uniform;
// stretched by up to 10:1 along axes of a random rotation.
std::vector<RVec3> RandomShapePoints(std::mt19937_64& rng) {
  std::uniform_real_distribution<RScalar> u(0, 1);
  std::normal_distribution<RScalar> g;
  const RScalar size = LogUniform(rng, 0.01, 100);
  RVec3 stretch(LogUniform(rng, 1, 10), LogUniform(rng, 1, 10), LogUniform(rng, 1, 10));
  stretch /= stretch.maxCoeff();
  const RMat3 R = RandomRotation(rng).toRotationMatrix();
  std::vector<RVec3> p;
  if (u(rng) < 0.25) {
    for (int i = 0; i < 8; ++i)
      p.push_back(size * RVec3((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1));
  } else {
    const int n = std::uniform_int_distribution<int>(4, 64)(rng);
    const bool onSphere = u(rng) < 0.5;
    for (int i = 0; i < n; ++i) {
      RVec3 v(g(rng), g(rng), g(rng));
      v.normalize();
      if (!onSphere) v *= std::cbrt(u(rng));
      p.push_back(size * v);
    }
  }
  RVec3 mean = RVec3::Zero();
  for (RVec3& v : p) {
    v = R * stretch.cwiseProduct(v);
    mean += v;
  }
  mean /= static_cast<RScalar>(p.size());
  for (RVec3& v : p) v -= mean;
  return p;
}

// Pair `index` of the suite. Offsets: B is placed along a random direction u at g times the
// distance T = h_A(u) + h_B(-u) beyond which the two are surely apart, g uniform in
// [0.3, 1.1]: about half the pairs overlap (the suite asserts the rate). Every 8th pair is
// then slid along the reference normal to a separation of +-10^[-10, -4] of its size, so
// that near-contact, inside and just outside the band, is well represented.
struct Generated {
  PairCase c;
  std::unique_ptr<OracleHull> a, b;
};

Generated MakePair(std::mt19937_64& rng, int index) {
  std::uniform_real_distribution<RScalar> u(0, 1);
  Generated out;
  for (;;) {
    out.c.pointsA = RandomShapePoints(rng);
    out.c.pointsB = RandomShapePoints(rng);
    try {
      out.a = std::make_unique<OracleHull>(out.c.pointsA);
      out.b = std::make_unique<OracleHull>(out.c.pointsB);
      break;
    } catch (const RHullError&) {
      // A 4-point cloud can be flat to 1e-9: draw again (rare, and deterministic).
    }
  }
  out.c.X_WA.q_WS = RandomRotation(rng);
  out.c.X_WB.q_WS = RandomRotation(rng);
  out.c.X_WA.position_W = RVec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
  const RVec3 dir = RandomRotation(rng) * RVec3::UnitX();
  const RScalar T =
      SupportExtent(*out.a, out.c.X_WA.q_WS, dir) + SupportExtent(*out.b, out.c.X_WB.q_WS, -dir);
  const RScalar g = 0.3 + 0.8 * u(rng);
  out.c.X_WB.position_W = out.c.X_WA.position_W + g * T * dir;
  if (index % 8 == 7) {
    const PairEval e = EvaluateReference(*out.a, out.c.X_WA, *out.b, out.c.X_WB);
    const RScalar target = (u(rng) < 0.5 ? -1 : 1) * e.scale * std::pow(10.0, -10 + 6 * u(rng));
    // Sliding B by delta along the reference normal changes the separation by exactly
    // delta, for the distance and for the depth alike (while the sign does not change; the
    // reference is recomputed anyway).
    out.c.X_WB.position_W += (target - e.refSeparation) * e.refNormal_W;
  }
  return out;
}

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
