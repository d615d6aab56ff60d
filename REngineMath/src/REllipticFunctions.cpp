#include <REngineMath/REllipticFunctions.h>

#include <cmath>

namespace REngine {

namespace {
constexpr int kMaxAgmIterations = 16;
}  // namespace

RJacobiSnCnDn JacobiSnCnDn(RScalar u, RScalar m, RScalar mc) {
  RJacobiSnCnDn r;
  if (m <= 0) {
    r.sn = std::sin(u);
    r.cn = std::cos(u);
    r.dn = 1;
    return r;
  }
  if (mc < RScalar(1e-17)) {
    r.sn = std::tanh(u);
    r.cn = 1 / std::cosh(u);
    r.dn = r.cn;
    return r;
  }
  RScalar a[kMaxAgmIterations + 1];
  RScalar c[kMaxAgmIterations + 1];
  a[0] = 1;
  RScalar b = std::sqrt(mc);
  c[0] = std::sqrt(m);
  int n = 0;
  while (std::abs(c[n]) > RTol::kEpsilon * a[n] && n < kMaxAgmIterations) {
    a[n + 1] = RScalar(0.5) * (a[n] + b);
    c[n + 1] = RScalar(0.5) * (a[n] - b);
    b = std::sqrt(a[n] * b);
    ++n;
  }
  RScalar phi = std::ldexp(a[n] * u, n);
  RScalar phiPrev = phi;
  for (int j = n; j >= 1; --j) {
    phiPrev = phi;
    phi = RScalar(0.5) * (phi + std::asin(c[j] / a[j] * std::sin(phi)));
  }
  r.sn = std::sin(phi);
  r.cn = std::cos(phi);
  // dn = cos(phi0) / cos(phi1 - phi0): keeps full relative accuracy where
  // sqrt(1 - m sn^2) would cancel (m -> 1, sn -> 1).
  r.dn = n > 0 ? r.cn / std::cos(phiPrev - phi) : RScalar(1);
  return r;
}

RScalar EllipticK(RScalar mc) {
  if (mc <= 0) return std::numeric_limits<RScalar>::infinity();
  RScalar a = 1;
  RScalar b = std::sqrt(mc);
  for (int i = 0; i < kMaxAgmIterations && std::abs(a - b) > RTol::kEpsilon * a; ++i) {
    const RScalar an = RScalar(0.5) * (a + b);
    b = std::sqrt(a * b);
    a = an;
  }
  return kPi / (2 * a);
}

}  // namespace REngine
