// Shape casts and overlaps (RQueries::CastShape, CastBody, Overlap*): closed forms (a sphere
// against a sphere, a turned cube falling onto a face, a sphere onto a box's corner and edge),
// random hull pairs against the exact distance by enumeration and FCL, overlap verdicts
// against the separating axis test and FCL on random cases, the tree against the loop over
// every body, and bad input.
//
// The tolerance of a cast is its stopping rule: the shape at the reported fraction is within
// the touching band (1e-9 of the two bounding radii summed) of the body and has not touched
// it before, so the reported travel is short of the true one by at most band / cos(angle
// between the path and the contact normal), plus the rounding of coordinates.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RQueries.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "support/CollisionOracles.h"
#include "support/RandomWorlds.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

const RVec3 kFar(1e7, -2e7, 3e7);
constexpr RScalar kEps = std::numeric_limits<RScalar>::epsilon();

RVec3 Unit(std::mt19937_64& rng) {
  std::normal_distribution<RScalar> n(0, 1);
  const RScalar z = n(rng), y = n(rng), x = n(rng);
  return RVec3(x, y, z).normalized();
}

std::shared_ptr<const RPreparedShape> Sphere(RScalar r) {
  RShape s;
  s = RShape::Sphere(r);
  return PrepareShape(s);
}
std::shared_ptr<const RPreparedShape> Box(const RVec3& half) {
  RShape s;
  s = RShape::Box(half);
  return PrepareShape(s);
}
std::shared_ptr<const RPreparedShape> Hull(const std::vector<RVec3>& points) {
  RShape s;
  s = RShape::Hull(points);
  return PrepareShape(s);
}

bool SameBits(RScalar a, RScalar b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool SameBits(const RVec3& a, const RVec3& b) {
  return SameBits(a.x(), b.x()) && SameBits(a.y(), b.y()) && SameBits(a.z(), b.z());
}

}  // namespace

// |p + f D - c| = R + r: the cast sphere's centre is a ray against a sphere of radius R + r.
TEST(ShapeCast, SphereAgainstSphereAtTheClosedForm) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<RScalar> u(0, 1);
  for (const RVec3& base : {RVec3::Zero().eval(), kFar}) {
    RBodies bodies;
    const RScalar R = 2, r = 0.7;
    const RVec3 c = base + RVec3(1, 2, 3);
    const RBodyHandle h = bodies.Add(SphereDef(R).At(c));
    const auto cast = Sphere(r);
    RQueries queries;
    for (int k = 0; k < 200; ++k) {
      const RScalar b = (R + r) * std::sqrt(u(rng)) * 0.95;  // impact parameter
      const RVec3 d = Unit(rng);
      const RVec3 side = d.cross(Unit(rng)).normalized();
      const RScalar L = R + r + 1 + 20 * u(rng);
      const RVec3 p = c + b * side - L * d;
      const RVec3 D = (L + 5) * d;
      const RVec3 v = p - c;  // exact
      const RScalar s = -v.dot(d), perp2 = (v + s * d).squaredNorm();
      const RScalar travel = s - std::sqrt((R + r) * (R + r) - perp2);
      const auto hit = queries.CastShape(bodies, *cast, p, RQuat::Identity(), D);
      ASSERT_TRUE(hit) << k;
      EXPECT_EQ(hit->body, h);
      const RScalar cosine = std::sqrt((R + r) * (R + r) - perp2) / (R + r);
      const RScalar tol = 1e-9 * (R + r) / cosine + 1e-12 * L + 8 * kEps * base.norm();
      EXPECT_LE(hit->fraction * D.norm(), travel + tol) << k;  // never past the touch
      EXPECT_GE(hit->fraction * D.norm(), travel - tol) << k;
      const RVec3 n = (v + travel * d) / (R + r);
      EXPECT_NEAR((hit->normal_W - n).norm(), 0, 1e-7) << k;
      EXPECT_NEAR((hit->point_W - (c + R * n)).norm(), 0, 1e-7 * R + 8 * kEps * base.norm()) << k;
    }
  }
}

// A cube of edge 1 turned at random, falling (with some sideways drift) onto the top face of a
// large static slab at y = 0: it first touches when its lowest corner reaches y = 0, at
// travel (y0 - sum_j |R_1j| h) along y: one step of conservative advancement, a face.
TEST(ShapeCast, TurnedCubeFallsOntoAFaceAtTheClosedForm) {
  std::mt19937_64 rng(22);
  std::uniform_real_distribution<RScalar> u(-1, 1);
  for (const RVec3& base : {RVec3::Zero().eval(), kFar}) {
    RBodies bodies;
    const RBodyHandle ground = bodies.Add(BoxDef(RVec3(50, 0.5, 50)).Static().At(base + RVec3(0, -0.5, 0)));
    const auto cube = Box(RVec3::Constant(0.5));
    RQueries queries;
    for (int k = 0; k < 100; ++k) {
      const RQuat q = k == 0 ? RQuat::Identity() : RandomRotation(rng);
      const RScalar y0 = 1 + 3 * std::abs(u(rng));
      const RVec3 p = base + RVec3(10 * u(rng), y0, 10 * u(rng));
      const RVec3 D(2 * u(rng), -5, 2 * u(rng));
      const RMat3 R = q.toRotationMatrix();
      const RScalar low = 0.5 * R.row(1).cwiseAbs().sum();  // how far the cube reaches down
      const auto hit = queries.CastShape(bodies, *cube, p, q, D);
      ASSERT_TRUE(hit) << k;
      EXPECT_EQ(hit->body, ground);
      const RScalar expect = (y0 - low) / 5;
      EXPECT_NEAR(hit->fraction, expect, (2e-9 + 8 * kEps * base.norm()) / 5) << k;
      EXPECT_LE(hit->fraction, expect + 8 * kEps * (1 + base.norm()));
      EXPECT_NEAR((hit->normal_W - RVec3::UnitY()).norm(), 0, 1e-12) << k;
      EXPECT_NEAR(hit->point_W.y() - base.y(), 0, 2e-9 + 8 * kEps * base.norm()) << k;
    }
  }
}

// A sphere aimed at a box's corner along the corner's diagonal, and at an edge across it: the
// first touch is the corner (edge) itself, when the centre is r from it.
TEST(ShapeCast, SphereOntoABoxCornerAndEdgeAtTheClosedForm) {
  for (const RVec3& base : {RVec3::Zero().eval(), kFar}) {
    RBodies bodies;
    const RVec3 he(1, 2, 3);
    bodies.Add(BoxDef(he).At(base));
    const RScalar r = 0.25;
    const auto ball = Sphere(r);
    RQueries queries;
    struct Case {
      RVec3 feature, away;  // the feature's point and the direction the sphere comes from
    };
    const Case cases[] = {{he, RVec3(1, 1, 1).normalized()},
                          {RVec3(-1, 2, -3), RVec3(-1, 1, -1).normalized()},
                          {RVec3(1, 2, 0.5), RVec3(1, 1, 0).normalized()},
                          {RVec3(-1, 0.3, 3), RVec3(-1, 0, 1).normalized()}};
    for (const Case& c : cases) {
      const RVec3 start = base + c.feature + 4 * c.away;
      const auto hit = queries.CastShape(bodies, *ball, start, RQuat::Identity(), -8 * c.away);
      ASSERT_TRUE(hit);
      EXPECT_NEAR(hit->fraction * 8, 4 - r, 1e-9 + 8 * kEps * base.norm());
      EXPECT_NEAR((hit->normal_W - c.away).norm(), 0, 1e-7);
      EXPECT_NEAR((hit->point_W - (base + c.feature)).norm(), 0, 1e-7 + 8 * kEps * base.norm());
    }
  }
}

// Random hull pairs against the separating axis test, exact for polytopes (> 0 exactly when
// some axis separates them; when they overlap, minus the exact depth): at the reported
// fraction the pair is not deeper than the band, 1e-8 of the path earlier it is apart, and
// 1e-8 later (unless the path grazes) it overlaps; 1e-3 earlier FCL's distance (its libccd
// solver: its own GJK, GST_INDEP, was off by up to 3 cm here in a clang build) agrees with the
// exact one by enumeration. Where no touch is reported, FCL's collide finds none along the
// path (finely sampled) that the exact test confirms.
TEST(ShapeCast, RandomHullPairsTouchWhereTheExactTestSays) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<RScalar> u(-1, 1);
  int hits = 0, casts = 0;
  for (int k = 0; k < 120; ++k, ++casts) {
    const RVec3 base = k % 2 ? kFar : RVec3::Zero();
    const std::vector<RVec3> pa = RandomCloud(rng, 8 + k % 20, 1.5, k % 3 == 0);
    const std::vector<RVec3> pb = RandomCloud(rng, 6 + k % 13, 0.8, k % 4 == 0);
    const OracleHull ha(pa), hb(pb);
    RBodies bodies;
    const RQuat qa = RandomRotation(rng), qb = RandomRotation(rng);
    const RVec3 xa = base + RVec3(u(rng), u(rng), u(rng));
    bodies.Add(HullDef(pa).At(xa).Oriented(qa));
    const auto cast = Hull(pb);
    // From 6 m away, aimed within 1.5 m of the body's frame origin.
    const RVec3 d = Unit(rng);
    const RVec3 start = xa - 6 * d + 1.2 * RVec3(u(rng), u(rng), u(rng));
    const RVec3 D = (xa + 1.5 * RVec3(u(rng), u(rng), u(rng)) - start) * 1.6;
    RQueries queries;
    const auto hit = queries.CastShape(bodies, *cast, start, qb, D);
    const OraclePose X_WA{xa, qa};
    const RScalar scale = ha.Radius() + hb.Radius();
    const RScalar band = 1e-9 * scale;
    // The pair with B's frame at fraction f, in a frame at the body (offsets exact).
    const RConvexPolyhedron A = ha.Polyhedron().Transformed(qa.toRotationMatrix(), RVec3::Zero());
    auto posedB = [&](RScalar f) {
      return hb.Polyhedron().Transformed(qb.toRotationMatrix(), (start - xa) + f * D);
    };
    auto sat = [&](RScalar f) { return SatSeparation(A, posedB(f), 1e-12, 1e-9).separation; };
    if (hit) {
      ++hits;
      const RScalar f = hit->fraction;
      EXPECT_GE(sat(f), -band - 16 * kEps * base.norm()) << k;
      if (f > 0) {
        EXPECT_GT(sat(f - 1e-8), 0) << k;
        const RScalar early = std::max(RScalar(0), f - 1e-3);
        const OracleDistance fcl =
            FclDistance(ha, X_WA, hb, OraclePose{start + early * D, qb}, FclSolver::kLibccd, 1e-12);
        if (fcl.ok && sat(early) > 1e-6 * scale) {
          EXPECT_NEAR(fcl.distance, BruteForceDistance(A, posedB(early)).distance, 1e-6 * scale) << k;
        }
      }
      if (-D.normalized().dot(hit->normal_W) > 0.05) {
        EXPECT_LT(sat(f + 1e-8), 0) << k;
      }
    } else {
      for (int i = 0; i <= 400; ++i) {
        const RScalar f = i / 400.0;
        const OraclePenetration c =
            FclCollide(ha, X_WA, hb, OraclePose{start + f * D, qb}, FclSolver::kLibccd, 1e-12 * scale);
        if (c.ok && c.overlap) {
          EXPECT_GE(sat(f), -band) << k << " at " << f;
        }
      }
    }
  }
  EXPECT_GT(hits, casts / 4);
  EXPECT_LT(hits, casts);
}

TEST(ShapeCast, OverlapAtTheStartIsFractionZeroAndMovingAwayMisses) {
  RBodies bodies;
  bodies.Add(SphereDef(1).At(RVec3::Zero()));
  const auto ball = Sphere(0.5);
  RQueries queries;
  const auto start = queries.CastShape(bodies, *ball, RVec3(1.2, 0, 0), RQuat::Identity(), RVec3(3, 0, 0));
  ASSERT_TRUE(start);
  EXPECT_EQ(start->fraction, 0);
  EXPECT_NEAR((start->normal_W - RVec3::UnitX()).norm(), 0, 1e-15);  // out along +x
  // Zero translation: the overlap alone.
  EXPECT_TRUE(queries.CastShape(bodies, *ball, RVec3(1.2, 0, 0), RQuat::Identity(), RVec3::Zero()));
  EXPECT_FALSE(queries.CastShape(bodies, *ball, RVec3(1.6, 0, 0), RQuat::Identity(), RVec3::Zero()));
  // Away, past, and short.
  EXPECT_FALSE(queries.CastShape(bodies, *ball, RVec3(2, 0, 0), RQuat::Identity(), RVec3(3, 0, 0)));
  EXPECT_FALSE(queries.CastShape(bodies, *ball, RVec3(-5, 1.6, 0), RQuat::Identity(), RVec3(10, 0, 0)));
  EXPECT_FALSE(queries.CastShape(bodies, *ball, RVec3(-5, 0, 0), RQuat::Identity(), RVec3(3.4, 0, 0)));
  EXPECT_NEAR(queries.CastShape(bodies, *ball, RVec3(-5, 0, 0), RQuat::Identity(), RVec3(3.5, 0, 0))->fraction,
              1, 1e-9);
}

// A missile swept from its launcher: it skips itself, the launcher it ignores, and what its
// mask leaves out, as the pair loop would; it stops at the first body left.
TEST(ShapeCast, CastBodyKeepsThePairLoopsRules) {
  RBodies bodies;
  BodyDef launcher = BoxDef(RVec3(2, 2, 2)).Static().At(RVec3::Zero());
  launcher.id = 1;
  const RBodyHandle hl = bodies.Add(launcher);
  BodyDef missile = SphereDef(0.2).At(RVec3(1, 0, 0));  // inside its launcher
  missile.id = 2, missile.ignore = {1}, missile.mask = ~4u;
  const RBodyHandle hm = bodies.Add(missile);
  BodyDef friendly = BoxDef(RVec3(0.1, 3, 3)).At(RVec3(10, 0, 0));
  friendly.category = 4;
  bodies.Add(friendly);
  const RBodyHandle target = bodies.Add(SphereDef(1).At(RVec3(20, 0, 0)));
  bodies[hl].IgnoreCollisionsWith(2);
  RQueries queries;
  const auto hit = queries.CastBody(bodies, hm, RVec3(40, 0, 0));
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->body, target);
  EXPECT_NEAR(hit->fraction * 40, 20 - 1 - 0.2 - 1, 1e-8);
  // Without the rules (the same shape as a plain cast), the launcher is hit at once.
  EXPECT_EQ(queries.CastShape(bodies, *bodies[hm].PreparedShape(), RVec3(1, 0, 0), RQuat::Identity(),
                              RVec3(40, 0, 0))->body, hl);
  EXPECT_THROW(queries.CastBody(bodies, RBodyHandle{}, RVec3(1, 0, 0)), RHandleError);
}

// ---- overlaps --------------------------------------------------------------------------------

// Random hulls around a query hull: each body's verdict against the separating axis test
// (exact for polytopes: apart if and only if some candidate axis separates them) wherever the
// pair is not within 1e-9 of its size of touching, and against FCL's collide (GST_LIBCCD) and
// libccd's GJK where it is not within 1e-6. (FCL 0.7's own GST_INDEP is not used: it calls two
// of these pairs, 9 and 13 cm deep, apart.)
TEST(Overlap, AgreesWithTheSeparatingAxisTestAndFcl) {
  std::mt19937_64 rng(24);
  std::uniform_real_distribution<RScalar> u(-1, 1);
  int overlapping = 0, pairs = 0, fclCompared = 0;
  for (int world = 0; world < 30; ++world) {
    const RVec3 base = world % 2 ? kFar : RVec3::Zero();
    RBodies bodies;
    std::vector<OracleHull> hulls;
    std::vector<OraclePose> poses;
    for (int i = 0; i < 40; ++i) {
      const std::vector<RVec3> points = RandomCloud(rng, 5 + (i * 7) % 20, 0.3 + 1.2 * std::abs(u(rng)), i % 3 == 0);
      hulls.emplace_back(points);
      poses.push_back({base + 4 * RVec3(u(rng), u(rng), u(rng)), RandomRotation(rng)});
      bodies.Add(HullDef(points).At(poses.back().position_W).Oriented(poses.back().q_WS));
    }
    RQueries queries;
    std::vector<RBodyHandle> found;
    for (int k = 0; k < 10; ++k) {
      const std::vector<RVec3> qp = RandomCloud(rng, 12, 1 + 2 * std::abs(u(rng)), k % 2 == 0);
      const OracleHull qh(qp);
      const OraclePose X{base + 3 * RVec3(u(rng), u(rng), u(rng)), RandomRotation(rng)};
      queries.Overlap(bodies, *Hull(qp), X.position_W, X.q_WS, found);
      EXPECT_TRUE(std::is_sorted(found.begin(), found.end()));
      for (std::size_t i = 0; i < hulls.size(); ++i, ++pairs) {
        const bool ours = std::binary_search(found.begin(), found.end(), bodies.HandleAt(i));
        // In a frame at the query shape: offsets exact.
        const RConvexPolyhedron A = qh.Polyhedron().Transformed(X.q_WS.toRotationMatrix(), RVec3::Zero());
        const RConvexPolyhedron B = hulls[i].Polyhedron().Transformed(
            poses[i].q_WS.toRotationMatrix(), poses[i].position_W - X.position_W);
        const RScalar scale = qh.Radius() + hulls[i].Radius();
        const RScalar sep = SatSeparation(A, B, 1e-12, 1e-9).separation;
        overlapping += sep <= 0;
        if (std::abs(sep) > 1e-9 * scale) {
          EXPECT_EQ(ours, sep < 0) << "world " << world << " query " << k << " body " << i
                                   << ": separation " << sep;
        }
        if (std::abs(sep) > 1e-6 * scale) {
          const OraclePenetration fcl =
              FclCollide(qh, X, hulls[i], poses[i], FclSolver::kLibccd, 1e-12 * scale);
          const int ccd = CcdGJKIntersect(PoseForCcd(qh, X), PoseForCcd(hulls[i], poses[i]),
                                          MakeCcdConfig(scale));
          if (!fcl.ok || ccd < 0) continue;
          ++fclCompared;
          EXPECT_EQ(ours, fcl.overlap) << "world " << world << " query " << k << " body " << i
                                       << ": separation " << sep;
          EXPECT_EQ(ours, ccd == 1) << "world " << world << " query " << k << " body " << i
                                    << ": separation " << sep;
        }
      }
    }
  }
  // Both verdicts are common: the suite does not pass on easy cases alone.
  EXPECT_GT(overlapping, pairs / 20);
  EXPECT_LT(overlapping, pairs / 2);
  EXPECT_GT(fclCompared, pairs * 9 / 10);
}

// The conveniences against closed forms: a sphere overlaps a sphere when the centres are at
// most r1 + r2 apart and a box when the centre's distance to the box (clamped in its frame) is
// at most r; an axis-aligned box overlaps a sphere when the sphere's centre, clamped to the
// box, is within r of it.
TEST(Overlap, SphereAndBoxConveniencesAreExact) {
  std::mt19937_64 rng(25);
  std::uniform_real_distribution<RScalar> u(-1, 1);
  for (const RVec3& base : {RVec3::Zero().eval(), kFar}) {
    RBodies bodies;
    struct Body {
      bool sphere;
      RVec3 x, he;
      RQuat q;
      RScalar r;
    };
    std::vector<Body> list;
    for (int i = 0; i < 200; ++i) {
      Body b{i % 2 == 0, base + 20 * RVec3(u(rng), u(rng), u(rng)), RVec3(0.3 + std::abs(u(rng)), 0.4, 0.8),
             RandomRotation(rng), 0.2 + std::abs(u(rng))};
      list.push_back(b);
      bodies.Add(b.sphere ? SphereDef(b.r).At(b.x) : BoxDef(b.he).At(b.x).Oriented(b.q));
    }
    RQueries queries;
    std::vector<RBodyHandle> found;
    int inside = 0;
    for (int k = 0; k < 100; ++k) {
      const RVec3 c = base + 20 * RVec3(u(rng), u(rng), u(rng));
      const RScalar r = 0.5 + 4 * std::abs(u(rng));
      queries.OverlapSphere(bodies, c, r, found);
      for (std::size_t i = 0; i < list.size(); ++i) {
        const Body& b = list[i];
        RScalar gap;
        if (b.sphere) {
          gap = (c - b.x).norm() - b.r - r;
        } else {
          const RVec3 local = b.q.conjugate() * (c - b.x);
          gap = (local - local.cwiseMax(-b.he).cwiseMin(b.he)).norm() - r;
        }
        if (std::abs(gap) < 1e-8) continue;
        inside += gap < 0;
        EXPECT_EQ(std::binary_search(found.begin(), found.end(), bodies.HandleAt(i)), gap < 0) << k << " " << i;
      }
      const RVec3 lo = c - RVec3(r, 0.5 * r, 2 * r), hi = c + RVec3(r, 0.5 * r, 2 * r);
      queries.OverlapBox(bodies, lo, hi, found);
      for (std::size_t i = 0; i < list.size(); i += 2) {  // the spheres
        const RScalar gap = (list[i].x - list[i].x.cwiseMax(lo).cwiseMin(hi)).norm() - list[i].r;
        if (std::abs(gap) < 1e-8) continue;
        EXPECT_EQ(std::binary_search(found.begin(), found.end(), bodies.HandleAt(i)), gap < 0) << k << " " << i;
      }
    }
    EXPECT_GT(inside, 20);
  }
}

// Casts and overlaps through the tree against the loop over every body, bit for bit, on
// random worlds at 0 and 1e7 m, before and after steps.
TEST(Overlap, TreeAnswersOfCastsAndOverlapsEqualTheLoop) {
  const auto shapes = {Sphere(0.7), Box(RVec3(2, 0.3, 1)),
                       Hull({RVec3(0, 0, 0), RVec3(3, 0, 0), RVec3(0, 2, 0), RVec3(0, 0, 1), RVec3(1, 1, 1)})};
  int castHits = 0, overlaps = 0;
  for (const RVec3& origin : {RVec3::Zero().eval(), kFar}) {
    RBodies bodies;
    for (const RBodyDef& d : RandomWorld(5, origin, 300, 60)) bodies.Add(d);
    RQueries tree, loop(RQueries::RSettings{false});
    RIntegrator integrator;
    std::mt19937_64 rng(26);
    std::uniform_real_distribution<RScalar> u(-1, 1);
    std::vector<RBodyHandle> a, b;
    for (int step = 0; step < 2; ++step) {
      for (int k = 0; k < 150; ++k) {
        for (const auto& shape : shapes) {
          const RVec3 p = origin + 60 * RVec3(u(rng), u(rng), u(rng));
          const RQuat q = RandomRotation(rng);
          const RVec3 D = 40 * RVec3(u(rng), u(rng), u(rng));
          const auto x = tree.CastShape(bodies, *shape, p, q, D), y = loop.CastShape(bodies, *shape, p, q, D);
          ASSERT_EQ(x.has_value(), y.has_value()) << k;
          if (x) {
            ++castHits;
            EXPECT_EQ(x->body, y->body);
            EXPECT_TRUE(SameBits(x->fraction, y->fraction) && SameBits(x->point_W, y->point_W) &&
                        SameBits(x->normal_W, y->normal_W));
          }
          tree.Overlap(bodies, *shape, p, q, a), loop.Overlap(bodies, *shape, p, q, b);
          EXPECT_EQ(a, b);
          overlaps += !a.empty();
          tree.OverlapSphere(bodies, p, 3, a), loop.OverlapSphere(bodies, p, 3, b);
          EXPECT_EQ(a, b);
          tree.OverlapBox(bodies, p, p + RVec3(4, 2, 3), a), loop.OverlapBox(bodies, p, p + RVec3(4, 2, 3), b);
          EXPECT_EQ(a, b);
        }
      }
      integrator.Update(bodies, 1.0 / 60);
    }
  }
  EXPECT_GT(castHits, 200);
  EXPECT_GT(overlaps, 50);
}

TEST(Overlap, BadShapesPosesAndPathsAreRefused) {
  RBodies bodies;
  bodies.Add(SphereDef(1));
  RQueries queries;
  const auto ball = Sphere(1);
  const RScalar nan = std::nan("");
  std::vector<RBodyHandle> out;
  auto field = [](auto&& f) {
    try {
      f();
    } catch (const RQueryError& e) {
      return e.Field();
    }
    return std::string("(accepted)");
  };
  const RQuat id = RQuat::Identity();
  EXPECT_EQ(field([&] { queries.CastShape(bodies, *ball, RVec3(nan, 0, 0), id, RVec3::UnitX()); }), "position");
  EXPECT_EQ(field([&] { queries.CastShape(bodies, *ball, RVec3::Zero(), RQuat(0, 0, 0, 0), RVec3::UnitX()); }),
            "orientation");
  EXPECT_EQ(field([&] { queries.CastShape(bodies, *ball, RVec3::Zero(), id, RVec3(0, nan, 0)); }), "translation");
  EXPECT_EQ(field([&] { queries.Overlap(bodies, *ball, RVec3(0, 0, 1e16), id, out); }), "position");
  EXPECT_EQ(field([&] { queries.OverlapSphere(bodies, RVec3::Zero(), 0, out); }), "radius");
  EXPECT_EQ(field([&] { queries.OverlapSphere(bodies, RVec3::Zero(), nan, out); }), "radius");
  EXPECT_EQ(field([&] { queries.OverlapBox(bodies, RVec3::Zero(), RVec3(1, 0, 1), out); }), "max");
  EXPECT_EQ(field([&] { queries.OverlapBox(bodies, RVec3::Zero(), RVec3(1, -1, 1), out); }), "max");
  EXPECT_EQ(field([&] { queries.OverlapBox(bodies, RVec3(nan, 0, 0), RVec3(1, 1, 1), out); }), "min");
}
