// The rollback sample's game: an arena where two players each steer two ships (boxes on the
// ground) by thrust impulses and fire shots (spheres, spawned by the input and removed 45
// frames later), beside a pile of crates that falls asleep until a shot wakes it. Everything
// the game keeps lives in the physics world (a shot's spawn frame is its user data), so a
// snapshot of the world is a snapshot of the game.
#pragma once

#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>

#include <array>
#include <cstdint>

namespace rollback {

constexpr int kPlayers = 2;
constexpr int kShipsEach = 2;
constexpr double kDt = 1.0 / 60;  // s, one frame
constexpr std::uint64_t kShotLife = 45;  // frames

// One player's input for one frame: a thrust direction per ship (-1, 0 or 1 along world x
// and z) and whether the player's first ship fires.
struct Input {
  std::array<std::int8_t, 2 * kShipsEach> thrust{};
  bool fire = false;
  friend bool operator==(const Input& a, const Input& b) { return a.thrust == b.thrust && a.fire == b.fire; }
  friend bool operator!=(const Input& a, const Input& b) { return !(a == b); }
};
using FrameInputs = std::array<Input, kPlayers>;

// What a player presses: a deterministic stream (SplitMix64 from a seed), holding each
// choice for a few frames as hands do, so that "repeat the last input" predicts most frames.
class Player {
 public:
  explicit Player(std::uint64_t seed) : m_state(seed) {}
  Input Next();

 private:
  std::uint64_t Random();
  std::uint64_t m_state;
  Input m_held;
  int m_hold = 0;
};

class Arena {
 public:
  // threads: the step's (the result is the same bits on any number).
  explicit Arena(int threads = 1);
  // Applies the frame's inputs (impulses, shots, expired shots removed) and steps one frame:
  // afterwards the integrator's StepCount() is the frame.
  void Advance(const FrameInputs& inputs);
  // Every body's state (handle, pose, velocities, sleeping) bit for bit.
  std::uint64_t Hash() const;
  std::size_t Shots() const;
  std::size_t Sleeping() const { return integrator.PairStats().sleepingBodies; }

  REngine::RBodies bodies;
  REngine::RIntegrator integrator;
  std::array<REngine::RBodyHandle, kPlayers * kShipsEach> ships;
};

}  // namespace rollback
