// OpenGL 3.3 drawing of a list of shapes and lines (DrawList): each shape from its collision
// shape's triangles (one GPU mesh per prepared shape, shared as the engine shares the
// shape), lit by a sun, a fill light and a dim sky, over a star field. What goes in the
// list is the caller's: the game's view (GameView.h) or a trajectory's (rengine-view).
//
// Precision: bodies are 1e6 m out, where a float's step is 6 cm. Each body's model matrix
// is built from (position - eye) in double and only then cast to float, so what the GPU
// gets is a distance from the eye, exact to float's precision at that distance.
#pragma once

#include <REnginePhysics/RRigidBody.h>
#include <epoxy/gl.h>

#include <unordered_map>
#include <vector>

#include "Camera.h"
#include "ShapeMeshes.h"

namespace spacegame {

struct DrawItem {
  const REngine::RPreparedShape* shape = nullptr;      // null: a ball of radius `scale`
  REngine::RVec3 position_W = REngine::RVec3::Zero();  // the shape frame S, world, m
  REngine::RQuat q_WS = REngine::RQuat::Identity();
  Eigen::Vector3f colour = Eigen::Vector3f::Constant(0.7f);  // linear RGB
  float scale = 1;                                           // of the shape's size
  float emissive = 0;  // 1: drawn in its colour, unlit (a flash)
};

struct DrawLine {
  REngine::RVec3 a_W, b_W;  // world, m
  Eigen::Vector3f colour;
};

// What to draw this frame; cleared and refilled each frame (its vectors keep their room).
struct DrawList {
  std::vector<DrawItem> items;
  std::vector<DrawLine> lines;
  void Clear() { items.clear(), lines.clear(); }
  void Line(const REngine::RVec3& a_W, const REngine::RVec3& b_W, const Eigen::Vector3f& c) {
    lines.push_back({a_W, b_W, c});
  }
  // The twelve edges of an axis-aligned box, world, m.
  void Box(const REngine::RVec3& lo_W, const REngine::RVec3& hi_W, const Eigen::Vector3f& c);
};

class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  void Draw(const DrawList& list, const Camera& camera, int width, int height);

 private:
  struct GpuMesh {
    GLuint vao = 0, vbo = 0;
    GLsizei count = 0;
  };
  const GpuMesh& MeshFor(const REngine::RPreparedShape* shape);
  static GpuMesh Upload(const std::vector<MeshVertex>& vertices);
  void DrawMesh(const GpuMesh& mesh, const Camera& camera, const REngine::RVec3& position_W,
                const REngine::RQuat& q_WS, float scale, const Eigen::Vector3f& colour,
                float emissive);
  void DrawStars(const Eigen::Matrix4f& viewProj);
  void DrawLines(const Eigen::Matrix4f& viewProj);

  GLuint m_litProgram = 0, m_lineProgram = 0, m_starProgram = 0;
  GLint m_uModel = -1, m_uViewProj = -1, m_uColour = -1, m_uEmissive = -1, m_uSunDir = -1;
  GLint m_uLineViewProj = -1, m_uStarViewProj = -1;
  std::unordered_map<const REngine::RPreparedShape*, GpuMesh> m_meshes;
  GpuMesh m_ballMesh;  // a unit ball
  GLuint m_starVao = 0, m_starVbo = 0, m_lineVao = 0, m_lineVbo = 0;
  GLsizei m_starCount = 0;
  std::vector<float> m_lines;  // x y z r g b per vertex, camera-relative; reused each frame
  Eigen::Matrix4f m_viewProj = Eigen::Matrix4f::Identity();
};

}  // namespace spacegame
