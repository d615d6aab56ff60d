// Collision shapes and their mass properties.
#pragma once

#include <REnginePhysics/RAbi.h>
#include <REngineMath/RMath.h>
#include <REnginePhysics/RConvexPolyhedron.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace REngine {

// (Values are stored in saved states: new types are appended.)
enum class RShapeType : std::uint8_t { kSphere, kBox, kHull, kCapsule, kCylinder, kCompound, kMesh };

struct RCompoundChild;

// A shape in its own frame S (the frame the scene gives sizes and points in), metres. Made by
// the factories, each of which takes exactly what its kind needs:
//
//   RShape::Box(RVec3(1, 0.5, 2))            RShape::Sphere(0.5)
//   RShape::Capsule(0.2, 1.5)                RShape::Cylinder(0.5, 0.1)
//   RShape::Hull(points_S)                   RShape::Mesh(vertices_S, triangles)
//   RShape::Compound({{RShape::Box(e), position_S, q_SC, density}, ...})
//
// The fields stay public (a scene loader or an editor fills them), but every size starts at
// 0 and every list empty: a size the kind needs and nobody gave is refused when the body is
// made (PrepareShape, RBodies::Add: RBodyError "shape.radius", must be > 0) rather than taken
// as some default, and a field the kind does not read that is not 0 or empty is refused too
// (RBodyError naming it: "shape.radius" on a box), rather than ignored.
struct RShape {
  RShapeType type = RShapeType::kSphere;
  RScalar radius = 0;                 // kSphere, kCapsule, kCylinder, m
  // kCapsule: the segment from (0, -halfHeight, 0) to (0, halfHeight, 0) in S, swept by a
  // sphere of `radius`, m. kCylinder: the solid of `radius` about S's y axis, its flat ends
  // at y = +-halfHeight, m.
  RScalar halfHeight = 0;
  RVec3 halfExtents = RVec3::Zero();  // kBox, m, along S's axes
  // kHull: the hull of these points; kMesh: the mesh's vertices. S frame, m.
  std::vector<RVec3> points;
  // kMesh: corner indices into points, three a triangle (two-sided). A mesh is for static and
  // kinematic bodies only: it has no volume, so no mass.
  std::vector<std::array<std::uint32_t, 3>> triangles;
  // kCompound: a rigid union of convex children, each placed in S (at most kMaxChildren).
  std::vector<RCompoundChild> children;
  static constexpr std::size_t kMaxChildren = 256;

  // A solid ball about S's origin, m.
  static RShape Sphere(RScalar radius);
  // A box of these half extents along S's axes, centred on S's origin, m.
  static RShape Box(const RVec3& halfExtents);
  // A capsule along S's y axis: the segment y in [-halfHeight, halfHeight] swept by a ball
  // of `radius`, m.
  static RShape Capsule(RScalar radius, RScalar halfHeight);
  // A solid cylinder of `radius` about S's y axis, its flat ends at y = +-halfHeight, m.
  static RShape Cylinder(RScalar radius, RScalar halfHeight);
  // The convex hull of these points (a convex polyhedron), S frame, m.
  static RShape Hull(std::vector<RVec3> points_S);
  // A triangle mesh (static and kinematic bodies only): vertices in S, m, and corner
  // indices into them, three a triangle.
  static RShape Mesh(std::vector<RVec3> vertices_S, std::vector<std::array<std::uint32_t, 3>> triangles);
  // A rigid union of convex children, each placed in S (at most kMaxChildren).
  static RShape Compound(std::vector<RCompoundChild> children);
};

// A child of a compound: a convex shape (any type but kCompound) with its own frame C placed
// in the compound's frame S, and its own density. Where children overlap, their shared
// volume counts twice in the mass (as the scene format says).
struct RCompoundChild {
  RShape shape;
  RVec3 position_S = RVec3::Zero();  // origin of C in S, m
  RQuat q_SC = RQuat::Identity();    // C's orientation in S (normalised when prepared)
  RScalar density = 1;               // kg/m^3, finite and > 0
};

// Mass properties of a solid of uniform density 1 kg/m^3 (scale by density or by
// mass / volume), in the shape frame S. A compound's are at its children's densities: its
// `volume` is then the mass, kg, at a body density of 1 (a body's density scales them).
struct RMassProperties {
  RScalar volume = 0;                       // m^3
  RVec3 com_S = RVec3::Zero();              // centre of mass, S frame, m
  RVec3 principalMoments = RVec3::Ones();   // about the centre of mass, kg m^2 per kg/m^3
  RQuat q_SB = RQuat::Identity();           // principal (body) frame B to S: columns are axes
};

// Exact mass properties. A mesh has none (volume 0). Sphere, box, capsule and cylinder in closed form, with the body frame equal to the
// shape frame (so the scene's orientation passes through untouched); a hull from its
// polyhedron (below). Throws RHullError for hull points that do not span a solid.
RMassProperties ComputeMassProperties(const RShape& shape);

// Mass properties of a polyhedron's solid: exact volume, centroid and inertia, then the
// principal moments in ascending order and a right-handed principal frame.
RMassProperties ComputeMassProperties(const RConvexPolyhedron& polyhedron);

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_SHAPE(X) \
  X(RQuat) \
  X(RVec4) \
  X(RShape) \
  X(RCompoundChild) \
  X(RMassProperties)
RENGINE_ABI_CHECK(kShape, RENGINE_ABI_TYPES_SHAPE)
