// Private to REnginePhysics: the contact solver's row arithmetic, shared by the contact
// solver, the impact phase and the island solver (RIntegrator's subsystem files): a
// direction's lever arms and effective mass, the relative speed along it, an impulse
// applied along it, and the friction step through the 2 x 2 tangent block.
#pragma once

#include <REngineMath/RMath.h>

#include <Eigen/Core>

#include <cstdint>
#include <limits>

namespace REngine::solver {

inline std::uint64_t PairKey(std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; }

// The linear part of the coupling between unit directions d1 and d2 through one body:
// d1 . (M^-1 d2) with M^-1 its inverse mass, per world axis when it has linear locks (0 on
// a locked axis). dd is d1 . d2 (1 when d1 = d2), so an unlocked body computes what it did
// before locks existed, bit for bit.
template <class Body>
RScalar LinearCoupling(const Body& s, const RVec3& d1, const RVec3& d2, RScalar dd) {
  return s.linLocked ? s.invM * d1.cwiseProduct(s.linMask).dot(d2) : s.invM * dd;
}

// The inverse effective mass of a direction whose lever arms are set (dir.rAxd, dir.rBxd).
// With linear locks a direction can lie in what the locks hold, all but for rounding: a
// sphere locked on x and z, hit along the xz-plane by a kinematic paddle, answers only
// through a normal's y component of 1e-16 (its lever arm crosses the normal to zero), an
// effective mass of 1e-32 of its own, and an impulse of 1e30 N s. Below 1e-12 of the
// bodies' inverse masses (a response a millionth of the direction's) the direction has no
// effective mass: nothing the locks let the bodies do can answer it, and the contact gives
// way as between two kinematic bodies. Without locks the linear part alone is above that.
template <class Dir, class Body>
void SetEffectiveMass(Dir& dir, const Body& a, const Body& b) {
  dir.iA = a.invI * dir.rAxd;
  dir.iB = b.invI * dir.rBxd;
  if (!a.linLocked && !b.linLocked) {
    dir.k = a.invM + b.invM + dir.rAxd.dot(dir.iA) + dir.rBxd.dot(dir.iB);
    return;
  }
  dir.k = LinearCoupling(a, dir.d, dir.d, 1) + LinearCoupling(b, dir.d, dir.d, 1) +
          dir.rAxd.dot(dir.iA) + dir.rBxd.dot(dir.iB);
  if (!(dir.k > RScalar(1e-12) * (a.invM + b.invM))) dir.k = 0;
}

template <class Dir, class Body>
void SetDirection(Dir& dir, const RVec3& d, const RVec3& rA, const RVec3& rB, const Body& a,
                  const Body& b) {
  dir.d = d;
  dir.rAxd = rA.cross(d);
  dir.rBxd = rB.cross(d);
  SetEffectiveMass(dir, a, b);
}

template <class Dir>
RScalar Speed(const Dir& dir, const RVec3& va, const RVec3& wa, const RVec3& vb,
              const RVec3& wb) {
  return dir.d.dot(vb - va) + dir.rBxd.dot(wb) - dir.rAxd.dot(wa);
}

// A body of inverse mass 0 (static, kinematic) is not written: impulses cannot move it, and
// islands solved on several threads share the ground, which must then be only read. Along a
// locked axis a body's velocity does not change (its inverse mass is 0 there).
template <class Dir, class Body>
void Push(const Dir& dir, RScalar lambda, const Body& a, const Body& b, RVec3& va, RVec3& wa,
          RVec3& vb, RVec3& wb) {
  if (a.invM != 0) {
    const RVec3 dv = (a.invM * lambda) * dir.d;
    va -= a.linLocked ? RVec3(dv.cwiseProduct(a.linMask)) : dv;
    wa -= lambda * dir.iA;
  }
  if (b.invM != 0) {
    const RVec3 dv = (b.invM * lambda) * dir.d;
    vb += b.linLocked ? RVec3(dv.cwiseProduct(b.linMask)) : dv;
    wb += lambda * dir.iB;
  }
}

// A previous point closer than this fraction of the pair's size to a new one is taken as
// the same contact when no feature id matches (a corner sliding past a reference edge
// changes its id, not its place).
inline constexpr RScalar kWarmMatchDistance = RScalar(0.05);

// The tangential impulses that stop the sliding velocity (v1, v2) along two tangents of a
// point, solved together through their 2 x 2 effective mass. Bodies a and b: their linear
// coupling of the tangents is 0 (t1 . t2 = 0) unless one has linear locks.
template <class Dir, class Body>
Eigen::Matrix<RScalar, 2, 1> TangentStep(const Dir& t1, const Dir& t2, RScalar v1, RScalar v2,
                                         const Body& a, const Body& b) {
  RScalar k12 = t1.rAxd.dot(t2.iA) + t1.rBxd.dot(t2.iB);
  if (a.linLocked || b.linLocked) k12 += LinearCoupling(a, t1.d, t2.d, 0) + LinearCoupling(b, t1.d, t2.d, 0);
  const RScalar det = t1.k * t2.k - k12 * k12;
  // A direction with no effective mass (both bodies infinitely heavy along it: kinematic or
  // static against a body locked on the axes it would need) takes no impulse.
  if (!(det > 0)) return {t1.k > 0 ? -v1 / t1.k : 0, t2.k > 0 ? -v2 / t2.k : 0};
  return {-(t2.k * v1 - k12 * v2) / det, -(t1.k * v2 - k12 * v1) / det};
}

// The target of a row that is not in contact at the end of the step: never reached.
inline constexpr RScalar kNever = -std::numeric_limits<RScalar>::infinity();

}  // namespace REngine::solver
