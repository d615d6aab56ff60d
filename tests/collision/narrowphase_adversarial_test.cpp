// The narrow phase (RCollisionSolver) on adversarial pairs against the exact references
// (support/CollisionOracles.h): face-aligned, exactly touching, thin, tiny against huge,
// duplicated and coplanar hull points, identical poses, and a signed distance swept through
// contact. Each pair at offsets 0, 1e6 m and 1e7 m (collision/AdversarialPairs.h). The pairs
// GJK or EPA alone cannot answer: narrowphase_hard_pairs_test.cpp. Random pairs and
// libccd/FCL: narrowphase_random_pairs_test.cpp.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RRigidBody.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "collision/AdversarialPairs.h"
#include "support/CollisionOracles.h"
#include "support/NarrowphaseTolerances.h"

using namespace REngine;
using namespace REngine::test;

TEST(CollisionAdversarial, FaceAlignedCubes) {
  const BodySpec a{BoxShape(RVec3::Ones()), RVec3::Zero()};
  const BodySpec b{BoxShape(RVec3::Ones()), RVec3(0, 0, 1.9)};
  const Reference ref = ReferenceFor(a, b);
  // Closed form: depth 0.1 along +z; the SAT reference must say so too.
  EXPECT_NEAR(ref.separation, -0.1, 1e-15);
  ASSERT_EQ(ref.normals.size(), 1u);
  EXPECT_LE(Angle(ref.normals[0], RVec3::UnitZ()), 1e-15);
  for (const OffsetAnswer& ans : CheckAtOffsets("face-aligned cubes", a, b, ref)) {
    // Face contact: the manifold keeps the four corners of the overlap square, each 0.1 deep,
    // midway between the faces (z = 0.95 before the offset).
    EXPECT_EQ(ans.manifold.pointCount, 4) << "offset " << ans.offset;
    for (int i = 0; i < ans.manifold.pointCount; ++i) {
      const RVec3 p = ans.manifold.points[i].position - ans.offset * kDiagonal;
      EXPECT_NEAR(ans.manifold.points[i].separation, -0.1, 1e-9 + 4 * Ulp(ans.offset));
      EXPECT_NEAR(p.z(), 0.95, 1e-9 + 4 * Ulp(ans.offset));
      EXPECT_LE(std::max(std::abs(p.x()), std::abs(p.y())), 1 + 1e-9 + 4 * Ulp(ans.offset));
    }
  }
}

TEST(CollisionAdversarial, ExactlyTouchingBoxes) {
  const BodySpec a{BoxShape(RVec3::Ones()), RVec3::Zero()};
  // Face on face, aligned; then shifted in the plane and turned about z (z stays exact).
  const BodySpec aligned{BoxShape(RVec3::Ones()), RVec3(0, 0, 2)};
  const BodySpec turned{BoxShape(RVec3(1, 0.5, 1)), RVec3(0.7, -0.4, 2),
                        QuatAxisAngle(RVec3::UnitZ(), 0.3)};
  for (const BodySpec* b : {&aligned, &turned}) {
    const Reference ref = ReferenceFor(a, *b);
    EXPECT_EQ(ref.separation, 0);
    for (const OffsetAnswer& ans : CheckAtOffsets("exactly touching boxes", a, *b, ref)) {
      EXPECT_EQ(ans.r.status, RCollisionStatus::kTouching);
      EXPECT_LE(std::abs(ans.r.separation), ref.band);
      EXPECT_TRUE(ans.contact);
      // The origin lies inside the +z facet of the Minkowski difference: the normal is +z.
      EXPECT_LE(Angle(ans.normal_W, RVec3::UnitZ()), kNormalTolerance);
    }
  }
}

TEST(CollisionAdversarial, ThinSlabAgainstRotatedBox) {
  const BodySpec slab{BoxShape(RVec3(1, 0.005, 1)), RVec3::Zero()};
  const RQuat q = QuatAxisAngle(RVec3(1, 2, 3).normalized(), 0.7);
  const RShape box = BoxShape(RVec3(0.3, 0.2, 0.25));
  const RScalar hy = Extent({box, RVec3::Zero(), q}, -RVec3::UnitY());
  // The box's leftmost corner, put 1 mm inside the slab's side face, midway through its
  // thickness.
  const RVec3 left = SupportVertex({box, RVec3::Zero(), q}, -RVec3::UnitX());
  const struct {
    const char* name;
    RVec3 position;
  } cases[] = {
      {"slab face, 2 mm deep", RVec3(0.1, 0.005 + hy - 0.002, -0.2)},
      {"slab face, 1 mm apart", RVec3(0.1, 0.005 + hy + 0.001, -0.2)},
      {"box through the slab", RVec3(0.1, 0, -0.2)},
      {"slab side face, corner 1 mm in", RVec3(1 - 0.001, 0, 0.3) - left},
  };
  for (const auto& c : cases) {
    const BodySpec b{box, c.position, q};
    CheckAtOffsets(c.name, slab, b, ReferenceFor(slab, b));
  }
}

TEST(CollisionAdversarial, LargeBoxAgainstSmallBox) {
  const BodySpec big{BoxShape(RVec3::Constant(2.5)), RVec3::Zero()};
  const RShape small = BoxShape(RVec3::Constant(0.1));
  const RQuat q = QuatAxisAngle(RVec3(-2, 1, 0.5).normalized(), 1.1);
  const RScalar hz = Extent({small, RVec3::Zero(), q}, -RVec3::UnitZ());
  const struct {
    const char* name;
    RVec3 position;
  } cases[] = {
      {"small box 1 cm into the face", RVec3(0.3, -0.7, 2.5 + hz - 0.01)},
      {"small box 1 cm above the face", RVec3(0.3, -0.7, 2.5 + hz + 0.01)},
      {"small box over the edge", RVec3(2.45, 0.2, 2.5 + hz - 0.005)},
      {"small box inside", RVec3(1.9, 0.5, -0.3)},
  };
  for (const auto& c : cases) {
    const BodySpec b{small, c.position, q};
    CheckAtOffsets(c.name, big, b, ReferenceFor(big, b));
  }
}

TEST(CollisionAdversarial, HullsWithDuplicateAndCoplanarVertices) {
  // A box's corners, each three times, plus face centres, edge midpoints, points inside
  // faces and interior points.
  std::vector<RVec3> boxish;
  const RVec3 e(0.5, 0.4, 0.3);
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 8; ++i)
      boxish.emplace_back((i & 1) ? e.x() : -e.x(), (i & 2) ? e.y() : -e.y(),
                          (i & 4) ? e.z() : -e.z());
  for (int axis = 0; axis < 3; ++axis)
    for (const RScalar sign : {-1.0, 1.0}) {
      RVec3 c = RVec3::Zero();
      c[axis] = sign * e[axis];
      boxish.push_back(c);
      RVec3 f = c;
      f[(axis + 1) % 3] = 0.3 * e[(axis + 1) % 3];
      f[(axis + 2) % 3] = -0.6 * e[(axis + 2) % 3];
      boxish.push_back(f);
      RVec3 m = c;
      m[(axis + 1) % 3] = e[(axis + 1) % 3];  // an edge midpoint
      boxish.push_back(m);
    }
  boxish.push_back(RVec3::Zero());
  boxish.push_back(RVec3(0.1, -0.1, 0.05));
  // A hexagonal prism with points on its side faces and duplicated rims.
  std::vector<RVec3> prism;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 6; ++i) {
      const RScalar t = kPi / 3 * i;
      prism.emplace_back(0.35 * std::cos(t), 0.35 * std::sin(t), -0.45);
      prism.emplace_back(0.35 * std::cos(t), 0.35 * std::sin(t), 0.45);
      const RScalar u = kPi / 3 * (i + 0.5);
      prism.emplace_back(0.35 * std::cos(kPi / 6) * std::cos(u),
                         0.35 * std::cos(kPi / 6) * std::sin(u), 0.1 * (i - 2.5));
    }
  const BodySpec a{HullShape(boxish), RVec3(0.2, 0.1, -0.3),
                   QuatAxisAngle(RVec3(1, 1, 0).normalized(), 0.4)};
  const RQuat qb = QuatAxisAngle(RVec3(0, 1, 1).normalized(), -0.9);
  const RVec3 dir = RVec3(0.3, -0.5, 0.8).normalized();
  const RScalar reach = Extent(a, dir) + Extent({HullShape(prism), RVec3::Zero(), qb}, -dir);
  int overlapping = 0, apart = 0;
  for (const RScalar g : {0.6, 0.9, 0.97, 1.05}) {
    const BodySpec b{HullShape(prism), a.position_W + g * reach * dir, qb};
    const Reference ref = ReferenceFor(a, b);
    (ref.separation < 0 ? overlapping : apart) += 1;
    const std::string name = "dup/coplanar hulls at " + std::to_string(g).substr(0, 4) + " reach";
    CheckAtOffsets(name.c_str(), a, b, ref);
  }
  EXPECT_GT(overlapping, 0);
  EXPECT_GT(apart, 0);
}

TEST(CollisionAdversarial, IdenticalShapesAtIdenticalPoses) {
  // A box: the depth is its smallest width, along its local x.
  const RQuat q = QuatAxisAngle(RVec3(1, -2, 0.5).normalized(), 0.8);
  const BodySpec box{BoxShape(RVec3(1, 2, 3)), RVec3(0.3, -0.2, 0.1), q};
  const Reference boxRef = ReferenceFor(box, box);
  EXPECT_NEAR(boxRef.separation, -2, 1e-14);
  for (const OffsetAnswer& ans : CheckAtOffsets("identical boxes", box, box, boxRef))
    EXPECT_GE(std::abs(ans.normal_W.dot(q * RVec3::UnitX())), std::cos(kNormalTolerance));
  // A random hull: the depth is its minimal width (the SAT reference), either sign.
  std::mt19937_64 rng(7);
  std::normal_distribution<RScalar> g;
  std::vector<RVec3> cloud;
  for (int i = 0; i < 24; ++i) cloud.emplace_back(0.9 * g(rng), 0.5 * g(rng), 0.3 * g(rng));
  const BodySpec hull{HullShape(cloud), RVec3(-0.4, 0.2, 0.7),
                      RQuat(0.3, -0.2, 0.9, 0.1).normalized()};
  const Reference hullRef = ReferenceFor(hull, hull);
  EXPECT_GE(hullRef.normals.size(), 2u);  // n and -n tie: D = A - A is centrally symmetric
  CheckAtOffsets("identical hulls", hull, hull, hullRef);
}

// Two face-aligned boxes of half size 0.1 (band 3.5e-10 m) swept through contact, gap -1e-9
// to +1e-9 m in steps of 1e-11 m. The offsets run along x: along the diagonal, 1e7 m rounds
// positions to 9e-10 m, coarser than the sweep.
TEST(CollisionAdversarial, SignedDistanceSweepThroughContact) {
  const BodySpec a{BoxShape(RVec3::Constant(0.1)), RVec3::Zero()};
  RScalar band = 0;
  for (const RScalar offset : {0.0, 1e6, 1e7}) {
    RScalar previous = -1e300;
    int touching = 0;
    for (int k = -100; k <= 100; ++k) {
      const RScalar gap = 1e-11 * k;
      const BodySpec b{BoxShape(RVec3::Constant(0.1)), RVec3(0.03, -0.02, 0.2 + gap)};
      const RRigidBody A = MakeBody(a, offset * RVec3::UnitX()),
                       B = MakeBody(b, offset * RVec3::UnitX());
      band = RCollisionSolver::kTouchingTolerance * (A.BoundingRadius() + B.BoundingRadius());
      RDistanceResult r;
      EXPECT_NO_THROW(r = RCollisionSolver::Distance(ShapeOf(A), ShapeOf(B), RelativePose(A, B)));
      // The gap actually posed: 0.2 + gap rounds to ulp(0.2) = 2.8e-17.
      const RScalar posed = (B.Position_W().z() - A.Position_W().z()) - 0.2;
      SCOPED_TRACE("offset " + std::to_string(offset) + ", gap " + std::to_string(gap));
      ASSERT_TRUE(std::isfinite(r.separation));
      // Support points of face-aligned boxes are exact, so GJK/EPA see the gap to a few
      // roundings of coordinates <= 0.3 (ulp 5.6e-17): 1e-15 is 18 of them.
      EXPECT_NEAR(r.separation, posed, 1e-15);
      EXPECT_GE(r.separation, previous) << "not monotone";
      previous = r.separation;
      if (std::abs(posed) > band * (1 + 1e-3)) {
        EXPECT_EQ(r.status,
                  posed > 0 ? RCollisionStatus::kSeparated : RCollisionStatus::kPenetrating);
      } else if (std::abs(posed) < band * (1 - 1e-3)) {
        EXPECT_EQ(r.status, RCollisionStatus::kTouching);
      }
      touching += r.status == RCollisionStatus::kTouching;
      if (std::abs(posed) > 2 * band) {
        EXPECT_LE(Angle(a.q_WS * r.normal, RVec3::UnitZ()), kNormalTolerance);
      }
    }
    // The band (3.5e-10 m) covers ~70 of the 201 steps.
    std::printf("  sweep at offset %7.0e m: %d of 201 steps touching (band %.3g m)\n", offset,
                touching, band);
    EXPECT_GT(touching, 50);
    EXPECT_LT(touching, 100);
  }
}
