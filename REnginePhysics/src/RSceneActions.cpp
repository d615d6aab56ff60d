// A scene's actions (SCENE_FORMAT.md, "Actions"): read, checked against the bodies that exist
// at each step, and sorted by step.
#include "RSceneJson.h"

#include <algorithm>
#include <map>
#include <set>
#include <tuple>

namespace REngine::scenejson {

namespace {

RSceneAction ReadAction(const json& j, const std::string& path, const RSceneLimits& limits) {
  const Object action(j, path, {"step", "add", "remove", "impulse", "set_velocity"});
  RSceneAction a;
  a.path = path;
  a.step = ReadSteps(action.Required("step"), action.PathOf("step"));
  int verbs = 0;
  for (const char* verb : {"add", "remove", "impulse", "set_velocity"}) verbs += action.Has(verb);
  if (verbs != 1) {
    Fail(path, "must have exactly one of the verbs add, remove, impulse, set_velocity (has " +
                   std::to_string(verbs) + ")");
  }
  if (action.Has("add")) {
    a.verb = RSceneAction::Verb::kAdd;
    a.def = ReadBody(action.Required("add"), action.PathOf("add"), a.ignore, limits);
    a.body = a.def.name;
  } else if (action.Has("remove")) {
    a.verb = RSceneAction::Verb::kRemove;
    a.body = ReadName(action.Required("remove"), action.PathOf("remove"));
  } else if (action.Has("impulse")) {
    a.verb = RSceneAction::Verb::kImpulse;
    const Object impulse(action.Required("impulse"), action.PathOf("impulse"),
                         {"body", "impulse", "point"});
    a.body = ReadName(impulse.Required("body"), impulse.PathOf("body"));
    a.impulse_W = ReadVec3(impulse.Required("impulse"), impulse.PathOf("impulse"));
    if (impulse.Has("point")) a.point_W = ReadVec3(impulse.Required("point"), impulse.PathOf("point"));
  } else {
    a.verb = RSceneAction::Verb::kSetVelocity;
    const Object set(action.Required("set_velocity"), action.PathOf("set_velocity"),
                     {"body", "velocity", "angular_velocity"});
    a.body = ReadName(set.Required("body"), set.PathOf("body"));
    if (set.Has("velocity")) a.velocity_W = ReadVec3(set.Required("velocity"), set.PathOf("velocity"));
    if (set.Has("angular_velocity")) {
      a.angularVelocity_W = ReadVec3(set.Required("angular_velocity"), set.PathOf("angular_velocity"));
    }
  }
  return a;
}

}  // namespace

void ReadActions(const json& j, RScene& scene, const RSceneLimits& limits) {
  if (!j.is_array()) Fail("actions", "must be an array of actions" + Got(j));
  if (j.size() > limits.maxActions) {
    Fail("actions", "has " + std::to_string(j.size()) + " actions; at most " +
                        std::to_string(limits.maxActions) + " are allowed");
  }
  scene.actions.reserve(j.size());
  for (std::size_t i = 0; i < j.size(); ++i) {
    scene.actions.push_back(ReadAction(j[i], Element("actions", i), limits));
  }
  std::stable_sort(scene.actions.begin(), scene.actions.end(),
                   [](const RSceneAction& x, const RSceneAction& y) { return x.step < y.step; });

  // Replay the names: every action names a body that exists at its step, an added body's
  // name is new among them, and an added body's ignore list names bodies that exist.
  std::set<std::string> live;
  for (const RBodyDef& b : scene.bodies) live.insert(b.name);
  ShapeCache shapes;
  for (RSceneAction& a : scene.actions) {
    if (a.verb == RSceneAction::Verb::kAdd) {
      const std::string field = Field(a.path, "add");
      if (live.count(a.body)) {
        Fail(Field(field, "name"), "\"" + a.body + "\" is already the name of a body at step " +
                                       std::to_string(a.step));
      }
      for (std::size_t k = 0; k < a.ignore.size(); ++k) {
        const std::string path = Element(Field(field, "ignore"), k);
        if (a.ignore[k] == a.body) Fail(path, "a body cannot ignore itself");
        if (!live.count(a.ignore[k])) {
          Fail(path, "no body is named \"" + a.ignore[k] + "\" at step " + std::to_string(a.step));
        }
      }
      // The body's checks (mass, inertia) at load, as for the scene's bodies: a scene that
      // loads runs.
      try {
        a.def.prepared = shapes.Get(a.def.shape);
        (void)RRigidBody(a.def);
      } catch (const RBodyError& e) {
        Fail(Field(field, e.Field()), e.Problem());
      }
      live.insert(a.body);
      continue;
    }
    const char* verb = a.verb == RSceneAction::Verb::kRemove     ? "remove"
                       : a.verb == RSceneAction::Verb::kImpulse ? "impulse.body"
                                                                 : "set_velocity.body";
    if (!live.count(a.body)) {
      Fail(Field(a.path, verb), "no body is named \"" + a.body + "\" at step " + std::to_string(a.step));
    }
    if (a.verb == RSceneAction::Verb::kRemove) live.erase(a.body);
  }
}

}  // namespace REngine::scenejson
