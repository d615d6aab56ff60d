#include "ShapeMeshes.h"

#include <REnginePhysics/RConvexPolyhedron.h>

#include <cmath>

namespace spacegame {
using namespace REngine;

namespace {

using Tris = std::vector<MeshVertex>;

MeshVertex Vertex(const RVec3& p, const RVec3& n) {
  return {{float(p.x()), float(p.y()), float(p.z())}, {float(n.x()), float(n.y()), float(n.z())}};
}

void Triangle(Tris& out, const RVec3& a, const RVec3& b, const RVec3& c, const RVec3& n) {
  out.push_back(Vertex(a, n)), out.push_back(Vertex(b, n)), out.push_back(Vertex(c, n));
}

// A convex polygon fanned from its first corner, counter-clockwise seen from outside.
void Polygon(Tris& out, const std::vector<RVec3>& loop, const RVec3& n) {
  for (std::size_t i = 1; i + 1 < loop.size(); ++i) Triangle(out, loop[0], loop[i], loop[i + 1], n);
}

void Polyhedron(Tris& out, const RConvexPolyhedron& poly) {
  std::vector<RVec3> loop;
  for (const RFace& f : poly.Faces()) {
    loop.clear();
    for (std::uint32_t k = 0; k < f.vertexCount; ++k)
      loop.push_back(poly.Vertices()[poly.LoopVertices()[f.firstVertex + k]]);
    Polygon(out, loop, f.plane.normal);
  }
}

void Box(Tris& out, const RVec3& h) {
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign = -1; sign <= 1; sign += 2) {
      RVec3 n = RVec3::Zero();
      n[axis] = sign;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      auto corner = [&](double su, double sv) {
        RVec3 p = RVec3::Zero();
        p[axis] = sign * h[axis], p[u] = su * h[u], p[v] = sv * h[v];
        return p;
      };
      // (u, v, n) is right-handed, so this loop is counter-clockwise seen from +n.
      std::vector<RVec3> loop = {corner(-1, -1), corner(1, -1), corner(1, 1), corner(-1, 1)};
      if (sign < 0) std::swap(loop[1], loop[3]);
      Polygon(out, loop, n);
    }
  }
}

// A surface of revolution about y: `profile` gives (radius, y, normal's radial part, normal's
// y part) down from the top; smooth normals.
struct Ring {
  double r, y, nr, ny;
};
void Revolve(Tris& out, const std::vector<Ring>& profile, int segments) {
  auto at = [&](const Ring& p, int k, RVec3& pos, RVec3& n) {
    const double a = 2 * kPi * k / segments, c = std::cos(a), s = std::sin(a);
    pos = RVec3(p.r * c, p.y, p.r * s);
    n = RVec3(p.nr * c, p.ny, p.nr * s).normalized();
  };
  for (std::size_t i = 0; i + 1 < profile.size(); ++i) {
    for (int k = 0; k < segments; ++k) {
      RVec3 p[4], n[4];
      at(profile[i], k, p[0], n[0]), at(profile[i], k + 1, p[1], n[1]);
      at(profile[i + 1], k, p[2], n[2]), at(profile[i + 1], k + 1, p[3], n[3]);
      // Top ring to the next one down, outward-facing: (0, 1, 2) and (1, 3, 2).
      out.push_back(Vertex(p[0], n[0])), out.push_back(Vertex(p[1], n[1])),
          out.push_back(Vertex(p[2], n[2]));
      out.push_back(Vertex(p[1], n[1])), out.push_back(Vertex(p[3], n[3])),
          out.push_back(Vertex(p[2], n[2]));
    }
  }
}

// A ball of radius r about y = ±h halves (a sphere when h is 0; a capsule otherwise).
void Capsule(Tris& out, double r, double h) {
  constexpr int kRings = 8;
  std::vector<Ring> profile;
  for (int i = 0; i <= kRings; ++i) {  // upper half ball
    const double a = 0.5 * kPi * i / kRings, c = std::cos(a), s = std::sin(a);
    profile.push_back({r * s, h + r * c, s, c});
  }
  for (int i = 0; i <= kRings; ++i) {  // lower half ball
    const double a = 0.5 * kPi + 0.5 * kPi * i / kRings, c = std::cos(a), s = std::sin(a);
    profile.push_back({r * s, -h + r * c, s, c});
  }
  Revolve(out, profile, 24);
}

void Cylinder(Tris& out, double r, double h) {
  // The side with radial normals; the ends as flat discs (their own rings, so the edge
  // stays sharp).
  Revolve(out, {{0, h, 0, 1}, {r, h, 0, 1}}, 32);
  Revolve(out, {{r, h, 1, 0}, {r, -h, 1, 0}}, 32);
  Revolve(out, {{r, -h, 0, -1}, {0, -h, 0, -1}}, 32);
}

void Shape(Tris& out, const RShape& s) {
  switch (s.type) {
    case RShapeType::kSphere:
      Capsule(out, s.radius, 0);
      break;
    case RShapeType::kCapsule:
      Capsule(out, s.radius, s.halfHeight);
      break;
    case RShapeType::kCylinder:
      Cylinder(out, s.radius, s.halfHeight);
      break;
    case RShapeType::kBox:
      Box(out, s.halfExtents);
      break;
    case RShapeType::kHull:
      Polyhedron(out, RConvexPolyhedron::Hull(s.points));
      break;
    case RShapeType::kCompound:
      for (const RCompoundChild& c : s.children) {
        const std::size_t first = out.size();
        Shape(out, c.shape);
        const Eigen::Matrix3f R = c.q_SC.normalized().toRotationMatrix().cast<float>();
        const Eigen::Vector3f t = c.position_S.cast<float>();
        for (std::size_t i = first; i < out.size(); ++i) {
          Eigen::Map<Eigen::Vector3f> p(out[i].position), n(out[i].normal);
          p = R * p + t;
          n = R * n;
        }
      }
      break;
    case RShapeType::kMesh:
      for (const auto& t : s.triangles) {
        const RVec3 &a = s.points[t[0]], &b = s.points[t[1]], &c = s.points[t[2]];
        const RVec3 n = (b - a).cross(c - a).normalized();
        Triangle(out, a, b, c, n);
        Triangle(out, a, c, b, -n);
      }
      break;
  }
}

}  // namespace

std::vector<MeshVertex> Tessellate(const RShape& shape) {
  Tris out;
  Shape(out, shape);
  return out;
}

}  // namespace spacegame
