// The narrow phase on two shapes (box, sphere, capsule or a small hull) at fuzzed poses: random,
// touching, identical, deep, and 1e7 m from the origin. The answer is checked, not only the
// absence of a crash: a finite separation, a unit normal, a status that matches the
// separation, Intersect agreeing with Distance outside the touching band, a manifold of
// finite points; and against exact answers where there are closed forms: two spheres, and
// two boxes by the separating axis test over their 15 axes (exact for the depth; for a
// separated pair a lower bound on the distance, so only the verdict is compared there).
//
// Tolerances. The API resolves separations to its band, 1e-9 of the pair's size. Poses
// 1e7 m out are rounded to 1e7 * 2^-52 ~ 2e-9 m before the pair is formed, so the band
// grows by a few of those.
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RRigidBody.h>

#include "FuzzInput.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace REngine;
using namespace REngine::fuzz;

namespace {

// Raw mode reads sizes and poses as exact doubles (reproducers from elsewhere, bit for bit).
RShape ShapeFrom(FuzzInput& in, bool raw) {
  RShape s;
  const std::uint8_t kind = in.Byte();
  if (kind == 254) {  // a cylinder (the values below 254 keep the corpus's meaning)
    const double radius = raw ? in.RawDouble() : in.Decades(-2, 3);  // read in this order
    s = RShape::Cylinder(radius, raw ? in.RawDouble() : in.Decades(-2, 3));
    return s;
  }
  if (kind == 255) {  // (the other values keep the corpus's meaning)
    const double radius = raw ? in.RawDouble() : in.Decades(-2, 3);  // read in this order
    s = RShape::Capsule(radius, raw ? in.RawDouble() : in.Decades(-2, 3));
    return s;
  }
  switch (kind % 3) {
    case 0:
      s.type = RShapeType::kBox;
      if (raw) {
        s.halfExtents = in.RawVec();
      } else {
        const double x = in.Decades(-2, 3), y = in.Decades(-2, 3), z = in.Decades(-2, 3);
        s.halfExtents = RVec3(x, y, z);
      }
      break;
    case 1:
      s = RShape::Sphere(raw ? in.RawDouble() : in.Decades(-2, 3));
      break;
    default: {
      s.type = RShapeType::kHull;
      const double size = in.Decades(-2, 3);
      const int n = 4 + in.Byte() % 12;
      for (int i = 0; i < n; ++i) s.points.push_back(size * in.Vec(-1, 1));
    }
  }
  return s;
}

// Largest separation over the 15 axes of two boxes (half extents ea, eb; B posed in A's
// frame by R, t), and its axis from A to B.
double BoxSat(const RVec3& ea, const RVec3& eb, const RMat3& R, const RVec3& t, RVec3& axis) {
  double best = -1e300;
  auto test = [&](RVec3 n) {
    const double len = n.norm();
    if (!(len > 1e-9)) return;
    n /= len;
    const double ra = ea.dot(n.cwiseAbs()), rb = eb.dot((R.transpose() * n).cwiseAbs());
    const double s = std::abs(n.dot(t)) - ra - rb;
    if (s > best) best = s, axis = n.dot(t) >= 0 ? n : RVec3(-n);
  };
  for (int i = 0; i < 3; ++i) test(RVec3::Unit(i)), test(R.col(i));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) test(RVec3::Unit(i).cross(R.col(j)));
  return best;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  const std::uint8_t flags = in.Byte();
  const bool raw = flags & 0x80;
  const std::uint8_t mode = (flags & 0x7f) % 5;  // random, touching, identical, deep, far
  RBodyDef da, db;
  da.shape = ShapeFrom(in, raw);
  db.shape = ShapeFrom(in, raw);
  da.q_WS = raw ? in.RawQuat() : in.Rotation();
  db.q_WS = raw ? in.RawQuat() : in.Rotation();
  const RVec3 offset = mode == 4 ? in.Vec(-1e7, 1e7) : RVec3::Zero();
  const double reach = 4 * std::max(1.0, std::max(da.shape.halfExtents.norm(), db.shape.halfExtents.norm()));
  da.position_W = offset + (raw ? in.RawVec() : RVec3::Zero());
  db.position_W = offset + (raw ? in.RawVec() : mode == 2 ? RVec3::Zero() : in.Vec(-reach, reach));
  if (mode == 2 && !raw) db.shape = da.shape, db.q_WS = da.q_WS;
  std::vector<RRigidBody> bodies;
  try {
    bodies.emplace_back(da), bodies.emplace_back(db);
  } catch (const RBodyError&) {
    return 0;  // a degenerate hull or a needle: refused at the door, as it should be
  }
  RRigidBody& a = bodies[0];
  RRigidBody& b = bodies[1];
  const bool boxes = da.shape.type == RShapeType::kBox && db.shape.type == RShapeType::kBox;
  if (boxes && !raw && (mode == 1 || mode == 3)) {
    // Touching (within a band either way), or 1% of the smaller box deep, along the SAT axis.
    const RRelativePose X = RelativePose(a, b);
    RVec3 axis;
    const double s = BoxSat(da.shape.halfExtents, db.shape.halfExtents, X.R_AB, X.t_AB, axis);
    const double target = mode == 1 ? in.Range(-1e-9, 1e-9) : -0.01 * da.shape.halfExtents.minCoeff();
    b.SetShapePose(b.ShapePosition_W() + a.Orientation_WB() * (axis * (target - s)),
                   b.ShapeOrientation_WS());
  }
  const RConvexShape sa = ShapeOf(a), sb = ShapeOf(b);
  const RRelativePose X = RelativePose(a, b);
  const double scale = sa.boundingRadius + sb.boundingRadius;
  const double band = RCollisionSolver::kTouchingTolerance * scale + 8 * 2.3e-16 * offset.cwiseAbs().maxCoeff();
  const RDistanceResult r = RCollisionSolver::Distance(sa, sb, X);
  RENGINE_FUZZ_CHECK(std::isfinite(r.separation) && AllFinite(r.normal) && AllFinite(r.witnessA) &&
                         AllFinite(r.witnessB),
                     "non-finite answer, separation %g", r.separation);
  RENGINE_FUZZ_CHECK(std::abs(r.normal.norm() - 1) <= 1e-9, "normal length %.17g", r.normal.norm());
  RENGINE_FUZZ_CHECK(r.status != RCollisionStatus::kIterationCap, "no verdict");
  const double ownBand = RCollisionSolver::kTouchingTolerance * scale;
  const RCollisionStatus expect = r.separation > ownBand    ? RCollisionStatus::kSeparated
                                  : r.separation < -ownBand ? RCollisionStatus::kPenetrating
                                                            : RCollisionStatus::kTouching;
  RENGINE_FUZZ_CHECK(r.status == expect, "status %d for separation %.3g", int(r.status), r.separation);
  const bool intersect = RCollisionSolver::Intersect(sa, sb, X);
  if (std::abs(r.separation) > 2 * ownBand) {
    RENGINE_FUZZ_CHECK(intersect == (r.separation < 0), "Intersect %d, separation %.17g", intersect,
                       r.separation);
  }
  // Exact answers.
  if (da.shape.type == RShapeType::kSphere && db.shape.type == RShapeType::kSphere) {
    const double ref = X.t_AB.norm() - da.shape.radius - db.shape.radius;
    RENGINE_FUZZ_CHECK(std::abs(r.separation - ref) <= 1e-12 * scale + band, "spheres %.17g vs %.17g",
                       r.separation, ref);
  }
  // A capsule against a sphere or a capsule: the distance of the cores (a point and a
  // segment: the clamped projection; two segments: the least over a fine walk along one and
  // the clamped projection onto the other, refined) less the radii.
  const bool roundA = da.shape.type == RShapeType::kSphere || da.shape.type == RShapeType::kCapsule;
  const bool roundB = db.shape.type == RShapeType::kSphere || db.shape.type == RShapeType::kCapsule;
  if (roundA && roundB && (da.shape.type == RShapeType::kCapsule || db.shape.type == RShapeType::kCapsule)) {
    const double ha = da.shape.type == RShapeType::kCapsule ? da.shape.halfHeight : 0;
    const double hb = db.shape.type == RShapeType::kCapsule ? db.shape.halfHeight : 0;
    const RVec3 a0(0, -ha, 0), a1(0, ha, 0);
    const RVec3 b0 = X.R_AB * RVec3(0, -hb, 0) + X.t_AB, b1 = X.R_AB * RVec3(0, hb, 0) + X.t_AB;
    auto toB = [&](const RVec3& p) {
      const RVec3 d = b1 - b0;
      const double t = d.squaredNorm() > 0 ? std::clamp((p - b0).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
      return (b0 + t * d - p).norm();
    };
    double lo = 0, hi = 1;  // the distance to B's core is convex along A's
    for (int k = 0; k < 200; ++k) {
      const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (toB(a0 + m1 * (a1 - a0)) < toB(a0 + m2 * (a1 - a0))) hi = m2; else lo = m1;
    }
    const double ref = toB(a0 + 0.5 * (lo + hi) * (a1 - a0)) - da.shape.radius - db.shape.radius;
    RENGINE_FUZZ_CHECK(std::abs(r.separation - ref) <= 1e-9 * scale + band, "capsules %.17g vs %.17g",
                       r.separation, ref);
  }
  if (boxes) {
    RVec3 axis;
    const double ref = BoxSat(da.shape.halfExtents, db.shape.halfExtents, X.R_AB, X.t_AB, axis);
    if (ref < -2 * band) {
      RENGINE_FUZZ_CHECK(std::abs(r.separation - ref) <= 1e-6 * std::abs(ref) + band,
                         "box depth %.17g, SAT %.17g (mode %d)", r.separation, ref, mode);
    } else if (ref > 2 * band) {
      RENGINE_FUZZ_CHECK(r.separation >= ref - 1e-6 * ref - band,
                         "box distance %.17g below the SAT bound %.17g (mode %d)", r.separation, ref, mode);
    } else {
      RENGINE_FUZZ_CHECK(std::abs(r.separation) <= 3 * band + 1e-6 * std::abs(ref),
                         "touching boxes: separation %.17g, SAT %.17g", r.separation, ref);
    }
  }
  // The manifold the integrator uses.
  RContactManifold m;
  if (RCollisionSolver::CheckCollision(a, b, 1.0 / 60, m)) {
    RENGINE_FUZZ_CHECK(m.pointCount >= 0 && m.pointCount <= 4, "%d points", m.pointCount);
    RENGINE_FUZZ_CHECK(std::abs(m.normal.norm() - 1) <= 1e-9, "manifold normal %.17g", m.normal.norm());
    // The manifold's normal is the query's, or a face's aligned with it to 0.9998 in cosine,
    // less the 1e-3 by which A's face is preferred over B's (RCollisionSolver.cpp: stable
    // feature ids); and no point is deeper than the shapes overlap along it.
    const RVec3 n_W = m.normal;
    RENGINE_FUZZ_CHECK(n_W.dot(m.query.normal) >= 0.9998 - 1e-3 - 1e-12,
                       "manifold normal %.6f from the query's", n_W.dot(m.query.normal));
    auto extent = [&](const RRigidBody& body, const RVec3& d) {  // max over the body of d.x
      if (body.Shape().type == RShapeType::kCapsule) {  // its core's farther end, and the radius
        const RVec3 axis = body.Orientation_WB() * RVec3(0, body.Shape().halfHeight, 0);
        return d.dot(body.Position_W()) + std::abs(d.dot(axis)) + body.Shape().radius;
      }
      if (body.Shape().type == RShapeType::kCylinder) {  // its axis's reach and its rim's
        // d's part across the axis from d in the body frame, not sqrt(|d|^2 - along^2):
        // near the axis that difference cancels to rounding, and its square root made the
        // rim's reach 2e-8 m short on a normal 1e-8 rad from a cylinder's axis.
        const RVec3 d_B = body.Orientation_WB().conjugate() * d;
        const double along = d_B.y(), across = std::hypot(d_B.x(), d_B.z());
        return d.dot(body.Position_W()) + body.Shape().halfHeight * std::abs(along) + body.Shape().radius * across;
      }
      if (!body.Polyhedron_B()) return d.dot(body.Position_W()) + body.BoundingRadius();
      double most = -1e300;
      const RMat3 R = body.Orientation_WB().toRotationMatrix();
      for (const RVec3& v : body.Polyhedron_B()->Vertices()) {
        most = std::max(most, d.dot(R * v + body.Position_W()));
      }
      return most;
    };
    const double overlap = extent(a, n_W) + extent(b, -n_W);
    for (int i = 0; i < m.pointCount; ++i) {
      RENGINE_FUZZ_CHECK(AllFinite(m.points[i].position) && std::isfinite(m.points[i].separation),
                         "manifold point %d", i);
      RENGINE_FUZZ_CHECK(m.points[i].separation >= -overlap - 1e-9 * std::abs(overlap) - band,
                         "a manifold point %.17g deeper than the overlap %.17g along its normal",
                         m.points[i].separation, overlap);
    }
  }
  return 0;
}
