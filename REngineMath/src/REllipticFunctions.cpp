#include <REngineMath/REllipticFunctions.h>
#include <REngineMath/RFunctions.h>

#include <cmath>

namespace REngine {

namespace {
constexpr int kMaxAgmIterations = 16;
constexpr RScalar kSeriesMaxU = RScalar(0.05);
}  // namespace

RJacobiSnCnDn JacobiSnCnDn(RScalar u, RScalar m, RScalar mc) {
  RJacobiSnCnDn r;
  if (std::abs(u) <= kSeriesMaxU) {
    // Maclaurin series (Abramowitz and Stegun 16.22) through u^11 / u^10. The poles of
    // sn, cn, dn nearest the origin are at distance K(mc) >= pi/2, so the first omitted
    // term is below (0.05 / (pi/2))^12 ~ 1e-18 for |u| <= 0.05 and any m in [0, 1].
    const RScalar m2 = m * m, m3 = m2 * m, m4 = m3 * m, m5 = m4 * m;
    const RScalar u2 = u * u;
    r.sn = u * (1 + u2 * (-(1 + m) / 6 +
                          u2 * ((1 + 14 * m + m2) / 120 +
                                u2 * (-(1 + 135 * m + 135 * m2 + m3) / 5040 +
                                      u2 * ((1 + 1228 * m + 5478 * m2 + 1228 * m3 + m4) / 362880 -
                                            u2 * (1 + 11069 * m + 165826 * m2 + 165826 * m3 +
                                                  11069 * m4 + m5) /
                                                39916800)))));
    r.cn = 1 + u2 * (RScalar(-0.5) +
                     u2 * ((1 + 4 * m) / 24 +
                           u2 * (-(1 + 44 * m + 16 * m2) / 720 +
                                 u2 * ((1 + 408 * m + 912 * m2 + 64 * m3) / 40320 -
                                       u2 * (1 + 3688 * m + 30768 * m2 + 15808 * m3 + 256 * m4) /
                                           3628800))));
    r.dn = 1 + m * u2 * (RScalar(-0.5) +
                         u2 * ((4 + m) / 24 +
                               u2 * (-(16 + 44 * m + m2) / 720 +
                                     u2 * ((64 + 912 * m + 408 * m2 + m3) / 40320 -
                                           u2 * (256 + 15808 * m + 30768 * m2 + 3688 * m3 + m4) /
                                               3628800))));
    return r;
  }
  if (m <= 0) {
    r.sn = Sin(u);
    r.cn = Cos(u);
    r.dn = 1;
    return r;
  }
  if (mc <= 0) {
    // Exactly on the separatrix: the limit is exact, not an approximation (for mc > 0,
    // however small, the functions are periodic and differ from it beyond ~K/2).
    r.sn = Tanh(u);
    r.cn = 1 / Cosh(u);
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
    phi = RScalar(0.5) * (phi + Asin(c[j] / a[j] * Sin(phi)));
  }
  r.sn = Sin(phi);
  r.cn = Cos(phi);
  // dn = cos(phi0) / cos(phi1 - phi0): keeps full relative accuracy where
  // sqrt(1 - m sn^2) would cancel (m -> 1, sn -> 1).
  r.dn = n > 0 ? r.cn / Cos(phiPrev - phi) : RScalar(1);
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
