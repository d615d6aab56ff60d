// OpenGL 3.3 drawing of the game: every enabled body from its collision shape (one GPU mesh
// per prepared shape, shared as the engine shares the shape), lit by a sun, a fill light
// and a dim sky; a star field; the laser; explosion flashes; and, on request, debug lines
// (contact points with their normals, bounding boxes, joints) with sleeping bodies tinted.
//
// Precision: bodies are 1e6 m out, where a float's step is 6 cm. Each body's model matrix
// is built from (position - eye) in double and only then cast to float, so what the GPU
// gets is a distance from the eye, exact to float's precision at that distance.
#pragma once

#include <epoxy/gl.h>

#include <unordered_map>
#include <vector>

#include "Camera.h"
#include "Game.h"

namespace spacegame {

struct DebugDraw {
  bool contacts = false;  // manifold points and their normals
  bool bounds = false;    // world bounding boxes
  bool sleeping = true;   // sleeping bodies tinted blue
  bool joints = true;     // joints as lines between the bodies' centres
};

class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  void Draw(const Game& game, const Camera& camera, int width, int height, const DebugDraw& debug);

 private:
  struct GpuMesh {
    GLuint vao = 0, vbo = 0;
    GLsizei count = 0;
  };
  struct Flash {
    REngine::RVec3 point_W;
    double age = 0;  // s
  };
  const GpuMesh& MeshFor(const REngine::RPreparedShape* shape);
  void DrawMesh(const GpuMesh& mesh, const Camera& camera, const REngine::RVec3& position_W,
                const REngine::RQuat& q_WS, float scale, const Eigen::Vector3f& colour,
                float emissive);
  void DrawStars(const Eigen::Matrix4f& viewProj);
  void DrawLines(const Eigen::Matrix4f& viewProj);
  void Line(const Camera& camera, const REngine::RVec3& a_W, const REngine::RVec3& b_W,
            const Eigen::Vector3f& colour);
  void Box(const Camera& camera, const REngine::RVec3& lo_W, const REngine::RVec3& hi_W,
           const Eigen::Vector3f& colour);

  GLuint m_litProgram = 0, m_lineProgram = 0, m_starProgram = 0;
  GLint m_uModel = -1, m_uViewProj = -1, m_uColour = -1, m_uEmissive = -1, m_uSunDir = -1;
  GLint m_uLineViewProj = -1, m_uStarViewProj = -1;
  std::unordered_map<const REngine::RPreparedShape*, GpuMesh> m_meshes;
  GpuMesh m_flashMesh;  // a unit sphere
  GLuint m_starVao = 0, m_starVbo = 0, m_lineVao = 0, m_lineVbo = 0;
  GLsizei m_starCount = 0;
  std::vector<float> m_lines;  // x y z r g b per vertex, camera-relative; reused each frame
  std::vector<Flash> m_flashes;
  Eigen::Matrix4f m_viewProj = Eigen::Matrix4f::Identity();
  std::uint64_t m_lastStep = 0;
};

}  // namespace spacegame
