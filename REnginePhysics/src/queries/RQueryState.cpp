// Keeping the queries' body forms and tree current (RQueryState.h).
#include "queries/RQueryState.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace REngine {

RConvexShape ConvexShapeOf(const RPreparedShape& prepared) {
  RConvexShape s;
  s.polyhedron = prepared.polyhedron_B.get();
  const bool capsule = prepared.shape.type == RShapeType::kCapsule;
  const bool cylinder = prepared.shape.type == RShapeType::kCylinder;
  s.radius = s.polyhedron || cylinder ? 0 : capsule ? prepared.shape.radius : prepared.boundingRadius;
  s.halfHeight = capsule || cylinder ? prepared.shape.halfHeight : 0;
  s.cylinderRadius = cylinder ? prepared.shape.radius : 0;
  if (!prepared.children.empty()) {  // a compound: its children, no radius of its own
    s.radius = 0;
    s.children = prepared.children.data();
    s.childCount = static_cast<std::uint32_t>(prepared.children.size());
  }
  if (prepared.mesh_B) {  // a mesh: its triangles, no radius of its own
    s.radius = 0;
    s.mesh = prepared.mesh_B.get();
  }
  s.boundingRadius = prepared.boundingRadius;
  return s;
}

RLocalBox LocalBoxOf(const RConvexShape& shape) {
  RLocalBox box;
  if (shape.mesh) {
    box.center_B = RScalar(0.5) * (shape.mesh->BoxMin() + shape.mesh->BoxMax());
    box.half_B = RScalar(0.5) * (shape.mesh->BoxMax() - shape.mesh->BoxMin());
    return box;
  }
  if (shape.children) {
    // The children's boxes turned into the body frame, joined.
    RVec3 lo = RVec3::Constant(std::numeric_limits<RScalar>::infinity()), hi = -lo;
    for (std::uint32_t i = 0; i < shape.childCount; ++i) {
      const RShapeChild& c = shape.children[i];
      const RLocalBox child = LocalBoxOf(c.shape);
      const RVec3 center = c.R_BC * child.center_B + c.p_BC, half = c.R_BC.cwiseAbs() * child.half_B;
      lo = lo.cwiseMin(center - half), hi = hi.cwiseMax(center + half);
    }
    box.center_B = RScalar(0.5) * (lo + hi);
    box.half_B = RScalar(0.5) * (hi - lo);
    return box;
  }
  if (!shape.polyhedron) {
    const RScalar across = shape.radius + shape.cylinderRadius;  // one of them is 0
    box.half_B = RVec3(across, shape.halfHeight + shape.radius, across);
    return box;
  }
  RVec3 lo = RVec3::Constant(std::numeric_limits<RScalar>::infinity()), hi = -lo;
  for (const RVec3& v : shape.polyhedron->Vertices()) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  box.center_B = RScalar(0.5) * (lo + hi);
  box.half_B = RScalar(0.5) * (hi - lo);
  return box;
}

RBoundsTree::RBox WorldBox(const RLocalBox& local, RScalar boundingRadius, const RMat3& R_WB,
                           const RVec3& x_W) {
  const RVec3 c_W = x_W + R_WB * local.center_B;
  const RVec3 e_W = R_WB.cwiseAbs() * local.half_B;
  const RScalar pad = RScalar(2e-9) * boundingRadius + RScalar(1e-14) * x_W.cwiseAbs().maxCoeff();
  RBoundsTree::RBox box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = std::max(c_W[a] - e_W[a], x_W[a] - boundingRadius) - pad;
    box.hi[a] = std::min(c_W[a] + e_W[a], x_W[a] + boundingRadius) + pad;
  }
  return box;
}

void RQueryState::Sync(const RBodies& bodies, bool useTree) {
  const std::uint64_t nowLayout = bodies.LayoutStamp(), nowPose = bodies.PoseStamp();
  const std::uint64_t nowEdits = BodyEditCount();
  if (fresh || nowLayout != layout || nowPose != pose || nowEdits != edits) {
    const std::size_t n = bodies.EnabledCount();
    if (fresh || nowLayout != layout) {
      proxies.resize(n), local.resize(n), boxes.resize(n), ids.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        const RRigidBody& b = bodies.At(i);
        proxies[i].handle = bodies.HandleAt(i);
        proxies[i].shape = ShapeOf(b);
        proxies[i].serial = b.Serial();
        local[i] = LocalBoxOf(proxies[i].shape);
        ids[i] = static_cast<std::uint32_t>(i);
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      const RRigidBody& b = bodies.At(i);
      RQueryProxy& p = proxies[i];
      // A body the game assigned over another in its place (an edit) may have another shape.
      if (p.serial != b.Serial()) {
        p.shape = ShapeOf(b), p.serial = b.Serial();
        local[i] = LocalBoxOf(p.shape);
      }
      p.R_WB = b.Orientation_WB().toRotationMatrix();
      p.x_W = b.Position_W();
      p.category = b.Category();
      boxes[i] = WorldBox(local[i], p.shape.boundingRadius, p.R_WB, p.x_W);
    }
    layout = nowLayout, pose = nowPose, edits = nowEdits, fresh = false;
  }
  if (!useTree || (treeLayout == layout && treePose == pose && treeEdits == edits)) return;
  // Moved only: the tree's shape is kept and its boxes refitted, unless the refit has let
  // it grow to twice the area of its last build (bodies drifted far from where it was
  // built: queries would visit too many nodes). Anything added or removed: built again.
  bool build = treeLayout != layout;
  if (!build) {
    tree.Refit(boxes.data());
    ++refits;
    build = tree.InnerArea() > 2 * builtArea;
  }
  if (build) {
    tree.Build(boxes.data(), ids.data(), boxes.size());
    builtArea = tree.InnerArea();
    ++builds;
  }
  treeLayout = layout, treePose = pose, treeEdits = edits;
}

}  // namespace REngine
