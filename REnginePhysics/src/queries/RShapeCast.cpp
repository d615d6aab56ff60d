// A convex shape swept along a straight path against another (ShapeCastShape, RQueries.h):
// conservative advancement on the narrow phase's distance.
#include <REnginePhysics/RQueries.h>

#include "shape/RCompound.h"

#include <cmath>

namespace REngine {

bool ShapeCastShape(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X_AB,
                    const RVec3& translation_A, RScalar maxFraction, RShapeCastResult& out) {
  if (a.mesh || b.mesh) return ShapeCastMesh(a, b, X_AB, translation_A, maxFraction, out);
  if (a.children || b.children) {
    // A compound is not convex, and advancing along the nearest pair's normal could stop
    // where the nearest child pair slides past (a ball beside a U's wall): the first touch
    // of any child pair, each cast alone (each pair is convex).
    RShapeChild aloneA, aloneB;
    std::uint32_t na, nb;
    const RShapeChild* ca = ChildrenOf(a, aloneA, na);
    const RShapeChild* cb = ChildrenOf(b, aloneB, nb);
    bool found = false;
    for (std::uint32_t i = 0; i < na; ++i) {
      for (std::uint32_t j = 0; j < nb; ++j) {
        RShapeCastResult r;
        const RScalar limit = found ? out.fraction : maxFraction;
        if (!ShapeCastShape(ca[i].shape, cb[j].shape, ChildPose(ca[i], cb[j], X_AB),
                            ca[i].R_BC.transpose() * translation_A, limit, r)) {
          continue;
        }
        if (found && !(r.fraction < out.fraction)) continue;
        out = r;
        out.point = ca[i].R_BC * r.point + ca[i].p_BC;
        out.normal = ca[i].R_BC * r.normal;
        found = true;
      }
    }
    return found;
  }
  const RScalar band =
      RCollisionSolver::kTouchingTolerance * (a.boundingRadius + b.boundingRadius);
  RRelativePose X = X_AB;
  RScalar fraction = 0;
  for (int k = 1; k <= kMaxCastIterations; ++k) {
    X.t_AB = X_AB.t_AB + fraction * translation_A;
    const RDistanceResult r = RCollisionSolver::Distance(a, b, X);
    out.iterations = k;
    out.fraction = fraction;
    out.point = r.witnessA;
    if (r.separation <= band) {
      // Touching, the closest points are a rounding error apart, and for two flat faces their
      // direction is noise: it can point the wrong way, B moving away from A along it. A
      // touch reached by advancing was approached along the last normal of a clear gap: that
      // one, then. (A normal that agrees with the approach is kept, bit for bit.)
      if (k == 1 || -translation_A.dot(r.normal) > 0) out.normal = r.normal;
      return (out.converged = true);
    }
    out.normal = r.normal;
    // The plane through A's closest point, normal r.normal, has all of A behind it and B at
    // r.separation in front: B, moving along the translation, cannot touch A before it has
    // closed that gap along the normal. Not closing it at all (moving parallel or away), it
    // never touches: the distance along a straight path is convex, and it is not falling.
    const RScalar approach = -translation_A.dot(r.normal);
    if (!(approach > 0)) return false;
    fraction += r.separation / approach;
    if (!(fraction <= maxFraction)) return false;
  }
  // The cap (grazing paths close the last gap slowly): where it got to, short of the touch.
  out.converged = false;
  return true;
}

}  // namespace REngine
