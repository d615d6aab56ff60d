// Save and load: a world's whole state as bytes, restored so that the world continues bit for
// bit as if it had never stopped (rollback netcode, replays, bug reports).
//
//   std::vector<std::uint8_t> saved = SaveState(integrator, bodies);   // after step k
//   ... steps, spawns, removals ...
//   LoadState(integrator, bodies, saved);   // back at step k: the same steps from here give
//                                           // the same bodies, contacts and events
//
// What a state holds. Everything that carries from one step to the next and changes what a
// later step computes:
//   - the container: every slot's generation, the free list, the dense order and which bodies
//     are enabled, so handles a game keeps name the same bodies after a load, and bodies added
//     later get the handles they got the first time; the departures (removals, disables) the
//     next step has yet to wake islands for;
//   - every body, enabled or not: its definition (name, kind, mass, locks, restitution,
//     friction, responds, id, ignore list, filter bits, drag, gravity scale, user data) and its
//     state (pose, velocities, accumulated forces and impulses, sleeping, rest time, island,
//     the exact free rotation's cached elliptic constants, which the next step reuses bit for
//     bit); its shape by a key of the shape's definition (RShape), not its geometry;
//   - the container's joints: each joint's definition, the frames it keeps in its bodies,
//     its last impulses (the next step's warm start) and the joints' slot table;
//   - the integrator: its settings (all but `threads`, which changes no result: the loading
//     integrator keeps its own), the step count, the warm starts, the manifold memory of
//     contact reuse (with its cached block inverses), sleeping's bookkeeping, the pairs that
//     touched at the end of the last step (contact events) and NonFinite().
//   - the world's characters, when saved with them (RCharacter::RState: pose, velocities,
//     commands, ground and the place on it, the last contacts).
// What it does not hold: the last step's outputs (Contacts(), Events(), PairStats(),
// Profile(), NonFiniteInLastStep() are empty after a load: the next Update fills them), the
// broad phase's trees and pair list (they change no result: the pairs found are exactly the
// all-pairs loop's), world-space caches (recomputed from the poses, to the same bits), the
// pair filter and job system (the game's; the loading integrator keeps its own), and shape
// geometry.
//
// Shapes. A body is rebuilt from its saved definition and a prepared shape (RPreparedShape)
// whose RShape has the saved key: one of the bodies the loading container already holds
// (enabled or not), or one of RLoadOptions::shapes. A world built the same way (the same
// scene, the same spawn code) holds them; a game that rolls back past a body it has since
// removed passes that body's prepared shape. The rebuilt body's mass properties must equal
// the saved ones bit for bit (else: a state from another build or platform).
//
// Identity. User data is saved as the integer it is: a pointer must be re-established by the
// game. RRigidBody::Serial() and the integrator's own ids are process-wide counters, never
// stored: a load draws new ones and keeps which remembered bodies are which, so a state
// continues bit for bit in another process.
//
// Refused (RStateError, naming the part of the state and the problem; the world is left as
// it was): bytes that are not a state (magic), another format version, a state cut short or
// altered (its length and checksum), another world's state (its world tag, see SaveState,
// or a body whose handle the loading container holds with another name, shape, kind or
// mass), a shape that is neither in the container nor in the options, a plain vector's state
// loaded into an RBodies or the other way round, and values no saved world has: a state is
// checked as strictly as a scene. Every value in the range the API and the scene loader
// allow (positions within 1e15 m, unit orientations, axes and rotations within 1e-6,
// settings as Update takes them: 1 to kMaxSolverIterations solver passes, gravity finite,
// speeds, slops and times >= 0), joints only as AddJoint makes them (limits and motors on a
// hinge or slider, a hinge's limits within [-pi, pi], a second anchor on a distance joint), the
// exact rotation's cache as a step leaves it, remembered impulses within 1e30, every index
// into the container within it (a sleeping body's island among the slots; only a dynamic,
// enabled body sleeps or names an island) and every handle a remembered pair names one the
// container issued (a body it holds, or held before a removal).
//
// Format (version 3). Little-endian; doubles as their IEEE 754 bits. A 32-byte header: the
// magic "\x89RSTATE\n", the format version (u32), 0 (u32), the payload's length (u64), and
// its checksum (u64, a 64-bit hash that detects corruption, not tampering); then the
// payload: the world tag, the settings, the integrator's memory, the container and the
// bodies, the characters (src/state/RStateRecords.cpp writes and reads the bodies' records,
// RStateCharacters.cpp the characters'). A plain binary writer rather than a general format (CBOR through nlohmann_json, which the scene loader
// uses): the engine proper does not depend on a JSON library, every double must come back
// bit for bit, and a rollback game saves every frame, so a save is a copy of each field and
// nothing else.
#pragma once

#include <REnginePhysics/RAbi.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RCharacter.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RRigidBody.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace REngine {

// A state that cannot be loaded: Field() says where ("header.magic", "bodies[3].velocity",
// "world_tag"), Problem() what is wrong.
class RStateError : public RError {
 public:
  using RError::RError;
};

struct RLoadOptions {
  // Must equal the tag the state was saved with (SaveState's worldTag).
  std::uint64_t worldTag = 0;
  // Prepared shapes for bodies the loading container does not hold ("Shapes" above), matched
  // by their RShape: the shapes a game spawns from.
  std::vector<std::shared_ptr<const RPreparedShape>> shapes;
  // The world's characters (RCharacter.h), when its state was saved with them: the same
  // count, in the same order, with the same names; their states are restored with the rest.
  std::vector<RCharacter>* characters = nullptr;
};

// What a state's header and first fields say, checked (magic, version, length, checksum) but
// not loaded: a tool's look at a file, or a caller that must know the step before loading
// (rengine-sim replays a scene's actions up to it). Throws RStateError as LoadState does.
struct RStateInfo {
  std::uint32_t version = 0;
  std::uint64_t worldTag = 0;
  std::uint64_t stepCount = 0;   // RIntegrator::StepCount() when saved
  std::uint64_t bodyCount = 0;   // bodies in the container, enabled or not
  bool plainVector = false;      // saved from a std::vector<RRigidBody>
};
RStateInfo ReadStateInfo(const std::uint8_t* state, std::size_t size);

// The state of `integrator` and the bodies it steps, between two Updates. worldTag is the
// game's name for the world the state belongs to (a level, a scene's hash; rengine-sim uses
// a hash of the scene file and dt): LoadState refuses a state saved under another. The
// second form writes into `out`, reusing its capacity (a game that saves every frame
// allocates nothing once it has grown). Cost: linear in what it holds: about 0.36 KB a body
// (0.67 KB for one of three distinct moments of inertia, with its rotation's cache), 0.4 KB
// a remembered manifold (0.66 KB with its block inverse) and 0.12 KB a warm-started point;
// the 1000-box pile of scenes/box_pile_1000.json in mid-fall (1000 contacts) is 1.5 MB.
std::vector<std::uint8_t> SaveState(const RIntegrator& integrator, const RBodies& bodies,
                                    std::uint64_t worldTag = 0);
void SaveState(const RIntegrator& integrator, const RBodies& bodies, std::vector<std::uint8_t>& out,
               std::uint64_t worldTag = 0);
// With the world's characters (RCharacter.h), whose states are saved after the bodies
// (about 0.5 KB a character and 0.1 KB a contact of it); load with RLoadOptions::characters.
void SaveState(const RIntegrator& integrator, const RBodies& bodies, const std::vector<RCharacter>& characters,
               std::vector<std::uint8_t>& out, std::uint64_t worldTag = 0);
// A plain vector of bodies (identity by position).
std::vector<std::uint8_t> SaveState(const RIntegrator& integrator, const std::vector<RRigidBody>& bodies,
                                    std::uint64_t worldTag = 0);

// Replaces the integrator's memory and the container's bodies with the saved ones (see the
// top of this file). The whole state is read and checked before anything changes: on any
// error, RStateError, and the integrator and bodies are as they were. Caches of the bodies
// outside the step (RQueries) see a new layout and rebuild.
void LoadState(RIntegrator& integrator, RBodies& bodies, const std::uint8_t* state, std::size_t size,
               const RLoadOptions& options = {});
void LoadState(RIntegrator& integrator, RBodies& bodies, const std::vector<std::uint8_t>& state,
               const RLoadOptions& options = {});
void LoadState(RIntegrator& integrator, std::vector<RRigidBody>& bodies, const std::vector<std::uint8_t>& state,
               const RLoadOptions& options = {});

}  // namespace REngine

// This header's public types, whose layouts are checked against the library's (RAbi.h).
#define RENGINE_ABI_TYPES_WORLD_STATE(X) \
  X(RLoadOptions) \
  X(RStateInfo)
RENGINE_ABI_CHECK(kWorldState, RENGINE_ABI_TYPES_WORLD_STATE)
