#include "Renderer.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "ShapeMeshes.h"

namespace spacegame {
using namespace REngine;

namespace {

// Lit shapes: a warm sun, a cool fill from the other side and a dim sky term, so a face
// turned away from the sun still reads as a shape against black space; Blinn specular for
// the station's and ship's edges. Colours go out gamma-encoded (sRGB-ish).
const char* kLitVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
uniform mat4 uModel;     // shape frame to camera-relative world, scaled
uniform mat4 uViewProj;
out vec3 vNormal;
out vec3 vToEye;
void main() {
  vec4 p = uModel * vec4(aPosition, 1.0);
  vNormal = mat3(uModel) * aNormal;
  vToEye = -p.xyz;
  gl_Position = uViewProj * p;
})";
const char* kLitFragment = R"(#version 330 core
in vec3 vNormal;
in vec3 vToEye;
uniform vec3 uColour;
uniform float uEmissive;
uniform vec3 uSunDir;    // towards the sun, unit
out vec4 fragColour;
void main() {
  vec3 n = normalize(vNormal);
  vec3 v = normalize(vToEye);
  if (dot(n, v) < 0.0) n = -n;  // two-sided: meshes are seen from inside
  float sun = max(dot(n, uSunDir), 0.0);
  float fill = max(dot(n, normalize(vec3(-0.5, -0.3, -0.6))), 0.0);
  float sky = 0.5 + 0.5 * n.y;
  float spec = pow(max(dot(n, normalize(uSunDir + v)), 0.0), 40.0);
  vec3 light = vec3(1.0, 0.95, 0.85) * 0.95 * sun + vec3(0.35, 0.45, 0.65) * 0.45 * fill +
               vec3(0.10, 0.12, 0.16) * sky + vec3(0.05);
  vec3 c = uColour * light + vec3(0.35) * spec * sun;
  c = mix(c, uColour, uEmissive);
  fragColour = vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
})";

const char* kLineVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aColour;
uniform mat4 uViewProj;
out vec3 vColour;
void main() { vColour = aColour; gl_Position = uViewProj * vec4(aPosition, 1.0); })";
const char* kLineFragment = R"(#version 330 core
in vec3 vColour;
out vec4 fragColour;
void main() { fragColour = vec4(vColour, 1.0); })";

// Stars: directions at infinity (w = 0), so only the view's rotation moves them.
const char* kStarVertex = R"(#version 330 core
layout(location = 0) in vec4 aStar;  // direction, brightness
uniform mat4 uViewProj;
out float vBright;
void main() {
  vBright = aStar.w;
  gl_Position = uViewProj * vec4(aStar.xyz, 0.0);
  gl_Position.z = gl_Position.w * 0.99999;  // at the far plane
  gl_PointSize = 1.0 + 2.0 * aStar.w;
})";
const char* kStarFragment = R"(#version 330 core
in float vBright;
out vec4 fragColour;
void main() { fragColour = vec4(vec3(0.45 + 0.55 * vBright) * vec3(0.9, 0.95, 1.0), 1.0); })";

GLuint Compile(GLenum type, const char* source) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("shader: ") + log);
  }
  return s;
}

GLuint Program(const char* vertex, const char* fragment) {
  const GLuint p = glCreateProgram();
  const GLuint v = Compile(GL_VERTEX_SHADER, vertex), f = Compile(GL_FRAGMENT_SHADER, fragment);
  glAttachShader(p, v);
  glAttachShader(p, f);
  glLinkProgram(p);
  glDeleteShader(v);
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) throw std::runtime_error("shader program does not link");
  return p;
}

}  // namespace

Renderer::Renderer() {
  m_litProgram = Program(kLitVertex, kLitFragment);
  m_uModel = glGetUniformLocation(m_litProgram, "uModel");
  m_uViewProj = glGetUniformLocation(m_litProgram, "uViewProj");
  m_uColour = glGetUniformLocation(m_litProgram, "uColour");
  m_uEmissive = glGetUniformLocation(m_litProgram, "uEmissive");
  m_uSunDir = glGetUniformLocation(m_litProgram, "uSunDir");
  m_lineProgram = Program(kLineVertex, kLineFragment);
  m_uLineViewProj = glGetUniformLocation(m_lineProgram, "uViewProj");
  m_starProgram = Program(kStarVertex, kStarFragment);
  m_uStarViewProj = glGetUniformLocation(m_starProgram, "uViewProj");

  // Stars from a fixed seed (a 64-bit LCG): the sky is the same every run.
  std::uint64_t state = 4242;
  auto uniform = [&state](double lo, double hi) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * double(state >> 11) * (1.0 / 9007199254740992.0);
  };
  std::vector<float> stars;
  for (int k = 0; k < 2500; ++k) {
    RVec3 d(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    if (d.squaredNorm() > 1 || d.squaredNorm() < 1e-6) continue;
    d.normalize();
    const double b = uniform(0, 1);
    stars.insert(stars.end(), {float(d.x()), float(d.y()), float(d.z()), float(b * b * b)});
  }
  m_starCount = GLsizei(stars.size() / 4);
  glGenVertexArrays(1, &m_starVao);
  glGenBuffers(1, &m_starVbo);
  glBindVertexArray(m_starVao);
  glBindBuffer(GL_ARRAY_BUFFER, m_starVbo);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(stars.size() * sizeof(float)), stars.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);

  glGenVertexArrays(1, &m_lineVao);
  glGenBuffers(1, &m_lineVbo);
  glBindVertexArray(m_lineVao);
  glBindBuffer(GL_ARRAY_BUFFER, m_lineVbo);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                        reinterpret_cast<const void*>(3 * sizeof(float)));
  glBindVertexArray(0);
  m_lines.reserve(6 * 4096);

  RShape sphere;
  sphere = RShape::Sphere(1);
  const std::vector<MeshVertex> v = Tessellate(sphere);
  m_ballMesh = Upload(v);
}

// A mesh's triangles to the GPU: a vertex array of positions and normals.
Renderer::GpuMesh Renderer::Upload(const std::vector<MeshVertex>& v) {
  GpuMesh m;
  glGenVertexArrays(1, &m.vao);
  glGenBuffers(1, &m.vbo);
  glBindVertexArray(m.vao);
  glBindBuffer(GL_ARRAY_BUFFER, m.vbo);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(v.size() * sizeof(MeshVertex)), v.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(MeshVertex), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(MeshVertex),
                        reinterpret_cast<const void*>(offsetof(MeshVertex, normal)));
  glBindVertexArray(0);
  m.count = GLsizei(v.size());
  return m;
}

Renderer::~Renderer() {
  for (auto& [shape, mesh] : m_meshes)
    glDeleteVertexArrays(1, &mesh.vao), glDeleteBuffers(1, &mesh.vbo);
  glDeleteVertexArrays(1, &m_ballMesh.vao), glDeleteBuffers(1, &m_ballMesh.vbo);
  glDeleteVertexArrays(1, &m_starVao), glDeleteBuffers(1, &m_starVbo);
  glDeleteVertexArrays(1, &m_lineVao), glDeleteBuffers(1, &m_lineVbo);
  glDeleteProgram(m_litProgram), glDeleteProgram(m_lineProgram), glDeleteProgram(m_starProgram);
}

const Renderer::GpuMesh& Renderer::MeshFor(const RPreparedShape* shape) {
  auto it = m_meshes.find(shape);
  if (it != m_meshes.end()) return it->second;
  // Once per prepared shape: a split rock's halves come from the shared rock shapes, so
  // even splitting builds nothing new after the first of each.
  const GpuMesh m = Upload(Tessellate(shape->shape));
  return m_meshes.emplace(shape, m).first->second;
}

void Renderer::DrawMesh(const GpuMesh& mesh, const Camera& camera, const RVec3& position_W,
                        const RQuat& q_WS, float scale, const Eigen::Vector3f& colour,
                        float emissive) {
  Eigen::Matrix4f M = Eigen::Matrix4f::Identity();
  M.topLeftCorner<3, 3>() = scale * q_WS.toRotationMatrix().cast<float>();
  M.topRightCorner<3, 1>() = (position_W - camera.eye_W).cast<float>();  // double, then float
  glUniformMatrix4fv(m_uModel, 1, GL_FALSE, M.data());
  glUniform3fv(m_uColour, 1, colour.data());
  glUniform1f(m_uEmissive, emissive);
  glBindVertexArray(mesh.vao);
  glDrawArrays(GL_TRIANGLES, 0, mesh.count);
}

void DrawList::Box(const RVec3& lo, const RVec3& hi, const Eigen::Vector3f& c) {
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int k = 0; k < 4; ++k) {
      RVec3 a = lo;
      a[u] = (k & 1) ? hi[u] : lo[u], a[v] = (k & 2) ? hi[v] : lo[v];
      RVec3 b = a;
      b[axis] = hi[axis];
      Line(a, b, c);
    }
  }
}

void Renderer::Draw(const DrawList& list, const Camera& camera, int width, int height) {
  glViewport(0, 0, width, height);
  glClearColor(0.008f, 0.010f, 0.022f, 1.0f);  // space: near black, a touch of blue
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  m_viewProj = camera.Projection(float(width) / float(std::max(height, 1))) * camera.View();
  DrawStars(m_viewProj);

  glUseProgram(m_litProgram);
  glUniformMatrix4fv(m_uViewProj, 1, GL_FALSE, m_viewProj.data());
  const Eigen::Vector3f sun = Eigen::Vector3f(0.55f, 0.62f, 0.35f).normalized();
  glUniform3fv(m_uSunDir, 1, sun.data());
  for (const DrawItem& item : list.items) {
    DrawMesh(item.shape ? MeshFor(item.shape) : m_ballMesh, camera, item.position_W, item.q_WS,
             item.scale, item.colour, item.emissive);
  }

  m_lines.clear();
  for (const DrawLine& l : list.lines) {
    const Eigen::Vector3f a = (l.a_W - camera.eye_W).cast<float>();  // double, then float
    const Eigen::Vector3f b = (l.b_W - camera.eye_W).cast<float>();
    const Eigen::Vector3f& k = l.colour;
    m_lines.insert(m_lines.end(), {a.x(), a.y(), a.z(), k.x(), k.y(), k.z(), b.x(), b.y(), b.z(),
                                   k.x(), k.y(), k.z()});
  }
  DrawLines(m_viewProj);
  glBindVertexArray(0);
}

void Renderer::DrawStars(const Eigen::Matrix4f& viewProj) {
  glEnable(GL_PROGRAM_POINT_SIZE);
  glDepthMask(GL_FALSE);
  glUseProgram(m_starProgram);
  glUniformMatrix4fv(m_uStarViewProj, 1, GL_FALSE, viewProj.data());
  glBindVertexArray(m_starVao);
  glDrawArrays(GL_POINTS, 0, m_starCount);
  glDepthMask(GL_TRUE);
}

void Renderer::DrawLines(const Eigen::Matrix4f& viewProj) {
  if (m_lines.empty()) return;
  glUseProgram(m_lineProgram);
  glUniformMatrix4fv(m_uLineViewProj, 1, GL_FALSE, viewProj.data());
  glBindVertexArray(m_lineVao);
  glBindBuffer(GL_ARRAY_BUFFER, m_lineVbo);
  // Orphan and refill: one upload a frame, the buffer's storage reused by the driver.
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(m_lines.size() * sizeof(float)), m_lines.data(),
               GL_STREAM_DRAW);
  glDrawArrays(GL_LINES, 0, GLsizei(m_lines.size() / 6));
}

}  // namespace spacegame
