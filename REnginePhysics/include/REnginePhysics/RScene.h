// Scene files (../shared/SCENE_FORMAT.md, "rengine-scene/1"): a world's settings, its step
// and step count, and its bodies, read from JSON and checked field by field.
//
// Every problem is reported, never repaired: a typo in a field name, a NaN, a zero-length
// quaternion or a flat hull is an RSceneError naming the file, the JSON path and what is
// wrong, so a scene that loads is the scene its author meant.
#pragma once

#include <REngineMath/RMath.h>
#include <REnginePhysics/RIntegrator.h>
#include <REnginePhysics/RRigidBody.h>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace REngine {

// A scene that cannot be used. what() is "<file>: <json path>: <problem>", e.g.
// "scene.json: bodies[3].shape.radius: must be a finite number > 0 (got -1)"; the path is
// left out when the problem is the file itself (cannot be read, not valid JSON).
class RSceneError : public std::runtime_error {
 public:
  RSceneError(std::string file, std::string jsonPath, std::string problem);

  const std::string& File() const { return m_file; }
  const std::string& JsonPath() const { return m_jsonPath; }  // "" for a file-level problem
  const std::string& Problem() const { return m_problem; }

 private:
  std::string m_file, m_jsonPath, m_problem;
};

struct RScene {
  RWorldSettings settings;
  RScalar dt = RScalar(1) / 60;  // s
  std::uint64_t steps = 600;
  std::vector<RBodyDef> bodies;  // in file order, which is also the CSV's row order
  // Per body: indices of the bodies it never collides with; symmetric, sorted, unique.
  std::vector<std::vector<std::size_t>> ignore;
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
  std::uint64_t maxBodies = 100000;         // the pair loop visits n^2 / 2 pairs a step
  // Per hull: building grows about as n^2 (measured: 20 ms at 1000 points, 1.3 s at 10000,
  // about 2 min at 100000).
  std::uint64_t maxHullPoints = 10000;
  std::uint64_t maxSteps = 100000000;       // 1e8: 19 days of game time at 60 Hz
  // bodies x steps: 1e10 is a 30000-body scene for 3e5 steps, or hours of stepping.
  double maxBodySteps = 1e10;
};

// Reads and validates a scene file. Throws RSceneError (also when the file cannot be read).
RScene LoadScene(const std::string& path, const RSceneLimits& limits = {});

// Validates scene JSON held in memory; fileNameForMessages only labels errors.
RScene ParseScene(const std::string& jsonText, const std::string& fileNameForMessages,
                  const RSceneLimits& limits = {});

// Checks a scene's size against the limits (ParseScene does; call it again after changing
// steps or bodies). Throws RSceneError naming "steps" or "bodies".
void CheckSceneLimits(const RScene& scene, const RSceneLimits& limits);

// The scene's bodies, in scene order. A definition that parses but has no valid mass
// properties (a box so large that its mass overflows) throws RSceneError with the path of
// the body's offending field.
std::vector<RRigidBody> CreateBodies(const RScene& scene);

}  // namespace REngine
