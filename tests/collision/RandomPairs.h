// Random hull pairs for the narrow phase's cross-checks (narrowphase_random_pairs_test,
// narrowphase_references_test): pair `index` of a seeded suite, its exact reference
// (support/CollisionOracles.h), our Distance and Intersect, the checks of our answer, and a
// failing pair written as a TEST that pastes into a file including this header
// (ExpectPairMatchesReference). The tolerances: support/NarrowphaseTolerances.h.
#pragma once

#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RCollision.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "support/CollisionOracles.h"
#include "support/NarrowphaseTolerances.h"
#include "support/TestBodies.h"

namespace REngine::test {

// ---------------------------------------------------------------------------------------
// Pasteable reproduction.

inline std::string Cpp(const RVec3& v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "RVec3(%.17g, %.17g, %.17g)", v.x(), v.y(), v.z());
  return buf;
}
inline std::string Cpp(const RQuat& q) {  // RQuat's constructor takes (w, x, y, z)
  char buf[160];
  std::snprintf(buf, sizeof buf, "RQuat(%.17g, %.17g, %.17g, %.17g)", q.w(), q.x(), q.y(), q.z());
  return buf;
}
inline std::string Cpp(const std::vector<RVec3>& points) {
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

inline std::string Reproduction(const PairCase& c, const std::string& name) {
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

inline RConvexShape ShapeFor(const OracleHull& h) {
  RConvexShape s;
  s.polyhedron = &h.Polyhedron();
  s.boundingRadius = h.Radius();
  return s;
}

// X_AB from the world poses: p_A = R_A^T (p_W - x_A).
inline RRelativePose RelativeFromWorld(const OraclePose& X_WA, const OraclePose& X_WB) {
  const RMat3 R_WA = X_WA.q_WS.toRotationMatrix(), R_WB = X_WB.q_WS.toRotationMatrix();
  RRelativePose X;
  X.R_AB = R_WA.transpose() * R_WB;
  X.t_AB = R_WA.transpose() * (X_WB.position_W - X_WA.position_W);
  return X;
}

// The exact reference for a pair (fills scale, band, the posed polyhedra and the reference
// fields of `e`).
inline PairEval EvaluateReference(const OracleHull& a, const OraclePose& X_WA,
                                  const OracleHull& b, const OraclePose& X_WB) {
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
inline void EvaluateOurs(const OracleHull& a, const OraclePose& X_WA, const OracleHull& b,
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

inline PairEval Evaluate(const OracleHull& a, const OraclePose& X_WA, const OracleHull& b,
                         const OraclePose& X_WB) {
  PairEval e = EvaluateReference(a, X_WA, b, X_WB);
  EvaluateOurs(a, X_WA, b, X_WB, e);
  return e;
}

// What is wrong with our answer, or an empty list.
inline std::vector<std::string> CheckOurs(const PairEval& e) {
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

inline void ExpectPairMatchesReference(const PairCase& c) {
  const OracleHull a(c.pointsA), b(c.pointsB);
  for (const std::string& f : CheckOurs(Evaluate(a, c.X_WA, b, c.X_WB))) ADD_FAILURE() << f;
}

// ---------------------------------------------------------------------------------------
// Random pairs.

inline RScalar LogUniform(std::mt19937_64& rng, RScalar lo, RScalar hi) {
  std::uniform_real_distribution<RScalar> u(std::log(lo), std::log(hi));
  return std::exp(u(rng));
}


// A hull's input points in its own frame, centred on their mean: a box (a quarter of the
// shapes) or a cloud of 4 to 64 points in or on a ball; size 1 cm to 100 m log-uniform;
// stretched by up to 10:1 along axes of a random rotation.
inline std::vector<RVec3> RandomShapePoints(std::mt19937_64& rng) {
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

inline Generated MakePair(std::mt19937_64& rng, int index) {
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

}  // namespace REngine::test
