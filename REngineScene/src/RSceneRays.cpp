// A scene's rays (docs/scene-format.md, "Rays"): read, checked at the door, sorted by step.
#include "RSceneJson.h"

#include <algorithm>
#include <set>
#include <utility>

namespace REngine::scenejson {

namespace {

RSceneRay ReadRay(const json& j, const std::string& path) {
  const Object ray(j, path, {"name", "step", "origin", "direction", "max_distance", "mask", "all"});
  RSceneRay r;
  r.path = path;
  r.name = ReadName(ray.Required("name"), ray.PathOf("name"));
  r.step = ReadSteps(ray.Required("step"), ray.PathOf("step"));
  // As RQueries checks them, so that a scene that loads is a scene whose rays can be cast.
  r.origin_W = ReadVec3(ray.Required("origin"), ray.PathOf("origin"));
  if (r.origin_W.cwiseAbs().maxCoeff() > 1e15) {
    Fail(ray.PathOf("origin"), "must be within 1e15 m of the origin" + Got(ray.Required("origin")));
  }
  r.direction_W = ReadVec3(ray.Required("direction"), ray.PathOf("direction"));
  if (r.direction_W.cwiseAbs().maxCoeff() == 0) {
    Fail(ray.PathOf("direction"), "must have a non-zero length" + Got(ray.Required("direction")));
  }
  r.maxDistance = ReadNonNegative(ray.Required("max_distance"), ray.PathOf("max_distance"));
  r.mask = ray.Get("mask", r.mask, ReadBits);
  r.all = ray.Get("all", r.all, ReadBool);
  return r;
}

}  // namespace

void ReadRays(const json& j, RScene& scene, const RSceneLimits& limits) {
  if (!j.is_array()) Fail("rays", "must be an array of rays" + Got(j));
  if (j.size() > limits.maxRays) {
    Fail("rays", "has " + std::to_string(j.size()) + " rays; at most " +
                     std::to_string(limits.maxRays) + " are allowed");
  }
  scene.rays.reserve(j.size());
  // A name is the ray's column in the CSV, beside its step: unique among the rays of a step
  // (the same laser may be asked at every step).
  std::set<std::pair<std::uint64_t, std::string>> seen;
  for (std::size_t i = 0; i < j.size(); ++i) {
    RSceneRay r = ReadRay(j[i], Element("rays", i));
    if (!seen.emplace(r.step, r.name).second) {
      Fail(Field(r.path, "name"), "\"" + r.name + "\" is already the name of a ray at step " +
                                      std::to_string(r.step));
    }
    scene.rays.push_back(std::move(r));
  }
  std::stable_sort(scene.rays.begin(), scene.rays.end(),
                   [](const RSceneRay& x, const RSceneRay& y) { return x.step < y.step; });
}

}  // namespace REngine::scenejson
