// A scene's joints (docs/scene-format.md, "Joints") and the joint objects of its add_joint actions:
// read and checked at the door, every check RBodies::AddJoint makes included, so that a scene
// that loads makes its joints and a bad one is refused naming the JSON path rather than the
// engine's field.
#include "RSceneJson.h"

#include <REnginePhysics/RLimits.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_map>
#include <utility>

namespace REngine::scenejson {

namespace {

// Hinges and sliders have an axis, limits and a motor.
bool Axial(RJointType t) { return t == RJointType::kHinge || t == RJointType::kSlider; }

const char* TypeName(RJointType t) {
  switch (t) {
    case RJointType::kBall: return "ball";
    case RJointType::kHinge: return "hinge";
    case RJointType::kSlider: return "slider";
    case RJointType::kFixed: return "fixed";
    case RJointType::kDistance: return "distance";
  }
  return "?";
}

// A world point RBodies accepts: bodies are limited to 1e12 m in size, so coordinates beyond
// 1e15 m are not a place.
RVec3 ReadPoint(const json& j, const std::string& path) {
  const RVec3 p = ReadVec3(j, path);
  if (p.cwiseAbs().maxCoeff() > 1e15) Fail(path, "must be within 1e15 m of the origin" + Got(j));
  return p;
}

// A direction of any length but 0, made unit length. Scaled by its largest component first:
// [1e200, 0, 0] (whose squared norm overflows) and [1e-320, 0, 0] (whose squared norm
// underflows) are the x axis like [1, 0, 0].
RVec3 ReadAxis(const json& j, const std::string& path) {
  const RVec3 v = ReadVec3(j, path);
  const RScalar largest = v.cwiseAbs().maxCoeff();
  if (largest == 0) Fail(path, "must have a non-zero length" + Got(j));
  return (v / largest).normalized();
}

}  // namespace

bool Immovable(const RBodyDef& def) {
  const RBodyKind kind = def.kind;
  if (kind != RBodyKind::kDynamic) return true;
  for (int k = 0; k < 3; ++k) {
    if (!def.locks.linear[k] || !def.locks.angular[k]) return false;
  }
  return true;
}

RSceneJoint ReadJoint(const json& j, const std::string& path, const char* when) {
  const Object joint(j, path,
                     {"name", "type", "a", "b", "anchor", "axis", "anchor_b", "limits", "motor",
                      "min_distance", "max_distance", "collide_connected"});
  RSceneJoint out;
  out.path = path;
  out.name = ReadName(joint.Required("name"), joint.PathOf("name"));
  RJointDef& def = out.def;
  def.type = ReadChoice<RJointType>(joint.Required("type"), joint.PathOf("type"),
                                    {{"ball", RJointType::kBall},
                                     {"hinge", RJointType::kHinge},
                                     {"slider", RJointType::kSlider},
                                     {"fixed", RJointType::kFixed},
                                     {"distance", RJointType::kDistance}});
  // A field another type has is not a typo: say whose it is.
  const std::string thisType = std::string(" (this is a ") + TypeName(def.type) + " joint)";
  for (const char* field : {"axis", "limits", "motor"}) {
    if (joint.Has(field) && !Axial(def.type)) {
      Fail(joint.PathOf(field),
           std::string("only a hinge or a slider joint has ") + field + thisType);
    }
  }
  for (const char* field : {"anchor_b", "min_distance", "max_distance"}) {
    if (joint.Has(field) && def.type != RJointType::kDistance) {
      Fail(joint.PathOf(field), std::string("only a distance joint has ") + field + thisType);
    }
  }

  // The bodies' names: whether they exist, and can be joined, depends on where the joint is
  // made (CheckJointBodies).
  out.a = ReadName(joint.Required("a"), joint.PathOf("a"));
  if (joint.Has("b")) out.b = ReadName(joint.Required("b"), joint.PathOf("b"));

  def.anchor_W = ReadPoint(joint.Required("anchor"), joint.PathOf("anchor"));
  if (Axial(def.type)) def.axis_W = ReadAxis(joint.Required("axis"), joint.PathOf("axis"));
  if (joint.Has("limits")) {
    const std::string at = joint.PathOf("limits");
    const json& limits = joint.Required("limits");
    const auto l = ReadVector<2>(limits, at);
    if (!(l[0] <= l[1])) Fail(at, "must be [lower, upper] with lower <= upper" + Got(limits));
    if (def.type == RJointType::kHinge && (l[0] < -kPi || l[1] > kPi)) {
      Fail(at, "a hinge's limits are angles within [-pi, pi] rad" + Got(limits));
    }
    def.hasLimits = true, def.lower = l[0], def.upper = l[1];
  }
  if (joint.Has("motor")) {
    const Object motor(joint.Required("motor"), joint.PathOf("motor"), {"speed", "max_force"});
    def.motor.enabled = true;
    // The motors RBodies::AddJoint accepts (RLimits.h).
    static constexpr Interval kSpeed{-kMaxMotorSpeed, kMaxMotorSpeed, false, "a finite number within 1e15"};
    static constexpr Interval kForce{0, kMaxMotorForce, false, "a finite number >= 0 and at most 1e30"};
    def.motor.speed = ReadNumber(motor.Required("speed"), motor.PathOf("speed"), kSpeed);
    def.motor.maxForce = ReadNumber(motor.Required("max_force"), motor.PathOf("max_force"), kForce);
  }
  if (def.type == RJointType::kDistance) {
    if (joint.Has("anchor_b")) {
      def.hasAnchorB = true;
      def.anchorB_W = ReadPoint(joint.Required("anchor_b"), joint.PathOf("anchor_b"));
    }
    def.minDistance = joint.Get("min_distance", RScalar(-1), ReadNonNegative);
    def.maxDistance = joint.Get("max_distance", RScalar(-1), ReadNonNegative);
    // A range left out is the anchors' distance when the joint is made, as RJointDef's is.
    const RScalar now = ((def.hasAnchorB ? def.anchorB_W : def.anchor_W) - def.anchor_W).norm();
    const RScalar lo = def.minDistance < 0 ? now : def.minDistance;
    const RScalar hi = def.maxDistance < 0 ? now : def.maxDistance;
    const auto text = [](RScalar x) {
      char s[32];
      std::snprintf(s, sizeof s, "%.17g", x);
      return std::string(s);
    };
    if (lo > hi) {
      if (def.minDistance < 0) {
        Fail(joint.PathOf("max_distance"),
             "is less than the anchors' distance " + std::string(when) + " (" + text(now) +
                 " m), which min_distance is when left out" + Got(joint.Required("max_distance")));
      }
      Fail(joint.PathOf("min_distance"), "must not exceed max_distance (" + text(hi) + " m)" +
                                             Got(joint.Required("min_distance")));
    }
    if (hi == 0) {
      Fail(joint.Has("max_distance") ? joint.PathOf("max_distance") : path,
           "a distance joint needs max_distance > 0, or anchors apart (anchor_b): anchors "
           "that stay together are a ball joint");
    }
  }
  def.collideConnected = joint.Get("collide_connected", def.collideConnected, ReadBool);
  return out;
}

void CheckJointBodies(const RSceneJoint& joint, const JointBodies& bodies,
                      const std::function<std::string(const std::string&)>& noBodyNamed) {
  // Two different bodies (or one and the world) that exist here, one of them movable.
  const auto find = [&](const std::string& name, const char* field) {
    const auto it = bodies.find(name);
    if (it == bodies.end()) Fail(Field(joint.path, field), noBodyNamed(name));
    return it->second;
  };
  const bool aImmovable = find(joint.a, "a");
  const bool bImmovable = joint.b.empty() || find(joint.b, "b");
  if (joint.b == joint.a) Fail(Field(joint.path, "b"), "must be another body than a (\"" + joint.a + "\")");
  if (aImmovable && bImmovable) {
    const std::string what =
        joint.b.empty() ? "\"" + joint.a + "\" is static or kinematic and b is the world"
                        : "\"" + joint.a + "\" and \"" + joint.b + "\" are both static or kinematic";
    Fail(Field(joint.path, "a"), what + ": a joint needs a dynamic body");
  }
}

void ReadJoints(const json& j, RScene& scene, const RSceneLimits& limits) {
  if (!j.is_array()) Fail("joints", "must be an array of joints" + Got(j));
  if (j.size() > limits.maxJoints) {
    Fail("joints", "has " + std::to_string(j.size()) + " joints; at most " +
                       std::to_string(limits.maxJoints) + " are allowed");
  }
  JointBodies bodies;
  for (const RBodyDef& b : scene.bodies) bodies.emplace(b.name, Immovable(b));
  const auto noBodyNamed = [](const std::string& name) {
    return "no body of the scene is named \"" + name +
           "\" (a joint joins bodies the scene starts with; add_joint actions join bodies that exist at "
           "their step)";
  };
  std::unordered_map<std::string, std::size_t> indexOf;
  scene.joints.reserve(j.size());
  for (std::size_t i = 0; i < j.size(); ++i) {
    RSceneJoint joint = ReadJoint(j[i], Element("joints", i), "as the scene starts");
    CheckJointBodies(joint, bodies, noBodyNamed);
    const auto [it, isNew] = indexOf.emplace(joint.name, i);
    if (!isNew) {
      Fail(Field(joint.path, "name"), "\"" + joint.name + "\" is already the name of " +
                                          Element("joints", it->second));
    }
    scene.joints.push_back(std::move(joint));
  }
}

}  // namespace REngine::scenejson
