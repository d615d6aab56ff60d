#include <REngineMath/RFunctions.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

// Every function here is a fixed sequence of IEEE-754 double operations (+, -, *, /, sqrt and
// the exact scalings and remainders), evaluated in the order written: with -ffp-contract=off
// and without -ffast-math no compiler may fuse or reorder them, so the results are the same
// bits on every machine. Polynomials are truncated Taylor series on small reduced ranges,
// with terms enough that the truncation stays far below half an ulp; the constants are the
// doubles nearest to the exact values (pi/2, ln 2 and atan(k/8) split in two or three parts
// where a reduction needs more than 53 bits).
namespace REngine {
namespace {

// t rounded to the nearest integer (ties to even) for |t| < 2^51: adding 1.5 * 2^52 leaves no
// bits for the fraction. Cheaper than std::nearbyint on baseline x86-64 and the same result.
inline RScalar RoundToInt(RScalar t) {
  constexpr RScalar kShift = 0x1.8p52;
  return (t + kShift) - kShift;
}

// m * 2^k, exact where the result is normal.
inline RScalar Scale(RScalar m, int k) {
  if (k >= -1021 && k <= 1023) {
    const std::uint64_t bits = static_cast<std::uint64_t>(k + 1023) << 52;
    RScalar p;
    std::memcpy(&p, &bits, sizeof p);
    return m * p;
  }
  return std::ldexp(m, k);
}

// s + e == a + b exactly (Knuth's two-sum).
inline void TwoSum(RScalar a, RScalar b, RScalar& s, RScalar& e) {
  s = a + b;
  const RScalar bb = s - a;
  e = (a - (s - bb)) + (b - bb);
}

// ---- sin, cos ----

constexpr RScalar kTwoOverPi = 0x1.45f306dc9c883p-1;
// pi/2 = kPio2_1 + kPio2_2 + kPio2_3 to 1e-37: the first two have 33 significant bits, so
// k * kPio2_1 and k * kPio2_2 are exact for |k| < 2^20.
constexpr RScalar kPio2_1 = 0x1.921fb544p+0;
constexpr RScalar kPio2_2 = 0x1.0b4611a6p-34;
constexpr RScalar kPio2_3 = 0x1.3198a2e037073p-69;
constexpr RScalar kTwoPiHi = 0x1.921fb54442d18p+2;
constexpr RScalar kTwoPiLo = 0x1.1a62633145c07p-52;
constexpr RScalar kPio4 = 0x1.921fb54442d18p-1;
// Beyond 2^19 pi/2 the quotient is first brought below 2 pi by an exact remainder.
constexpr RScalar kMediumLimit = 0x1p19 * 0x1.921fb54442d18p+0;

// x = k pi/2 + (hi + lo) with |hi| <= pi/4 (to rounding); returns k mod 4.
int Reduce(RScalar x, RScalar& hi, RScalar& lo) {
  if (std::abs(x) <= kPio4) {
    hi = x;
    lo = 0;
    return 0;
  }
  if (!(std::abs(x) < kMediumLimit)) {
    if (!std::isfinite(x)) {
      hi = x - x;  // NaN
      lo = 0;
      return 0;
    }
    // std::remainder is exact (IEEE-754 requires it): r0 = x - n kTwoPiHi. The part of 2 pi
    // below kTwoPiHi, n kTwoPiLo, is taken off next while n is an exact integer here.
    const RScalar r0 = std::remainder(x, kTwoPiHi);
    if (std::abs(x) < 0x1p50) {
      const RScalar n = RoundToInt((x - r0) / kTwoPiHi);
      x = r0 - n * kTwoPiLo;
    } else {
      x = r0;
    }
  }
  const RScalar k = RoundToInt(x * kTwoOverPi);
  const RScalar t = x - k * kPio2_1;  // exact: k kPio2_1 is, and x is within a factor 2 of it
  RScalar r, e;
  TwoSum(t, -(k * kPio2_2), r, e);
  e -= k * kPio2_3;
  hi = r + e;
  lo = (r - hi) + e;
  return static_cast<int>(static_cast<std::int64_t>(k) & 3);
}

// sin(y + lo) for |y| <= pi/4: the Taylor series to y^17 (the next term is below 1e-19 of y).
inline RScalar SinKernel(RScalar y, RScalar lo) {
  const RScalar z = y * y;
  const RScalar p =
      -0x1.5555555555555p-3 +
      z * (0x1.1111111111111p-7 +
           z * (-0x1.a01a01a01a01ap-13 +
                z * (0x1.71de3a556c734p-19 +
                     z * (-0x1.ae64567f544e4p-26 +
                          z * (0x1.6124613a86d09p-33 +
                               z * (-0x1.ae7f3e733b81fp-41 + z * 0x1.952c77030ad4ap-49))))));
  return y + (y * z * p + lo * (1 - RScalar(0.5) * z));
}

// cos(y + lo) for |y| <= pi/4: the Taylor series to y^18; 1 - y^2/2 is formed with its
// rounding error recovered, which keeps the result within an ulp near pi/4.
inline RScalar CosKernel(RScalar y, RScalar lo) {
  const RScalar z = y * y;
  const RScalar hz = RScalar(0.5) * z;
  const RScalar w = 1 - hz;
  const RScalar q =
      z * z *
      (0x1.5555555555555p-5 +
       z * (-0x1.6c16c16c16c17p-10 +
            z * (0x1.a01a01a01a01ap-16 +
                 z * (-0x1.27e4fb7789f5cp-22 +
                      z * (0x1.1eed8eff8d898p-29 +
                           z * (-0x1.93974a8c07c9dp-37 +
                                z * (0x1.ae7f3e733b81fp-45 + z * -0x1.6827863b97d97p-53)))))));
  return w + (((1 - w) - hz) + (q - y * lo));
}

// ---- atan ----

// atan(k/32), k = 0..32, as hi + lo.
constexpr RScalar kAtanHi[33] = {0, 0x1.ffd55bba97625p-6, 0x1.ff55bb72cfdeap-5,
    0x1.7ee182602f10fp-4, 0x1.fd5ba9aac2f6ep-4, 0x1.3d6eee8c6626cp-3, 0x1.7b97b4bce5b02p-3,
    0x1.b90d7529260a2p-3, 0x1.f5b75f92c80ddp-3, 0x1.18bf5a30bf178p-2, 0x1.362773707ebccp-2,
    0x1.530ad9951cd4ap-2, 0x1.6f61941e4def1p-2, 0x1.8b24d394a1b25p-2, 0x1.a64eec3cc23fdp-2,
    0x1.c0db4c94ec9f0p-2, 0x1.dac670561bb4fp-2, 0x1.f40dd0b541418p-2, 0x1.0657e94db30d0p-1,
    0x1.1255d9bfbd2a9p-1, 0x1.1e00babdefeb4p-1, 0x1.2958e59308e31p-1, 0x1.345f01cce37bbp-1,
    0x1.3f13fb89e96f4p-1, 0x1.4978fa3269ee1p-1, 0x1.538f57b89061fp-1, 0x1.5d58987169b18p-1,
    0x1.66d663923e087p-1, 0x1.700a7c5784634p-1, 0x1.78f6bbd5d315ep-1, 0x1.819d0b7158a4dp-1,
    0x1.89ff5ff57f1f8p-1, 0x1.921fb54442d18p-1};
constexpr RScalar kAtanLo[33] = {0, -0x1.5ec431444912cp-60, -0x1.c934d86d23f1dp-60,
    -0x1.cfb654c0c3d98p-58, -0x1.cd37686760c17p-59, 0x1.61a3b0ce9281bp-57, 0x1.347b0b4f881cap-58,
    0x1.17b10d2e0e5abp-61, 0x1.8ab6e3cf7afbdp-57, 0x1.30ca4748b1bf9p-57, -0x1.963a544b672d8p-57,
    -0x1.2566480884082p-57, -0x1.c63aae6f6e918p-56, 0x1.b6d0ba3748fa8p-56, -0x1.24dec1b50b7ffp-56,
    -0x1.cc1ce70934c34p-56, 0x1.a2b7f222f65e2p-56, -0x1.a3992dc382a23p-57, -0x1.d5b495f6349e6p-56,
    -0x1.2bdaee1c0ee35p-58, -0x1.928df287a668fp-58, -0x1.09e73b0c6c087p-56, 0x1.1021137c71102p-55,
    0x1.ecf8b492644f0p-56, 0x1.2419a87f2a458p-56, -0x1.1bb74abda520cp-55, 0x1.0028e4bc5e7cap-57,
    -0x1.6ea6febe8bbbap-56, -0x1.8c34d25aadef6p-56, 0x1.406a089803740p-55, -0x1.bf76229d3b917p-56,
    -0x1.55b9a5e177a1bp-55, 0x1.1a62633145c07p-55};
constexpr RScalar kPio2Hi = 0x1.921fb54442d18p+0, kPio2Lo = 0x1.1a62633145c07p-54;
constexpr RScalar kPiHi = 0x1.921fb54442d18p+1, kPiLo = 0x1.1a62633145c07p-53;

// atan(u) for |u| <= 0.08: the Taylor series to u^17 (the next term is below 1e-20 of u).
inline RScalar AtanSeries(RScalar u) {
  const RScalar z = u * u;
  const RScalar p =
      -0x1.5555555555555p-2 +
      z * (0x1.999999999999ap-3 +
           z * (-0x1.2492492492492p-3 +
                z * (0x1.c71c71c71c71cp-4 +
                     z * (-0x1.745d1745d1746p-4 +
                          z * (0x1.3b13b13b13b14p-4 +
                               z * (-0x1.1111111111111p-4 + z * 0x1.e1e1e1e1e1e1ep-5))))));
  return u + u * z * p;
}

// atan(t) for 0 <= t <= 1: the series below 5/64, else atan(c) + atan((t - c) / (1 + t c))
// about the nearest c = k/32, which leaves |u| <= 1/64, under a fifth of the result, so that
// the rounding of u adds little to the result's.
RScalar AtanUnit(RScalar t) {
  if (t < RScalar(0.078125)) return AtanSeries(t);
  const int k = static_cast<int>(t * 32 + RScalar(0.5));
  const RScalar c = k * RScalar(0.03125);
  const RScalar u = (t - c) / (1 + t * c);  // t - c is exact (t within a factor 2 of c)
  return kAtanHi[k] + (kAtanLo[k] + AtanSeries(u));
}

// ---- exp ----

constexpr RScalar kInvLn2 = 0x1.71547652b82fep+0;
// ln 2 = kLn2Hi + kLn2Lo to 1e-26; kLn2Hi has 32 significant bits, so k kLn2Hi is exact.
constexpr RScalar kLn2Hi = 0x1.62e42feep-1;
constexpr RScalar kLn2Lo = 0x1.a39ef35793c76p-33;

// x = k ln 2 + (r + lo), |r| <= ln(2)/2 (to rounding), for |x| <= 746.
int ReduceLn2(RScalar x, RScalar& r, RScalar& lo) {
  const RScalar k = RoundToInt(x * kInvLn2);
  const RScalar t = x - k * kLn2Hi;  // exact
  TwoSum(t, -(k * kLn2Lo), r, lo);
  return static_cast<int>(k);
}

// exp(r + lo) - 1 = hi + lo for |r| <= 0.35: the Taylor series to r^14 (the next term is
// below 1e-18 of r), r added last and its rounding error kept, so that a caller adding a
// constant to it rounds once.
inline void Expm1Kernel(RScalar r, RScalar lo, RScalar& hi, RScalar& hiLo) {
  const RScalar p =
      0x1p-1 +
      r * (0x1.5555555555555p-3 +
           r * (0x1.5555555555555p-5 +
                r * (0x1.1111111111111p-7 +
                     r * (0x1.6c16c16c16c17p-10 +
                          r * (0x1.a01a01a01a01ap-13 +
                               r * (0x1.a01a01a01a01ap-16 +
                                    r * (0x1.71de3a556c734p-19 +
                                         r * (0x1.27e4fb7789f5cp-22 +
                                              r * (0x1.ae64567f544e4p-26 +
                                                   r * (0x1.1eed8eff8d898p-29 +
                                                        r * (0x1.6124613a86d09p-33 +
                                                             r * 0x1.93974a8c07c9dp-37)))))))))));
  const RScalar t = r * r * p + lo * (1 + r);  // |t| < |r|
  hi = r + t;
  hiLo = (r - hi) + t;
}

// c + (hi + lo), rounded once (to within the tiny error of adding lo).
inline RScalar AddTo(RScalar c, RScalar hi, RScalar lo) {
  RScalar s, e;
  TwoSum(c, hi, s, e);
  return s + (e + lo);
}

// e^x 2^extra for |x| <= 746.
RScalar ExpScaled(RScalar x, int extra) {
  RScalar r, lo, hi, hiLo;
  const int k = ReduceLn2(x, r, lo);
  Expm1Kernel(r, lo, hi, hiLo);
  return Scale(AddTo(1, hi, hiLo), k + extra);
}

}  // namespace

RScalar Sin(RScalar x) {
  if (x == 0) return x;  // keeps the sign of zero
  RScalar y, lo;
  switch (Reduce(x, y, lo)) {
    case 0: return SinKernel(y, lo);
    case 1: return CosKernel(y, lo);
    case 2: return -SinKernel(y, lo);
    default: return -CosKernel(y, lo);
  }
}

RScalar Cos(RScalar x) {
  RScalar y, lo;
  switch (Reduce(x, y, lo)) {
    case 0: return CosKernel(y, lo);
    case 1: return -SinKernel(y, lo);
    case 2: return -CosKernel(y, lo);
    default: return SinKernel(y, lo);
  }
}

void SinCos(RScalar x, RScalar& s, RScalar& c) {
  if (x == 0) {
    s = x;
    c = 1;
    return;
  }
  RScalar y, lo;
  const int quadrant = Reduce(x, y, lo);
  const RScalar sy = SinKernel(y, lo), cy = CosKernel(y, lo);
  switch (quadrant) {
    case 0: s = sy; c = cy; break;
    case 1: s = cy; c = -sy; break;
    case 2: s = -sy; c = -cy; break;
    default: s = -cy; c = sy; break;
  }
}

RScalar Atan2(RScalar y, RScalar x) {
  if (std::isnan(x) || std::isnan(y)) return x + y;
  const RScalar ax = std::abs(x), ay = std::abs(y);
  RScalar a;  // the angle of (|x|, |y|), in [0, pi/2]
  if (std::isinf(ax) && std::isinf(ay)) {
    a = kPio4;
  } else if (ay <= ax) {
    a = ax == 0 ? RScalar(0) : AtanUnit(ay / ax);
  } else {
    a = kPio2Hi + (kPio2Lo - AtanUnit(ax / ay));
  }
  if (std::signbit(x)) a = kPiHi + (kPiLo - a);
  return std::copysign(a, y);
}

RScalar Asin(RScalar x) {
  if (!(std::abs(x) <= 1)) return std::isnan(x) ? x : std::numeric_limits<RScalar>::quiet_NaN();  // outside [-1, 1]
  return Atan2(x, std::sqrt((1 - x) * (1 + x)));
}

RScalar Exp(RScalar x) {
  if (std::isnan(x)) return x;
  if (x > 710) return kInf;
  if (x < -746) return 0;
  return ExpScaled(x, 0);
}

RScalar Expm1(RScalar x) {
  if (x == 0 || std::isnan(x)) return x;
  if (x > 710) return kInf;
  if (x < -40) return -1;  // e^-40 is below half an ulp of 1
  RScalar hi, hiLo;
  if (std::abs(x) <= RScalar(0.34)) {
    Expm1Kernel(x, 0, hi, hiLo);
    return hi + hiLo;
  }
  RScalar r, lo;
  const int k = ReduceLn2(x, r, lo);
  Expm1Kernel(r, lo, hi, hiLo);  // e^x - 1 = 2^k (1 + hi + hiLo) - 1
  // 1 - 2^-k is exact up to k = 53; beyond, 2^-k joins the low part.
  if (k > 53) return Scale(AddTo(1, hi, hiLo - Scale(1, -k)), k);
  if (k > 0) return Scale(AddTo(1 - Scale(1, -k), hi, hiLo), k);
  // 2^k - 1 is exact (k >= -58 here); 2^k (hi + hiLo) is scaled exactly before the sum.
  return AddTo(Scale(1, k) - 1, Scale(hi, k), Scale(hiLo, k));
}

RScalar Tanh(RScalar x) {
  if (x == 0 || std::isnan(x)) return x;
  const RScalar ax = std::abs(x);
  if (ax > 22) return std::copysign(RScalar(1), x);  // 1 - tanh(22) is below 2^-63
  const RScalar e = Expm1(2 * ax);
  return std::copysign(e / (e + 2), x);
}

RScalar Cosh(RScalar x) {
  const RScalar ax = std::abs(x);
  if (std::isnan(x)) return x;
  if (ax < 0x1p-27) return 1;
  if (ax <= 22) {
    const RScalar e = Exp(ax);
    return RScalar(0.5) * e + RScalar(0.5) / e;
  }
  // e^-x is below 1e-19 of e^x: cosh = e^x / 2, halved exactly inside (e^x alone overflows
  // before cosh does).
  if (ax > 711) return kInf;
  return ExpScaled(ax, -1);
}

RScalar Hypot(RScalar x, RScalar y) {
  RScalar ax = std::abs(x), ay = std::abs(y);
  if (std::isinf(ax) || std::isinf(ay)) return kInf;
  if (std::isnan(ax) || std::isnan(ay)) return ax + ay;
  if (ax < ay) std::swap(ax, ay);
  if (ay == 0) return ax;
  // Scaled by powers of two (exact) so that neither square overflows nor loses digits to
  // underflow.
  RScalar scale = 1;
  if (ax > 0x1p500) {
    ax *= 0x1p-600;
    ay *= 0x1p-600;
    scale = 0x1p600;
  } else if (ax < 0x1p-500) {
    ax *= 0x1p600;
    ay *= 0x1p600;
    scale = 0x1p-600;
  }
  return scale * std::sqrt(ax * ax + ay * ay);
}

}  // namespace REngine
