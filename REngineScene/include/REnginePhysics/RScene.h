// Scene files (docs/scene-format.md, "rengine-scene/1"): a world's settings, its step
// and step count, its bodies and joints, read from JSON and checked field by field.
//
// Every problem is reported, never repaired: a typo in a field name, a NaN, a zero-length
// quaternion or a flat hull is an RSceneError naming the file, the JSON path and what is
// wrong, so a scene that loads is the scene its author meant.
#pragma once

#include <REnginePhysics/RError.h>

#include <REngineMath/RMath.h>
#include <REnginePhysics/RBodies.h>
#include <REnginePhysics/RCharacter.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RJoint.h>
#include <REnginePhysics/RQueries.h>
#include <REnginePhysics/RRigidBody.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace REngine {

// A scene that cannot be used. what() is "<file>: <json path>: <problem>", e.g.
// "scene.json: bodies[3].shape.radius: must be a finite number > 0 (got -1)"; the path is
// left out when the problem is the file itself (cannot be read, not valid JSON).
// Field() is the JSON path.
class RSceneError : public RError {
 public:
  RSceneError(std::string file, std::string jsonPath, std::string problem);

  const std::string& File() const { return m_file; }
  const std::string& JsonPath() const { return Field(); }  // "" for a file-level problem

 private:
  std::string m_file;
};

// A joint of the scene (docs/scene-format.md, "Joints"), added by RSceneWorld after the scene's
// bodies and before the actions of step 0, or by an add_joint action at its step. Its anchors
// and axis are world values as the bodies stand when it is added (as the scene starts, or at
// the action's step); every check RBodies::AddJoint makes is made at load, so a scene that
// loads makes its joints.
struct RSceneJoint {
  std::string name;  // unique among the joints that exist when it is added
  std::string path;  // "joints[3]" or "actions[5].add_joint", for messages
  // The bodies it joins, by name: for the scene's joints, bodies the scene starts with; for an
  // add_joint, bodies that exist at its step. b empty: the world.
  std::string a, b;
  // Everything but the handles (def.a and def.b are left invalid: RSceneWorld fills them).
  // def.axis_W is the file's axis made unit length; a distance joint's minDistance or
  // maxDistance is -1 where the file leaves it out (the anchors' distance when it is added).
  RJointDef def;
};

// What the game does between steps (docs/scene-format.md, "Actions"), so that its spawning
// and despawning can be replayed from a file: applied when `step` steps have run, before
// the next one, in list order among actions of the same step.
struct RSceneAction {
  enum class Verb : std::uint8_t { kAdd, kRemove, kImpulse, kSetVelocity, kAddJoint, kRemoveJoint };
  std::uint64_t step = 0;
  Verb verb = Verb::kAdd;
  std::string path;              // "actions[3]", for messages
  std::string body;              // the body acted on (kAdd: the new body's name); joint verbs: ""
  // kAdd: the new body (its shape prepared at load, shared by every add of an equal shape,
  // so spawning builds no hull), and the names of bodies it never collides with.
  RBodyDef def;
  std::vector<std::string> ignore;
  // kImpulse: N s at a world point (the centre of mass when absent).
  RVec3 impulse_W = RVec3::Zero();
  std::optional<RVec3> point_W;
  // kSetVelocity: either may be absent (left as it is).
  std::optional<RVec3> velocity_W, angularVelocity_W;
  // kAddJoint: the joint (docs/scene-format.md, "Actions"). kRemoveJoint: joint.name alone,
  // a joint that exists at the step.
  RSceneJoint joint;
};

// A ray the scene asks after a step (docs/scene-format.md, "Rays"), answered by rengine-sim into
// --rays FILE with RQueries::CastRay (or CastRayAll when `all`).
struct RSceneRay {
  std::string name;
  std::uint64_t step = 0;  // asked after this many steps (and that step's actions); 0: at the start
  std::string path;        // "rays[3]", for messages
  RVec3 origin_W = RVec3::Zero();     // m, within 1e15 m of the origin
  RVec3 direction_W = RVec3::UnitX(); // finite, any length but 0
  RScalar maxDistance = 0;            // m, finite, >= 0
  std::uint32_t mask = 0xFFFFFFFFu;   // bodies whose category shares a bit with it
  bool all = false;                   // every body hit, nearest first; false: the nearest
};

// A character of the scene (docs/scene-format.md, "Characters"): an RCharacter made as the
// scene starts, driven by its inputs, a row of the trajectory like a body.
struct RSceneCharacter {
  // What a game's controls say from `step` on (applied when that many steps have run,
  // before the next, as actions are): the desired velocity along the ground (m/s, world)
  // holds until the next input; a jump (m/s along up, > 0) is asked once, at this step.
  struct Input {
    std::uint64_t step = 0;
    RVec3 velocity_W = RVec3::Zero();
    RScalar jump = 0;  // 0: none
  };
  std::string path;  // "characters[2]", for messages
  // The definition as RCharacter takes it (name, shape, pose, up, slopes, steps, pushing,
  // filters; ignore holds the ids of the scene bodies it names), checked at load.
  RCharacterDef def;
  std::vector<Input> inputs;  // sorted by step, one per step
};

struct RScene {
  // A body's restitution when its entry gives none: the scene format's contract
  // (docs/scene-format.md), kept apart from RBodyDef's own default of 0 so that a scene file
  // means what it always has.
  static constexpr RScalar kDefaultRestitution = 0.5;

  RWorldSettings settings;
  RScalar dt = RScalar(1) / 60;  // s
  std::uint64_t steps = 600;
  std::vector<RBodyDef> bodies;  // in file order, which is also the CSV's row order
  // Per body: indices of the bodies it never collides with; symmetric, sorted, unique.
  std::vector<std::vector<std::size_t>> ignore;
  // Sorted by step (stably: list order within a step). Every name they use is checked at
  // load against the bodies and joints that exist at that step.
  std::vector<RSceneAction> actions;
  // Sorted by step (stably: list order within a step); names unique among a step's rays.
  std::vector<RSceneRay> rays;
  // In file order, which is the order RSceneWorld adds them in.
  std::vector<RSceneJoint> joints;
  // In file order, which is their rows' order in the trajectory (after the bodies').
  std::vector<RSceneCharacter> characters;
  // The name the scene was loaded under, for CreateBodies' messages.
  std::string fileName;
};

// How much work a scene may ask for, so that a file from a stranger cannot make the loader
// or rengine-sim run out of memory or run for days: a scene beyond a limit is bad input
// like any other (RSceneError naming the field). Every shipped and planned scene is far
// inside them (the largest scaling scenes have 30000 bodies; dzhanibekov runs 36000 steps);
// a game that really wants more passes its own limits.
struct RSceneLimits {
  std::uint64_t maxFileBytes = std::uint64_t(256) << 20;  // the scene file: 256 MiB
  // Bodies in the scene plus those its actions add: the pair loop visits n^2 / 2 pairs a
  // step.
  std::uint64_t maxBodies = 100000;
  // Per hull: building grows about as n^2 (measured: 20 ms at 1000 points, 1.3 s at 10000,
  // about 2 min at 100000).
  std::uint64_t maxHullPoints = 10000;
  std::uint64_t maxSteps = 100000000;       // 1e8: 19 days of game time at 60 Hz
  // bodies x steps: 1e10 is a 30000-body scene for 3e5 steps, or hours of stepping.
  double maxBodySteps = 1e10;
  std::uint64_t maxActions = 1000000;       // entries of "actions"
  std::uint64_t maxRays = 1000000;          // entries of "rays"
  // Per mesh, vertices and triangles each: the tree builds in n log n, and a triangle costs
  // about 100 bytes prepared.
  std::uint64_t maxMeshTriangles = 4000000;
  // Joints in the scene plus those its actions add: an island's joints are solved as one
  // block each pass. (New limits go last, so the fields above keep their places in aggregate
  // initialisation.)
  std::uint64_t maxJoints = 1000000;
  std::uint64_t maxCharacters = 10000;   // entries of "characters"
  std::uint64_t maxInputs = 1000000;     // inputs of every character together
};

// Reads and validates a scene file. Throws RSceneError (also when the file cannot be read).
RScene LoadScene(const std::string& path, const RSceneLimits& limits = {});

// Validates scene JSON held in memory; fileNameForMessages only labels errors.
RScene ParseScene(const std::string& jsonText, const std::string& fileNameForMessages,
                  const RSceneLimits& limits = {});

// Checks a scene's size against the limits (ParseScene does; call it again after changing
// steps or bodies). Throws RSceneError naming "steps", "bodies" or "joints" ("actions" when
// the bodies or joints the actions add go beyond the limit), or an action or a ray after the
// last step (it would never be applied or answered: "actions[3].step", "rays[3].step").
void CheckSceneLimits(const RScene& scene, const RSceneLimits& limits);

// The scene's bodies, in scene order. A definition that parses but has no valid mass
// properties (a box so large that its mass overflows) throws RSceneError with the path of
// the body's offending field.
std::vector<RRigidBody> CreateBodies(const RScene& scene);

// A scene's world as it runs: its bodies in an RBodies, the live ones in order of creation
// (the scene's order, then the order they were added: the trajectory's row order), and its
// actions applied at their steps. Scene body i has id i; the k-th body added has id
// (bodies in the scene) + k.
class RSceneWorld {
 public:
  // Makes the scene's bodies, then its joints; throws RSceneError as CreateBodies does, and
  // for a joint RBodies::AddJoint refuses (an RJointError, named "joints[i].<field>"; an
  // add_joint's "actions[i].add_joint.<field>" when it is applied). The scene must outlive the
  // world. A body an action removes takes its joints with it.
  explicit RSceneWorld(const RScene& scene);
  // Applies the actions of step `stepsRun` (0 before the first step, then k after the k-th):
  // each must come at or after the last step applied. Throws RSceneError naming the action
  // when game code could not do what it says (an impulse that overflows the body's sum).
  // The characters' inputs of that step are given to them too.
  void ApplyActions(std::uint64_t stepsRun);
  // Moves the characters by dt under gravity_W (RCharacter::Update), in scene order: call
  // after each RIntegrator::Update of the bodies.
  void UpdateCharacters(RScalar dt, const RVec3& gravity_W);
  std::vector<RCharacter>& Characters() { return m_characters; }
  const std::vector<RCharacter>& Characters() const { return m_characters; }
  RBodies& Bodies() { return m_bodies; }
  const RBodies& Bodies() const { return m_bodies; }
  const std::vector<RBodyHandle>& Live() const { return m_live; }
  // The live body of that name, or an invalid handle.
  RBodyHandle Find(const std::string& name) const;
  // The joint of that name (the scene's, or an add_joint's) while it exists, or an invalid
  // handle.
  RJointHandle FindJoint(const std::string& name) const;
  // Whether the bodies hold exactly the joints named so far: true unless something other than
  // the scene's joints and actions added or removed joints (a state loaded from elsewhere).
  bool HoldsExactlyItsJoints() const;

 private:
  // A joint of the scene or an add_joint; `when` ends a refusal's message.
  void AddJoint(const RSceneJoint& j, const std::string& when);
  void RemoveBody(RBodyHandle h);

  const RScene* m_scene;
  RBodies m_bodies;
  std::vector<RBodyHandle> m_live;
  std::unordered_map<std::string, RBodyHandle> m_byName;
  std::unordered_map<std::string, std::uint32_t> m_idByName;
  std::unordered_map<std::string, RJointHandle> m_jointByName;
  // Per joint slot (RJointHandle::index), the name of the joint in it: a removed body's
  // joints are forgotten by name.
  std::vector<std::string> m_jointNameOfSlot;
  std::size_t m_nextAction = 0;
  std::vector<RCharacter> m_characters;
  std::vector<std::size_t> m_nextInput;  // per character
  RQueries m_queries;
  std::uint32_t m_nextId = 0;
};

}  // namespace REngine
