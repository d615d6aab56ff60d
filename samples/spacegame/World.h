// SpaceWorld: the game's bodies and the engine objects that step and query them, and the
// scene the game starts from: a player ship, a spinning station with its static cargo bay
// (crates inside), and a field of asteroids, all 1e6 m from the origin by default (space
// games live far out: REngine computes in double and every pair in its own frame, and the
// renderer draws relative to the camera).
//
// What each body is to the game is kept in RBodyDef::userData (Role and a size class), so
// anything that meets a body by handle (an event, a ray hit) knows what it met without a
// lookup table. Collision categories keep lasers off the ship that fires them.
#pragma once

#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RQueries.h>

#include <cstdint>
#include <vector>

#include "Shapes.h"

namespace spacegame {

using REngine::RBodyHandle;
using REngine::RQuat;
using REngine::RScalar;
using REngine::RVec3;

enum class Role : std::uint8_t {
  kNone,
  kShip,
  kAsteroid,
  kStation,
  kBay,
  kCrate,
  kMissile,
  kDebris
};

// Collision categories (RBodyDef::category).
namespace category {
constexpr std::uint32_t kShip = 1u << 0;
constexpr std::uint32_t kAsteroid = 1u << 1;
constexpr std::uint32_t kStation = 1u << 2;
constexpr std::uint32_t kMissile = 1u << 3;
constexpr std::uint32_t kDebris = 1u << 4;
constexpr std::uint32_t kCrate = 1u << 5;
constexpr std::uint32_t kCrew = 1u << 6;  // a character (Crew.h), not a body
}  // namespace category

// userData layout: the role in the low byte, the asteroid size class in the next.
inline std::uintptr_t PackUserData(Role role, int sizeClass = 0) {
  return std::uintptr_t(role) | (std::uintptr_t(sizeClass) << 8);
}
inline Role RoleOf(const REngine::RRigidBody& b) { return Role(b.UserData() & 0xFF); }
inline int SizeClassOf(const REngine::RRigidBody& b) { return int((b.UserData() >> 8) & 0xFF); }

struct WorldConfig {
  RVec3 origin_W = RVec3(1e6, 1e6, 1e6);  // where the station is, world, m
  std::uint64_t seed = 17;
  int asteroids = 40;
  double stationSpin = 0.1;  // rad/s about the station's axis (world y)
  double bayGravity = 9.81;  // m/s^2 towards the bay floor, inside the bay only
  int threads = 1;           // the step's threads (results are the same for any count)
  double dt = 1.0 / 60;      // the fixed step, s
};

// Total momentum, angular momentum about the station's centre and kinetic energy of the
// dynamic bodies: the run's conservation figures.
struct Conservation {
  RVec3 momentum_W = RVec3::Zero();         // kg m/s
  RVec3 angularMomentum_W = RVec3::Zero();  // kg m^2/s, about WorldConfig::origin_W
  double kineticEnergy = 0;                 // J
};

class SpaceWorld {
 public:
  explicit SpaceWorld(const WorldConfig& config = {});

  const WorldConfig& Config() const { return m_config; }
  const GameShapes& Shapes() const { return m_shapes; }
  REngine::RBodies& Bodies() { return m_bodies; }
  const REngine::RBodies& Bodies() const { return m_bodies; }
  REngine::RIntegrator& Integrator() { return m_integrator; }
  const REngine::RIntegrator& Integrator() const { return m_integrator; }
  REngine::RQueries& Queries() { return m_queries; }

  RBodyHandle Ship() const { return m_ship; }
  RBodyHandle Station() const { return m_station; }
  RBodyHandle Bay() const { return m_bay; }
  // An asteroid of a size class from one of the shared rock shapes.
  RBodyHandle AddAsteroid(int sizeClass, int variant, const RVec3& position_W, const RQuat& q_WS,
                          const RVec3& velocity_W, const RVec3& angularVelocity_W);

  // Bodies inside the cargo bay feel its gravity (gravityScale 1), all others none: the
  // world's gravity is the bay's, switched per body as it enters or leaves. Called after
  // each step; changes only the bodies that crossed the bay's boundary (setting the scale
  // wakes a body, so resting ones are left alone).
  void UpdateBayGravity();
  bool InBay(const RVec3& p_W) const;

  // Momentum the game added from outside (thrust, lasers, blasts, spawns less despawns),
  // so the HUD can tell the solver's share of a change from the game's.
  void AddExternalImpulse(const RVec3& j_W, const RVec3& at_W);
  // A force on a body at a world point for the next step: applied (AddForceAtPoint_W) and
  // put in the ledger when the step is taken. Its angular impulse about the origin is
  // taken about the body's centre midway between its start and end (kick-drift-kick moves
  // x by v0 dt + a dt^2/2, and for that motion the midpoint gives x1 x m v1 - x0 x m v0
  // exactly), plus the force's own torque about the centre (held over the step).
  void AddExternalForce(RBodyHandle body, const RVec3& f_W, const RVec3& at_W);
  // A body the game brings in or takes out brings or takes its momentum and spin.
  void NoteSpawn(const REngine::RRigidBody& b) { NoteBody(b, 1); }
  void NoteDespawn(const REngine::RRigidBody& b) { NoteBody(b, -1); }
  const Conservation& External() const { return m_external; }
  Conservation Measure() const;

  // One fixed step of the engine (WorldConfig::dt), and the ledger of the forces it applied.
  RScalar StepDt() const { return m_config.dt; }
  void Step();

 private:
  void BuildScene();
  void NoteBody(const REngine::RRigidBody& b, double sign);

  WorldConfig m_config;
  GameShapes m_shapes;
  REngine::RBodies m_bodies;
  REngine::RIntegrator m_integrator;
  REngine::RQueries m_queries;
  RBodyHandle m_ship, m_station, m_bay;
  Conservation m_external;
  struct PendingForce {
    RBodyHandle body;
    RVec3 f_W, arm_W, x0_W;  // force; from the centre to its point; the centre before the step
  };
  std::vector<PendingForce> m_forces;  // this step's; reserved, cleared each step
};

}  // namespace spacegame
