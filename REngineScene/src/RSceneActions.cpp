// A scene's actions (docs/scene-format.md, "Actions"), joint actions included: read,
// checked against the bodies and joints that exist at each step, and sorted by step.
#include "RSceneJson.h"

#include <REnginePhysics/RLimits.h>

#include <algorithm>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace REngine::scenejson {

namespace {

// The impulses RRigidBody::AddImpulse_W accepts (RLimits.h).
constexpr Interval kImpulseRange{-kMaxImpulse, kMaxImpulse, false, "a finite number within 1e30 (N s)"};

RSceneAction ReadAction(const json& j, const std::string& path, const RSceneLimits& limits) {
  const Object action(j, path, {"step", "add", "remove", "impulse", "set_velocity", "add_joint", "remove_joint"});
  RSceneAction a;
  a.path = path;
  a.step = ReadSteps(action.Required("step"), action.PathOf("step"));
  int verbs = 0;
  for (const char* verb : {"add", "remove", "impulse", "set_velocity", "add_joint", "remove_joint"}) {
    verbs += action.Has(verb);
  }
  if (verbs != 1) {
    Fail(path, "must have exactly one of the verbs add, remove, impulse, set_velocity, add_joint, "
               "remove_joint (has " + std::to_string(verbs) + ")");
  }
  if (action.Has("add")) {
    a.verb = RSceneAction::Verb::kAdd;
    a.def = ReadBody(action.Required("add"), action.PathOf("add"), a.ignore, limits);
    a.body = a.def.name;
  } else if (action.Has("remove")) {
    a.verb = RSceneAction::Verb::kRemove;
    a.body = ReadName(action.Required("remove"), action.PathOf("remove"));
  } else if (action.Has("add_joint")) {
    // Its bodies are checked in the replay, against those that exist at its step.
    a.verb = RSceneAction::Verb::kAddJoint;
    a.joint = ReadJoint(action.Required("add_joint"), action.PathOf("add_joint"), "when the action applies");
  } else if (action.Has("remove_joint")) {
    a.verb = RSceneAction::Verb::kRemoveJoint;
    a.joint.name = ReadName(action.Required("remove_joint"), action.PathOf("remove_joint"));
    a.joint.path = action.PathOf("remove_joint");
  } else if (action.Has("impulse")) {
    a.verb = RSceneAction::Verb::kImpulse;
    const Object impulse(action.Required("impulse"), action.PathOf("impulse"),
                         {"body", "impulse", "point"});
    a.body = ReadName(impulse.Required("body"), impulse.PathOf("body"));
    a.impulse_W = ReadVector<3>(impulse.Required("impulse"), impulse.PathOf("impulse"), kImpulseRange);
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

// The joints that exist at each step of the loader's replay, by name, with their bodies. A body
// removed takes its joints along, as RBodies::Remove does, so that a later remove_joint of one
// of them is refused, and an add_joint may take its name again, as the run will find them.
class LiveJoints {
 public:
  explicit LiveJoints(const std::vector<RSceneJoint>& sceneJoints) {
    for (const RSceneJoint& j : sceneJoints) Insert(j);
  }

  void Add(const RSceneJoint& j, std::uint64_t step) {
    if (m_joints.count(j.name)) {
      Fail(Field(j.path, "name"), "\"" + j.name + "\" is already the name of a joint at step " + std::to_string(step));
    }
    Insert(j);
  }

  void Remove(const RSceneAction& a) {
    const auto it = m_joints.find(a.joint.name);
    if (it == m_joints.end()) {
      // Where it went, when it was there once: the usual mistake is a joint its body took along.
      const auto gone = m_gone.find(a.joint.name);
      Fail(a.joint.path, "no joint is named \"" + a.joint.name + "\" at step " + std::to_string(a.step) +
                             (gone == m_gone.end() ? "" : " (" + gone->second + ")"));
    }
    m_joints.erase(it);
    m_gone[a.joint.name] = "removed by " + a.path + " at step " + std::to_string(a.step);
  }

  // Each name in m_ofBody[body] was a joint of the body once; it goes if it still is.
  void RemoveBody(const RSceneAction& a) {
    const auto of = m_ofBody.find(a.body);
    if (of == m_ofBody.end()) return;
    for (const std::string& name : of->second) {
      const auto it = m_joints.find(name);
      if (it == m_joints.end() || (it->second.first != a.body && it->second.second != a.body)) continue;
      m_joints.erase(it);
      m_gone[name] = "it went with body \"" + a.body + "\", removed by " + a.path + " at step " + std::to_string(a.step);
    }
    m_ofBody.erase(of);
  }

 private:
  void Insert(const RSceneJoint& j) {
    m_joints.emplace(j.name, std::make_pair(j.a, j.b));
    m_gone.erase(j.name);
    m_ofBody[j.a].push_back(j.name);
    if (!j.b.empty()) m_ofBody[j.b].push_back(j.name);
  }

  std::unordered_map<std::string, std::pair<std::string, std::string>> m_joints;  // name -> a, b
  std::unordered_map<std::string, std::vector<std::string>> m_ofBody;
  std::unordered_map<std::string, std::string> m_gone;  // name -> how it went
};

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
  // name is new among them, and an added body's ignore list names bodies that exist; an added
  // joint's name is new among the joints, its bodies exist and can be joined, and a removed
  // joint exists.
  JointBodies live;
  for (const RBodyDef& b : scene.bodies) live.emplace(b.name, Immovable(b));
  LiveJoints joints(scene.joints);
  ShapeCache shapes;
  for (RSceneAction& a : scene.actions) {
    if (a.verb == RSceneAction::Verb::kAddJoint) {
      CheckJointBodies(a.joint, live, [&a](const std::string& name) {
        return "no body is named \"" + name + "\" at step " + std::to_string(a.step);
      });
      joints.Add(a.joint, a.step);
      continue;
    }
    if (a.verb == RSceneAction::Verb::kRemoveJoint) {
      joints.Remove(a);
      continue;
    }
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
      live.emplace(a.body, Immovable(a.def));
      continue;
    }
    const char* verb = a.verb == RSceneAction::Verb::kRemove     ? "remove"
                       : a.verb == RSceneAction::Verb::kImpulse ? "impulse.body"
                                                                 : "set_velocity.body";
    if (!live.count(a.body)) {
      Fail(Field(a.path, verb), "no body is named \"" + a.body + "\" at step " + std::to_string(a.step));
    }
    if (a.verb == RSceneAction::Verb::kRemove) {
      live.erase(a.body);
      joints.RemoveBody(a);
    }
  }
}

}  // namespace REngine::scenejson
