// The adversarial pairs' harness (narrowphase_adversarial_test, narrowphase_hard_pairs_test):
// a pair of posed shapes, its exact reference (support/CollisionOracles.h) and the narrow
// phase's answers checked against it at offsets 0, 1e6 m and 1e7 m from the origin. The
// tolerances: support/NarrowphaseTolerances.h.
//
// Both bodies are translated by the same offset along (1, 1, 1)/sqrt(3) (or x where stated).
// The exact reference is computed once, at offset 0; at an offset, the bodies' positions
// round to ulp(offset) per coordinate, so their difference (all the pair frame sees) moves
// by up to ~2 ulp: the tolerance grows by 4 ulp(offset) (7.5e-9 m at 1e7 m).
#pragma once

#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RRigidBody.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "support/CollisionOracles.h"
#include "support/NarrowphaseTolerances.h"
#include "support/TestBodies.h"

namespace REngine::test {

inline const RVec3 kDiagonal = RVec3::Ones().normalized();

inline RShape BoxShape(const RVec3& halfExtents) { return BoxDef(halfExtents).shape; }
inline RShape HullShape(const std::vector<RVec3>& points) { return HullDef(points).shape; }

struct BodySpec {
  RShape shape;
  RVec3 position_W = RVec3::Zero();  // of the shape frame S
  RQuat q_WS = RQuat::Identity();
};

inline RRigidBody MakeBody(const BodySpec& spec, const RVec3& offset) {
  RBodyDef def;
  def.restitution = 0.5;
  def.shape = spec.shape;
  def.position_W = spec.position_W + offset;
  def.q_WS = spec.q_WS;
  return RRigidBody(def);
}

inline RConvexPolyhedron WorldPolyhedron(const RRigidBody& body) {
  return body.Polyhedron_B()->Transformed(body.Orientation_WB().toRotationMatrix(),
                                          body.Position_W());
}

// The vertex of a posed shape furthest along d, relative to its shape frame's origin (to
// place bodies at a chosen gap).
inline RVec3 SupportVertex(const BodySpec& spec, const RVec3& d) {
  const RConvexPolyhedron posed = WorldPolyhedron(MakeBody(spec, RVec3::Zero()));
  const RVec3* best = &posed.Vertices()[0];
  for (const RVec3& v : posed.Vertices())
    if (d.dot(v) > d.dot(*best)) best = &v;
  return *best - spec.position_W;
}
inline RScalar Extent(const BodySpec& spec, const RVec3& d) {
  return d.dot(SupportVertex(spec, d));
}

struct Reference {
  RScalar separation = 0;
  std::vector<RVec3> normals;  // acceptable normals (the near-optimal SAT axes, or the
                               // closest-point direction for separated pairs)
  RScalar band = 0;
};

inline Reference ReferenceFor(const BodySpec& sa, const BodySpec& sb) {
  const RRigidBody a = MakeBody(sa, RVec3::Zero()), b = MakeBody(sb, RVec3::Zero());
  const RConvexPolyhedron A = WorldPolyhedron(a), B = WorldPolyhedron(b);
  Reference ref;
  ref.band = RCollisionSolver::kTouchingTolerance * (a.BoundingRadius() + b.BoundingRadius());
  const SatResult sat = SatSeparation(A, B, ref.band, kNormalTolerance);
  if (sat.separation > 0) {
    const BruteDistance d = BruteForceDistance(A, B);
    ref.separation = d.distance;
    ref.normals = {(d.pointB - d.pointA).normalized()};
  } else {
    ref.separation = sat.separation;
    ref.normals = sat.nearOptimalAxes;
  }
  return ref;
}

inline RScalar Ulp(RScalar x) { return std::nextafter(std::abs(x), 1e300) - std::abs(x); }

struct OffsetAnswer {
  RScalar offset = 0;
  RDistanceResult r;  // pair frame
  RVec3 normal_W, witnessA_W, witnessB_W;
  bool contact = false;       // CheckCollision(dt = 0)
  RContactManifold manifold;  // world frame, when contact
};

// Runs the pair at offsets 0, 1e6 and 1e7 m along `dir`, checks every answer against the
// reference, and returns the answers for case-specific checks.
inline std::vector<OffsetAnswer> CheckAtOffsets(const char* name, const BodySpec& sa,
                                                const BodySpec& sb, const Reference& ref,
                                                const RVec3& dir = kDiagonal) {
  std::vector<OffsetAnswer> out;
  for (const RScalar offset : {0.0, 1e6, 1e7}) {
    SCOPED_TRACE(std::string(name) + " at offset " + std::to_string(offset) + " m");
    const RRigidBody a = MakeBody(sa, offset * dir), b = MakeBody(sb, offset * dir);
    OffsetAnswer ans;
    ans.offset = offset;
    EXPECT_NO_THROW({
      ans.r = RCollisionSolver::Distance(ShapeOf(a), ShapeOf(b), RelativePose(a, b));
      ans.contact = RCollisionSolver::CheckCollision(a, b, 0, ans.manifold);
    });
    const RDistanceResult& r = ans.r;
    ans.normal_W = a.Orientation_WB() * r.normal;
    ans.witnessA_W = a.Orientation_WB() * r.witnessA + a.Position_W();
    ans.witnessB_W = a.Orientation_WB() * r.witnessB + a.Position_W();
    const RScalar tol = kRelativeTolerance * std::abs(ref.separation) + ref.band + 4 * Ulp(offset);
    RScalar angle = 10;
    for (const RVec3& n : ref.normals) angle = std::min(angle, Angle(ans.normal_W, n));
    std::printf(
        "  %-34s offset %7.0e m: %-11s separation %+.17g (reference %+.17g, error "
        "%.1e), normal error %.1e rad, gjk %d epa %d\n",
        name, offset, StatusName(r.status), r.separation, ref.separation,
        std::abs(r.separation - ref.separation), angle, r.gjkIterations, r.epaIterations);
    EXPECT_TRUE(std::isfinite(r.separation) && AllFinite(r.normal) && AllFinite(r.witnessA) &&
                AllFinite(r.witnessB));
    EXPECT_NE(r.status, RCollisionStatus::kIterationCap);
    EXPECT_NEAR(r.separation, ref.separation, tol);
    EXPECT_NEAR(r.normal.norm(), 1, 1e-12);
    if (std::abs(ref.separation) > 2 * ref.band) {
      EXPECT_EQ(r.status,
                ref.separation > 0 ? RCollisionStatus::kSeparated : RCollisionStatus::kPenetrating);
      EXPECT_LE(angle, kNormalTolerance);
      EXPECT_EQ(ans.contact, ref.separation < 0);
    } else if (std::abs(ref.separation) < 0.5 * ref.band) {
      EXPECT_EQ(r.status, RCollisionStatus::kTouching);
      EXPECT_TRUE(ans.contact);
    }
    // Witnesses on the surfaces (reference polyhedra moved by the same offset) and apart by
    // separation * normal.
    const RRigidBody a0 = MakeBody(sa, offset * dir), b0 = MakeBody(sb, offset * dir);
    EXPECT_LE(std::abs(SurfaceOffset(WorldPolyhedron(a0), ans.witnessA_W)),
              ref.band + 4 * Ulp(offset));
    EXPECT_LE(std::abs(SurfaceOffset(WorldPolyhedron(b0), ans.witnessB_W)),
              ref.band + 4 * Ulp(offset));
    EXPECT_LE((r.witnessB - r.witnessA - r.separation * r.normal).norm(),
              kRelativeTolerance * std::abs(r.separation) + ref.band);
    if (ans.contact) {
      EXPECT_TRUE(AllFinite(ans.manifold.query.normal));
      EXPECT_GE(ans.manifold.pointCount, 1);
      EXPECT_LE(ans.manifold.pointCount, 4);
      for (int i = 0; i < ans.manifold.pointCount; ++i)
        EXPECT_TRUE(AllFinite(ans.manifold.points[i].position) &&
                    std::isfinite(ans.manifold.points[i].separation));
    }
    out.push_back(ans);
  }
  // The pair frame makes the answer independent of the offset, to its rounding.
  for (const OffsetAnswer& ans : out)
    EXPECT_NEAR(ans.r.separation, out[0].r.separation, 4 * Ulp(ans.offset) + 1e-15 * ref.band)
        << name << " at offset " << ans.offset;
  return out;
}

}  // namespace REngine::test
