#include <REnginePhysics/RShape.h>

#include "shape/RCompound.h"

#include <Eigen/Eigenvalues>

#include <stdexcept>
#include <utility>

namespace REngine {

RShape RShape::Sphere(RScalar radius) {
  RShape s;
  s.type = RShapeType::kSphere, s.radius = radius;
  return s;
}

RShape RShape::Box(const RVec3& halfExtents) {
  RShape s;
  s.type = RShapeType::kBox, s.halfExtents = halfExtents;
  return s;
}

RShape RShape::Capsule(RScalar radius, RScalar halfHeight) {
  RShape s;
  s.type = RShapeType::kCapsule, s.radius = radius, s.halfHeight = halfHeight;
  return s;
}

RShape RShape::Cylinder(RScalar radius, RScalar halfHeight) {
  RShape s;
  s.type = RShapeType::kCylinder, s.radius = radius, s.halfHeight = halfHeight;
  return s;
}

RShape RShape::Hull(std::vector<RVec3> points_S) {
  RShape s;
  s.type = RShapeType::kHull, s.points = std::move(points_S);
  return s;
}

RShape RShape::Mesh(std::vector<RVec3> vertices_S, std::vector<std::array<std::uint32_t, 3>> triangles) {
  RShape s;
  s.type = RShapeType::kMesh, s.points = std::move(vertices_S), s.triangles = std::move(triangles);
  return s;
}

RShape RShape::Compound(std::vector<RCompoundChild> children) {
  RShape s;
  s.type = RShapeType::kCompound, s.children = std::move(children);
  return s;
}

RMassProperties ComputeMassProperties(const RShape& shape) {
  RMassProperties mp;
  switch (shape.type) {
    case RShapeType::kSphere: {
      const RScalar r = shape.radius;
      mp.volume = RScalar(4) / 3 * kPi * r * r * r;
      // I = 2/5 m r^2 with m = volume * 1
      mp.principalMoments = RVec3::Constant(RScalar(2) / 5 * mp.volume * r * r);
      return mp;
    }
    case RShapeType::kBox: {
      const RVec3 e = shape.halfExtents;
      const RVec3 d = 2 * e;  // full side lengths
      mp.volume = d.x() * d.y() * d.z();
      // I_x = m (d_y^2 + d_z^2) / 12, and cyclically
      mp.principalMoments = RVec3(d.y() * d.y() + d.z() * d.z(), d.x() * d.x() + d.z() * d.z(),
                                  d.x() * d.x() + d.y() * d.y()) *
                            (mp.volume / 12);
      return mp;
    }
    case RShapeType::kCapsule: {
      // A cylinder of length L = 2h and two half balls. About the axis (y): m_c r^2/2 and
      // 2/5 m_s r^2. Across it: the cylinder's m_c (L^2/12 + r^2/4); each half ball's own
      // 2/5 (m_s/2) r^2 about its flat face's centre, moved by the parallel-axis theorem
      // to its centroid (3r/8 from the face) and then to h + 3r/8 from the centre:
      // m_s (2r^2/5 + L^2/4 + 3 L r/8) for the two.
      const RScalar r = shape.radius, L = 2 * shape.halfHeight;
      const RScalar mc = kPi * r * r * L, ms = RScalar(4) / 3 * kPi * r * r * r;
      mp.volume = mc + ms;
      const RScalar axial = mc * r * r / 2 + ms * RScalar(2) / 5 * r * r;
      const RScalar across = mc * (L * L / 12 + r * r / 4) + ms * (RScalar(2) / 5 * r * r + L * L / 4 + RScalar(3) / 8 * L * r);
      mp.principalMoments = RVec3(across, axial, across);
      return mp;
    }
    case RShapeType::kCylinder: {
      // About the axis (y) m r^2 / 2; across it m (3 r^2 + L^2) / 12 with L = 2h.
      const RScalar r = shape.radius, L = 2 * shape.halfHeight;
      mp.volume = kPi * r * r * L;
      const RScalar axial = mp.volume * r * r / 2;
      const RScalar across = mp.volume * (3 * r * r + L * L) / 12;
      mp.principalMoments = RVec3(across, axial, across);
      return mp;
    }
    case RShapeType::kCompound:
      return CompoundMassProperties(shape);
    case RShapeType::kMesh:
      // Triangles enclose no volume: a mesh's body is static or kinematic, massless.
      mp.volume = 0;
      mp.principalMoments = RVec3::Zero();
      return mp;
    case RShapeType::kHull:
      break;
  }
  return ComputeMassProperties(RConvexPolyhedron::Hull(shape.points));
}

RMassProperties ComputeMassProperties(const RConvexPolyhedron& polyhedron) {
  const RPolyhedronMass pm = polyhedron.MassProperties();
  RMassProperties mp;
  mp.volume = pm.volume;
  mp.com_S = pm.centroid;
  const Eigen::SelfAdjointEigenSolver<RMat3> eig(pm.inertia);
  mp.principalMoments = eig.eigenvalues();  // ascending
  RMat3 axes = eig.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);  // a rotation, not a reflection
  mp.q_SB = RQuat(axes);
  mp.q_SB.normalize();
  return mp;
}

}  // namespace REngine
