#include <REnginePhysics/RScene.h>

#include "RSceneJson.h"

#include <REngineMath/RQuaternion.h>
#include <REnginePhysics/RConvexPolyhedron.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace REngine {

using namespace scenejson;

namespace {

// The step size RIntegrator::Update takes: > 0 and at most RIntegrator::kMaxDt.
RScalar ReadStepSize(const json& j, const std::string& path) {
  static constexpr Interval kStepSize{0, RIntegrator::kMaxDt, true, "a finite number > 0 and at most 1 (s)"};
  return ReadNumber(j, path, kStepSize);
}

RScene ReadScene(const json& doc, const RSceneLimits& limits) {
  const Object root(doc, "",
                    {"format", "gravity", "dt", "steps", "restitution_combine",
                     "friction_combine", "solver", "bodies", "joints", "actions", "rays", "characters"});
  RScene scene;
  if (root.Has("format")) {
    const json& format = root.Required("format");
    if (format != "rengine-scene/1") {
      Fail("format", "must be \"rengine-scene/1\", the format this build reads" + Got(format));
    }
  }
  RWorldSettings& settings = scene.settings;
  settings.gravity_W = root.Get("gravity", settings.gravity_W, ReadVec3);
  scene.dt = root.Get("dt", scene.dt, ReadStepSize);
  scene.steps = root.Get("steps", scene.steps, ReadSteps);
  settings.restitutionCombine =
      root.Get("restitution_combine", settings.restitutionCombine, ReadRestitutionCombine);
  settings.frictionCombine =
      root.Get("friction_combine", settings.frictionCombine, ReadFrictionCombine);
  if (root.Has("solver")) {
    const Object solver(root.Required("solver"), "solver",
                        {"iterations", "restitution_threshold", "sleeping", "broadphase"});
    settings.solverIterations = solver.Get("iterations", settings.solverIterations, ReadIterations);
    settings.restitutionThreshold =
        solver.Get("restitution_threshold", settings.restitutionThreshold, ReadNonNegative);
    settings.shortcuts.sleeping = solver.Get("sleeping", settings.shortcuts.sleeping, ReadBool);
    settings.shortcuts.broadPhase =
        solver.Get("broadphase", settings.shortcuts.broadPhase, ReadBool);
  }

  const json& bodies = root.Required("bodies");
  if (!bodies.is_array()) Fail("bodies", "must be an array of bodies" + Got(bodies));
  if (bodies.size() > limits.maxBodies) {
    Fail("bodies", "has " + std::to_string(bodies.size()) + " bodies; at most " +
                       std::to_string(limits.maxBodies) + " are allowed");
  }
  std::vector<std::vector<std::string>> ignoreNames(bodies.size());
  std::unordered_map<std::string, std::size_t> indexOf;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const std::string path = Element("bodies", i);
    scene.bodies.push_back(ReadBody(bodies[i], path, ignoreNames[i], limits));
    const auto [it, isNew] = indexOf.emplace(scene.bodies.back().name, i);
    if (!isNew) {
      Fail(Field(path, "name"), "\"" + it->first + "\" is already the name of " +
                                    Element("bodies", it->second));
    }
  }

  scene.ignore.resize(bodies.size());
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    for (std::size_t k = 0; k < ignoreNames[i].size(); ++k) {
      const std::string path = Element(Field(Element("bodies", i), "ignore"), k);
      const auto it = indexOf.find(ignoreNames[i][k]);
      if (it == indexOf.end()) Fail(path, "no body is named \"" + ignoreNames[i][k] + "\"");
      if (it->second == i) Fail(path, "a body cannot ignore itself");
      scene.ignore[i].push_back(it->second);
      scene.ignore[it->second].push_back(i);
    }
  }
  for (std::vector<std::size_t>& list : scene.ignore) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  if (root.Has("joints")) ReadJoints(root.Required("joints"), scene, limits);
  if (root.Has("actions")) ReadActions(root.Required("actions"), scene, limits);
  if (root.Has("rays")) ReadRays(root.Required("rays"), scene, limits);
  if (root.Has("characters")) ReadCharacters(root.Required("characters"), scene, limits);
  return scene;
}

}  // namespace

RSceneError::RSceneError(std::string file, std::string jsonPath, std::string problem)
    : RError(jsonPath, problem, file + ": " + (jsonPath.empty() ? "" : jsonPath + ": ") + problem),
      m_file(std::move(file)) {}

void CheckSceneLimits(const RScene& scene, const RSceneLimits& limits) {
  // Every body and joint the run may hold: the scene's and those its actions add.
  std::size_t adds = 0, jointAdds = 0;
  for (const RSceneAction& a : scene.actions) {
    adds += a.verb == RSceneAction::Verb::kAdd;
    jointAdds += a.verb == RSceneAction::Verb::kAddJoint;
  }
  const std::size_t bodies = scene.bodies.size() + adds;
  if (bodies > limits.maxBodies) {
    throw RSceneError(scene.fileName, adds ? "actions" : "bodies",
                      "has " + std::to_string(bodies) + " bodies" +
                          (adds ? " with those the actions add" : "") + "; at most " +
                          std::to_string(limits.maxBodies) + " are allowed");
  }
  const std::size_t joints = scene.joints.size() + jointAdds;
  if (joints > limits.maxJoints) {
    throw RSceneError(scene.fileName, jointAdds ? "actions" : "joints",
                      "has " + std::to_string(joints) + " joints" +
                          (jointAdds ? " with those the actions add" : "") + "; at most " +
                          std::to_string(limits.maxJoints) + " are allowed");
  }
  if (scene.steps > limits.maxSteps) {
    throw RSceneError(scene.fileName, "steps",
                      "must be at most " + std::to_string(limits.maxSteps) + " (got " +
                          std::to_string(scene.steps) + ")");
  }
  if (static_cast<double>(scene.steps) * static_cast<double>(bodies) > limits.maxBodySteps) {
    char limit[32];
    std::snprintf(limit, sizeof limit, "%.3g", limits.maxBodySteps);
    throw RSceneError(scene.fileName, "steps",
                      std::to_string(scene.steps) + " steps of " +
                          std::to_string(bodies) + " bodies exceed " + limit +
                          " body-steps");
  }
  // Actions and rays are sorted by step: the last is the latest. One after the last step
  // would silently never happen: a scene (or a run shortened by --steps) that ends first.
  if (!scene.actions.empty() && scene.actions.back().step > scene.steps) {
    const RSceneAction& a = scene.actions.back();
    throw RSceneError(scene.fileName, a.path + ".step",
                      "is after the last step (" + std::to_string(scene.steps) +
                          "): the action would never be applied (got " + std::to_string(a.step) + ")");
  }
  if (!scene.rays.empty() && scene.rays.back().step > scene.steps) {
    const RSceneRay& r = scene.rays.back();
    throw RSceneError(scene.fileName, r.path + ".step",
                      "is after the last step (" + std::to_string(scene.steps) +
                          "): the ray would never be asked (got " + std::to_string(r.step) + ")");
  }
}

RScene ParseScene(const std::string& jsonText, const std::string& fileNameForMessages,
                  const RSceneLimits& limits) {
  RScene scene;
  try {
    scene = ReadScene(ParseJson(jsonText), limits);
  } catch (const Invalid& e) {
    throw RSceneError(fileNameForMessages, e.path, e.problem);
  }
  scene.fileName = fileNameForMessages;
  CheckSceneLimits(scene, limits);
  return scene;
}

RScene LoadScene(const std::string& path, const RSceneLimits& limits) {
  struct Close {
    void operator()(std::FILE* f) const { std::fclose(f); }
  };
  const std::unique_ptr<std::FILE, Close> file(std::fopen(path.c_str(), "rb"));
  if (!file) throw RSceneError(path, "", std::string("cannot open: ") + std::strerror(errno));
  std::string text;
  char chunk[1 << 16];
  std::size_t n;
  while ((n = std::fread(chunk, 1, sizeof chunk, file.get())) > 0) {
    text.append(chunk, n);
    if (text.size() > limits.maxFileBytes) {
      throw RSceneError(path, "", "larger than " + std::to_string(limits.maxFileBytes) +
                                      " bytes, the most a scene may be");
    }
  }
  // A directory opens but does not read (EISDIR).
  if (std::ferror(file.get())) {
    throw RSceneError(path, "", std::string("cannot read: ") + std::strerror(errno));
  }
  return ParseScene(text, path, limits);
}

std::vector<RRigidBody> CreateBodies(const RScene& scene) {
  std::vector<RRigidBody> bodies;
  bodies.reserve(scene.bodies.size());
  scenejson::ShapeCache shapes;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    try {
      RBodyDef def = scene.bodies[i];
      if (!def.prepared) def.prepared = shapes.Get(def.shape);
      def.id = static_cast<std::uint32_t>(i);
      for (std::size_t j : scene.ignore[i]) def.ignore.push_back(static_cast<std::uint32_t>(j));
      bodies.emplace_back(def);
    } catch (const RBodyError& e) {
      throw RSceneError(scene.fileName, Field(Element("bodies", i), e.Field()), e.Problem());
    }
  }
  return bodies;
}

}  // namespace REngine
