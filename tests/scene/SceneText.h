// Scene texts for the scene suites (scene_test, scene_rejects_test): a valid scene of one
// body named "a", a sphere's shape and more fields beside it, a shape field. In a namespace
// of their own: support/CliRunner.h has a kSphere of another radius.
#pragma once

#include <string>

namespace REngine::test::scenetext {

// A valid scene with one body named "a": `body` holds the body's other fields (its shape
// at least), `top` extra top-level fields.
inline std::string OneBody(const std::string& body, const std::string& top = "") {
  return "{" + top + (top.empty() ? "" : ", ") + R"("bodies": [{"name": "a", )" + body + "}]}";
}
inline const std::string kSphere = R"("shape": {"type": "sphere", "radius": 1})";
inline std::string Sphere(const std::string& more) { return kSphere + ", " + more; }
inline std::string Shape(const std::string& shape) { return R"("shape": )" + shape; }

}  // namespace REngine::test::scenetext
