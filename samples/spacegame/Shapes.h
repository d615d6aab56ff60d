// The game's shared collision shapes, each prepared once (PrepareShape) and shared by every
// body made from it: spawning a rock, a missile or a piece of debris copies a pointer, and
// the renderer keys its GPU meshes by the same pointer, so one shape is one mesh on screen.
//
// Frames: every shape is given in its own frame S (RShape), metres. The ship's S has +z
// forward (the nose), +y up; a missile's S has +y forward (a capsule's axis).
#pragma once

#include <REnginePhysics/RRigidBody.h>

#include <array>
#include <cstdint>
#include <memory>

namespace spacegame {

using Prepared = std::shared_ptr<const REngine::RPreparedShape>;

// Asteroids come in three sizes; a laser splits one into two of the next size down.
constexpr int kRockSizes = 3;
constexpr int kRockVariants = 3;
// Mean radius of each size class, m.
constexpr std::array<double, kRockSizes> kRockRadius = {2.5, 5.0, 9.0};

// A small deterministic generator (splitmix64): the same seed gives the same world on every
// machine, which std::uniform_real_distribution does not promise.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : m_state(seed) {}
  std::uint64_t Next() {
    std::uint64_t z = (m_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double Uniform(double lo, double hi) {
    return lo + (hi - lo) * double(Next() >> 11) * (1.0 / 9007199254740992.0);
  }

 private:
  std::uint64_t m_state;
};

struct GameShapes {
  // rocks[size][variant]: hulls of 28 points on a lumpy sphere of kRockRadius[size].
  std::array<std::array<Prepared, kRockVariants>, kRockSizes> rocks;
  Prepared ship;     // a compound of four hulls: fuselage, two wings, a fin
  Prepared station;  // a compound: hub cylinder, four spokes, a ring of twelve boxes
  Prepared bay;      // the cargo bay: a static triangle mesh, floor and three walls
  Prepared crate;    // a box, 1 m half extents
  Prepared missile;  // a capsule along S's y
  Prepared debris;   // a small box

  // Geometry the game logic needs beside the shapes (station frame S, m).
  static constexpr double kStationRingRadius = 45;
  static constexpr double kStationRingHalfAxial = 4;
  static constexpr double kStationHubHalfHeight = 8;
  static constexpr double kBayY = -30;  // the bay floor's height below the station
  static constexpr double kBayHalfWidth = 15;
  static constexpr double kBayWallHeight = 6;
  static constexpr double kShipHalfHeight = 1.2;  // belly to the centre of the hull frame
  static constexpr double kShipNose = 7.5;        // nose's distance ahead of the ship's S origin
};

// Builds every shape (a few ms: Qhull for the hulls). The rocks depend on the seed only.
GameShapes MakeGameShapes(std::uint64_t seed);

}  // namespace spacegame
