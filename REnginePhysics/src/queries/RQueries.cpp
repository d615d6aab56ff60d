// Ray casts, shape casts and overlaps against the bodies (RQueries.h): the checks at the
// door, the tree (or the loop over every body) choosing candidates, and the choice among
// their answers. The narrow phases are RRayCast.cpp and RShapeCast.cpp; the tree's upkeep
// is RQueryState.cpp.
#include <REnginePhysics/RQueries.h>
#include <REnginePhysics/RLimits.h>

#include <REngineMath/RQuaternion.h>

#include "queries/RQueryState.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

namespace {


void CheckPoint(const RVec3& p, const char* field) {
  if (!(AllFinite(p) && p.cwiseAbs().maxCoeff() <= kMaxPosition)) {
    throw RQueryError(field, "must be finite and within 1e15 m of the origin");
  }
}

// The unit direction of a ray, refused when it has none. Scaled before normalising, so
// that neither 1e-320 nor 1e300 loses it to underflow or overflow.
RVec3 UnitDirection(const RRay& ray) {
  CheckPoint(ray.origin_W, "ray.origin");
  if (!AllFinite(ray.direction_W)) throw RQueryError("ray.direction", "must be finite");
  const RScalar scale = ray.direction_W.cwiseAbs().maxCoeff();
  if (!(scale > 0)) throw RQueryError("ray.direction", "must have a non-zero length");
  if (std::isnan(ray.maxDistance) || ray.maxDistance < 0) {
    throw RQueryError("ray.max_distance", "must be >= 0 (infinity allowed)");
  }
  const RVec3 d = ray.direction_W / scale;
  return d / d.norm();
}

// How far past the best answer so far the tree still looks: 1e-9 of it. The tree's slab
// tests round in world coordinates, the narrow phase in the body's; the padding of the
// boxes covers the rounding of coordinates, this the rounding of the distance along the
// segment, so the tree never skips a body whose answer would tie with or beat the best.
RScalar Slack(RScalar t) { return t + RScalar(1e-9) * t; }

// A cast or overlap shape posed in the world: its body frame B (the prepared shape's), as
// RRigidBody::SetShapePose computes it from the shape frame's pose.
struct Posed {
  RConvexShape shape;
  RMat3 R_WB;
  RVec3 x_W;
  RLocalBox local;
};

Posed Pose(const RPreparedShape& prepared, const RVec3& position_W, const RQuat& q) {
  CheckPoint(position_W, "position");
  const std::optional<RQuat> q_WS = QuatNormalized(q);
  if (!q_WS) throw RQueryError("orientation", "must be a finite quaternion of non-zero length");
  RQuat q_WB = *q_WS * prepared.q_BS.conjugate();
  q_WB.normalize();
  Posed p;
  p.shape = ConvexShapeOf(prepared);
  p.R_WB = q_WB.toRotationMatrix();
  p.x_W = position_W - q_WB * prepared.p_BS;
  p.local = LocalBoxOf(p.shape);
  return p;
}

// The pose of the posed shape in a body's frame: the difference of centres first, exact
// for two neighbours far from the origin (as RelativePose in the narrow phase).
RRelativePose InBody(const RQueryProxy& body, const Posed& s) {
  RRelativePose X;
  X.R_AB = body.R_WB.transpose() * s.R_WB;
  X.t_AB = body.R_WB.transpose() * (s.x_W - body.x_W);
  return X;
}

bool Accepts(const RQueryFilter& f, const RBodies& bodies, std::uint32_t i, RBodyHandle h) {
  return !f.callback || f.callback(h, bodies.At(i), f.user);
}

bool Before(RScalar t, RBodyHandle h, RScalar bestT, RBodyHandle bestH) {
  return t < bestT || (t == bestT && h < bestH);
}

}  // namespace

RQueries::RQueries() : m_s(std::make_unique<RQueryState>()) {}
RQueries::RQueries(const RSettings& settings) : RQueries() { m_settings = settings; }
RQueries::~RQueries() = default;
RQueries::RQueries(const RQueries& other)
    : m_settings(other.m_settings), m_s(std::make_unique<RQueryState>()) {}
RQueries& RQueries::operator=(const RQueries& other) {
  if (this != &other) m_settings = other.m_settings, m_s = std::make_unique<RQueryState>();
  return *this;
}
RQueries::RQueries(RQueries&&) noexcept = default;
RQueries& RQueries::operator=(RQueries&&) noexcept = default;
std::uint64_t RQueries::TreeBuilds() const { return m_s->builds; }
std::uint64_t RQueries::TreeRefits() const { return m_s->refits; }

// ---- rays ----------------------------------------------------------------------------------

namespace {

// The ray in the body's frame (about its centre of mass: exact for a body far from the
// origin), tested, and the hit taken back to the world.
bool RayBody(const RQueryProxy& p, const RVec3& o_W, const RVec3& d_W, RScalar limit,
             RRayHit& hit) {
  const RVec3 o_B = p.R_WB.transpose() * (o_W - p.x_W);
  const RVec3 d_B = p.R_WB.transpose() * d_W;
  RShapeRayHit h;
  if (!RayCastShape(p.shape, o_B, d_B, limit, h)) return false;
  hit.body = p.handle;
  hit.distance = h.distance;
  hit.point_W = o_W + h.distance * d_W;
  hit.normal_W = p.R_WB * h.normal;
  return true;
}

// Calls test(i) for every body the segment (grown by grow) may meet: the tree's candidates
// nearest first, with test returning the new limit, or every body.
template <class Test>
void Segment(RQueryState& s, bool useTree, const RVec3& origin, const RVec3& dir, RScalar tMax,
             const RVec3& grow, const Test& test) {
  if (!useTree) {
    for (std::uint32_t i = 0; i < s.proxies.size(); ++i) test(i);
    return;
  }
  s.tree.Ray(origin.data(), dir.data(), Slack(tMax), grow.data(),
             [&test](std::uint32_t i, RScalar) { return Slack(test(i)); });
}

}  // namespace

std::optional<RRayHit> RQueries::CastRay(const RBodies& bodies, const RRay& ray,
                                         const RQueryFilter& filter) {
  const RVec3 d = UnitDirection(ray);
  RQueryState& s = *m_s;
  s.Sync(bodies, m_settings.useTree);
  RRayHit best;
  bool found = false;
  auto test = [&](std::uint32_t i) {
    const RQueryProxy& p = s.proxies[i];
    const RScalar limit = found ? best.distance : ray.maxDistance;
    RRayHit h;
    if ((p.category & filter.mask) != 0 && RayBody(p, ray.origin_W, d, limit, h) &&
        (!found || Before(h.distance, h.body, best.distance, best.body)) &&
        Accepts(filter, bodies, i, p.handle)) {
      best = h, found = true;
    }
    return found ? best.distance : ray.maxDistance;
  };
  Segment(s, m_settings.useTree, ray.origin_W, d, ray.maxDistance, RVec3::Zero(), test);
  return found ? std::optional<RRayHit>(best) : std::nullopt;
}

void RQueries::CastRayAll(const RBodies& bodies, const RRay& ray, std::vector<RRayHit>& hits,
                          const RQueryFilter& filter) {
  const RVec3 d = UnitDirection(ray);
  hits.clear();
  RQueryState& s = *m_s;
  s.Sync(bodies, m_settings.useTree);
  auto test = [&](std::uint32_t i) {
    const RQueryProxy& p = s.proxies[i];
    RRayHit h;
    if ((p.category & filter.mask) != 0 && RayBody(p, ray.origin_W, d, ray.maxDistance, h) &&
        Accepts(filter, bodies, i, p.handle)) {
      hits.push_back(h);
    }
    return ray.maxDistance;
  };
  Segment(s, m_settings.useTree, ray.origin_W, d, ray.maxDistance, RVec3::Zero(), test);
  std::sort(hits.begin(), hits.end(), [](const RRayHit& a, const RRayHit& b) {
    return Before(a.distance, a.body, b.distance, b.body);
  });
}

// ---- shape casts -----------------------------------------------------------------------------

namespace {

// The nearest first touch of a posed shape moved by translation_W; `skip(i)` drops a body
// before any work (CastBody's pair rules).
template <class Skip>
std::optional<RShapeCastHit> Cast(RQueryState& s, bool useTree, const RBodies& bodies,
                                  const Posed& cast, const RVec3& translation_W,
                                  const RQueryFilter& filter, const Skip& skip) {
  if (!AllFinite(translation_W)) throw RQueryError("translation", "must be finite");
  s.Sync(bodies, useTree);
  RShapeCastHit best;
  bool found = false;
  auto test = [&](std::uint32_t i) {
    const RQueryProxy& p = s.proxies[i];
    const RScalar limit = found ? best.fraction : 1;
    RShapeCastResult r;
    if ((p.category & filter.mask) != 0 && !skip(i) &&
        ShapeCastShape(p.shape, cast.shape, InBody(p, cast),
                       p.R_WB.transpose() * translation_W, limit, r) &&
        (!found || Before(r.fraction, p.handle, best.fraction, best.body)) &&
        Accepts(filter, bodies, i, p.handle)) {
      best.body = p.handle;
      best.fraction = r.fraction;
      best.point_W = p.x_W + p.R_WB * r.point;
      best.normal_W = p.R_WB * r.normal;
      found = true;
    }
    return found ? best.fraction : RScalar(1);
  };
  // The tree sees the cast shape's box swept along the path: a segment from its centre,
  // every box grown by its half extents (and its padding, as a body's).
  const RBoundsTree::RBox box = WorldBox(cast.local, cast.shape.boundingRadius, cast.R_WB, cast.x_W);
  RVec3 centre, half;
  for (int a = 0; a < 3; ++a) {
    centre[a] = RScalar(0.5) * (box.lo[a] + box.hi[a]);
    half[a] = RScalar(0.5) * (box.hi[a] - box.lo[a]);
    half[a] += RScalar(1e-14) * std::abs(centre[a]);  // the rounding of that midpoint
  }
  Segment(s, useTree, centre, translation_W, 1, half, test);
  return found ? std::optional<RShapeCastHit>(best) : std::nullopt;
}

}  // namespace

std::optional<RShapeCastHit> RQueries::CastShape(const RBodies& bodies,
                                                 const RPreparedShape& shape,
                                                 const RVec3& position_W, const RQuat& q_WS,
                                                 const RVec3& translation_W,
                                                 const RQueryFilter& filter) {
  const Posed cast = Pose(shape, position_W, q_WS);
  return Cast(*m_s, m_settings.useTree, bodies, cast, translation_W, filter,
              [](std::uint32_t) { return false; });
}

std::optional<RShapeCastHit> RQueries::CastBody(const RBodies& bodies, RBodyHandle caster,
                                                const RVec3& translation_W,
                                                const RQueryFilter& filter) {
  const RRigidBody& c = bodies[caster];  // RHandleError when stale
  Posed cast;
  cast.shape = ShapeOf(c);
  cast.R_WB = c.Orientation_WB().toRotationMatrix();
  cast.x_W = c.Position_W();
  cast.local = LocalBoxOf(cast.shape);
  return Cast(*m_s, m_settings.useTree, bodies, cast, translation_W, filter,
              [&](std::uint32_t i) {
                return m_s->proxies[i].handle == caster || !c.ShouldCheckCollision(bodies.At(i));
              });
}

// ---- overlaps ------------------------------------------------------------------------------

namespace {

void Overlaps(RQueryState& s, bool useTree, const RBodies& bodies, const Posed& shape,
              std::vector<RBodyHandle>& out, const RQueryFilter& filter) {
  out.clear();
  s.Sync(bodies, useTree);
  auto test = [&](std::uint32_t i) {
    const RQueryProxy& p = s.proxies[i];
    if ((p.category & filter.mask) != 0 &&
        RCollisionSolver::Intersect(p.shape, shape.shape, InBody(p, shape)) &&
        Accepts(filter, bodies, i, p.handle)) {
      out.push_back(p.handle);
    }
  };
  if (useTree) {
    s.candidates.clear();
    s.tree.Query(WorldBox(shape.local, shape.shape.boundingRadius, shape.R_WB, shape.x_W),
                 s.candidates, s.stack);
    for (std::uint32_t i : s.candidates) test(i);
  } else {
    for (std::uint32_t i = 0; i < s.proxies.size(); ++i) test(i);
  }
  std::sort(out.begin(), out.end());
}

}  // namespace

void RQueries::Overlap(const RBodies& bodies, const RPreparedShape& shape,
                       const RVec3& position_W, const RQuat& q_WS, std::vector<RBodyHandle>& out,
                       const RQueryFilter& filter) {
  Overlaps(*m_s, m_settings.useTree, bodies, Pose(shape, position_W, q_WS), out, filter);
}

void RQueries::OverlapSphere(const RBodies& bodies, const RVec3& center_W, RScalar radius,
                             std::vector<RBodyHandle>& out, const RQueryFilter& filter) {
  CheckPoint(center_W, "center");
  if (!(std::isfinite(radius) && radius > 0)) {
    throw RQueryError("radius", "must be finite and > 0");
  }
  Posed sphere;
  sphere.shape.radius = sphere.shape.boundingRadius = radius;
  sphere.R_WB = RMat3::Identity();
  sphere.x_W = center_W;
  sphere.local.half_B = RVec3::Constant(radius);
  Overlaps(*m_s, m_settings.useTree, bodies, sphere, out, filter);
}

void RQueries::OverlapBox(const RBodies& bodies, const RVec3& min_W, const RVec3& max_W,
                          std::vector<RBodyHandle>& out, const RQueryFilter& filter) {
  CheckPoint(min_W, "min");
  CheckPoint(max_W, "max");
  const RVec3 half = RScalar(0.5) * (max_W - min_W);
  if (!((half.array() > 0).all() && half.minCoeff() >= RScalar(1e-4) * half.maxCoeff())) {
    throw RQueryError("max", "must exceed min along every axis, by at least 1e-4 of the "
                             "box's largest side");
  }
  RQueryState& s = *m_s;
  if (half != s.boxHalf) s.boxPolyhedron = RConvexPolyhedron::Box(half), s.boxHalf = half;
  Posed box;
  box.shape.polyhedron = &s.boxPolyhedron;
  box.shape.boundingRadius = s.boxPolyhedron.MaxRadius();
  box.R_WB = RMat3::Identity();
  box.x_W = RScalar(0.5) * (min_W + max_W);
  box.local.half_B = half;
  Overlaps(s, m_settings.useTree, bodies, box, out, filter);
}

}  // namespace REngine
