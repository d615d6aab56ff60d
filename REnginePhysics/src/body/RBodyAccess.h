// Private to REnginePhysics: the engine's way to the state of a body, of the body container
// and of the integrator. Each holds its state as a private base (RBodyCore in
// detail/RBodyCore.h, RBodiesCore, RIntegratorCore, RFreeRotationCore), so that a game sees only their
// functions and no engine class needs to be their friend. An explicit conversion between a
// class and its private base is well defined (a C-style cast is the one that may name an
// inaccessible base); these functions are the only places that make it.
#pragma once

#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RRigidBody.h>

#include <type_traits>

namespace REngine {

// The casts below are conversions to and from a base only while each class derives from its
// core, without virtual functions or other data (a cast between unrelated types would
// compile too, as a reinterpretation).
static_assert(std::is_base_of_v<RBodyCore, RRigidBody> && sizeof(RRigidBody) == sizeof(RBodyCore));
static_assert(std::is_base_of_v<RBodiesCore, RBodies> && !std::is_polymorphic_v<RBodies>);
static_assert(std::is_base_of_v<RIntegratorCore, RIntegrator> && !std::is_polymorphic_v<RIntegrator>);
static_assert(std::is_base_of_v<RFreeRotationCore, RFreeRotation> &&
              sizeof(RFreeRotation) == sizeof(RFreeRotationCore));

inline RBodyCore& Core(RRigidBody& b) { return (RBodyCore&)b; }
inline const RBodyCore& Core(const RRigidBody& b) { return (const RBodyCore&)b; }
inline RRigidBody& Body(RBodyCore& c) { return (RRigidBody&)c; }
inline const RRigidBody& Body(const RBodyCore& c) { return (const RRigidBody&)c; }
inline RBodiesCore& Core(RBodies& b) { return (RBodiesCore&)b; }
inline const RBodiesCore& Core(const RBodies& b) { return (const RBodiesCore&)b; }
inline RFreeRotationCore& Core(RFreeRotation& r) { return (RFreeRotationCore&)r; }
inline const RFreeRotationCore& Core(const RFreeRotation& r) { return (const RFreeRotationCore&)r; }
inline RIntegratorCore& Core(RIntegrator& i) { return (RIntegratorCore&)i; }
inline const RIntegratorCore& Core(const RIntegrator& i) { return (const RIntegratorCore&)i; }

}  // namespace REngine
