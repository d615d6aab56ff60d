#include <REngineMath/RQuaternion.h>
#include <REngineMath/RFunctions.h>

#include <cmath>

namespace REngine {

RQuat QuatExp(const RVec3& theta) {
  const RScalar angle = theta.norm();
  const RScalar half = RScalar(0.5) * angle;
  // sin(half)/angle; below 1e-4 rad the Taylor series to x^4 is exact to rounding
  // (the next term is x^6/5040 ~ 2e-28 relative).
  RScalar s, c;
  SinCos(half, s, c);
  if (angle < RScalar(1e-4)) {
    const RScalar h2 = half * half;
    s = RScalar(0.5) * (1 - h2 / 6 * (1 - h2 / 20));
  } else {
    s /= angle;
  }
  return RQuat(c, s * theta.x(), s * theta.y(), s * theta.z());
}

RVec3 QuatLog(const RQuat& q) {
  RQuat p = q;
  if (p.w() < 0) p.coeffs() = -p.coeffs();
  const RVec3 v = p.vec();
  const RScalar sinHalf = v.norm();
  if (sinHalf == 0) return RVec3::Zero();
  const RScalar angle = 2 * Atan2(sinHalf, p.w());
  return v * (angle / sinHalf);
}

RQuat QuatAxisAngle(const RVec3& axis, RScalar angle) {
  const RScalar half = RScalar(0.5) * angle;
  RScalar s, c;
  SinCos(half, s, c);
  return RQuat(c, s * axis.x(), s * axis.y(), s * axis.z());
}

RScalar QuatAngleBetween(const RQuat& a, const RQuat& b) {
  const RQuat d = a.conjugate() * b;
  return 2 * Atan2(d.vec().norm(), std::abs(d.w()));
}

RQuat QuatFromTo(const RVec3& from, const RVec3& to) {
  // q = (1 + c, from x to) / norm: the half-angle construction, exact for small angles.
  const RScalar c = from.dot(to);
  if (c < RScalar(-1) + RScalar(1e-12)) {
    RVec3 b, d;
    OrthonormalBasis(from, b, d);
    return RQuat(0, b.x(), b.y(), b.z());
  }
  const RVec3 axis = from.cross(to);
  RQuat q(1 + c, axis.x(), axis.y(), axis.z());
  q.normalize();
  return q;
}

std::optional<RQuat> QuatNormalized(const RQuat& q) {
  if (!AllFinite(q)) return std::nullopt;
  // Divide by the largest component first: |q|^2 of (1e200, 0, 0, 0) overflows and of
  // (1e-170, 0, 0, 0) underflows, though both have a direction.
  const RScalar big = q.coeffs().cwiseAbs().maxCoeff();
  if (big == 0) return std::nullopt;
  RQuat r(q.coeffs() / big);
  r.coeffs() /= r.norm();
  return r;
}

}  // namespace REngine
