// REngineMath: quaternion helpers, orthonormal basis, Jacobi elliptic functions.
#include <REngineMath/REllipticFunctions.h>
#include <REngineMath/RQuaternion.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace REngine;

namespace {
RVec3 RandomUnit(std::mt19937_64& rng) {
  std::normal_distribution<RScalar> n;
  return RVec3(n(rng), n(rng), n(rng)).normalized();
}
}  // namespace

TEST(Quaternion, ExpMatchesAxisAngleAndLogInvertsIt) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<RScalar> angle(0, 3.1);
  for (int i = 0; i < 1000; ++i) {
    const RVec3 axis = RandomUnit(rng);
    const RScalar a = angle(rng);
    const RQuat q = QuatExp(axis * a);
    const RQuat ref(Eigen::AngleAxis<RScalar>(a, axis));
    EXPECT_LT(QuatAngleBetween(q, ref), 1e-14);
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
    EXPECT_LT((QuatLog(q) - axis * a).norm(), 1e-13);
  }
}

TEST(Quaternion, ExpIsAccurateForTinyAngles) {
  // Across the series/closed-form switch at 1e-4 rad the two must agree to rounding, and a
  // tiny rotation must rotate by exactly its angle.
  for (RScalar a : {1e-300, 1e-12, 1e-8, 0.99e-4, 1.01e-4, 1e-3}) {
    const RQuat q = QuatExp(RVec3(a, 0, 0));
    EXPECT_NEAR(q.x(), std::sin(a / 2), 1e-17 + 1e-16 * std::sin(a / 2)) << a;
    EXPECT_NEAR(q.w(), std::cos(a / 2), 1e-16) << a;
  }
}

TEST(Quaternion, FromToIsMinimalAndHandlesAntiparallel) {
  std::mt19937_64 rng(2);
  for (int i = 0; i < 1000; ++i) {
    const RVec3 a = RandomUnit(rng), b = RandomUnit(rng);
    const RQuat q = QuatFromTo(a, b);
    EXPECT_LT((q * a - b).norm(), 1e-14);
    // Minimal: the rotation angle equals the angle between the vectors (atan2 form, exact
    // for small angles where acos is not).
    EXPECT_NEAR(QuatAngleBetween(RQuat::Identity(), q), std::atan2(a.cross(b).norm(), a.dot(b)),
                1e-14);
  }
  const RVec3 a = RVec3(1, 2, 3).normalized();
  const RQuat q = QuatFromTo(a, -a);
  EXPECT_LT((q * a + a).norm(), 1e-14);
}

TEST(Quaternion, NormalizedRefusesZeroAndNonFinite) {
  EXPECT_FALSE(QuatNormalized(RQuat(0, 0, 0, 0)).has_value());
  // Any non-zero scale has a direction, including ones whose squared norm over- or
  // underflows.
  for (RScalar scale : {1e-200, 1e-13, 1e200}) {
    const auto q = QuatNormalized(RQuat(scale, 0, 0, scale));
    ASSERT_TRUE(q.has_value()) << scale;
    EXPECT_NEAR(q->w(), std::sqrt(0.5), 2.3e-16) << scale;  // 2 ulps
  }
  EXPECT_FALSE(QuatNormalized(RQuat(NAN, 0, 0, 1)).has_value());
  EXPECT_FALSE(QuatNormalized(RQuat(INFINITY, 0, 0, 1)).has_value());
  const auto q = QuatNormalized(RQuat(2, 0, 0, 0));
  ASSERT_TRUE(q.has_value());
  EXPECT_EQ(q->w(), 1.0);
}

TEST(Math, OrthonormalBasisIsRightHandedAndOrthonormal) {
  std::mt19937_64 rng(3);
  for (int i = 0; i < 1000; ++i) {
    RVec3 a = RandomUnit(rng);
    if (i == 0) a = RVec3(0, 0, -1);  // the branch's edge case
    if (i == 1) a = RVec3(0, 0, 1);
    RVec3 b, c;
    OrthonormalBasis(a, b, c);
    EXPECT_NEAR(b.norm(), 1, 1e-15);
    EXPECT_NEAR(c.norm(), 1, 1e-15);
    EXPECT_NEAR(a.dot(b), 0, 1e-15);
    EXPECT_NEAR(a.dot(c), 0, 1e-15);
    EXPECT_LT((a.cross(b) - c).norm(), 1e-15);
  }
}

TEST(Math, SkewIsTheCrossProduct) {
  const RVec3 v(1, -2, 3), w(0.5, 4, -1);
  EXPECT_LT((Skew(v) * w - v.cross(w)).norm(), 1e-15);
}

// Reference values from an independent algorithm: for phi = am(u|m), u = F(phi|m), with F
// from Carlson's symmetric integral, F(phi|m) = sin(phi) RF(cos^2 phi, 1 - m sin^2 phi, 1)
// on |phi| <= pi/2 and F(phi + n pi) = F(phi) + 2 n K. Then sn = sin(phi), cn = cos(phi),
// dn = sqrt(1 - m sin^2 phi), the last written cos^2 + mc sin^2 to keep its digits.
namespace {
RScalar CarlsonRF(RScalar x, RScalar y, RScalar z) {
  for (int i = 0; i < 60; ++i) {
    const RScalar sx = std::sqrt(x), sy = std::sqrt(y), sz = std::sqrt(z);
    const RScalar lam = sx * sy + sy * sz + sz * sx;
    x = 0.25 * (x + lam), y = 0.25 * (y + lam), z = 0.25 * (z + lam);
  }
  return 1 / std::sqrt(x);  // x, y, z have converged to one value
}
RScalar IncompleteF(RScalar phi, RScalar mc) {
  const RScalar n = std::round(phi / kPi);
  const RScalar r = phi - n * kPi;
  const RScalar s = std::sin(r), c = std::cos(r);
  const RScalar K = CarlsonRF(0, mc, 1);
  return s * CarlsonRF(c * c, c * c + mc * s * s, 1) + 2 * n * K;
}
}  // namespace

TEST(Elliptic, SnCnDnInvertTheIncompleteIntegral) {
  for (RScalar m : {0.0, 0.1, 0.5, 0.9, 0.999, 1 - 1e-8}) {
    for (RScalar phi : {-2.0, -0.3, -0.049, 1e-5, 0.01, 0.03, 0.0499, 0.051, 0.7, 1.5, 3.0, 7.0}) {
      const RScalar mc = 1 - m;
      const RScalar u = IncompleteF(phi, mc);
      const RJacobiSnCnDn r = JacobiSnCnDn(u, m, mc);
      const RScalar s = std::sin(phi), c = std::cos(phi);
      EXPECT_NEAR(r.sn, s, 2e-16 + 1e-13 * std::abs(u)) << "m=" << m << " phi=" << phi;
      EXPECT_NEAR(r.cn, std::cos(phi), 1e-13) << "m=" << m << " phi=" << phi;
      EXPECT_NEAR(r.dn, std::sqrt(c * c + mc * s * s), 1e-13)
          << "m=" << m << " phi=" << phi;
    }
  }
}

TEST(Elliptic, LimitsAndIdentities) {
  // m = 1: sn = tanh, cn = dn = sech; the identities hold for every m.
  const RJacobiSnCnDn h = JacobiSnCnDn(0.8, 1, 0);
  EXPECT_NEAR(h.sn, std::tanh(0.8), 2e-16);
  EXPECT_NEAR(h.cn, 1 / std::cosh(0.8), 2e-16);
  for (RScalar mc : {1.0, 0.3, 1e-6, 1e-12, 1e-16, 1e-18}) {
    const RScalar m = 1 - mc;
    for (RScalar u : {-5.0, 0.1, 1.0, 4.0, 30.0}) {
      const RJacobiSnCnDn r = JacobiSnCnDn(u, m, mc);
      EXPECT_NEAR(r.sn * r.sn + r.cn * r.cn, 1, 4e-15);
      EXPECT_NEAR(r.dn * r.dn + m * r.sn * r.sn, 1, 4e-15);
    }
  }
  // Quarter period: sn(K) = 1, and K(0) = pi/2.
  EXPECT_NEAR(EllipticK(1), kPi / 2, 1e-15);
  for (RScalar m : {0.3, 0.9, 0.999999}) {
    const RScalar K = EllipticK(1 - m);
    EXPECT_NEAR(JacobiSnCnDn(K, m, 1 - m).sn, 1, 1e-14) << m;
    EXPECT_NEAR(JacobiSnCnDn(K, m, 1 - m).cn, 0, 1e-13) << m;
  }
}
