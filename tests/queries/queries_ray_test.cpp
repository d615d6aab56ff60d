// Ray casts (RQueries::CastRay, CastRayAll, RayCastShape) against closed forms: the distance,
// point and normal where a ray meets a sphere, a box face and an octahedron face, at the origin
// and 1e7 m from it; random hulls against their own face planes; rays that start inside;
// ordering, masks and callbacks; the tree's answers against the loop over every body, bit for
// bit, on random worlds; and bad rays.
#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RQueries.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "support/CollisionOracles.h"
#include "support/RandomWorlds.h"
#include "support/TestBodies.h"

using namespace REngine;
using namespace REngine::test;

namespace {

const RVec3 kFar(1e7, -2e7, 3e7);  // 1e7 m out: a float would resolve about 1 m here

RVec3 RandomUnit(std::mt19937_64& rng) {
  std::normal_distribution<RScalar> n(0, 1);
  const RScalar z = n(rng), y = n(rng), x = n(rng);
  return RVec3(x, y, z).normalized();
}

RQuat DrawRotation(std::mt19937_64& rng) {
  std::normal_distribution<RScalar> n(0, 1);
  const RScalar z = n(rng), y = n(rng), x = n(rng), w = n(rng);
  return RQuat(w, x, y, z).normalized();
}

// A unit vector at an angle to `n` whose cosine is at least `minCos` (into the face: -n side).
RVec3 Into(const RVec3& n, std::mt19937_64& rng, RScalar minCos) {
  for (;;) {
    const RVec3 d = RandomUnit(rng);
    if (-d.dot(n) >= minCos) return d;
  }
}

// The tolerance of the closed-form checks: 1e-9 of the ray's scale (how far it travels plus
// the body's size), the bound the queries promise. The rounding of the inputs themselves is
// below it: a world coordinate of 3e7 m is held to 3.7e-9 m, moving the entry by that over
// the cosine.
RScalar Tol(RScalar distance, RScalar size) { return 1e-9 * (distance + size); }

// World points are held to the rounding of their coordinates (3.7e-9 m at 3e7 m) on top.
RScalar PointTol(RScalar distance, RScalar size, const RVec3& at) {
  return Tol(distance, size) + 4 * std::numeric_limits<RScalar>::epsilon() * at.cwiseAbs().maxCoeff();
}

// Where the ray o + t d (world, as rounded) crosses the plane n_S . (y - p_S) = 0 of a shape at
// (x, q), in long double from the exact offset o - x: the closed form, from the inputs as
// they are.
long double PlaneCrossing(const RVec3& n_S, const RVec3& p_S, const RQuat& q, const RVec3& x,
                          const RVec3& o, const RVec3& d) {
  const RVec3 v = o - x;  // exact: two doubles within a factor 2 of each other
  const Eigen::Matrix<long double, 3, 3> R = q.toRotationMatrix().cast<long double>();
  const Eigen::Matrix<long double, 3, 1> n = R * n_S.cast<long double>();
  const Eigen::Matrix<long double, 3, 1> p = R * p_S.cast<long double>();
  return n.dot(p - v.cast<long double>()) / n.dot(d.cast<long double>());
}

bool SameBits(RScalar a, RScalar b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool SameBits(const RVec3& a, const RVec3& b) {
  return SameBits(a.x(), b.x()) && SameBits(a.y(), b.y()) && SameBits(a.z(), b.z());
}

}  // namespace

TEST(Rays, SphereHitsAtTheClosedForm) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<RScalar> u(0, 1);
  for (const RVec3& base : {RVec3::Zero().eval(), kFar}) {
    RBodies bodies;
    const RScalar r = 2.5;
    const RVec3 c = base + RVec3(3, -1, 2);
    const RBodyHandle h = bodies.Add(SphereDef(r).At(c).Oriented(DrawRotation(rng)));
    RQueries queries;
    for (int k = 0; k < 200; ++k) {
      // In the frame of the ray: it passes at impact parameter b from the centre, starting L
      // before the closest approach (L up to 1e4 m: a far origin).
      const RScalar b = r * std::sqrt(u(rng)) * 0.999;
      const RScalar L = r + (k % 4 == 0 ? 1e4 * u(rng) : 20 * u(rng));
      const RVec3 d = RandomUnit(rng);
      RVec3 side = d.cross(RandomUnit(rng)).normalized();
      const RVec3 origin = c + b * side - L * d;
      // Closed form from the origin as rounded (its offset from the centre is exact).
      const RVec3 v = origin - c;
      const long double s = -(static_cast<long double>(v.x()) * d.x() +
                              static_cast<long double>(v.y()) * d.y() +
                              static_cast<long double>(v.z()) * d.z());
      const long double px = v.x() + s * d.x(), py = v.y() + s * d.y(), pz = v.z() + s * d.z();
      const long double t = s - std::sqrt(static_cast<long double>(r) * r - (px * px + py * py + pz * pz));
      const auto hit = queries.CastRay(bodies, {origin, 3 * d, 2 * L});
      ASSERT_TRUE(hit) << k;
      EXPECT_EQ(hit->body, h);
      EXPECT_NEAR(hit->distance, static_cast<RScalar>(t), Tol(L, r)) << k;
      const RVec3 local = v + static_cast<RScalar>(t) * d;  // the hit point from the centre
      EXPECT_NEAR((hit->point_W - c - local).norm(), 0, PointTol(L, r, c)) << k;
      EXPECT_NEAR((hit->normal_W - local / r).norm(), 0, 1e-9) << k;
      EXPECT_NEAR(hit->normal_W.norm(), 1, 1e-15);
      // Passing just outside misses.
      EXPECT_FALSE(queries.CastRay(bodies, {c + r * 1.0001 * side - L * d, d, 2 * L})) << k;
    }
  }
}

// A box's faces, and a hull's: an octahedron |x| + |y| + |z| <= a, whose faces have normals
// (+-1, +-1, +-1)/sqrt(3). A hit point is drawn on a face, the ray comes into it from L away:
// distance L, that point, that face's normal, exactly (up to the rounding of the inputs).
TEST(Rays, BoxAndOctahedronFacesAtTheClosedForm) {
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<RScalar> u(-1, 1);
  const RVec3 he(1.5, 0.4, 2.0);
  const RScalar a = 1.7;
  for (const RVec3& base : {RVec3::Zero().eval(), kFar}) {
    RBodies bodies;
    const RQuat qBox = DrawRotation(rng), qOct = DrawRotation(rng);
    const RVec3 xBox = base + RVec3(-4, 1, 0.5), xOct = base + RVec3(5, -2, 1);
    // Categories 1 and 2, so that each ray sees only the body it is aimed at.
    const RBodyHandle box = bodies.Add(BoxDef(he).At(xBox).Oriented(qBox));
    BodyDef octDef = HullDef({RVec3(a, 0, 0), RVec3(-a, 0, 0), RVec3(0, a, 0), RVec3(0, -a, 0),
                              RVec3(0, 0, a), RVec3(0, 0, -a)});
    octDef.At(xOct).Oriented(qOct);
    octDef.category = 2;
    const RBodyHandle oct = bodies.Add(octDef);
    RQueries queries;
    for (int k = 0; k < 300; ++k) {
      RVec3 p_S, n_S;
      RVec3 x = xBox;
      RQuat q = qBox;
      RBodyHandle expect = box;
      if (k % 2 == 0) {  // a box face: axis k/2 % 3, either side
        const int axis = (k / 2) % 3;
        const RScalar sign = (k / 6) % 2 ? 1 : -1;
        p_S = RVec3(u(rng) * he.x(), u(rng) * he.y(), u(rng) * he.z()) * 0.999;
        p_S[axis] = sign * he[axis];
        n_S = RVec3::Zero();
        n_S[axis] = sign;
      } else {  // an octahedron face: signs from k, a point inside it (barycentric weights)
        const RVec3 s((k & 2) ? 1 : -1, (k & 4) ? 1 : -1, (k & 8) ? 1 : -1);
        RVec3 w(0.05 + std::abs(u(rng)), 0.05 + std::abs(u(rng)), 0.05 + std::abs(u(rng)));
        w /= w.sum();
        p_S = a * s.cwiseProduct(w);
        n_S = s / std::sqrt(RScalar(3));
        x = xOct, q = qOct, expect = oct;
      }
      const RVec3 n_W = q * n_S;
      const RVec3 p_W = x + q * p_S;
      const RVec3 d = Into(n_W, rng, 0.2);
      const RScalar L = 0.5 + 30 * std::abs(u(rng));
      const RVec3 o = p_W - L * d;
      const RScalar t = static_cast<RScalar>(PlaneCrossing(n_S, p_S, q, x, o, d));
      EXPECT_NEAR(t, L, 1e-7);  // the plane is where it was meant to be, to the inputs' rounding
      RQueryFilter only;
      only.mask = expect == box ? 1u : 2u;
      const auto hit = queries.CastRay(bodies, {o, d, 100}, only);
      ASSERT_TRUE(hit) << k;
      EXPECT_EQ(hit->body, expect) << k;
      EXPECT_NEAR(hit->distance, t, Tol(L, 4)) << k;
      EXPECT_NEAR((hit->point_W - (o + t * d)).norm(), 0, PointTol(L, 4, x)) << k;
      EXPECT_NEAR((hit->normal_W - n_W).norm(), 0, 1e-12) << k;
    }
  }
}

// Random hulls against the definition of a ray's entry: the point at the reported distance is
// on the surface (the largest signed distance to the face planes of the hull, built from the
// scene's points in the shape frame, is 0), a point 1e-7 of the size before it is outside, and
// the normal is the plane that is largest there.
TEST(Rays, RandomHullsAreEnteredWhereTheirSurfaceIs) {
  std::mt19937_64 rng(16);
  std::uniform_real_distribution<RScalar> u(-1, 1);
  int hits = 0, rays = 0;
  for (int world = 0; world < 40; ++world) {
    std::vector<RVec3> points;
    for (int i = 0; i < 8 + world % 24; ++i) points.push_back(RVec3(3 * u(rng), u(rng), 2 * u(rng)));
    const OracleHull hull(points);
    const RVec3 base = world % 2 ? kFar : RVec3::Zero();
    RBodies bodies;
    const RQuat q = DrawRotation(rng);
    const RVec3 x = base + RVec3(u(rng), u(rng), u(rng));
    bodies.Add(HullDef(points).At(x).Oriented(q));
    RQueries queries;
    for (int k = 0; k < 50; ++k, ++rays) {
      const RVec3 target = x + RVec3(2 * u(rng), u(rng), 1.5 * u(rng));
      const RVec3 d = RandomUnit(rng);
      const RVec3 origin = target - (6 + 10 * std::abs(u(rng))) * d;
      const auto hit = queries.CastRay(bodies, {origin, d, 100});
      // Along the ray in the shape frame (exact offsets from x, as the engine does).
      const RVec3 o_S = q.conjugate() * (origin - x), d_S = q.conjugate() * d;
      const RScalar size = hull.Radius();
      if (!hit) {
        // A miss: no point of the segment is inside (sampled finely through the hull's reach).
        for (int i = 0; i <= 4000; ++i) {
          const RScalar t = 100.0 * i / 4000;
          EXPECT_GT(SurfaceOffset(hull.Polyhedron(), o_S + t * d_S), -1e-9 * size) << world << " " << k;
        }
        continue;
      }
      ++hits;
      const RVec3 at = o_S + hit->distance * d_S;
      EXPECT_NEAR(SurfaceOffset(hull.Polyhedron(), at), 0, 1e-9 * (size + hit->distance));
      EXPECT_GT(SurfaceOffset(hull.Polyhedron(), o_S + (hit->distance - 1e-7 * size) * d_S), 0);
      RScalar best = -1e300;
      RVec3 n_S = RVec3::Zero();
      for (const RFace& f : hull.Polyhedron().Faces()) {
        if (f.plane.SignedDistance(at) > best) best = f.plane.SignedDistance(at), n_S = f.plane.normal;
      }
      // At an edge two planes tie and either normal is right; random rays meet faces.
      EXPECT_NEAR((hit->normal_W - q * n_S).norm(), 0, 1e-9) << world << " " << k;
    }
  }
  // Both outcomes are exercised, not only easy misses.
  EXPECT_GT(hits, rays / 4);
  EXPECT_LT(hits, rays);
}

TEST(Rays, StartingInsideHitsAtZeroFacingTheRay) {
  for (const RVec3& base : {RVec3::Zero().eval(), kFar}) {
    RBodies bodies;
    const RBodyHandle sphere = bodies.Add(SphereDef(1).At(base + RVec3(-5, 0, 0)));
    const RQuat q = RQuat(0.9, 0.1, 0.3, 0.2).normalized();
    const RBodyHandle box = bodies.Add(BoxDef(RVec3(1, 2, 3)).At(base).Oriented(q));
    const RBodyHandle hull = bodies.Add(
        HullDef({RVec3(0, 0, 0), RVec3(2, 0, 0), RVec3(0, 2, 0), RVec3(0, 0, 2)}).At(base + RVec3(5, 0, 0)));
    RQueries queries;
    const RVec3 d = RVec3(1, -2, 0.5).normalized();
    struct Case {
      RVec3 origin;
      RBodyHandle body;
    };
    for (const Case& c : {Case{base + RVec3(-5.3, 0.2, 0.1), sphere}, Case{base + q * RVec3(0.5, -1, 2), box},
                          Case{base + RVec3(5.3, 0.3, 0.2), hull}}) {
      const auto hit = queries.CastRay(bodies, {c.origin, 7 * d, 0});  // even at max distance 0
      ASSERT_TRUE(hit);
      EXPECT_EQ(hit->body, c.body);
      EXPECT_EQ(hit->distance, 0);
      EXPECT_EQ(hit->point_W, c.origin);
      EXPECT_NEAR((hit->normal_W + d).norm(), 0, 1e-15);
      std::vector<RRayHit> all;
      queries.CastRayAll(bodies, {c.origin, d, 1e9}, all);
      ASSERT_FALSE(all.empty());
      EXPECT_EQ(all[0].body, c.body);
      EXPECT_EQ(all[0].distance, 0);
    }
  }
}

TEST(Rays, MaxDistanceIsClosedAndMissesMiss) {
  RBodies bodies;
  bodies.Add(BoxDef(RVec3(1, 1, 1)).At(RVec3(10, 0, 0)));  // its -x face at x = 9
  RQueries queries;
  EXPECT_TRUE(queries.CastRay(bodies, {RVec3::Zero(), RVec3::UnitX(), 9}));
  EXPECT_FALSE(queries.CastRay(bodies, {RVec3::Zero(), RVec3::UnitX(), std::nextafter(9.0, 0.0)}));
  EXPECT_FALSE(queries.CastRay(bodies, {RVec3::Zero(), -RVec3::UnitX()}));  // away
  // Parallel to a face, just outside it and just inside its plane.
  EXPECT_FALSE(queries.CastRay(bodies, {RVec3(0, 1.000001, 0), RVec3::UnitX()}));
  const auto inside = queries.CastRay(bodies, {RVec3(0, 0.999999, 0), RVec3::UnitX()});
  ASSERT_TRUE(inside);
  EXPECT_EQ(inside->distance, 9);
  EXPECT_EQ(inside->normal_W, -RVec3::UnitX());
  RBodies empty;
  EXPECT_FALSE(queries.CastRay(empty, {RVec3::Zero(), RVec3::UnitX()}));
}

TEST(Rays, AllHitsComeNearestFirstTiesByHandle) {
  RBodies bodies;
  std::vector<RBodyHandle> order;
  // Spheres along x at 20, 4, 12, 8 (radius 1); two equal ones at 16; one off the line.
  for (RScalar x : {20.0, 4.0, 12.0, 8.0}) order.push_back(bodies.Add(SphereDef(1).At(RVec3(x, 0, 0))));
  const RBodyHandle twinA = bodies.Add(SphereDef(1).At(RVec3(16, 0, 0)));
  const RBodyHandle twinB = bodies.Add(SphereDef(1).At(RVec3(16, 0, 0)));
  bodies.Add(SphereDef(1).At(RVec3(10, 3, 0)));
  RQueries queries;
  std::vector<RRayHit> hits;
  queries.CastRayAll(bodies, {RVec3::Zero(), RVec3::UnitX(), 30}, hits);
  ASSERT_EQ(hits.size(), 6u);
  const std::vector<RBodyHandle> expect = {order[1], order[3], order[2], twinA < twinB ? twinA : twinB,
                                           twinA < twinB ? twinB : twinA, order[0]};
  const std::vector<RScalar> distances = {3, 7, 11, 15, 15, 19};
  for (std::size_t i = 0; i < hits.size(); ++i) {
    EXPECT_EQ(hits[i].body, expect[i]) << i;
    EXPECT_EQ(hits[i].distance, distances[i]) << i;
    EXPECT_EQ(hits[i].normal_W, -RVec3::UnitX()) << i;
  }
  // The nearest is the first of them; among the twins (a ray starting past the others) the
  // lower handle wins.
  EXPECT_EQ(queries.CastRay(bodies, {RVec3::Zero(), RVec3::UnitX(), 30})->body, order[1]);
  EXPECT_EQ(queries.CastRay(bodies, {RVec3(13.5, 0, 0), RVec3::UnitX(), 30})->body, expect[3]);
  // A shorter ray stops short.
  queries.CastRayAll(bodies, {RVec3::Zero(), RVec3::UnitX(), 11}, hits);
  EXPECT_EQ(hits.size(), 3u);
}

TEST(Rays, MaskAndCallbackSkipBodiesAndRevealWhatIsBehind) {
  RBodies bodies;
  BodyDef shield = BoxDef(RVec3(0.1, 5, 5)).At(RVec3(5, 0, 0));
  shield.category = 4;
  const RBodyHandle front = bodies.Add(shield);
  const RBodyHandle back = bodies.Add(BoxDef(RVec3(1, 1, 1)).At(RVec3(10, 0, 0)));
  RQueries queries;
  const RRay ray{RVec3::Zero(), RVec3::UnitX(), 100};
  EXPECT_EQ(queries.CastRay(bodies, ray)->body, front);
  RQueryFilter noShields;
  noShields.mask = ~4u;
  const auto behind = queries.CastRay(bodies, ray, noShields);
  ASSERT_TRUE(behind);
  EXPECT_EQ(behind->body, back);
  EXPECT_EQ(behind->distance, 9);
  RQueryFilter onlyShields;
  onlyShields.mask = 4;
  std::vector<RRayHit> hits;
  queries.CastRayAll(bodies, ray, hits, onlyShields);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0].body, front);
  // The callback: asked with the handle and body, only for bodies the ray hits.
  struct Seen {
    RBodyHandle reject;
    std::vector<RBodyHandle> asked;
  } seen{front, {}};
  RQueryFilter callback;
  callback.user = &seen;
  callback.callback = [](RBodyHandle h, const RRigidBody& b, void* user) {
    auto* s = static_cast<Seen*>(user);
    s->asked.push_back(h);
    EXPECT_EQ(b.Category(), h == s->reject ? 4u : 1u);
    return h != s->reject;
  };
  bodies.Add(SphereDef(1).At(RVec3(0, 50, 0)));  // never hit: never asked
  EXPECT_EQ(queries.CastRay(bodies, ray, callback)->body, back);
  std::sort(seen.asked.begin(), seen.asked.end());
  EXPECT_EQ(seen.asked, (std::vector<RBodyHandle>{front, back}));
  queries.CastRayAll(bodies, ray, hits, callback);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0].body, back);
}

// The tree against the loop over every body (RSettings::useTree = false): the same hit,
// bit for bit, for nearest and all hits, on random worlds (1 cm to 100 m bodies, spheres, boxes
// and hulls, some static, some asleep) at the origin and 1e7 m out, before and after steps.
TEST(Rays, TreeAnswersEqualTheLoopOverEveryBody) {
  std::uint64_t hits = 0, rays = 0;
  for (const RVec3& origin : {RVec3::Zero().eval(), kFar}) {
    for (std::uint64_t seed : {1u, 2u, 3u}) {
      RBodies bodies;
      for (const RBodyDef& d : RandomWorld(seed, origin, 300, 60)) bodies.Add(d);
      RQueries tree, loop(RQueries::RSettings{false});
      RIntegrator integrator;
      std::mt19937_64 rng(seed * 7);
      std::uniform_real_distribution<RScalar> u(-1, 1);
      std::vector<RRayHit> all, allRef;
      for (int step = 0; step < 3; ++step) {
        for (int k = 0; k < 400; ++k, ++rays) {
          RRay ray;
          ray.origin_W = origin + 70 * RVec3(u(rng), u(rng), u(rng));
          // Half aimed at a body's centre, half anywhere.
          const RRigidBody& target = bodies.At(static_cast<std::size_t>(std::abs(u(rng)) * static_cast<RScalar>(bodies.Size() - 1)));
          ray.direction_W = k % 2 ? RVec3(target.Position_W() - ray.origin_W) : RandomUnit(rng);
          ray.maxDistance = k % 3 == 0 ? std::numeric_limits<RScalar>::infinity() : 200 * std::abs(u(rng));
          const auto a = tree.CastRay(bodies, ray), b = loop.CastRay(bodies, ray);
          ASSERT_EQ(a.has_value(), b.has_value()) << seed << " " << step << " " << k;
          if (a) {
            ++hits;
            EXPECT_EQ(a->body, b->body);
            EXPECT_TRUE(SameBits(a->distance, b->distance) && SameBits(a->point_W, b->point_W) &&
                        SameBits(a->normal_W, b->normal_W));
          }
          tree.CastRayAll(bodies, ray, all), loop.CastRayAll(bodies, ray, allRef);
          ASSERT_EQ(all.size(), allRef.size());
          for (std::size_t i = 0; i < all.size(); ++i) {
            EXPECT_EQ(all[i].body, allRef[i].body);
            EXPECT_TRUE(SameBits(all[i].distance, allRef[i].distance));
          }
        }
        integrator.Update(bodies, 1.0 / 60);
      }
      // Built once, then refitted after each step (or built again where refits degraded it).
      EXPECT_EQ(tree.TreeBuilds() + tree.TreeRefits(), 3u);
      EXPECT_EQ(loop.TreeBuilds(), 0u);
    }
  }
  EXPECT_GT(hits, rays / 4);
  EXPECT_LT(hits, rays);
}

// The tree follows the bodies without being told: steps, a teleport, adds, removes, disables.
TEST(Rays, TreeFollowsTheBodiesBetweenQueries) {
  RBodies bodies;
  const RBodyHandle a = bodies.Add(SphereDef(1).At(RVec3(10, 0, 0)).Moving(RVec3(0, 30, 0)));
  RQueries queries;
  const RRay ray{RVec3::Zero(), RVec3::UnitX(), 100};
  EXPECT_EQ(queries.CastRay(bodies, ray)->body, a);
  EXPECT_EQ(queries.TreeBuilds(), 1u);
  EXPECT_EQ(queries.CastRay(bodies, ray)->body, a);  // nothing changed: nothing redone
  EXPECT_EQ(queries.TreeBuilds() + queries.TreeRefits(), 1u);
  RIntegrator integrator;
  integrator.Update(bodies, 1.0 / 60);  // 0.5 m up: the ray passes 0.5 m from the centre
  EXPECT_NEAR(queries.CastRay(bodies, ray)->distance, 10 - std::sqrt(RScalar(0.75)), 1e-12);
  EXPECT_EQ(queries.TreeRefits(), 1u);
  integrator.Update(bodies, 1.0 / 60);
  integrator.Update(bodies, 1.0 / 60);  // 1.5 m up: missed
  EXPECT_FALSE(queries.CastRay(bodies, ray));
  bodies[a].SetShapePose(RVec3(20, 0, 0), RQuat::Identity());
  EXPECT_EQ(queries.CastRay(bodies, ray)->distance, 19);
  const RBodyHandle b = bodies.Add(BoxDef(RVec3(1, 1, 1)).At(RVec3(5, 0, 0)));
  EXPECT_EQ(queries.CastRay(bodies, ray)->body, b);
  bodies.Disable(b);
  EXPECT_EQ(queries.CastRay(bodies, ray)->body, a);
  bodies.Enable(b);
  EXPECT_EQ(queries.CastRay(bodies, ray)->body, b);
  bodies.Remove(b);
  EXPECT_EQ(queries.CastRay(bodies, ray)->body, a);
  // Another container (a copy), asked through the same object: its own bodies.
  RBodies copy = bodies;
  copy[a].SetShapePose(RVec3(30, 0, 0), RQuat::Identity());
  EXPECT_EQ(queries.CastRay(copy, ray)->distance, 29);
  EXPECT_EQ(queries.CastRay(bodies, ray)->distance, 19);
}

TEST(Rays, BadRaysAreRefusedNamingTheArgument) {
  RBodies bodies;
  bodies.Add(SphereDef(1));
  RQueries queries;
  const RScalar nan = std::nan(""), inf = std::numeric_limits<RScalar>::infinity();
  struct Case {
    RRay ray;
    const char* field;
  };
  const Case cases[] = {
      {{RVec3(nan, 0, 0), RVec3::UnitX(), 1}, "ray.origin"},
      {{RVec3(0, inf, 0), RVec3::UnitX(), 1}, "ray.origin"},
      {{RVec3(0, 0, 2e15), RVec3::UnitX(), 1}, "ray.origin"},
      {{RVec3::Zero(), RVec3::Zero(), 1}, "ray.direction"},
      {{RVec3::Zero(), RVec3(0, nan, 0), 1}, "ray.direction"},
      {{RVec3::Zero(), RVec3(inf, 0, 0), 1}, "ray.direction"},
      {{RVec3::Zero(), RVec3::UnitX(), -1}, "ray.max_distance"},
      {{RVec3::Zero(), RVec3::UnitX(), nan}, "ray.max_distance"},
  };
  std::vector<RRayHit> hits;
  for (const Case& c : cases) {
    try {
      queries.CastRay(bodies, c.ray);
      ADD_FAILURE() << c.field << ": accepted";
    } catch (const RQueryError& e) {
      EXPECT_EQ(e.Field(), c.field);
      EXPECT_EQ(std::string(e.what()).rfind(std::string(c.field) + ": ", 0), 0u) << e.what();
    }
    EXPECT_THROW(queries.CastRayAll(bodies, c.ray, hits), RQueryError);
  }
  // Lengths that under- or overflow when squared are still directions.
  EXPECT_EQ(queries.CastRay(bodies, {RVec3(-5, 0, 0), RVec3(1e-300, 0, 0), 10})->distance, 4);
  EXPECT_EQ(queries.CastRay(bodies, {RVec3(-5, 0, 0), RVec3(1e300, 0, 0), 10})->distance, 4);
  EXPECT_NEAR(queries.CastRay(bodies, {RVec3(-5, -5, 0), RVec3(1e300, 1e300, 0), 10})->distance,
              5 * std::sqrt(RScalar(2)) - 1, 1e-14);
}

// A body the game assigns over another in its place (same handle, same pose, another
// shape) is seen with its new shape: the queries keep no pointer to the old one.
TEST(Rays, ABodyReplacedInPlaceIsSeenWithItsNewShape) {
  RBodies bodies;
  const RBodyHandle h = bodies.Add(BoxDef(RVec3::Constant(0.5)).Static());
  RQueries queries;
  const RRay ray{RVec3(-10, 0, 0), RVec3::UnitX(), 100};
  EXPECT_EQ(queries.CastRay(bodies, ray)->distance, 9.5);
  bodies[h] = RRigidBody(BoxDef(RVec3::Constant(2)).Static());  // the old shape is freed
  EXPECT_EQ(queries.CastRay(bodies, ray)->distance, 8);
}
