// Fracture (RFracture.h): Voronoi cells of sites within a convex polyhedron, and the bodies
// made of them.
#include <REnginePhysics/RFracture.h>

#include <REnginePhysics/RRigidBody.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace REngine {

namespace {

// The point on three planes (n . x = d each), or false when they meet in no single point.
bool Corner(const RPlane& a, const RPlane& b, const RPlane& c, RVec3& x) {
  const RVec3 bc = b.normal.cross(c.normal);
  const RScalar det = a.normal.dot(bc);
  if (!(std::abs(det) > RScalar(1e-12))) return false;
  x = (a.offset * bc + b.offset * c.normal.cross(a.normal) + c.offset * a.normal.cross(b.normal)) / det;
  return AllFinite(x);
}

}  // namespace

std::vector<std::vector<RVec3>> VoronoiCells(const std::vector<RVec3>& vertices, const std::vector<RPlane>& faces,
                                             const std::vector<RVec3>& sites) {
  RScalar size = 0;
  for (const RVec3& v : vertices) size = std::max(size, v.cwiseAbs().maxCoeff());
  const RScalar eps = RScalar(1e-9) * std::max(size, RScalar(1e-300));
  std::vector<std::vector<RVec3>> cells(sites.size());
  std::vector<RPlane> planes;
  for (std::size_t i = 0; i < sites.size(); ++i) {
    // The cell: inside every face, and nearer to site i than to each other site (the
    // bisecting plane of the two, facing away from i).
    planes.assign(faces.begin(), faces.end());
    for (std::size_t j = 0; j < sites.size(); ++j) {
      if (j == i) continue;
      RPlane p;
      const RVec3 n = sites[j] - sites[i];
      p.normal = n.normalized();
      p.offset = p.normal.dot(RScalar(0.5) * (sites[i] + sites[j]));
      planes.push_back(p);
    }
    // Its corners: every point where three of the planes meet that no plane cuts away.
    std::vector<RVec3>& corners = cells[i];
    for (std::size_t a = 0; a < planes.size(); ++a)
      for (std::size_t b = a + 1; b < planes.size(); ++b)
        for (std::size_t c = b + 1; c < planes.size(); ++c) {
          RVec3 x;
          if (!Corner(planes[a], planes[b], planes[c], x)) continue;
          bool inside = true;
          for (const RPlane& p : planes) inside = inside && p.SignedDistance(x) <= eps;
          if (!inside) continue;
          bool seen = false;
          for (const RVec3& y : corners) seen = seen || (y - x).cwiseAbs().maxCoeff() <= eps;
          if (!seen) corners.push_back(x);
        }
  }
  return cells;
}

std::vector<RBodyHandle> Fracture(RBodies& bodies, RBodyHandle h, const RFractureDef& def) {
  const RRigidBody& parent = bodies[h];  // RHandleError when stale
  const RShape& shape = parent.Shape();
  if (shape.type != RShapeType::kBox && shape.type != RShapeType::kHull) {
    throw RFractureError("shape", "only a box or a hull can be fractured (a polyhedral cut of a round shape would "
                                  "not keep its mass; a compound's children are bodies of their own to fracture)");
  }
  if (def.sites_S.empty() || def.sites_S.size() > RFractureDef::kMaxSites) {
    throw RFractureError("sites", "must hold 1 to 256 sites");
  }
  // The shape in its own frame S, where the sites are.
  const RConvexPolyhedron poly = shape.type == RShapeType::kBox ? RConvexPolyhedron::Box(shape.halfExtents)
                                                                 : RConvexPolyhedron::Hull(shape.points);
  std::vector<RPlane> faces;
  for (const RFace& f : poly.Faces()) faces.push_back(f.plane);
  RScalar size = 0;
  for (const RVec3& v : poly.Vertices()) size = std::max(size, v.cwiseAbs().maxCoeff());
  for (std::size_t i = 0; i < def.sites_S.size(); ++i) {
    const std::string field = "sites[" + std::to_string(i) + "]";
    const RVec3& s = def.sites_S[i];
    if (!AllFinite(s)) throw RFractureError(field, "must be finite");
    for (const RPlane& p : faces) {
      if (p.SignedDistance(s) > 0) throw RFractureError(field, "is outside the shape");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if ((def.sites_S[j] - s).norm() <= RScalar(1e-6) * size) {
        throw RFractureError(field, "coincides with sites[" + std::to_string(j) + "]");
      }
    }
  }
  const std::vector<std::vector<RVec3>> cells = VoronoiCells(poly.Vertices(), faces, def.sites_S);

  // Every piece's definition first (a cell that is no solid is skipped): nothing changes
  // until all are made.
  const RScalar density = parent.Mass() / parent.PreparedShape()->unitMass.volume;
  const RVec3 x_S = parent.ShapePosition_W();
  const RQuat q_WS = parent.ShapeOrientation_WS();
  const RVec3 v = parent.Velocity_W(), w = parent.AngularVelocity_W();
  std::vector<RBodyDef> pieces;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (cells[i].size() < 4) continue;
    RBodyDef d;
    std::shared_ptr<const RPreparedShape> prepared;
    try {
      prepared = PrepareShape(RShape::Hull(cells[i]));
    } catch (const RError&) {
      continue;  // flat: no solid
    }
    if (!(prepared->unitMass.volume > RScalar(1e-12) * parent.PreparedShape()->unitMass.volume)) continue;
    d.name = parent.Name() + "#" + std::to_string(i);
    d.prepared = prepared;
    d.kind = parent.Kind();
    d.density = density;
    d.position_W = x_S;
    d.q_WS = q_WS;
    // The parent's rigid motion at the piece's centre of mass.
    const RVec3 c = x_S + q_WS * prepared->unitMass.com_S;
    d.velocity_W = parent.Kind() == RBodyKind::kStatic ? RVec3::Zero() : RVec3(v + w.cross(c - parent.Position_W()));
    d.angularVelocity_W = parent.Kind() == RBodyKind::kStatic ? RVec3::Zero() : w;
    d.restitution = parent.Restitution();
    d.friction = parent.Friction();
    d.responds = parent.Responds();
    d.oneWay = parent.OneWay();
    d.linearDamping = parent.LinearDamping();
    d.angularDamping = parent.AngularDamping();
    d.gravityScale = parent.GravityScale();
    d.locks = parent.Locks();
    d.category = parent.Category();
    d.mask = parent.Mask();
    d.userData = parent.UserData();
    pieces.push_back(std::move(d));
  }
  if (pieces.empty()) throw RFractureError("sites", "leave no solid piece");
  bodies.Remove(h);
  std::vector<RBodyHandle> out;
  out.reserve(pieces.size());
  for (const RBodyDef& d : pieces) out.push_back(bodies.Add(d));
  return out;
}

}  // namespace REngine
