// Exact torque-free rotation of a rigid body.
//
// Method. With no torque, the body-frame angular momentum L_B follows Euler's equations,
// whose solution is closed form: Jacobi elliptic functions for three distinct principal
// moments, a uniform precession for two equal moments, a constant for three. REngine steps
// that solution instead of approximating it: energy, |L| and the world angular momentum
// L_W = q_WB L_B are conserved to rounding at any step size, and the body's polhode (the
// path of L_B, hence the flips of the intermediate axis) is exact.
//
// The orientation follows from L_W being fixed: q_WB(t) = G Rot(e, psi(t)) m(l(t)), where
// l = L_B/|L|, e is the body axis the polhode circles, m(l) is the minimal rotation taking
// l to e and G is constant. The only quantity not in closed form is the angle psi, whose
// rate is psi' = omega . (l + e) / (1 + l . e) (regular: l . e > 0 on every polhode about
// e). It is integrated over each step with 3-point Gauss-Legendre quadrature at the exact
// omega(t), on enough panels that each spans at most 0.25 rad of phase: error O(h^7) per
// step, so the orientation error is O(h^6) globally and
// conservation of L_W is untouched by it (Rot(e, psi) fixes e, whatever psi is).
//
// Cost per body-step. A symmetric or spherical body: two or one quaternion exponentials.
// A general body: two Jacobi evaluations when its angular momentum changed this step
// (a collision, a torque), none when it did not (they are cached), plus four addition
// formulas and three quaternion products. Measured by tools/bench/bench_motion.
#pragma once

#include <REnginePhysics/RAbi.h>
#include <REngineMath/REllipticFunctions.h>
#include <REngineMath/RMath.h>

#include <cstdint>

namespace REngine {

// What the principal moments allow; decided once when the moments are set.
enum class RInertiaSymmetry : std::uint8_t {
  kSpherical,  // I1 = I2 = I3: omega is constant
  kSymmetric,  // two equal moments: L_B precesses uniformly about the third axis
  kGeneral,    // three distinct moments: Jacobi elliptic functions
};

// The free rotation's constants and cache: RFreeRotation holds them as a private base, and
// save and load reach them (the cache, bit for bit) through the engine's private header
// body/RBodyAccess.h.
struct RFreeRotationCore {
  RVec3 m_I_B = RVec3::Ones();
  RInertiaSymmetry m_symmetry = RInertiaSymmetry::kSpherical;
  int m_axisUnique = 0;         // kSymmetric: the axis whose moment differs
  int m_sorted[3] = {0, 1, 2};  // kGeneral: body axes by ascending moment

  // kGeneral: the polhode's constants and the Jacobi values at the step's quadrature nodes,
  // valid while the step size and the angular momentum are those they were computed for.
  // The cache key is the step's own output bit for bit, so reuse is exact, not approximate.
  bool m_cacheValid = false;
  RScalar m_cacheH = 0;
  RVec3 m_cacheW_B = RVec3::Zero();  // omega the last step produced
  int m_a = 0, m_b = 1, m_c = 2;     // body axes in the roles of the solution
  RScalar m_signC = 1;               // sign of omega_c, constant on the polhode
  RScalar m_invM = 0;                // 1 / |L|, 1/(kg m^2/s)
  RQuat m_align0 = RQuat::Identity();  // minimal rotation taking l of the last output to e
  RScalar m_amp[3] = {0, 0, 0};      // amplitudes of omega_a, omega_b, omega_c, rad/s
  RScalar m_m = 0, m_mc = 1;         // elliptic parameter k^2 and 1 - k^2
  RScalar m_lambda = 0;              // phase rate, rad/s (signed)
  int m_panels = 1;                  // quadrature panels per step
  RJacobiSnCnDn m_phase;             // Jacobi functions at the last output's phase
  RJacobiSnCnDn m_node[3];           // at the phase offsets of a panel's 3 Gauss nodes
  RJacobiSnCnDn m_panelStep;         // at the phase offset of one panel
  RJacobiSnCnDn m_end;               // at the phase offset of the step less its periods
  // A step longer than a period of the polhode (a fast spin: 1e8 rad/s, or a 4 mm box given
  // 100 N m): omega is periodic, so the precession over a whole period is the same from any
  // phase. The step is m_periods whole periods of m_psiPeriod each and a remainder m_hRest
  // integrated by panels, so its work is bounded by one period's panels however fast the
  // body spins. Otherwise m_periods = 0 and m_hRest = h.
  RScalar m_periods = 0;             // whole periods in a step
  RScalar m_psiPeriod = 0;           // precession over one period, rad
  RScalar m_hRest = 0;               // the step less its whole periods, s
  int m_periodPanels = 0;            // panels of the one-period integral
};

class RFreeRotation : private RFreeRotationCore {
 public:
  // I_B: principal moments about the centre of mass, body frame, kg m^2, all > 0.
  void SetInertia(const RVec3& I_B);
  RInertiaSymmetry Symmetry() const { return m_symmetry; }

  // Advances (w_B, q_WB) by h seconds of torque-free motion. w_B: angular velocity, body
  // frame, rad/s; q_WB: body-to-world rotation. h may be negative (runs time backwards).
  void Advance(RScalar h, RVec3& w_B, RQuat& q_WB);
  // The same flow without touching the cache: where (w_B, q_WB) is h seconds on. The
  // spherical and symmetric closed forms are Advance's own; a general body's works out its
  // constants on a copy. (The impact phase asks where a body has turned to at an impact's
  // time, and the motion then continues from there with Advance.)
  void Flow(RScalar h, RVec3& w_B, RQuat& q_WB) const;

  // Quadrature panels the last general-case step integrated (its cost): at most
  // 2 x 4096 however fast the body spins (see m_periods).
  int QuadraturePanels() const { return m_panels + (m_periods > 0 ? m_periodPanels : 0); }

 private:
  // The spherical and symmetric closed forms; false for a general body, which they leave as it was.
  bool AdvanceClosedForm(RScalar h, RVec3& w_B, RQuat& q_WB) const;
  // Fills the polhode's constants for (h, w_B); false for a steady spin (omega constant).
  bool ComputeConstants(RScalar h, const RVec3& w_B);
  // The body axis the polhode circles, signed to the side the angular momentum is on.
  RVec3 PoleAxis() const {
    RVec3 e = RVec3::Zero();
    e[m_c] = m_signC;
    return e;
  }

  RVec3 OmegaOf(const RJacobiSnCnDn& j) const;
  // The precession angle over `panels` panels of `length` s from phase `start`, by 3-point
  // Gauss-Legendre on each (nodes: Jacobi values at the Gauss offsets of one panel).
  RScalar PsiIntegral(const RJacobiSnCnDn& start, int panels, const RJacobiSnCnDn* nodes,
                      const RJacobiSnCnDn& panelStep, RScalar length) const;
};

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_FREE_ROTATION(X) \
  X(RFreeRotationCore) \
  X(RFreeRotation)
RENGINE_ABI_CHECK(kFreeRotation, RENGINE_ABI_TYPES_FREE_ROTATION)
