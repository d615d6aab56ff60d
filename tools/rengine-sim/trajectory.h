// rengine-sim's trajectory (docs/scene-format.md, "Trajectory CSV"): each live body's state
// in its column order, the CSV of it, and the final-state hash= over the same numbers.
#pragma once

#include <REnginePhysics/RScene.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace REngine::sim {

// What the CSV reports of a body, in its column order: the pose of the shape frame S
// (x, y, z, qw, qx, qy, qz), then the world velocity and angular velocity.
std::array<RScalar, 13> BodyState(const RRigidBody& b);
// The same columns for a character: its shape frame's pose, the velocity it moved with over
// the last step (RCharacter::MovedVelocity_W) and a zero angular velocity.
std::array<RScalar, 13> CharacterState(const RCharacter& c);

// FNV-1a, 64 bit, over the raw bytes (native byte order) of each live body's BodyState in
// order of creation, then each character's CharacterState: equal for bit-identical states,
// and cheap enough to print on every run.
std::uint64_t StateHash(const RSceneWorld& world);

// The trajectory CSV, formatted into one large buffer written in large chunks. Rows are the
// live bodies in order of creation (RSceneWorld::Live).
class TrajectoryWriter {
 public:
  // Buffers the header; `out` stays the caller's to close.
  explicit TrajectoryWriter(std::FILE* out);
  void Rows(std::uint64_t step, RScalar dt, const RSceneWorld& world);
  // Writes what is buffered; false when any write failed.
  bool Flush();

 private:
  static constexpr std::size_t kChunk = std::size_t(1) << 20;

  std::vector<std::string> m_characterNames;
  // The body's name as a CSV field, kept per slot (and generation) once made.
  const std::string& CsvName(RBodyHandle h, const RRigidBody& b);

  struct Name {
    bool valid = false;
    std::uint32_t generation = 0;
    std::string text;
  };
  std::FILE* m_out;
  std::vector<Name> m_names;
  std::string m_buffer;
  bool m_failed = false;
};

}  // namespace REngine::sim
