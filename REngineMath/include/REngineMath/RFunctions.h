// The transcendental functions the step uses, computed by REngine itself from IEEE additions,
// multiplications, divisions and square roots only, so that every machine and compiler gets
// the same bits. The C library's sin, cos, atan2, exp, ... are not correctly rounded and
// differ in their last bits between implementations: glibc's x86-64 build picks an FMA code
// path on CPUs that have FMA and another on those that do not, its 64-bit ARM build is
// compiled with contracted multiply-adds, and other C libraries use other polynomials. The
// engine's math therefore never calls them where a result reaches the simulation
// (tools/cross_check.sh compares whole runs on x86-64 and 64-bit ARM).
//
// Accuracy, measured against the long-double C library over millions of arguments
// (tests/math/functions_test.cpp asserts the bounds), in ulps (units in the last place of the
// exact result): within 1 ulp for Sin, Cos, Exp and Expm1, 1.5 for Atan2, Cosh and Hypot, 2.5
// for Asin and Tanh. Sin and Cos hold that for |x| < 8e5 rad; beyond, the reduction's absolute error
// is below 1e-15 rad up to 2^50 rad (where the argument's own spacing is 0.25 rad) and the
// result stays in [-1, 1] and is the same everywhere. Special values follow C99 Annex F (NaN
// in, NaN out; sin(-0) = -0; exp(-inf) = 0; atan2 of zeros and infinities by quadrant).
// These need -ffp-contract=off (REngineMath sets it, publicly) and no -ffast-math.
#pragma once

#include <REngineMath/RMath.h>

namespace REngine {

RScalar Sin(RScalar x);
RScalar Cos(RScalar x);
// sin(x) and cos(x) with one argument reduction.
void SinCos(RScalar x, RScalar& s, RScalar& c);
// The angle of (x, y) in [-pi, pi], as std::atan2(y, x).
RScalar Atan2(RScalar y, RScalar x);
RScalar Asin(RScalar x);
RScalar Exp(RScalar x);
// exp(x) - 1, accurate for small x.
RScalar Expm1(RScalar x);
RScalar Tanh(RScalar x);
RScalar Cosh(RScalar x);
// sqrt(x^2 + y^2) without overflow or underflow in the squares.
RScalar Hypot(RScalar x, RScalar y);

}  // namespace REngine
