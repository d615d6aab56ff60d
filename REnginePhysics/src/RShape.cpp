#include <REnginePhysics/RShape.h>

#include <Eigen/Eigenvalues>

#include <stdexcept>

namespace REngine {

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
