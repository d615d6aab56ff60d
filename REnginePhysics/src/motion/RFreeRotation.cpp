#include <REnginePhysics/RFreeRotation.h>
#include <REngineMath/RFunctions.h>

#include <REngineMath/REllipticFunctions.h>
#include <REngineMath/RQuaternion.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

namespace {

// 3-point Gauss-Legendre on [0, 1]: nodes 1/2 - c, 1/2, 1/2 + c with c = sqrt(3/5) / 2,
// weights 5/18, 8/18, 5/18.
constexpr RScalar kGaussOffset = RScalar(0.3872983346207416885179265399782400);
constexpr RScalar kGaussWeight[3] = {RScalar(5) / 18, RScalar(8) / 18, RScalar(5) / 18};
// Largest phase |lambda h| one quadrature panel spans: 3-point Gauss-Legendre's error is
// ~phase^7 / 2e6 relative, below 1e-16 at 0.25 rad.
constexpr RScalar kMaxPanelPhase = RScalar(0.25);
// Panels at most, per integral: a period spans 4 K(m) of phase, 26 panels on a round
// polhode and 320 at 1 - m = 1e-16; only a step exactly on the separatrix (no period) could
// ask for more, and gets this many (its precession then less accurate, its work bounded).
constexpr int kMaxPanels = 4096;

int Panels(RScalar phase) {
  return static_cast<int>(std::clamp(std::ceil(phase / kMaxPanelPhase), RScalar(1),
                                     RScalar(kMaxPanels)));
}

bool NearlyEqual(RScalar x, RScalar y) {
  return std::abs(x - y) <= RTol::kEqualMoments * std::max(x, y);
}

// Addition theorem: the Jacobi functions at u + v from those at u and at v. The
// denominator 1 - m sn_u^2 sn_v^2 is written dn_u^2 + m sn_u^2 cn_v^2: a sum of
// non-negative terms, with no cancellation near the separatrix (m -> 1).
RJacobiSnCnDn Add(const RJacobiSnCnDn& u, const RJacobiSnCnDn& v, RScalar m) {
  const RScalar den = u.dn * u.dn + m * u.sn * u.sn * v.cn * v.cn;
  if (!(den > 0)) {
    // Only on the separatrix (m = 1: sn = tanh, cn = dn = sech) far along it, where sech
    // has underflowed: the limit of the formula, tanh's own addition theorem (found by
    // fuzz_world: a box spun exactly onto the separatrix, stepped 1000 s, divided 0 by 0).
    const RScalar t = 1 + u.sn * v.sn;
    RJacobiSnCnDn r;
    r.sn = t != 0 ? std::clamp((u.sn + v.sn) / t, RScalar(-1), RScalar(1)) : u.sn;
    r.cn = r.dn = std::sqrt(std::max(RScalar(0), (1 - r.sn) * (1 + r.sn)));
    return r;
  }
  const RScalar inv = 1 / den;
  RJacobiSnCnDn r;
  r.sn = (u.sn * v.cn * v.dn + v.sn * u.cn * u.dn) * inv;
  r.cn = (u.cn * v.cn - u.sn * u.dn * v.sn * v.dn) * inv;
  r.dn = (u.dn * v.dn - m * u.sn * u.cn * v.sn * v.cn) * inv;
  return r;
}

}  // namespace

void RFreeRotation::SetInertia(const RVec3& I_B) {
  m_I_B = I_B;
  m_cacheValid = false;
  const bool e01 = NearlyEqual(I_B[0], I_B[1]);
  const bool e12 = NearlyEqual(I_B[1], I_B[2]);
  const bool e02 = NearlyEqual(I_B[0], I_B[2]);
  if (e01 && e12) {
    m_symmetry = RInertiaSymmetry::kSpherical;
  } else if (e01 || e12 || e02) {
    m_symmetry = RInertiaSymmetry::kSymmetric;
    m_axisUnique = e01 ? 2 : (e12 ? 0 : 1);
  } else {
    m_symmetry = RInertiaSymmetry::kGeneral;
    std::sort(m_sorted, m_sorted + 3, [&](int i, int j) { return I_B[i] < I_B[j]; });
  }
}

// Constants of the elliptic solution (Landau and Lifshitz, Mechanics, section 37), written
// for either side of the separatrix by naming the axes (a, b, c): c is the axis the polhode
// circles, b the intermediate one. With I_a < I_b < I_c, or I_a > I_b > I_c:
//   omega_a = A_a cn(tau), omega_b = A_b sn(tau), omega_c = s A_c dn(tau),
//   tau = lambda t, lambda = s sqrt((I_c - I_b)(M^2 - 2E I_a) / (I_a I_b I_c)),
//   k^2 = (I_b - I_a)(2E I_c - M^2) / ((I_c - I_b)(M^2 - 2E I_a)).
// Each of 2E I_c - M^2, M^2 - 2E I_a and M^2 - 2E I_b is summed from the components of L
// (terms of one sign, but for the last, whose sign is the side of the separatrix), never as
// the difference of two large numbers, so nothing cancels that the physics does not make
// sensitive. 1 - k^2 is computed on its own for the same reason.
bool RFreeRotation::ComputeConstants(RScalar h, const RVec3& w_B) {
  // A non-finite omega has no polhode: the caller's fallback carries the NaN to the
  // integrator, which puts the body back and reports it.
  if (!AllFinite(w_B) || !std::isfinite(h)) return false;
  const RVec3& I = m_I_B;
  // Every formula below is homogeneous in L: work with L / max|L_i| so that squares of
  // tiny components (1e-165) do not underflow to zero and divide it by itself.
  const RVec3 Lraw = I.cwiseProduct(w_B);
  const RScalar scale = Lraw.cwiseAbs().maxCoeff();
  // Below the smallest normal double there is no rotation to speak of (and 1 / scale would
  // overflow): the caller turns the body by omega h, which is nothing.
  if (!(scale >= std::numeric_limits<RScalar>::min())) return false;
  const RVec3 L = Lraw / scale;
  const int i1 = m_sorted[0], i2 = m_sorted[1], i3 = m_sorted[2];
  // M^2 - 2 E I_2 (scaled): positive when the polhode circles the axis of largest moment.
  const RScalar dSep = L[i1] * L[i1] * ((I[i1] - I[i2]) / I[i1]) +
                       L[i3] * L[i3] * ((I[i3] - I[i2]) / I[i3]);
  if (dSep >= 0) {
    m_a = i1, m_b = i2, m_c = i3;
  } else {
    m_a = i3, m_b = i2, m_c = i1;
  }
  const int a = m_a, b = m_b, c = m_c;
  const RScalar P = L[a] * L[a] * ((I[c] - I[a]) / I[a]) + L[b] * L[b] * ((I[c] - I[b]) / I[b]);
  const RScalar Q = L[b] * L[b] * ((I[b] - I[a]) / I[b]) + L[c] * L[c] * ((I[c] - I[a]) / I[c]);
  // Steady spins: about the axis of largest or smallest moment (P = 0: L_a = L_b = 0), or
  // exactly about the intermediate one (L_a = L_c = 0, on the separatrix's fixed point).
  // Omega is constant; the elliptic form would be 0/0 or lose its phase to underflow.
  // Q = 0 likewise: L_b and L_c so small against L_a that their squares underflow (found by
  // fuzz_world: (I_c - I_b) Q was a zero divisor); the spin is steady to 1e-300.
  if (P == 0 || Q == 0 || (L[a] == 0 && L[c] == 0)) return false;
  m_signC = w_B[c] < 0 ? RScalar(-1) : RScalar(1);
  // |L| from the scaled components when its square underflows (|L| < 1e-154; found by
  // fuzz_world: 1 / 0).
  const RScalar normL = Lraw.norm();
  m_invM = 1 / (normL > 0 ? normL : scale * L.norm());
  m_amp[0] = scale * std::sqrt(P / (I[a] * (I[c] - I[a])));
  m_amp[1] = scale * std::sqrt(P / (I[b] * (I[c] - I[b])));
  m_amp[2] = scale * std::sqrt(Q / (I[c] * (I[c] - I[a])));
  const RScalar denom = (I[c] - I[b]) * Q;
  m_m = std::clamp((I[b] - I[a]) * P / denom, RScalar(0), RScalar(1));
  m_mc = std::clamp((I[c] - I[a]) * dSep / denom, RScalar(0), RScalar(1));
  // Euler's equations change sign under an odd permutation of the axes, and so does the
  // direction the phase runs in.
  const bool evenOrder = (i2 - i1 + 3) % 3 == 1;
  m_lambda = (evenOrder ? m_signC : -m_signC) * scale * std::sqrt(denom / (I[a] * I[b] * I[c]));

  // Phase of the current state. The three ratios satisfy sn^2 + cn^2 = 1 and
  // dn^2 + k^2 sn^2 = 1 to rounding because the amplitudes came from this same state.
  m_phase.cn = w_B[a] / m_amp[0];
  m_phase.sn = w_B[b] / m_amp[1];
  m_phase.dn = std::abs(w_B[c]) / m_amp[2];

  // The precession angle is integrated by Gauss-Legendre on panels short enough in phase
  // (|lambda h| / panels <= kMaxPanelPhase) for its O(phase^7) error to stay at rounding
  // level; one panel at game rates, more for a body spinning at hundreds of rad/s.
  const RScalar rate = std::abs(m_lambda);
  if (!std::isfinite(rate)) return false;
  m_periods = 0, m_psiPeriod = 0, m_hRest = h;
  // A period is at least 2 pi of phase (K >= pi / 2): only beyond that can whole periods fit.
  // (h < 0 runs the flow backwards: whole periods are counted negative.)
  if (rate * std::abs(h) > 2 * kPi) {
    const RScalar period = 4 * EllipticK(m_mc) / rate;  // s
    if (std::isfinite(period) && period > 0 && period <= std::abs(h)) {
      m_periods = std::copysign(std::floor(std::abs(h) / period), h);
      m_hRest = h - m_periods * period;
      const int panels = m_periodPanels = Panels(rate * period);
      const RScalar hp = period / panels;
      RJacobiSnCnDn nodes[3];
      for (int j = 0; j < 3; ++j) {
        const RScalar offset = RScalar(0.5) + (j - 1) * kGaussOffset;
        nodes[j] = JacobiSnCnDn(m_lambda * (offset * hp), m_m, m_mc);
      }
      m_psiPeriod = PsiIntegral(m_phase, panels, nodes, JacobiSnCnDn(m_lambda * hp, m_m, m_mc),
                                period);
    }
  }
  m_panels = Panels(rate * std::abs(m_hRest));
  const RScalar hp = m_hRest / m_panels;
  // Each offset evaluated on its own: building h from h/2 by the addition theorem costs
  // less but rounds the state's phase twice per step, which the separatrix amplifies
  // (measured: 17x the orientation error on the Dzhanibekov scene).
  m_node[0] = JacobiSnCnDn(m_lambda * ((RScalar(0.5) - kGaussOffset) * hp), m_m, m_mc);
  m_node[1] = JacobiSnCnDn(m_lambda * (RScalar(0.5) * hp), m_m, m_mc);
  m_node[2] = JacobiSnCnDn(m_lambda * ((RScalar(0.5) + kGaussOffset) * hp), m_m, m_mc);
  m_end = JacobiSnCnDn(m_lambda * m_hRest, m_m, m_mc);
  m_panelStep = m_panels > 1 ? JacobiSnCnDn(m_lambda * hp, m_m, m_mc) : m_end;
  m_cacheH = h;
  return true;
}

// Inlined into Advance, the per-body call of every step: a call of its own costs a free body
// 30 instructions a step, 2% of a debris cloud's step.
#if defined(__GNUC__)
[[gnu::always_inline]]
#endif
inline bool RFreeRotation::AdvanceClosedForm(RScalar h, RVec3& w_B, RQuat& q_WB) const {
  switch (m_symmetry) {
    case RInertiaSymmetry::kSpherical:
      q_WB = q_WB * QuatExp(h * w_B);
      q_WB.normalize();
      return true;
    case RInertiaSymmetry::kSymmetric: {
      // H = |L|^2 / (2 I_t) + L_s^2 (1/I_s - 1/I_t) / 2: the two parts commute, so the
      // exact flow is the product of their flows. The first spins the body about L itself
      // (L_B unchanged); the second spins it about the symmetry axis e_s while L_B
      // precesses the other way about e_s.
      const int s = m_axisUnique;
      const int t = (s + 1) % 3;
      const RScalar Is = m_I_B[s], It = m_I_B[t];
      RVec3 spin = w_B;  // L_B / I_t
      spin[s] *= Is / It;
      const RScalar rate = w_B[s] * (1 - Is / It);  // L_s (1/I_s - 1/I_t)
      RVec3 axis = RVec3::Zero();
      axis[s] = 1;
      q_WB = q_WB * QuatExp(h * spin) * QuatAxisAngle(axis, h * rate);
      // omega_perp rotates by -h*rate about e_s (equal moments: omega_perp is L_perp / I_t).
      const int u = (s + 1) % 3, v = (s + 2) % 3;
      RScalar sn, cs;
      SinCos(h * rate, sn, cs);
      const RScalar wu = w_B[u], wv = w_B[v];
      w_B[u] = cs * wu + sn * wv;
      w_B[v] = -sn * wu + cs * wv;
      q_WB.normalize();
      return true;
    }
    case RInertiaSymmetry::kGeneral:
      break;
  }
  return false;
}

void RFreeRotation::Flow(RScalar h, RVec3& w_B, RQuat& q_WB) const {
  if (w_B.isZero(0) || AdvanceClosedForm(h, w_B, q_WB)) return;
  RFreeRotation general = *this;
  general.Advance(h, w_B, q_WB);
}

void RFreeRotation::Advance(RScalar h, RVec3& w_B, RQuat& q_WB) {
  if (w_B.isZero(0) || AdvanceClosedForm(h, w_B, q_WB)) return;

  const RVec3& I = m_I_B;
  if (!(m_cacheValid && m_cacheH == h && m_cacheW_B == w_B)) {
    if (!ComputeConstants(h, w_B)) {
      q_WB = q_WB * QuatExp(h * w_B);
      q_WB.normalize();
      m_cacheValid = false;
      return;
    }
    m_align0 = QuatFromTo(I.cwiseProduct(w_B) * m_invM, PoleAxis());
  }
  const RScalar m = m_m;
  const RVec3 e = PoleAxis();
  const RScalar dPsi = PsiIntegral(m_phase, m_panels, m_node, m_panelStep, m_hRest) +
                       m_periods * m_psiPeriod;

  const RJacobiSnCnDn phase1 = Add(m_phase, m_end, m);
  const RVec3 w1 = OmegaOf(phase1);
  // q1 = q0 m(l0)^-1 Rot(e, dPsi) m(l1): maps l1 to where q0 mapped l0, so L_W is fixed.
  // m(l1) is next step's m(l0) while the polhode is unchanged.
  const RQuat align1 = QuatFromTo(I.cwiseProduct(w1) * m_invM, e);
  q_WB = q_WB * m_align0.conjugate() * QuatAxisAngle(e, dPsi) * align1;
  m_align0 = align1;
  q_WB.normalize();

  w_B = w1;
  m_phase = phase1;
  m_cacheW_B = w_B;
  m_cacheValid = true;
}

RVec3 RFreeRotation::OmegaOf(const RJacobiSnCnDn& j) const {
  RVec3 w;
  w[m_a] = m_amp[0] * j.cn;
  w[m_b] = m_amp[1] * j.sn;
  w[m_c] = m_signC * m_amp[2] * j.dn;
  return w;
}

// psi' = omega . (l + e) / (1 + l . e), integrated by Gauss-Legendre on each panel.
RScalar RFreeRotation::PsiIntegral(const RJacobiSnCnDn& start, int panels,
                                   const RJacobiSnCnDn* nodes, const RJacobiSnCnDn& panelStep,
                                   RScalar length) const {
  const RVec3 e = PoleAxis();
  RScalar psi = 0;
  RJacobiSnCnDn panelStart = start;
  for (int p = 0; p < panels; ++p) {
    if (p > 0) panelStart = Add(panelStart, panelStep, m_m);
    for (int j = 0; j < 3; ++j) {
      const RVec3 w = OmegaOf(Add(panelStart, nodes[j], m_m));
      const RVec3 l = m_I_B.cwiseProduct(w) * m_invM;
      psi += kGaussWeight[j] * (w.dot(l + e) / (1 + l.dot(e)));
    }
  }
  return psi * (length / panels);
}

}  // namespace REngine
