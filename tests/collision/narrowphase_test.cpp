// Narrow phase and pair loop on cases with closed-form answers. The cross-checks against
// exact references, FCL and libccd live in narrowphase_oracle_tests
// (narrowphase_random_pairs_test.cpp, narrowphase_references_test.cpp,
// narrowphase_adversarial_test.cpp, narrowphase_hard_pairs_test.cpp).
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RIntegrator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

RContactManifold Check(const RBodyDef& a, const RBodyDef& b, RScalar dt = 0) {
  RContactManifold m;
  RCollisionSolver::CheckCollision(RRigidBody(a), RRigidBody(b), dt, m);
  return m;
}

const RScalar kOffsets[] = {0.0, 1e6, 1e7};

}  // namespace

// Face-aligned unit cubes (half size 1) at z = 0 and 1.9: depth 0.1 along +z, four contact
// points at the overlap square's corners, midway between the faces (z = 0.95).
TEST(Collision, FaceAlignedCubes) {
  for (RScalar off : kOffsets) {
    const RVec3 o(off, -off, off);
    const RContactManifold m =
        Check(BoxDef(RVec3(1, 1, 1)).At(o), BoxDef(RVec3(1, 1, 1)).At(o + RVec3(0, 0, 1.9)));
    EXPECT_EQ(m.query.status, RCollisionStatus::kPenetrating) << off;
    // o.z + 1.9 rounds (by up to ulp(1e7)/2 ~ 1e-9); the distance actually stored is
    // the difference, exact in floating point, and the answer must match it to rounding.
    const RScalar depth = 2 - ((o.z() + 1.9) - o.z());
    EXPECT_NEAR(m.query.separation, -depth, 1e-14) << off;
    EXPECT_LT((m.query.normal - RVec3(0, 0, 1)).norm(), 1e-14) << off;
    ASSERT_EQ(m.pointCount, 4) << off;
    std::set<std::pair<int, int>> corners;
    for (int i = 0; i < 4; ++i) {
      const RVec3 p = m.points[i].position - o;
      // World points carry the rounding of their large coordinates: ulp(1e7) ~ 2e-9.
      const RScalar tol = 1e-14 + 4 * RTol::kEpsilon * off;
      EXPECT_NEAR(p.z(), 1 - depth / 2, tol);
      EXPECT_NEAR(std::abs(p.x()), 1, tol);
      EXPECT_NEAR(std::abs(p.y()), 1, tol);
      EXPECT_NEAR(m.points[i].separation, -depth, 1e-14);
      corners.insert({p.x() > 0, p.y() > 0});
    }
    EXPECT_EQ(corners.size(), 4u) << "the four corners, not one twice";
  }
}

TEST(Collision, ExactlyTouchingBoxesAreTouching) {
  for (RScalar off : kOffsets) {
    const RVec3 o(off, 0, 0);
    const RContactManifold m = Check(BoxDef(RVec3(1, 1, 1)).At(o),
                                     BoxDef(RVec3(0.5, 0.5, 0.5)).At(o + RVec3(0.2, 0, 1.5)));
    EXPECT_EQ(m.query.status, RCollisionStatus::kTouching) << off;
    EXPECT_NEAR(m.query.separation, 0, 1e-14);
    EXPECT_EQ(m.pointCount, 4);
  }
}

// Signed distance swept across zero: the right sign outside the touching band, kTouching
// inside it, and monotone.
TEST(Collision, SignedDistanceSweptThroughZero) {
  RScalar prev = -1;
  for (int k = -20; k <= 20; ++k) {
    const RScalar gap = k * 1e-9;
    const RContactManifold m = Check(BoxDef(RVec3(1, 1, 1)),
                                     BoxDef(RVec3(1, 1, 1)).At(RVec3(0, 0, 2 + gap)));
    const RScalar band = RCollisionSolver::kTouchingTolerance * 2 * std::sqrt(3.0);
    EXPECT_NEAR(m.query.separation, gap, 1e-15) << gap;
    EXPECT_GE(m.query.separation, prev);
    prev = m.query.separation;
    if (gap > band) {
      EXPECT_EQ(m.query.status, RCollisionStatus::kSeparated) << gap;
    } else if (gap < -band) {
      EXPECT_EQ(m.query.status, RCollisionStatus::kPenetrating) << gap;
    } else {
      EXPECT_EQ(m.query.status, RCollisionStatus::kTouching) << gap;
    }
  }
}

TEST(Collision, SeparatedBoxesGiveDistanceAndWitnesses) {
  // Corner (1,1,1) of A against face x = 2.5 - 0.5 of B: distance 1 along x. (Manifold,
  // not CheckCollision: a pair beyond its margin leaves CheckCollision's output unspecified.
  // A sits at the origin unturned, so its frame is the world's.)
  const RRigidBody a(BoxDef(RVec3(1, 1, 1))), b(BoxDef(RVec3(0.5, 3, 3)).At(RVec3(2.5, 0, 0)));
  const RContactManifold m = RCollisionSolver::Manifold(ShapeOf(a), ShapeOf(b), RelativePose(a, b), 0);
  EXPECT_EQ(m.query.status, RCollisionStatus::kSeparated);
  EXPECT_NEAR(m.query.separation, 1.0, 1e-14);
  EXPECT_LT((m.query.normal - RVec3(1, 0, 0)).norm(), 1e-14);
  EXPECT_NEAR(m.query.witnessA.x(), 1, 1e-14);
  EXPECT_NEAR(m.query.witnessB.x(), 2, 1e-14);
  EXPECT_EQ(m.pointCount, 0);
}

TEST(Collision, SpherePairs) {
  for (RScalar off : kOffsets) {
    const RVec3 o(off, 0, 0);
    // Ball-ball: centres 1.25 apart (exact in binary at any offset here), radii 1 and 0.5.
    RContactManifold m = Check(SphereDef(1).At(o), SphereDef(0.5).At(o + RVec3(0, 1.25, 0)));
    EXPECT_NEAR(m.query.separation, -0.25, 1e-14);
    EXPECT_LT((m.query.normal - RVec3(0, 1, 0)).norm(), 1e-14);
    ASSERT_EQ(m.pointCount, 1);
    // Box-ball from outside the face, and a ball whose centre is inside the box.
    m = Check(BoxDef(RVec3(1, 1, 1)).At(o), SphereDef(0.5).At(o + RVec3(0, 0, 1.25)));
    EXPECT_NEAR(m.query.separation, -0.25, 1e-14);
    EXPECT_LT((m.query.normal - RVec3(0, 0, 1)).norm(), 1e-14);
    m = Check(SphereDef(0.5).At(o + RVec3(0.75, 0, 0)), BoxDef(RVec3(1, 1, 1)).At(o));
    EXPECT_NEAR(m.query.separation, -0.75, 1e-14);  // centre 0.25 inside, radius 0.5
    EXPECT_LT((m.query.normal - RVec3(-1, 0, 0)).norm(), 1e-14) << "from the ball to the box";
    // Ball near a box corner: distance to the corner.
    m = Check(BoxDef(RVec3(1, 1, 1)).At(o), SphereDef(0.25).At(o + RVec3(2, 2, 2)));
    EXPECT_NEAR(m.query.separation, std::sqrt(3.0) - 0.25, 1e-14);
  }
}

// Identical shapes at identical poses: the minimum translation is the thinnest width.
TEST(Collision, IdenticalPoses) {
  for (RScalar off : kOffsets) {
    const RVec3 o(off, off, off);
    const RQuat q = QuatExp(RVec3(0.2, -0.5, 0.9));
    const RBodyDef box = BoxDef(RVec3(1, 0.3, 2)).At(o).Oriented(q);
    const RContactManifold m = Check(box, box);
    EXPECT_NEAR(m.query.separation, -0.6, 1e-13);
    EXPECT_NEAR(std::abs(m.query.normal.dot(q * RVec3::UnitY())), 1, 1e-13);
    EXPECT_TRUE(AllFinite(m.query.normal));
  }
}

// A tilted small box resting on one vertex: one point, at that vertex's depth.
TEST(Collision, VertexContactIsOnePoint) {
  const RQuat q = QuatFromTo(RVec3(1, 1, 1).normalized(), RVec3(0, 0, -1));
  const RScalar h = 0.5 * std::sqrt(3.0);  // half the cube's diagonal
  const RContactManifold m = Check(BoxDef(RVec3(2, 2, 1)),
                                   BoxDef(RVec3(0.5, 0.5, 0.5))
                                       .At(RVec3(0.1, 0.2, 1 + h - 0.01))
                                       .Oriented(q));
  EXPECT_NEAR(m.query.separation, -0.01, 1e-13);
  ASSERT_EQ(m.pointCount, 1);
  EXPECT_NEAR(m.points[0].position.z(), 1 - 0.005, 1e-13);
}

// A hexagonal prism lying on a box face: up to 6 clip points, reduced to 4 that keep the
// deepest point and span the patch.
TEST(Collision, ManifoldReducedToFourKeepsDeepestAndArea) {
  RBodyDef prism;
  prism.restitution = 0.5;
  prism.name = "prism";
  prism.shape.type = RShapeType::kHull;
  for (int k = 0; k < 6; ++k) {
    const RScalar t = kPi * k / 3;
    prism.shape.points.emplace_back(std::cos(t), std::sin(t), -0.2);
    prism.shape.points.emplace_back(std::cos(t), std::sin(t), 0.2);
  }
  // Tilted slightly about x so the points differ in depth.
  prism.q_WS = QuatExp(RVec3(0.01, 0, 0));
  prism.position_W = RVec3(0, 0, 1.19);
  const RContactManifold m = Check(BoxDef(RVec3(3, 3, 1)), prism);
  ASSERT_EQ(m.pointCount, 4);
  RScalar deepest = 0;
  for (int i = 0; i < 4; ++i) deepest = std::min(deepest, m.points[i].separation);
  EXPECT_NEAR(deepest, m.query.separation, 1e-12);
  // The kept quadrilateral: the best 4 of the hexagon's 6 corners (unit circumradius)
  // enclose sqrt(3) ~ 1.73 of its 2.6; any poor choice (three neighbours) encloses <= 1.3.
  auto quadArea = [&](int i, int j, int k, int l) {
    const RVec3* p[4] = {&m.points[i].position, &m.points[j].position, &m.points[k].position,
                         &m.points[l].position};
    RVec3 sum = RVec3::Zero();
    for (int e = 0; e < 4; ++e) sum += p[e]->cross(*p[(e + 1) % 4]);
    return 0.5 * sum.norm();
  };
  const RScalar area = std::max({quadArea(0, 1, 2, 3), quadArea(0, 1, 3, 2), quadArea(0, 2, 1, 3)});
  EXPECT_NEAR(area, std::sqrt(3.0), 0.02);
}

// Feature ids stay the same while the same features touch (a small slide).
TEST(Collision, FeatureIdsAreStableUnderSmallMotion) {
  auto ids = [](RScalar dx) {
    const RContactManifold m = Check(BoxDef(RVec3(2, 2, 1)),
                                     BoxDef(RVec3(0.5, 0.5, 0.5)).At(RVec3(dx, 0.1, 1.49)));
    std::set<std::uint32_t> s;
    for (int i = 0; i < m.pointCount; ++i) s.insert(m.points[i].featureId);
    EXPECT_EQ(s.size(), static_cast<std::size_t>(m.pointCount)) << "ids are distinct";
    return s;
  };
  EXPECT_EQ(ids(0.0), ids(0.01));
  EXPECT_EQ(ids(0.3), ids(0.31));
}

// A projectile moving towards a plate: separated now, but the gap closes within the step,
// so the pair is reported (speculatively) with its positive separation.
TEST(Collision, SpeculativeContactWithinTheStep) {
  RBodyDef plate = BoxDef(RVec3(2, 2, 0.05));
  plate.kind = RBodyKind::kStatic;
  RBodyDef bullet = SphereDef(0.1).At(RVec3(0, 0, 20));
  bullet.velocity_W = RVec3(0, 0, -2000);
  RContactManifold m;
  EXPECT_TRUE(RCollisionSolver::CheckCollision(RRigidBody(plate), RRigidBody(bullet), 1.0 / 60, m));
  EXPECT_EQ(m.query.status, RCollisionStatus::kSeparated);
  EXPECT_NEAR(m.query.separation, 20 - 0.1 - 0.05, 1e-12);
  EXPECT_EQ(m.pointCount, 1);
  // Moving away (or too slowly to arrive): nothing.
  bullet.velocity_W = RVec3(0, 0, -100);
  EXPECT_FALSE(RCollisionSolver::CheckCollision(RRigidBody(plate), RRigidBody(bullet), 1.0 / 60, m));
}

// Faces that barely touch: the closest points are a rounding error apart, so their
// direction is noise (4e-5 rad seen for a box on a tilted slab 1e6 m from the origin); the
// manifold's normal, the one impulses act along, is the reference face's, exact.
// Boxes resting face on face overlap by rounding (1e-13 m): EPA's polytope is then flat to
// rounding and can find no face. The narrow phase must still give a verdict with a full
// manifold, or the solver skips the contact for a step and the box above drops g dt^2 / 2
// (seen: a 0.1 m stack overlapping 1.4 mm). Every pair here, a stack's boxes at sizes 0.1
// to 10 m with overlaps from -1e-12 to 1e-12 of the size and small sideways offsets, must
// report a contact with 4 points and the face normal.
TEST(Manifold, RestingFacesAlwaysGetAFullManifold) {
  int checked = 0;
  for (RScalar size : {0.1, 1.0, 10.0}) {
    for (int k = -20; k <= 20; ++k) {
      for (int s = 0; s < 8; ++s) {
        const RScalar overlap = k * 5e-14 * size;
        const RVec3 side(s * 1.3e-14 * size, 0, -s * 0.7e-14 * size);
        const RRigidBody lower(BoxDef(RVec3::Constant(0.5 * size)).At(RVec3(0, 1.5, 0) * size));
        const RRigidBody upper(BoxDef(RVec3::Constant(0.5 * size))
                                   .At(RVec3(0, 2.5, 0) * size - RVec3(0, overlap, 0) + side));
        RContactManifold m;
        ASSERT_TRUE(RCollisionSolver::CheckCollision(lower, upper, RMargin{1e-3 * size}, m))
            << size << " " << k << " " << s;
        EXPECT_NE(m.query.status, RCollisionStatus::kIterationCap) << size << " " << k << " " << s;
        EXPECT_EQ(m.pointCount, 4) << size << " " << k << " " << s;
        EXPECT_LT((m.normal - RVec3::UnitY()).norm(), 1e-12) << size << " " << k << " " << s;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 3 * 41 * 8);

  // The pose that failed, from the 0.1 m stack of envelope_tests (step 536): boxes 2 and 3,
  // tilted by 1e-16 rad, overlapping by 1e-13 m.
  RBodyDef lowerDef =
      BoxDef(RVec3::Constant(0.05))
          .At(RVec3(0x1.549805c8b8ep-53, 0x1.333333333332dp-3, 0x1.b36aefcdcff15p-54))
          .Oriented(RQuat(0x1p+0, 0x1.59c920377b13ep-52, 0x1.f786a92052d11p-99,
                          -0x1.554250a9a6377p-52));
  RBodyDef upperDef =
      BoxDef(RVec3::Constant(0.05))
          .At(RVec3(0x1.b6dd9508c3f29p-53, 0x1.ffffffffffff6p-3, 0x1.7bb155da28e7cp-53))
          .Oriented(RQuat(0x1p+0, 0x1.8702c020187c3p-52, 0x1.a1f7f9b44894dp-99,
                          -0x1.3ee4abbdb4756p-53));
  lowerDef.q_WS.normalize(), upperDef.q_WS.normalize();
  const RRigidBody lower(lowerDef), upper(upperDef);
  RContactManifold m;
  ASSERT_TRUE(RCollisionSolver::CheckCollision(lower, upper, RMargin{1e-3}, m));
  EXPECT_NE(m.query.status, RCollisionStatus::kIterationCap);
  EXPECT_EQ(m.pointCount, 4);
  EXPECT_LT((m.normal - RVec3::UnitY()).norm(), 1e-12);
  EXPECT_LT(std::abs(m.query.separation), 1e-12);
}

TEST(Manifold, BarelyTouchingFacesGetTheFaceNormal) {
  const RQuat tilt(Eigen::AngleAxis<RScalar>(20 * kPi / 180, RVec3::UnitZ()));
  for (RScalar offset : {0.0, 1e6}) {
    const RVec3 o(offset, -offset, offset);
    const RRigidBody slab(
        BoxDef(RVec3(50, 0.5, 50)).At(o + tilt * RVec3(0, -0.5, 0)).Oriented(tilt));
    const RRigidBody box(
        BoxDef(RVec3(0.5, 0.5, 0.5)).At(o + tilt * RVec3(0, 0.5, 0)).Oriented(tilt));
    RContactManifold m;
    ASSERT_TRUE(RCollisionSolver::CheckCollision(slab, box, RMargin{1e-3}, m)) << offset;
    EXPECT_EQ(m.pointCount, 4) << offset;
    EXPECT_LT((m.normal - tilt * RVec3::UnitY()).norm(), 1e-15) << offset;
    EXPECT_LT(std::abs(m.query.separation), 1e-9) << offset;
  }
}
