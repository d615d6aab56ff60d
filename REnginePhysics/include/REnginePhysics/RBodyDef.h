// What a game makes bodies from: the definition (RBodyDef), the prepared shape that bodies
// share, the kinds and locks, and the world form the pair sweep reads. RRigidBody.h holds the body.
#pragma once


#include <REnginePhysics/RAbi.h>
#include <REngineMath/RMath.h>
#include <REnginePhysics/RCollision.h>
#include <REnginePhysics/RError.h>
#include <REnginePhysics/RShape.h>
#include <REnginePhysics/RTriangleMesh.h>

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <optional>
#include <string>
#include <vector>


namespace REngine {

struct RConvexShape;  // RCollision.h

// World-space form of a body's collision shape, computed lazily and cached against the
// integrator's stamp: at most once per body per step, however many pairs ask. It holds what
// the pair sweep reads (the narrow phase works in the bodies' own frames).
struct RWorldForm {
  std::uint64_t stamp = 0;           // stamp it was computed at; 0: never
  RVec3 aabbMin_W = RVec3::Zero();   // axis-aligned bounding box, world, m
  RVec3 aabbMax_W = RVec3::Zero();
  RVec3 sphereCenter_W = RVec3::Zero();  // bounding sphere about the centre of mass, m
  RScalar sphereRadius = 0;
};

// A body definition that cannot make a body: which field (e.g. "shape.radius") and why.
class RBodyError : public RError {
 public:
  using RError::RError;
};

// A collision shape prepared once and shared, immutable, by every body made from it: the
// hull built (Qhull), its mass properties at unit density, the body frame. Spawning a
// missile or a fragment from one (RBodyDef::prepared) copies a pointer, not a hull.
struct RPreparedShape {
  RShape shape;                 // as given, shape frame S
  RMassProperties unitMass;     // at 1 kg/m^3, S frame
  RVec3 p_BS = RVec3::Zero();   // origin of S in the body frame B, m
  RQuat q_BS = RQuat::Identity();  // rotation S -> B
  std::shared_ptr<const RConvexPolyhedron> polyhedron_B;  // body frame; null but for a box or hull
  RScalar boundingRadius = 0;   // largest distance of the surface from the centre of mass, m
  // A compound: its children prepared (each its own shape, body frame and polyhedron), and
  // as the narrow phase sees them, posed in this body frame B (pointing into childShapes).
  std::vector<std::shared_ptr<const RPreparedShape>> childShapes;
  std::vector<RShapeChild> children;
  RVec3 boxCenter_B = RVec3::Zero(), boxHalf_B = RVec3::Zero();  // a compound's or mesh's box in B, m
  // A mesh: its triangles in B (B is S moved to the centre of the mesh's box; no rotation).
  std::shared_ptr<const RTriangleMesh> mesh_B;
};

// Checks a shape as RRigidBody does (sizes finite, > 0 and at most 1e12 m, a box no thinner
// than 1e-4 of its size, hull points that span a solid, every field its type does not read
// left at 0 or empty) and prepares it. Throws RBodyError naming the field ("shape.radius",
// "shape.half_extents", "shape.points"; "shape.radius" too for a radius set on a box).
std::shared_ptr<const RPreparedShape> PrepareShape(const RShape& shape);

// How a body moves. Dynamic: by forces, gravity and collisions. Static: never (infinite mass,
// zero velocity). Kinematic: by its own velocity and angular velocity alone, which the game
// sets; infinitely heavy to everything else (inverse mass and inertia 0 in the solver), it
// pushes and carries dynamic bodies with the velocity of its surface at the contact point,
// and collisions, forces, impulses and gravity never change its motion.
enum class RBodyKind : std::uint8_t { kDynamic, kStatic, kKinematic };

// Axes along which a body can neither move nor turn, world axes x, y, z. A collision treats
// a locked axis as infinitely heavy for that body: its inverse mass is 0 along a locked
// linear axis, and its world inverse inertia is that of the inertia restricted to the free
// angular axes (zero rows and columns on the locked ones). All six locked is the same as
// kinematic (its velocities along locked axes being 0, it never moves).
struct RBodyLocks {
  std::array<bool, 3> linear{false, false, false};
  std::array<bool, 3> angular{false, false, false};
};

// What a game or a scene file says about a body; RRigidBody copies it.
struct RBodyDef {
  std::string name;
  // Made by RShape's factories (RShape::Box(halfExtents), ...). Left as it is, it is a
  // sphere of radius 0, refused: no body gets a size nobody gave.
  RShape shape;
  // When set, the body is made from this shape and `shape` is not read: no hull is built.
  std::shared_ptr<const RPreparedShape> prepared;
  // How the body moves (RBodyKind). The scene format's `"static": true` is kind kStatic.
  RBodyKind kind = RBodyKind::kDynamic;
  std::optional<RScalar> mass;  // kg; when unset, density * volume
  RScalar density = 1;          // kg/m^3, used when mass is unset
  RVec3 position_W = RVec3::Zero();           // origin of S in the world, m (|x_i| <= 1e15)
  RQuat q_WS = RQuat::Identity();             // orientation of S in the world
  RVec3 velocity_W = RVec3::Zero();           // centre-of-mass velocity, world, m/s
  RVec3 angularVelocity_W = RVec3::Zero();    // world frame, rad/s
  // Coefficient of restitution, [0, 1]: the fraction of the approach speed a collision gives
  // back (RWorldSettings::restitutionCombine makes a pair's from the two bodies'). 0 by
  // default, as in Jolt and Box2D: a body bounces only where the game says so. (A scene file
  // body without "restitution" has 0.5: RScene::kDefaultRestitution.)
  RScalar restitution = 0;
  RScalar friction = RScalar(0.5);            // Coulomb coefficient, >= 0
  bool responds = true;  // false: collisions are reported, not resolved (missiles, sensors)
  // A one-way platform ("one_way"): solid only to what comes down onto it from above (along
  // a character's up; for bodies, opposite the world's gravity). What meets it from below or
  // the side, or overlaps it, passes through (RCharacter.h; RIntegrator.h for bodies).
  bool oneWay = false;
  // Drag rates c, 1/s, finite and >= 0 ("linear_damping", "angular_damping"): with no other
  // force or torque a dynamic body's speed decays exactly as v0 e^(-c t) and its angular
  // velocity (world frame) as w0 e^(-c t). 0: no drag, and no arithmetic.
  RScalar linearDamping = 0;
  RScalar angularDamping = 0;
  // Multiplies the world's gravity for this body, finite ("gravity_scale"); 1: the world's.
  RScalar gravityScale = 1;
  // World axes the body can neither move along nor turn about (see RBodyLocks).
  RBodyLocks locks;
  // The body's name in ignore lists, 0 to 2^32 - 2 (a scene gives each body its index in
  // its list). Unset by default: the body has no id, and no ignore list names it, so an
  // ignore list never matches bodies the game did not mean (ids that all default to one
  // value would make `ignore = {launcherId}` ignore everything). Several bodies may share
  // an id on purpose (a group ignored as one). In an RBodies, RBodies::IgnoreCollisions
  // takes handles instead and gives a body without an id one of its own.
  std::optional<std::uint32_t> id;
  // Ids of bodies this one never collides with (a missile and its launcher), each 0 to
  // 2^32 - 2.
  std::vector<std::uint32_t> ignore;
  // Collision filter bits, Box2D's rule: two bodies are tested against each other only if
  // (a.category & b.mask) != 0 and (b.category & a.mask) != 0 (both directions agree), and
  // neither ignores the other. Queries (RQueries.h) test their own mask against `category`.
  // The defaults let everything collide with everything.
  std::uint32_t category = 1;
  std::uint32_t mask = 0xFFFFFFFFu;
  // The game's own value (a pointer or an index, as std::uintptr_t); the engine never reads
  // it, copies it with the body and hands it back.
  std::uintptr_t userData = 0;
};

}  // namespace REngine
