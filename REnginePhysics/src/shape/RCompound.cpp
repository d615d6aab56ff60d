// Compound shapes: preparation, mass properties and the narrow phase child by child
// (RCompound.h).
#include "shape/RCompound.h"

#include "collision/RGjkEpa.h"

#include <REngineMath/RQuaternion.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace REngine {

namespace {

// Inertia tensor (S frame, about the centre of mass) of mass properties mp scaled by rho.
RMat3 InertiaOf(const RMassProperties& mp, RScalar rho) {
  const RMat3 R = mp.q_SB.toRotationMatrix();
  return rho * (R * mp.principalMoments.asDiagonal() * R.transpose());
}

}  // namespace

RMassProperties CompoundMassProperties(const RShape& shape) {
  // Each child's mass, centre and inertia in the compound's frame S, then the union's about
  // its centre of mass: I = sum (I_i + m_i (|d_i|^2 E - d_i d_i^T)), d_i from the centre.
  RScalar mass = 0;
  RVec3 moment = RVec3::Zero();
  struct Part {
    RScalar m;
    RVec3 c;
    RMat3 I;
  };
  std::vector<Part> parts;
  parts.reserve(shape.children.size());
  for (const RCompoundChild& child : shape.children) {
    const RMassProperties mp = ComputeMassProperties(child.shape);
    const RQuat q = child.q_SC.normalized();
    const RMat3 R = q.toRotationMatrix();
    Part p;
    p.m = child.density * mp.volume;
    p.c = child.position_S + R * mp.com_S;
    p.I = R * InertiaOf(mp, child.density) * R.transpose();
    mass += p.m;
    moment += p.m * p.c;
    parts.push_back(p);
  }
  RMassProperties out;
  out.volume = mass;
  out.com_S = moment / mass;
  RMat3 I = RMat3::Zero();
  for (const Part& p : parts) {
    const RVec3 d = p.c - out.com_S;
    I += p.I + p.m * (d.squaredNorm() * RMat3::Identity() - d * d.transpose());
  }
  const Eigen::SelfAdjointEigenSolver<RMat3> eig(RScalar(0.5) * (I + I.transpose()));
  out.principalMoments = eig.eigenvalues();  // ascending
  RMat3 axes = eig.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  out.q_SB = RQuat(axes);
  out.q_SB.normalize();
  return out;
}

void PrepareCompound(const RShape& shape, RPreparedShape& p) {
  if (shape.children.empty()) throw RBodyError("shape.children", "must hold at least one child");
  if (shape.children.size() > RShape::kMaxChildren) {
    throw RBodyError("shape.children", "has " + std::to_string(shape.children.size()) + " children; at most " +
                                           std::to_string(RShape::kMaxChildren) + " are allowed");
  }
  for (std::size_t i = 0; i < shape.children.size(); ++i) {
    const RCompoundChild& child = shape.children[i];
    const std::string at = "shape.children[" + std::to_string(i) + "].";
    if (child.shape.type == RShapeType::kCompound || child.shape.type == RShapeType::kMesh) {
      throw RBodyError(at + "shape.type", "a compound or a mesh cannot be a child (children are convex)");
    }
    if (!AllFinite(child.position_S) || child.position_S.cwiseAbs().maxCoeff() > 1e12) {
      throw RBodyError(at + "position", "must be finite and within 1e12 m");
    }
    const RScalar qn = child.q_SC.coeffs().norm();
    if (!std::isfinite(qn) || !(qn > 0)) throw RBodyError(at + "orientation", "must be a finite quaternion of non-zero length");
    if (!std::isfinite(child.density) || !(child.density > 0)) throw RBodyError(at + "density", "must be finite and > 0");
    try {
      p.childShapes.push_back(PrepareShape(child.shape));
    } catch (const RBodyError& e) {
      throw RBodyError(at + e.Field(), e.Problem());
    }
  }
  p.unitMass = CompoundMassProperties(shape);
  // The union's mass properties must be numbers a body can use (densities of 1e308 overflow
  // the mass, children 1e12 m apart the moments): named here, not as the body's density.
  const RMassProperties& mp = p.unitMass;
  if (!std::isfinite(mp.volume) || !(mp.volume > 0) || !AllFinite(mp.com_S) || !AllFinite(mp.principalMoments) ||
      !(mp.principalMoments.minCoeff() > 0)) {
    throw RBodyError("shape.children", "give a mass, centre or inertia that is not a finite positive number");
  }
  p.q_BS = p.unitMass.q_SB.conjugate();
  p.p_BS = -(p.q_BS * p.unitMass.com_S);
  // Each child's body frame Bc in the compound's body frame B: p_B = q_BS (q_SC p_C + t) +
  // p_BS with p_C = q_BcSc^-1 (p_Bc - p_BcSc).
  RVec3 lo = RVec3::Constant(std::numeric_limits<RScalar>::infinity()), hi = -lo;
  p.boundingRadius = 0;
  p.children.resize(shape.children.size());
  for (std::size_t i = 0; i < shape.children.size(); ++i) {
    const RCompoundChild& child = shape.children[i];
    const RPreparedShape& c = *p.childShapes[i];
    const RQuat q_BBc = (p.q_BS * child.q_SC.normalized() * c.q_BS.conjugate()).normalized();
    RShapeChild& sc = p.children[i];
    sc.R_BC = q_BBc.toRotationMatrix();
    sc.p_BC = p.p_BS + p.q_BS * child.position_S - sc.R_BC * c.p_BS;
    RConvexShape& s = sc.shape;
    s.polyhedron = c.polyhedron_B.get();
    s.boundingRadius = c.boundingRadius;
    const RShapeType t = c.shape.type;
    s.radius = t == RShapeType::kSphere ? c.boundingRadius : t == RShapeType::kCapsule ? c.shape.radius : 0;
    s.halfHeight = t == RShapeType::kCapsule || t == RShapeType::kCylinder ? c.shape.halfHeight : 0;
    s.cylinderRadius = t == RShapeType::kCylinder ? c.shape.radius : 0;
    p.boundingRadius = std::max(p.boundingRadius, sc.p_BC.norm() + c.boundingRadius);
    // The child's box (in its frame, about its origin) turned into B.
    RVec3 center_C = RVec3::Zero(), half_C;
    if (s.polyhedron) {
      RVec3 l = RVec3::Constant(std::numeric_limits<RScalar>::infinity()), h = -l;
      for (const RVec3& v : s.polyhedron->Vertices()) l = l.cwiseMin(v), h = h.cwiseMax(v);
      center_C = RScalar(0.5) * (l + h), half_C = RScalar(0.5) * (h - l);
    } else {
      const RScalar across = s.radius + s.cylinderRadius;
      half_C = RVec3(across, s.halfHeight + s.radius, across);
    }
    const RVec3 center_B = sc.R_BC * center_C + sc.p_BC, half_B = sc.R_BC.cwiseAbs() * half_C;
    lo = lo.cwiseMin(center_B - half_B), hi = hi.cwiseMax(center_B + half_B);
  }
  p.boxCenter_B = RScalar(0.5) * (lo + hi), p.boxHalf_B = RScalar(0.5) * (hi - lo);
}

void ChildToBody(const RShapeChild& ca, std::uint32_t ia, std::uint32_t ib, RContactManifold& m) {
  const RMat3& R = ca.R_BC;
  const RVec3& t = ca.p_BC;
  m.query.normal = R * m.query.normal;
  m.query.witnessA = R * m.query.witnessA + t;
  m.query.witnessB = R * m.query.witnessB + t;
  m.normal = R * m.normal;
  // Feature ids distinct per child pair (warm starts match by pair and feature).
  const std::uint32_t pairKey = (ia + 1) * 0x9e3779b1u ^ (ib + 1) * 0x85ebca6bu;
  for (int k = 0; k < m.pointCount; ++k) {
    m.points[k].position = R * m.points[k].position + t;
    if (ia || ib) m.points[k].featureId ^= pairKey;
  }
  m.childA = ia, m.childB = ib;
}

RDistanceResult CompoundDistance(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X,
                                 RScalar cutoff) {
  RShapeChild aloneA, aloneB;
  std::uint32_t na, nb;
  const RShapeChild* ca = ChildrenOf(a, aloneA, na);
  const RShapeChild* cb = ChildrenOf(b, aloneB, nb);
  RDistanceResult best;
  best.separation = std::numeric_limits<RScalar>::infinity();
  const RShapeChild* bestA = nullptr;
  for (std::uint32_t i = 0; i < na; ++i) {
    for (std::uint32_t j = 0; j < nb; ++j) {
      const RRelativePose Xc = ChildPose(ca[i], cb[j], X);
      const RScalar bound = std::min(cutoff, best.separation);
      // A pair whose bounding spheres lie farther apart than the best so far (or the
      // cutoff) cannot be the answer.
      const RScalar spheres = Xc.t_AB.norm() - ca[i].shape.boundingRadius - cb[j].shape.boundingRadius;
      if (bestA && spheres > bound) continue;
      const RDistanceResult r = RCollisionSolver::DistanceWithin(ca[i].shape, cb[j].shape, Xc, bound);
      if (!bestA || r.separation < best.separation) best = r, bestA = &ca[i];
    }
  }
  best.normal = bestA->R_BC * best.normal;
  best.witnessA = bestA->R_BC * best.witnessA + bestA->p_BC;
  best.witnessB = bestA->R_BC * best.witnessB + bestA->p_BC;
  // The status against the whole shapes' band.
  best.status = StatusOf(best.separation, RCollisionSolver::kTouchingTolerance * (a.boundingRadius + b.boundingRadius));
  return best;
}

RContactManifold CompoundManifold(const RConvexShape& a, const RConvexShape& b, const RRelativePose& X,
                                  RScalar margin, RScalar cutoff, RScalar* droppedMin) {
  RShapeChild aloneA, aloneB;
  std::uint32_t na, nb;
  const RShapeChild* ca = ChildrenOf(a, aloneA, na);
  const RShapeChild* cb = ChildrenOf(b, aloneB, nb);
  // The deepest child pair, then its manifold.
  RScalar best = std::numeric_limits<RScalar>::infinity();
  std::uint32_t bi = 0, bj = 0;
  for (std::uint32_t i = 0; i < na; ++i) {
    for (std::uint32_t j = 0; j < nb; ++j) {
      const RRelativePose Xc = ChildPose(ca[i], cb[j], X);
      const RScalar spheres = Xc.t_AB.norm() - ca[i].shape.boundingRadius - cb[j].shape.boundingRadius;
      if (spheres > std::min(cutoff, best)) continue;
      const RScalar s = RCollisionSolver::DistanceWithin(ca[i].shape, cb[j].shape, Xc, std::min(cutoff, best)).separation;
      if (s < best) best = s, bi = i, bj = j;
    }
  }
  RContactManifold m;
  if (!(best < std::numeric_limits<RScalar>::infinity())) {
    m.query = CompoundDistance(a, b, X, cutoff);
    m.normal = m.query.normal;
    return m;
  }
  m = RCollisionSolver::ManifoldWithin(ca[bi].shape, cb[bj].shape, ChildPose(ca[bi], cb[bj], X), margin, cutoff,
                                       droppedMin);
  ChildToBody(ca[bi], a.children ? bi : 0, b.children ? bj : 0, m);
  return m;
}

bool RayCastCompound(const RConvexShape& shape, const RVec3& origin, const RVec3& direction, RScalar maxDistance,
                     RShapeRayHit& hit) {
  bool found = false;
  for (std::uint32_t i = 0; i < shape.childCount; ++i) {
    const RShapeChild& c = shape.children[i];
    const RVec3 o = c.R_BC.transpose() * (origin - c.p_BC), d = c.R_BC.transpose() * direction;
    RShapeRayHit h;
    if (RayCastShape(c.shape, o, d, found ? hit.distance : maxDistance, h) && (!found || h.distance < hit.distance)) {
      hit = h;
      hit.normal = c.R_BC * h.normal;
      found = true;
    }
  }
  return found;
}

}  // namespace REngine
