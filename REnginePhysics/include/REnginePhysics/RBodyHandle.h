// RBodyHandle: a body's name in an RBodies (RBodies.h), and in what refers to bodies
// (joints: RJoint.h).
#pragma once

#include <cstdint>
#include <limits>

namespace REngine {

// A body's name in an RBodies: slot index and generation. Default-constructed: invalid.
struct RBodyHandle {
  static constexpr std::uint32_t kInvalidIndex = std::numeric_limits<std::uint32_t>::max();
  std::uint32_t index = kInvalidIndex;
  std::uint32_t generation = 0;
  bool IsValid() const { return index != kInvalidIndex; }
  friend bool operator==(RBodyHandle a, RBodyHandle b) {
    return a.index == b.index && a.generation == b.generation;
  }
  friend bool operator!=(RBodyHandle a, RBodyHandle b) { return !(a == b); }
  friend bool operator<(RBodyHandle a, RBodyHandle b) {
    return a.index < b.index || (a.index == b.index && a.generation < b.generation);
  }
};

}  // namespace REngine
