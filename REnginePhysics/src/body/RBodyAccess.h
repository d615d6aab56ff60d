// Private to REnginePhysics: the engine's way to a body's state. RRigidBody holds its state
// as a private base (RBodyCore, detail/RBodyCore.h), so that a game sees only RRigidBody's
// functions and no engine class needs to be its friend. An explicit conversion between a
// class and its private base is well defined (a C-style cast is the one that may name an
// inaccessible base); these two functions are the only places that make it.
#pragma once

#include <REnginePhysics/RRigidBody.h>

namespace REngine {

inline RBodyCore& Core(RRigidBody& b) { return (RBodyCore&)b; }
inline const RBodyCore& Core(const RRigidBody& b) { return (const RBodyCore&)b; }
inline RRigidBody& Body(RBodyCore& c) { return (RRigidBody&)c; }
inline const RRigidBody& Body(const RBodyCore& c) { return (const RRigidBody&)c; }

}  // namespace REngine
