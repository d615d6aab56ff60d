// RBodyHandle: a body's name in an RBodies (RBodies.h), and in what refers to bodies
// (joints: RJoint.h).
#pragma once

#include <REnginePhysics/RSlotMap.h>

namespace REngine {

struct RBodyTag;
// A body's name in an RBodies: slot index and generation (RSlotHandle). Default-constructed:
// invalid.
using RBodyHandle = RSlotHandle<RBodyTag>;

}  // namespace REngine
