// Private to REnginePhysics: the moves of one RCharacter::Update (RCharacter.h) against the
// bodies: casts that honour the character's filters and one-way bodies, collide-and-slide,
// steps, the contacts about it and the pushes it gives.
#pragma once

#include <REnginePhysics/RCharacter.h>
#include <REnginePhysics/RCollision.h>

#include <optional>

namespace REngine {

struct RCharacterMover {
  RCharacter& c;
  RBodies& bodies;
  RQueries& queries;
  RScalar dt;
  RVec3 gravity;
  // A body no cast of this move sees (the ground while it carries the character).
  RBodyHandle skip;
  // While carrying: the carrier, whose rigid motion the bodies that share it (a wall of the
  // same ship, moving with the deck) share too: they keep their places relative to the
  // character and are not in its way.
  const RRigidBody* carrier = nullptr;
  std::vector<RCharacterContact>& m_probe;  // scratch (the character's)

  // Whether a body is solid to the character: the filter rules both ways and the ignore
  // lists; not a one-way body it is passing through this Update.
  bool Solid(RBodyHandle h, const RRigidBody& b) const;
  // The first solid body the character meets moved by d from where it is; a one-way body
  // met otherwise than landing on it from above joins c.m_passed and the cast goes on.
  std::optional<RShapeCastHit> Cast(const RVec3& d);
  // Moves the character by d, sliding along what it meets (up to 8 casts), and stops
  // contactOffset short of it. walking: a face steeper than maxSlope blocks only the motion
  // across the plane of up into it (no climbing it by sliding); steep: set when one did.
  // vChar (m/s): the character's velocity for pushes, applied when push is true.
  void Slide(RVec3 d, bool walking, const RVec3& vChar, bool push, bool* steep = nullptr);
  // Walking by d blocked by a steep face: up by stepHeight, across, down onto walkable
  // ground. Kept when it gets further along d's horizontal part than `slid` (the position
  // sliding reached); the character is left at the better of the two.
  void TryStep(RVec3 start, RVec3 d, RVec3 slid);
  // The bodies within `probe` (m) of the character's surface, in handle order: signed
  // distance, normal from the body, point on it, its surface velocity.
  void Collect(RScalar probe, std::vector<RCharacterContact>& out);
  // The normal of the surface under a contact (world, unit): the contact's own where it is
  // walkable; at an edge or a corner (a step's nosing, whose contact normal leans towards the
  // character) the face just beyond it, found by a ray down from there. Walking and standing
  // go by this; blocking goes by the contact's normal.
  RVec3 SurfaceNormal(RBodyHandle body, const RVec3& point, const RVec3& normal);
  bool Walkable(const RVec3& n) const { return n.dot(c.m_up) >= c.m_cosSlope; }
  // Pushed out of what it overlaps (deeper than half the offset), up to 4 times.
  void Depenetrate();
  // The impulse that brings a dynamic body's surface point at p to the character's speed
  // along -n's part across the plane of up, at most maxPushForce * dt, once per body per
  // Update; none for a body met as walkable ground.
  void Push(RBodyHandle h, const RVec3& p, const RVec3& n, const RVec3& vChar);
  // The character's shape in its body frame, and that frame's pose.
  RConvexShape Shape() const;
  RMat3 R_WB() const;
  RVec3 x_B() const;
};

// The part of v across the plane of the unit vector up.
inline RVec3 AcrossUp(const RVec3& v, const RVec3& up) { return v - up * v.dot(up); }

// A body's velocity at a world point, m/s.
RVec3 SurfaceVelocity(const RRigidBody& b, const RVec3& p_W);

}  // namespace REngine
