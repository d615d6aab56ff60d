// REngine's own transcendental functions (REngineMath/RFunctions.h) against the C library's
// long-double functions, which carry 11 or more bits beyond a double: the error of each
// result in ulps of the exact value, over random arguments across each function's ranges,
// and the special values of C99 Annex F.
#include <REngineMath/RFunctions.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

using namespace REngine;

namespace {

using LD = long double;

// |got - exact| in units of the last place of the exact value as a double.
double UlpError(double got, LD exact) {
  if (std::isnan(static_cast<double>(exact))) return std::isnan(got) ? 0 : 1e9;
  const LD a = std::fabs(exact);
  int e = 0;
  std::frexp(static_cast<double>(a), &e);  // a in [2^(e-1), 2^e)
  const LD ulp = std::ldexp(LD(1), std::max(e - 53, -1074));
  return static_cast<double>(std::fabs(static_cast<LD>(got) - exact) / ulp);
}

// The largest error of f against ref over n arguments drawn uniformly in [lo, hi].
template <class F, class R>
double WorstUlp(F f, R ref, double lo, double hi, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  double worst = 0;
  double at = 0;
  for (int i = 0; i < n; ++i) {
    const double x = u(rng);
    const double err = UlpError(f(x), ref(static_cast<LD>(x)));
    if (err > worst) {
      worst = err;
      at = x;
    }
  }
  std::printf("  worst %.3f ulp at %.17g in [%g, %g]\n", worst, at, lo, hi);
  return worst;
}

constexpr int kSamples = 200000;

}  // namespace

// Measured: 0.77 ulp (sin and cos), in each range below.
TEST(Functions, SinAndCosWithinAnUlp) {
  const auto sin = [](double x) { return Sin(x); };
  const auto cos = [](double x) { return Cos(x); };
  const auto sinl = [](LD x) { return std::sin(x); };
  const auto cosl = [](LD x) { return std::cos(x); };
  for (const auto& [lo, hi] : {std::pair{-1e-6, 1e-6}, {-0.8, 0.8}, {-10.0, 10.0},
                               {-1e3, 1e3}, {-8e5, 8e5}}) {
    EXPECT_LE(WorstUlp(sin, sinl, lo, hi, kSamples, 1), 1.0) << lo << " " << hi;
    EXPECT_LE(WorstUlp(cos, cosl, lo, hi, kSamples, 2), 1.0) << lo << " " << hi;
  }
  // SinCos is the pair of them, bit for bit.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-100, 100);
  for (int i = 0; i < 10000; ++i) {
    const double x = u(rng);
    double s = 0, c = 0;
    SinCos(x, s, c);
    ASSERT_EQ(s, Sin(x));
    ASSERT_EQ(c, Cos(x));
  }
}

// Far out the argument's own spacing dwarfs the reduction's error: absolute error below
// 1e-15 up to 2^50, and a value in [-1, 1] beyond.
TEST(Functions, SinAndCosOfLargeArguments) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> exponent(19.5, 50);
  for (int i = 0; i < 20000; ++i) {
    const double x = std::exp2(exponent(rng));
    EXPECT_LE(std::fabs(Sin(x) - static_cast<double>(std::sin(static_cast<LD>(x)))), 1e-15) << x;
    EXPECT_LE(std::fabs(Cos(x) - static_cast<double>(std::cos(static_cast<LD>(x)))), 1e-15) << x;
  }
  for (const double x : {0x1p60, -0x1p80, 1e300, std::numeric_limits<double>::max()}) {
    EXPECT_LE(std::fabs(Sin(x)), 1.0);
    EXPECT_LE(std::fabs(Cos(x)), 1.0);
  }
}

// Measured: 1.3 ulp (atan2), 2.1 ulp (asin).
TEST(Functions, Atan2AndAsinWithinTheirBounds) {
  const auto atan = [](double t) { return Atan2(t, 1.0); };
  const auto atanl = [](LD t) { return std::atan2(t, LD(1)); };
  for (const auto& [lo, hi] : {std::pair{-0.1, 0.1}, {-1.0, 1.0}, {-20.0, 20.0}, {-1e6, 1e6}}) {
    EXPECT_LE(WorstUlp(atan, atanl, lo, hi, kSamples, 5), 1.5) << lo << " " << hi;
  }
  // Angles all round the circle: (cos a, sin a) scaled.
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> a(-3.2, 3.2), scale(-300, 300);
  double worst = 0;
  for (int i = 0; i < kSamples; ++i) {
    const double s = std::exp2(scale(rng)), angle = a(rng);
    const double y = s * std::sin(angle), x = s * std::cos(angle);
    worst = std::max(worst, UlpError(Atan2(y, x), std::atan2(static_cast<LD>(y), static_cast<LD>(x))));
  }
  EXPECT_LE(worst, 1.5);
  const auto asin = [](double x) { return Asin(x); };
  const auto asinl = [](LD x) { return std::asin(x); };
  for (const auto& [lo, hi] : {std::pair{-0.01, 0.01}, {-1.0, 1.0}, {0.999, 1.0}}) {
    EXPECT_LE(WorstUlp(asin, asinl, lo, hi, kSamples, 7), 2.5) << lo << " " << hi;
  }
}

// Measured: 0.61 ulp (exp), 0.94 ulp (expm1).
TEST(Functions, ExpAndExpm1WithinAnUlp) {
  const auto exp = [](double x) { return Exp(x); };
  const auto expl = [](LD x) { return std::exp(x); };
  const auto expm1 = [](double x) { return Expm1(x); };
  const auto expm1l = [](LD x) { return std::expm1(x); };
  for (const auto& [lo, hi] : {std::pair{-1e-8, 1e-8}, {-1.0, 1.0}, {-30.0, 30.0},
                               {-708.0, 709.7}}) {
    EXPECT_LE(WorstUlp(exp, expl, lo, hi, kSamples, 8), 1.0) << lo << " " << hi;
    EXPECT_LE(WorstUlp(expm1, expm1l, lo, hi, kSamples, 9), 1.0) << lo << " " << hi;
  }
}

// Measured: 2.2 ulp (tanh), 1.1 ulp (cosh), 1.2 ulp (hypot).
TEST(Functions, TanhCoshAndHypotWithinTheirBounds) {
  const auto tanh = [](double x) { return Tanh(x); };
  const auto tanhl = [](LD x) { return std::tanh(x); };
  const auto cosh = [](double x) { return Cosh(x); };
  const auto coshl = [](LD x) { return std::cosh(x); };
  for (const auto& [lo, hi] : {std::pair{-1e-6, 1e-6}, {-1.0, 1.0}, {-25.0, 25.0}}) {
    EXPECT_LE(WorstUlp(tanh, tanhl, lo, hi, kSamples, 10), 2.5) << lo << " " << hi;
    EXPECT_LE(WorstUlp(cosh, coshl, lo, hi, kSamples, 11), 1.5) << lo << " " << hi;
  }
  EXPECT_LE(WorstUlp(cosh, coshl, 700, 710, kSamples, 12), 1.5);
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> scale(-1000, 1000), ratio(-60, 60);
  double worst = 0;
  for (int i = 0; i < kSamples; ++i) {
    const double x = std::exp2(scale(rng)), y = x * std::exp2(ratio(rng));
    worst = std::max(worst, UlpError(Hypot(x, -y), std::hypot(static_cast<LD>(x), static_cast<LD>(y))));
  }
  EXPECT_LE(worst, 1.5);
}

TEST(Functions, SpecialValues) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::signbit(Sin(-0.0)));
  EXPECT_EQ(Cos(-0.0), 1.0);
  EXPECT_TRUE(std::isnan(Sin(inf)) && std::isnan(Cos(-inf)) && std::isnan(Sin(nan)));
  EXPECT_EQ(Atan2(0.0, 0.0), 0.0);
  EXPECT_TRUE(std::signbit(Atan2(-0.0, 1.0)));
  EXPECT_EQ(Atan2(0.0, -0.0), std::atan2(0.0, -0.0));
  EXPECT_EQ(Atan2(-0.0, -1.0), std::atan2(-0.0, -1.0));
  EXPECT_EQ(Atan2(1.0, 0.0), std::atan2(1.0, 0.0));
  EXPECT_EQ(Atan2(-1.0, -inf), std::atan2(-1.0, -inf));
  EXPECT_EQ(Atan2(inf, inf), std::atan2(inf, inf));
  EXPECT_EQ(Atan2(-inf, -inf), std::atan2(-inf, -inf));
  EXPECT_TRUE(std::isnan(Atan2(nan, 1.0)));
  EXPECT_EQ(Asin(1.0), std::asin(1.0));
  EXPECT_EQ(Asin(-1.0), std::asin(-1.0));
  EXPECT_TRUE(std::isnan(Asin(1.5)));
  EXPECT_EQ(Exp(0.0), 1.0);
  EXPECT_EQ(Exp(-inf), 0.0);
  EXPECT_EQ(Exp(inf), inf);
  EXPECT_EQ(Exp(710.0), inf);
  EXPECT_EQ(Exp(-800.0), 0.0);
  EXPECT_GT(Exp(-745.0), 0.0);  // the smallest subnormal
  EXPECT_TRUE(std::signbit(Expm1(-0.0)));
  EXPECT_EQ(Expm1(-inf), -1.0);
  EXPECT_EQ(Tanh(inf), 1.0);
  EXPECT_EQ(Tanh(-inf), -1.0);
  EXPECT_EQ(Cosh(-inf), inf);
  EXPECT_EQ(Hypot(3.0, 4.0), 5.0);
  EXPECT_EQ(Hypot(nan, inf), inf);
  EXPECT_EQ(Hypot(1e300, 1e300), std::hypot(1e300, 1e300));
  EXPECT_EQ(Hypot(0.0, -0.0), 0.0);
}
