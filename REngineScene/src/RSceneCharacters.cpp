// A scene's characters (docs/scene-format.md, "Characters"): read, checked at the door as
// RCharacter checks its definition, their inputs sorted by step.
#include "RSceneJson.h"

#include <REnginePhysics/RCharacter.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace REngine::scenejson {

namespace {

constexpr RScalar kPi = RScalar(3.141592653589793);

RScalar ReadSlopeDegrees(const json& j, const std::string& path) {
  static constexpr Interval kSlope{0, 90, false, "a number of degrees at least 0 and below 90"};
  const RScalar deg = ReadNumber(j, path, kSlope);
  if (deg == 90) Fail(path, "must be below 90 (a wall is not ground)" + Got(j));
  return deg;
}

RSceneCharacter::Input ReadInput(const json& j, const std::string& path) {
  const Object input(j, path, {"step", "velocity", "jump"});
  RSceneCharacter::Input in;
  in.step = ReadSteps(input.Required("step"), input.PathOf("step"));
  in.velocity_W = input.Get("velocity", in.velocity_W, ReadVec3);
  if (in.velocity_W.cwiseAbs().maxCoeff() > 1e15) {
    Fail(input.PathOf("velocity"), "must be within 1e15 m/s" + Got(input.Required("velocity")));
  }
  if (input.Has("jump")) {
    in.jump = ReadPositive(input.Required("jump"), input.PathOf("jump"));
    if (in.jump > 1e15) Fail(input.PathOf("jump"), "must be at most 1e15 m/s" + Got(input.Required("jump")));
  }
  return in;
}

RSceneCharacter ReadCharacter(const json& j, const std::string& path, const RScene& scene,
                              const std::unordered_map<std::string, std::uint32_t>& bodyIds,
                              const RSceneLimits& limits) {
  const Object ch(j, path,
                  {"name", "shape", "position", "orientation", "mass", "up", "max_slope_deg",
                   "step_height", "max_push_force", "contact_offset", "category", "mask",
                   "ignore", "inputs"});
  RSceneCharacter c;
  c.path = path;
  RCharacterDef& def = c.def;
  def.name = ReadName(ch.Required("name"), ch.PathOf("name"));
  def.shape = ReadShape(ch.Required("shape"), ch.PathOf("shape"), limits);
  if (def.shape.type == RShapeType::kCompound || def.shape.type == RShapeType::kMesh) {
    Fail(Field(ch.PathOf("shape"), "type"), "a character's shape must be convex: sphere, box, capsule, "
                                            "cylinder or hull");
  }
  def.position_W = ReadVec3(ch.Required("position"), ch.PathOf("position"));
  def.q_WS = ch.Get("orientation", def.q_WS, ReadOrientation);
  def.mass = ch.Get("mass", def.mass, ReadPositive);
  if (ch.Has("up")) {
    def.up_W = ReadVec3(ch.Required("up"), ch.PathOf("up"));
    if (std::abs(def.up_W.norm() - 1) > 1e-3) {
      Fail(ch.PathOf("up"), "must be a unit vector" + Got(ch.Required("up")));
    }
  } else if (scene.settings.gravity_W == RVec3::Zero()) {
    Fail(ch.PathOf("up"), "is required when gravity is zero (by default it is opposite gravity)");
  }
  def.maxSlope = ch.Get("max_slope_deg", RScalar(45), ReadSlopeDegrees) * kPi / 180;
  def.stepHeight = ch.Get("step_height", def.stepHeight, ReadNonNegative);
  def.maxPushForce = ch.Get("max_push_force", def.maxPushForce, ReadNonNegative);
  def.contactOffset = ch.Get("contact_offset", def.contactOffset, ReadPositive);
  def.category = ch.Get("category", def.category, ReadBits);
  def.mask = ch.Get("mask", def.mask, ReadBits);
  if (ch.Has("ignore")) {
    const std::vector<std::string> names = ReadNames(ch.Required("ignore"), ch.PathOf("ignore"));
    for (std::size_t i = 0; i < names.size(); ++i) {
      const auto it = bodyIds.find(names[i]);
      if (it == bodyIds.end()) Fail(Element(ch.PathOf("ignore"), i), "no body of the scene is named \"" + names[i] + "\"");
      def.ignore.push_back(it->second);
    }
  }
  // Every check RCharacter makes, here, so that a scene that loads makes its characters.
  try {
    RCharacter made(def);
  } catch (const RCharacterError& e) {
    static const std::unordered_map<std::string, std::string> kField = {
        {"max_slope", "max_slope_deg"}, {"orientation", "orientation"}};
    const auto renamed = kField.find(e.Field());
    Fail(ch.PathOf(renamed == kField.end() ? e.Field() : renamed->second), e.Problem());
  }
  if (ch.Has("inputs")) {
    const json& inputs = ch.Required("inputs");
    const std::string inputsPath = ch.PathOf("inputs");
    if (!inputs.is_array()) Fail(inputsPath, "must be an array of inputs" + Got(inputs));
    if (inputs.size() > limits.maxInputs) {
      Fail(inputsPath, "has " + std::to_string(inputs.size()) + " inputs; at most " +
                           std::to_string(limits.maxInputs) + " are allowed");
    }
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      c.inputs.push_back(ReadInput(inputs[i], Element(inputsPath, i)));
      if (c.inputs.back().step > scene.steps) {
        Fail(Field(Element(inputsPath, i), "step"), "is after the scene's last step (" +
                                                        std::to_string(scene.steps) + ")");
      }
      if (i > 0 && c.inputs[i - 1].step >= c.inputs[i].step) {
        Fail(Field(Element(inputsPath, i), "step"), "must come after the step of the input before it");
      }
    }
  }
  return c;
}

}  // namespace

void ReadCharacters(const json& j, RScene& scene, const RSceneLimits& limits) {
  if (!j.is_array()) Fail("characters", "must be an array of characters" + Got(j));
  if (j.size() > limits.maxCharacters) {
    Fail("characters", "has " + std::to_string(j.size()) + " characters; at most " +
                           std::to_string(limits.maxCharacters) + " are allowed");
  }
  // Scene body i has id i (RSceneWorld): an ignore list names bodies by it.
  std::unordered_map<std::string, std::uint32_t> bodyIds;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
    bodyIds.emplace(scene.bodies[i].name, static_cast<std::uint32_t>(i));
  }
  // Bodies the actions add are rows of the trajectory too.
  std::unordered_set<std::string> taken;
  for (const RSceneAction& a : scene.actions) {
    if (a.verb == RSceneAction::Verb::kAdd) taken.insert(a.body);
  }
  std::size_t inputs = 0;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string path = Element("characters", i);
    RSceneCharacter c = ReadCharacter(j[i], path, scene, bodyIds, limits);
    const std::string& name = c.def.name;
    if (bodyIds.count(name) || taken.count(name)) {
      Fail(Field(path, "name"), "\"" + name + "\" is already the name of a body (characters and "
                                              "bodies share the trajectory's rows)");
    }
    for (const RSceneCharacter& other : scene.characters) {
      if (other.def.name == name) Fail(Field(path, "name"), "\"" + name + "\" is already the name of " + other.path);
    }
    inputs += c.inputs.size();
    if (inputs > limits.maxInputs) {
      Fail(Field(path, "inputs"), "brings the scene's inputs to " + std::to_string(inputs) + "; at most " +
                                      std::to_string(limits.maxInputs) + " are allowed");
    }
    scene.characters.push_back(std::move(c));
  }
}

}  // namespace REngine::scenejson
