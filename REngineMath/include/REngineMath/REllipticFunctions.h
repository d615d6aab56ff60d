// Jacobi elliptic functions, the closed-form solution of the torque-free rigid body.
#pragma once

#include <REngineMath/RMath.h>

namespace REngine {

struct RJacobiSnCnDn {
  RScalar sn = 0;
  RScalar cn = 1;
  RScalar dn = 1;
};

// sn(u|m), cn(u|m), dn(u|m) for parameter m = k^2 in [0, 1]. The caller passes the
// complementary parameter mc = 1 - m separately because near m = 1 (a rigid body near its
// separatrix) computing 1 - m from m would cancel away the digits that decide the motion.
// Method: for |u| <= 0.05 (the phase one step of a body spinning at game rates advances),
// the Maclaurin series, about 40 flops. Otherwise the descending Landen transformation /
// arithmetic-geometric mean (Abramowitz and Stegun 16.4), 4 to 7 iterations for mc > 1e-8,
// at most 12 at mc = 1e-300, about 2 + 2n transcendental calls for n iterations; with the
// exact limits sin/cos/1 at m = 0 and tanh/sech/sech at mc = 0.
RJacobiSnCnDn JacobiSnCnDn(RScalar u, RScalar m, RScalar mc);

// Complete elliptic integral of the first kind K(m), given mc = 1 - m for the reason above:
// the quarter period of sn and cn. Infinite at mc = 0.
RScalar EllipticK(RScalar mc);

}  // namespace REngine
