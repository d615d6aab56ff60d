// What the narrow phase (RCollisionSolver) is held to against the exact references of
// support/CollisionOracles.h, shared by the random-pair and the adversarial oracle tests
// (narrowphase_oracle_tests: collision/RandomPairs.h, collision/AdversarialPairs.h).
//
// Tolerances. The API resolves separations to its touching band,
// band = RCollisionSolver::kTouchingTolerance * (rA + rB) = 1e-9 of the pair's size: below
// it, "touching" is the answer and the sign is not promised. Rounding in GJK/EPA is ~1e-16
// of the size per operation, far below the band; an EPA that stops early or a GJK that picks
// the wrong feature errs by much more. So values must match to 1e-6 relative plus the band,
// verdicts must match wherever the reference is two bands from zero (the reference itself
// is exact to ~1e-15 of the size), and normals must match to 1e-4 rad.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RCollision.h>

#include <cmath>

namespace REngine::test {

// Normal tolerance: 1e-4 rad. An EPA that ends on the right facet of the Minkowski difference
// has its normal to ~1e-15 rad times the facet's conditioning; one that ends on a
// neighbouring facet is off by the angle between facets, which for hulls of <= 64 points
// is >> 1e-4 rad except between near-tied facets, which the reference lists as alternatives.
inline constexpr RScalar kNormalTolerance = 1e-4;
// Relative value tolerance (depth or distance), on top of the band.
inline constexpr RScalar kRelativeTolerance = 1e-6;

// The angle between two directions, rad: accurate for tiny angles, unlike acos of the dot.
inline RScalar Angle(const RVec3& a, const RVec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

inline const char* StatusName(RCollisionStatus s) {
  switch (s) {
    case RCollisionStatus::kSeparated:
      return "separated";
    case RCollisionStatus::kTouching:
      return "touching";
    case RCollisionStatus::kPenetrating:
      return "penetrating";
    case RCollisionStatus::kIterationCap:
      return "iteration cap";
  }
  return "?";
}

}  // namespace REngine::test
