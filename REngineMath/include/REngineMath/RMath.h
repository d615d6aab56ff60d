// REngineMath: the one place that defines REngine's scalar, its Eigen aliases and its
// tolerance constants. Everything else in REngine includes this header and uses these names.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>
#include <limits>

namespace REngine {

// Double precision throughout: space games live far from the origin, where a float's 24-bit
// mantissa resolves only ~1 m at 1e7 m. Doubles resolve ~2 nm there.
using RScalar = double;

using RVec3 = Eigen::Matrix<RScalar, 3, 1>;
using RVec4 = Eigen::Matrix<RScalar, 4, 1>;
using RMat3 = Eigen::Matrix<RScalar, 3, 3>;
// Unit quaternion for rotations. Eigen stores (x, y, z, w) but constructs as (w, x, y, z);
// REngine's files and CSVs always write [w, x, y, z].
using RQuat = Eigen::Quaternion<RScalar>;

inline constexpr RScalar kPi = RScalar(3.14159265358979323846264338327950288);
inline constexpr RScalar kInf = std::numeric_limits<RScalar>::infinity();

// Tolerances, each with the one meaning it has everywhere it is used.
namespace RTol {
// Machine epsilon of RScalar: the relative rounding unit.
inline constexpr RScalar kEpsilon = std::numeric_limits<RScalar>::epsilon();
// Two principal moments closer than this, relative to the larger, are treated as equal.
// Equal moments give a symmetric body, whose torque-free motion is solved in closed form
// with fewer operations; the difference ignored (1e-12 relative) is far below what any mass
// model is accurate to, and far below where the general solution's conditioning suffers.
inline constexpr RScalar kEqualMoments = 1e-12;
}  // namespace RTol

// Skew-symmetric matrix [v]x such that [v]x * w == v.cross(w).
inline RMat3 Skew(const RVec3& v) {
  RMat3 m;
  m << 0, -v.z(), v.y(),  //
      v.z(), 0, -v.x(),   //
      -v.y(), v.x(), 0;
  return m;
}

// True when every component is finite (no NaN, no infinity).
template <typename Derived>
inline bool AllFinite(const Eigen::MatrixBase<Derived>& m) {
  return m.array().isFinite().all();
}
inline bool AllFinite(const RQuat& q) { return AllFinite(q.coeffs()); }

// Two unit vectors b, c completing the unit vector a to a right-handed orthonormal basis
// (a, b, c). Branch-free in the sign of a.z (Duff et al. 2017, "Building an orthonormal
// basis, revisited"), so it is continuous everywhere except across a.z = 0 sign flips and
// exact for the axes.
inline void OrthonormalBasis(const RVec3& a, RVec3& b, RVec3& c) {
  const RScalar sign = std::copysign(RScalar(1), a.z());
  const RScalar p = RScalar(-1) / (sign + a.z());
  const RScalar q = a.x() * a.y() * p;
  b = RVec3(1 + sign * a.x() * a.x() * p, sign * q, -sign * a.x());
  c = RVec3(q, sign + a.y() * a.y() * p, -a.y());
}

}  // namespace REngine
