// A hash of a world's state: what the autoplay prints (`hash=`) and the determinism tests
// compare. FNV-1a over the bytes of every enabled body's handle, pose, velocities and
// sleeping flag, in the container's dense order (which depends only on the sequence of
// Add, Remove, Disable and Enable calls), and of the joints' handles.
#pragma once

#include <REnginePhysics/RBodies.h>

#include <cstdint>
#include <string>

namespace spacegame {

std::uint64_t HashState(const REngine::RBodies& bodies);
std::string HashHex(std::uint64_t hash);

}  // namespace spacegame
