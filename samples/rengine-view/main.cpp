// rengine-view: plays back a trajectory of rengine-sim in a window.
//
//   rengine-view SCENE.json TRAJ.csv                  play, looping (space: pause)
//   rengine-view SCENE.json TRAJ.csv --frames 120 --screenshot shot.png
//
// The scene gives each body's shape (the bodies it starts with and those its actions add);
// the trajectory (docs/scene-format.md) gives the poses, drawn between rows. The camera circles
// the bodies' starting bounds. With --frames, N frames of 1/60 s of playback (times --speed)
// are drawn, the last written as a PNG, and the last line on stderr reads
// `frames=N time=T bodies=B`. The drawing is rengine-spacegame's (spacegame_render).
#include <REnginePhysics/RScene.h>
#include <SDL.h>
#include <imgui.h>
#include <imgui_impl_sdl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "Camera.h"
#include "Renderer.h"
#include "Screenshot.h"
#include "Trajectory.h"
#include "Window.h"

namespace {
using namespace REngine;
using rengineview::Trajectory;

struct Options {
  std::string scene, trajectory, screenshot;
  int frames = 0;  // 0: until closed
  double speed = 1;
  int width = 1280, height = 720;
  bool hud = true;
};

[[noreturn]] void Usage(const std::string& problem) {
  if (!problem.empty()) std::fprintf(stderr, "rengine-view: %s\n", problem.c_str());
  std::fprintf(stderr,
               "usage: rengine-view SCENE.json TRAJ.csv [--frames N] [--screenshot FILE.png]\n"
               "         [--speed X] [--width W] [--height H] [--no-hud]\n");
  std::exit(problem.empty() ? 0 : 2);
}

Options Parse(int argc, char** argv) {
  Options o;
  std::vector<std::string> files;
  auto value = [&](int& i) -> std::string {
    if (i + 1 >= argc) Usage(std::string(argv[i]) + " needs a value");
    return argv[++i];
  };
  auto number = [&](int& i, double lo, double hi) {
    const std::string name = argv[i], text = value(i);
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (*end || !(v >= lo && v <= hi)) Usage(name + ": out of range: " + text);
    return v;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--frames")
      o.frames = int(number(i, 1, 1e7));
    else if (a == "--screenshot")
      o.screenshot = value(i);
    else if (a == "--speed")
      o.speed = number(i, 1e-3, 1e3);
    else if (a == "--width")
      o.width = int(number(i, 64, 8192));
    else if (a == "--height")
      o.height = int(number(i, 64, 8192));
    else if (a == "--no-hud")
      o.hud = false;
    else if (a == "--help" || a == "-h")
      Usage("");
    else if (!a.empty() && a[0] == '-')
      Usage("unknown option " + a);
    else
      files.push_back(a);
  }
  if (files.size() != 2) Usage("a scene and a trajectory, please");
  if (!o.screenshot.empty() && o.frames == 0) Usage("--screenshot needs --frames");
  o.scene = files[0], o.trajectory = files[1];
  return o;
}

// Shapes by body name, prepared once; equal boxes, spheres, capsules and cylinders share one
// (a pile of a thousand boxes is one GPU mesh).
class ShapeBook {
 public:
  const RPreparedShape* For(const RBodyDef& def) {
    if (def.prepared) return def.prepared.get();
    const RShape& s = def.shape;
    if (s.type == RShapeType::kHull || s.type == RShapeType::kCompound ||
        s.type == RShapeType::kMesh) {
      m_own.push_back(PrepareShape(s));
      return m_own.back().get();
    }
    const auto key = std::make_tuple(int(s.type), s.radius, s.halfHeight, s.halfExtents.x(),
                                     s.halfExtents.y(), s.halfExtents.z());
    auto it = m_primitives.find(key);
    if (it == m_primitives.end()) it = m_primitives.emplace(key, PrepareShape(s)).first;
    return it->second.get();
  }

 private:
  std::vector<std::shared_ptr<const RPreparedShape>> m_own;
  std::map<std::tuple<int, double, double, double, double, double>,
           std::shared_ptr<const RPreparedShape>>
      m_primitives;
};

struct Body {
  const RPreparedShape* shape = nullptr;
  Eigen::Vector3f colour;
  bool immovable = false;  // static or kinematic
};

bool Immovable(const RBodyDef& def) {
  return def.kind != RBodyKind::kDynamic;
}

// Static bodies grey; the others spread round the colour wheel by the golden angle, so
// neighbours in the scene's order differ.
Eigen::Vector3f ColourOf(const RBodyDef& def, std::size_t k) {
  if (Immovable(def)) return {0.45f, 0.47f, 0.50f};
  const float h = std::fmod(0.618034f * float(k), 1.0f) * 6.0f;
  const float x = 1.0f - std::fabs(std::fmod(h, 2.0f) - 1.0f);
  Eigen::Vector3f rgb = h < 1   ? Eigen::Vector3f(1, x, 0)
                        : h < 2 ? Eigen::Vector3f(x, 1, 0)
                        : h < 3 ? Eigen::Vector3f(0, 1, x)
                        : h < 4 ? Eigen::Vector3f(0, x, 1)
                        : h < 5 ? Eigen::Vector3f(x, 0, 1)
                                : Eigen::Vector3f(1, 0, x);
  return 0.35f * Eigen::Vector3f::Ones() + 0.55f * rgb;  // pastel: lit shapes read best
}

int Run(const Options& o) {
  const RScene scene = LoadScene(o.scene);
  const Trajectory trajectory = Trajectory::ReadFile(o.trajectory);
  std::map<std::string, const RBodyDef*> defs;
  for (const RBodyDef& d : scene.bodies) defs.emplace(d.name, &d);
  for (const RSceneAction& a : scene.actions)
    if (a.verb == RSceneAction::Verb::kAdd) defs.emplace(a.def.name, &a.def);

  ShapeBook book;
  std::vector<Body> bodies;
  for (std::size_t k = 0; k < trajectory.Bodies().size(); ++k) {
    const auto it = defs.find(trajectory.Bodies()[k]);
    if (it == defs.end()) {
      std::fprintf(stderr, "rengine-view: %s: body `%s` is not in %s\n", o.trajectory.c_str(),
                   trajectory.Bodies()[k].c_str(), o.scene.c_str());
      return 2;
    }
    bodies.push_back({book.For(*it->second), ColourOf(*it->second, k), Immovable(*it->second)});
  }

  // The camera circles the moving bodies as they start (a scene's ground would fill the
  // frame): their centre, at a distance that holds the farthest one's bounding sphere in
  // view. A scene of immovable bodies alone is framed whole.
  const bool anyMoving =
      std::any_of(bodies.begin(), bodies.end(), [](const Body& b) { return !b.immovable; });
  auto framed = [&](std::size_t k) { return !anyMoving || !bodies[k].immovable; };
  RVec3 centre = RVec3::Zero();
  int counted = 0;
  RVec3 p;
  RQuat q;
  for (std::size_t k = 0; k < bodies.size(); ++k)
    if (framed(k) && trajectory.PoseAt(k, trajectory.StartTime(), p, q)) centre += p, ++counted;
  centre /= std::max(counted, 1);
  double radius = 1;
  for (std::size_t k = 0; k < bodies.size(); ++k)
    if (framed(k) && trajectory.PoseAt(k, trajectory.StartTime(), p, q))
      radius = std::max(radius, (p - centre).norm() + bodies[k].shape->boundingRadius);

  spacegame::Window window("rengine-view", o.width, o.height, o.frames == 0);
  {
    spacegame::Renderer renderer;
    spacegame::Camera camera;
    camera.farPlane = float(std::max(20000.0, 20 * radius));
    spacegame::DrawList list;
    list.items.reserve(bodies.size());
    const double span = std::max(trajectory.EndTime() - trajectory.StartTime(), 1e-9);
    double t = trajectory.StartTime();
    bool paused = false, running = true;
    std::size_t drawn = 0;
    for (int frame = 0; running; ++frame) {
      SDL_Event e;
      while (SDL_PollEvent(&e)) {
        ImGui_ImplSDL2_ProcessEvent(&e);
        if (e.type == SDL_QUIT) running = false;
        if (e.type == SDL_KEYDOWN && e.key.keysym.sym == SDLK_ESCAPE) running = false;
        if (e.type == SDL_KEYDOWN && e.key.keysym.sym == SDLK_SPACE) paused = !paused;
      }
      // Playback: 1/60 s a frame, times the speed; looping when watched, held at the end
      // when counted.
      if (frame > 0 && !paused) t += o.speed / 60.0;
      if (t > trajectory.EndTime())
        t = o.frames ? trajectory.EndTime()
                     : trajectory.StartTime() + std::fmod(t - trajectory.StartTime(), span);

      list.Clear();
      for (std::size_t k = 0; k < bodies.size(); ++k) {
        spacegame::DrawItem item;
        if (!trajectory.PoseAt(k, t, item.position_W, item.q_WS)) continue;
        item.shape = bodies[k].shape;
        item.colour = bodies[k].colour;
        list.items.push_back(item);
      }
      drawn = list.items.size();
      const double a = 0.6 + 0.15 * (t - trajectory.StartTime());  // a slow turn round
      // The bounding sphere of the moving bodies within 80% of the vertical field of view.
      const double distance = radius / std::sin(0.4 * camera.fovY);
      camera.LookAt(
          centre + distance * RVec3(std::cos(a) * 0.8, 0.55, std::sin(a) * 0.8).normalized(),
          centre, RVec3::UnitY());
      int w = 0, h = 0;
      window.DrawableSize(w, h);
      renderer.Draw(list, camera, w, h);
      if (o.hud) {
        window.BeginHud();
        ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
        ImGui::SetNextWindowBgAlpha(0.55f);
        ImGui::Begin("rengine-view", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
        ImGui::Text("%s", o.trajectory.c_str());
        ImGui::Text("t = %.3f s of %.3f s%s", t, trajectory.EndTime(), paused ? "  (paused)" : "");
        ImGui::Text("bodies %zu of %zu, rows %zu", drawn, bodies.size(), trajectory.Rows());
        ImGui::End();
        window.EndHud();
      }
      const bool last = o.frames && frame + 1 >= o.frames;
      if (last && !o.screenshot.empty()) spacegame::WriteScreenshot(o.screenshot, w, h);
      window.Swap();
      if (last) {
        running = false;
        std::fprintf(stderr, "frames=%d time=%.6f bodies=%zu\n", frame + 1, t, drawn);
      }
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(Parse(argc, argv));
  } catch (const RSceneError& e) {
    std::fprintf(stderr, "rengine-view: %s\n", e.what());
    return 2;
  } catch (const rengineview::TrajectoryError& e) {
    std::fprintf(stderr, "rengine-view: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rengine-view: %s\n", e.what());
    return 1;
  }
}
