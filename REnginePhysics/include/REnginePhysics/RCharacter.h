// RCharacter: a kinematic character controller. A player or a crew member that walks on
// ships, stations and tiled floors, moved by the game's commands through the world by shape
// casts, not by the rigid-body solver.
//
//   RCharacter player(def);                          // a capsule, standing on the deck
//   every frame:
//     integrator.Update(bodies, dt);                 // the world moves (platforms, crates)
//     player.SetDesiredVelocity(stick_W * 4.0);      // m/s along the ground
//     if (jumpPressed) player.Jump(5.0);             // m/s up, once
//     player.Update(bodies, queries, dt, gravity_W); // the character moves against the world
//
// Why kinematic. A character driven as a rigid body slides down slopes, bounces off steps,
// snags on the seams between floor tiles and drifts on a turning deck, and its friction and
// restitution fight the game's commands. Here the character goes exactly where the game
// says unless the world is in the way: the same choice as Jolt's CharacterVirtual, Bullet's
// btKinematicCharacterController and PhysX's controllers.
//
// One Update:
//   1. carried: standing on a body (static, kinematic or dynamic), the character keeps its
//      place on it: it is moved to where that place went since the last Update, exactly
//      (the body's pose change, not its velocity times dt, so a turning platform carries it
//      on the arc, without drift), and turned with the body about `up`;
//   2. pushed: a kinematic body it touched moves it by the part of its surface's velocity
//      that points into the character; any overlap left (a body that spawned or moved into it)
//      is pushed out along the contact normal;
//   3. walked: the desired velocity, along the ground (its horizontal part kept exactly, its
//      vertical part set so the motion follows the slope), or in the air with gravity's
//      component along `up` (kick-drift-kick: the exact parabola, apex v^2/2g);
//   4. moved by collide-and-slide: a shape cast along the motion, stopping `contactOffset`
//      short of the first surface, the rest of the motion slid along it, up to 8 times. A
//      cast cannot pass through anything, so no wall is thin enough at any speed. A wall
//      or a steep face met while walking is tried as a step: up by stepHeight, across, down
//      onto walkable ground; kept only where it gets further than sliding;
//   5. on the ground: a cast down finds the ground; walking on, the character is kept on
//      it down slopes and stairs (up to stepHeight below), at contactOffset above it.
//      Ground is walkable when its normal is within maxSlope of up; steeper ground blocks
//      horizontal motion into it and the character slides down it.
//
// Seams. The character hovers contactOffset above the ground and moves parallel to it, so a
// cast along a floor of adjacent boxes or mesh triangles meets no edge between them: there
// is nothing for an internal edge to catch.
//
// Pushing. A dynamic body met along the motion gets the impulse that brings its surface
// point to the character's speed along the contact normal's part across the plane of up, at
// most maxPushForce * dt per Update (applied by the next RIntegrator::Update); a dynamic body
// stood or landed on gets the character's weight (mass times gravity along up), not a blow. Dynamic bodies are not moved out of the
// character by the solver: the character is not a body of the world (give it a kinematic
// body of its own, moved to its pose each frame, for that).
//
// One-way bodies (RBodyDef::oneWay) are solid to the character only from above: met from
// below or from the side, or overlapping it, they are passed through; landed on from above
// (a contact normal within maxSlope of up, the character outside it) they hold it.
//
// Filters. The character has a category, a mask and an ignore list, as a body has: a body
// is solid to it when (body.category & mask) and (category & body.mask) are non-zero and
// neither ignores the other's id.
//
// Determinism and state. Update is serial and reads the bodies through the RQueries, whose
// answers are those of a loop over every body (ties by handle): the same inputs give the same
// bits for any thread count of the world. An RCharacter is a value: a copy is a snapshot
// that continues bit for bit; SaveCharacter/LoadCharacter (RWorldState.h) give it as bytes.
//
// Units: metres, seconds, kilograms, radians; every vector is in the world frame.
#pragma once

#include <REnginePhysics/RAbi.h>
#include <REngineMath/RMath.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RBodyDef.h>
#include <REnginePhysics/RError.h>
#include <REnginePhysics/RQueries.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace REngine {

// A definition or a call the character refuses: which field ("step_height") and why.
class RCharacterError : public RError {
 public:
  using RError::RError;
};

struct RCharacterDef {
  std::string name;
  // Convex: a sphere, box, capsule, cylinder or hull (RShape's factories; a capsule's axis is
  // the shape frame's y). Unset it is a sphere of radius 0, refused.
  RShape shape;
  std::shared_ptr<const RPreparedShape> prepared;  // when set, used instead of `shape`
  RVec3 position_W = RVec3::Zero();  // origin of the shape frame, m, within 1e15 of the origin
  RQuat q_WS = RQuat::Identity();    // orientation of the shape frame
  // Unit (normalised here): the character's up. Zero: opposite the gravity each Update is
  // given (a station's spin gravity turns it, and the shape turns with it by the least
  // rotation); Update refuses zero gravity then.
  RVec3 up_W = RVec3::Zero();
  RScalar mass = 80;             // kg, > 0: its weight on what it stands on
  RScalar maxSlope = 0.7853981633974483;  // rad, [0, pi/2): steepest walkable ground (45 deg)
  RScalar stepHeight = 0.3;      // m, >= 0: highest step climbed
  RScalar maxPushForce = 1000;   // N, >= 0: most force on a dynamic body it walks into
  // The gap kept between the character and every surface, m (> 0, at most a tenth of the
  // shape's size): large against the casts' touching band (1e-9 of the size), small against
  // what a player sees.
  RScalar contactOffset = 1e-3;
  std::optional<std::uint32_t> id;  // its name in bodies' ignore lists
  std::vector<std::uint32_t> ignore;  // ids of bodies it passes through
  std::uint32_t category = 1;
  std::uint32_t mask = 0xFFFFFFFFu;
};

enum class RGroundState : std::uint8_t {
  kOnGround,       // on walkable ground: walks, jumps, is carried
  kOnSteepGround,  // on ground steeper than maxSlope: slides down, is carried
  kInAir,          // nothing under it within contactOffset
};

struct RCharacterContact {
  RBodyHandle body;
  RVec3 point_W = RVec3::Zero();   // on the body's surface, m
  RVec3 normal_W = RVec3::UnitY(); // unit, from the body towards the character
  RScalar distance = 0;            // signed gap, m (about contactOffset when resting on it)
  RVec3 surfaceVelocity_W = RVec3::Zero();  // the body's velocity at point_W, m/s
};

struct RCharacterGround {
  RGroundState state = RGroundState::kInAir;
  RCharacterContact contact;  // what it stands on (state not kInAir)
  // Unit, world: the face it stands on. The contact's normal on a face; on a step's nosing
  // (whose contact normal leans towards the character) the face beyond the edge. Walkable
  // and the slope it walks along go by this.
  RVec3 surfaceNormal_W = RVec3::UnitY();
};

class RCharacter {
 public:
  // Checks the definition (RCharacterError naming the field: "shape" for a compound or mesh,
  // "up", "mass", "max_slope", "step_height", "max_push_force", "contact_offset",
  // "position", "orientation", "ignore") and prepares its shape.
  explicit RCharacter(const RCharacterDef& def);

  // The commands, held until changed: the velocity along the ground the game wants (m/s,
  // world; its component along up is ignored), and a jump: `speed` (m/s, > 0) along up at the
  // next Update, if the character is on the ground then (else it is dropped).
  void SetDesiredVelocity(const RVec3& v_W);
  void Jump(RScalar speed);

  // Moves the character by dt (s, as RIntegrator::Update takes it) against the bodies as
  // they stand, under gravity_W (m/s^2; the scene's, or a station's spin gravity where the
  // character is). Call after the world's Update: impulses it gives bodies act at the next.
  void Update(RBodies& bodies, RQueries& queries, RScalar dt, const RVec3& gravity_W);

  // Teleport (no cast): the shape frame's origin, m; the ground is forgotten.
  void SetPosition(const RVec3& position_W);
  // The character's own velocity (m/s): along up in the air (a launch pad), kept until it lands.
  void SetVelocity(const RVec3& v_W);

  const std::string& Name() const { return m_def.name; }
  const RCharacterDef& Def() const { return m_def; }
  const RPreparedShape& Shape() const { return *m_shape; }
  const RVec3& Position_W() const { return m_position; }
  const RQuat& Orientation_WS() const { return m_q; }
  // Its own velocity: the desired one while walking, with the air's vertical part.
  const RVec3& Velocity_W() const { return m_velocity; }
  // How far the last Update moved it, divided by dt (carrying and pushing included), m/s.
  const RVec3& MovedVelocity_W() const { return m_moved; }
  const RVec3& Up_W() const { return m_up; }
  const RVec3& DesiredVelocity_W() const { return m_desired; }
  const RCharacterGround& Ground() const { return m_ground; }
  bool OnGround() const { return m_ground.state == RGroundState::kOnGround; }
  // Every body within 2 contactOffset after the last Update, in handle order.
  const std::vector<RCharacterContact>& Contacts() const { return m_contacts; }
  std::uint64_t UpdateCount() const { return m_updates; }

  // The character's whole state, for save and load (RWorldState.h). Restore checks it as the
  // definition is checked.
  struct RState {
    RVec3 position = RVec3::Zero();
    RQuat q = RQuat::Identity();
    RVec3 velocity = RVec3::Zero(), desired = RVec3::Zero(), moved = RVec3::Zero();
    RVec3 up = RVec3::UnitY();
    RScalar jump = 0;
    // The ground's velocity when it left the ground, kept across the plane of up in the air.
    RVec3 airCarry = RVec3::Zero();
    RCharacterGround ground;
    // The ground point in the ground body's frame, and that body's orientation, at the last
    // Update: where carrying takes the character.
    RVec3 groundLocal = RVec3::Zero();
    RQuat groundQ = RQuat::Identity();
    std::uint64_t updates = 0;
    std::vector<RCharacterContact> contacts;  // the last Update's (kinematic bodies push from them)
  };
  RState State() const;
  void Restore(const RState& s);

 private:
  friend struct RCharacterMover;  // the moves (character/RCharacterMove.cpp)
  RCharacterDef m_def;
  std::shared_ptr<const RPreparedShape> m_shape;
  RScalar m_cosSlope = 0;
  RVec3 m_position = RVec3::Zero();
  RQuat m_q = RQuat::Identity();
  RVec3 m_velocity = RVec3::Zero(), m_desired = RVec3::Zero(), m_moved = RVec3::Zero();
  RVec3 m_up = RVec3::UnitY();
  RScalar m_jump = 0;
  RVec3 m_airCarry = RVec3::Zero();
  RCharacterGround m_ground;
  RVec3 m_groundLocal = RVec3::Zero();
  RQuat m_groundQ = RQuat::Identity();
  std::uint64_t m_updates = 0;
  std::vector<RCharacterContact> m_contacts;
  // Scratch, kept for its capacity.
  std::vector<RBodyHandle> m_near, m_passed, m_pushed, m_leaving;
  std::vector<RCharacterContact> m_scratch;
};

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_CHARACTER(X) \
  X(RCharacterDef) \
  X(RCharacterContact) \
  X(RCharacterGround) \
  X(RCharacter)
RENGINE_ABI_CHECK(kCharacter, RENGINE_ABI_TYPES_CHARACTER)
