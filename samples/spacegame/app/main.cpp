// rengine-spacegame: REngine's showcase, a space game on the engine's public API.
//
//   rengine-spacegame                       play (keys on the HUD)
//   rengine-spacegame --autoplay --frames 900 --screenshot shot.png
//   rengine-spacegame --autoplay --frames 900 --record frames/ --record-every 6
//   rengine-spacegame --autoplay --frames 300 --crew --screenshot crew.png
//
// --crew watches from behind the crew member walking round the station's ring (Crew.h).
// The autoplay feeds scripted input (Autoplay.h) for N frames of exactly 1/60 s, writes the
// last frame as a PNG, and ends with one line on stderr:
//   frames=N steps=S physics_ms_per_step=X hash=H
// H, the final state's hash, is the same on every run of the same build (the tests and CI
// compare two runs under a virtual display); X is wall-clock time and varies.
// --record DIR keeps every K-th frame of the autoplay (--record-every K, default 1: frames K,
// 2K, ..., 1-based) as DIR/frame_00000.png, frame_00001.png, ..., read back the way
// --screenshot is; the framebuffer is read only on those frames, and the physics and the hash
// are the same with or without it.
//
// This file is the thin front end: SDL2 for the window and input, OpenGL (epoxy) through
// Renderer, Dear ImGui for the HUD. Everything the game does is in the logic library.
#include <SDL.h>
#include <imgui_impl_sdl.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>
#include <system_error>

#include "Autoplay.h"
#include "Camera.h"
#include "Game.h"
#include "GameView.h"
#include "Hud.h"
#include "Renderer.h"
#include "Screenshot.h"
#include "StateHash.h"
#include "Window.h"

namespace {

struct Options {
  bool autoplay = false;
  // Frames to run, then quit; 0: the autoplay's 900 (the script docks near frame 870), or
  // until the window is closed when playing (a smoke test plays a few frames untouched).
  int frames = 0;
  std::string screenshot;
  std::string record;   // a directory: every recordEvery-th autoplay frame as a PNG
  int recordEvery = 0;  // 0: not given (1 with --record)
  int width = 1280, height = 720;
  bool hud = true;
  bool wide = false;   // the wide camera instead of the chase camera (autoplay: the default)
  bool chase = false;  // the chase camera in the autoplay
  bool crew = false;   // the camera behind the crew member walking inside the station's ring
  bool debug = false;  // contacts and joints drawn
  spacegame::WorldConfig world;
};

[[noreturn]] void Usage(const char* problem) {
  if (problem) std::fprintf(stderr, "rengine-spacegame: %s\n", problem);
  std::fprintf(stderr,
               "usage: rengine-spacegame [--autoplay] [--frames N] [--screenshot FILE.png]\n"
               "         [--record DIR [--record-every K]]\n"
               "         [--width W] [--height H] [--no-hud] [--wide | --chase | --crew] [--debug]\n"
               "         [--asteroids N] [--seed S] [--origin X]\n");
  std::exit(problem ? 2 : 0);
}

Options Parse(int argc, char** argv) {
  Options o;
  auto value = [&](int& i) -> const char* {
    if (i + 1 >= argc) Usage((std::string(argv[i]) + " needs a value").c_str());
    return argv[++i];
  };
  auto number = [&](int& i, long lo, long hi) {
    const char* name = argv[i];
    const char* text = value(i);
    char* end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (*end || v < lo || v > hi) Usage((std::string(name) + ": out of range: " + text).c_str());
    return v;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--autoplay")
      o.autoplay = true;
    else if (a == "--frames")
      o.frames = int(number(i, 1, 10000000));
    else if (a == "--screenshot")
      o.screenshot = value(i);
    else if (a == "--record") {
      o.record = value(i);
      if (o.record.empty()) Usage("--record: an empty directory name");
    } else if (a == "--record-every")
      o.recordEvery = int(number(i, 1, 10000000));
    else if (a == "--width")
      o.width = int(number(i, 64, 8192));
    else if (a == "--height")
      o.height = int(number(i, 64, 8192));
    else if (a == "--no-hud")
      o.hud = false;
    else if (a == "--wide")
      o.wide = true;
    else if (a == "--chase")
      o.chase = true;
    else if (a == "--crew")
      o.crew = true;
    else if (a == "--debug")
      o.debug = true;
    else if (a == "--asteroids")
      o.world.asteroids = int(number(i, 0, 2000));
    else if (a == "--seed")
      o.world.seed = std::uint64_t(number(i, 0, 1L << 40));
    else if (a == "--origin") {
      const double x = std::strtod(value(i), nullptr);
      o.world.origin_W = REngine::RVec3(x, x, x);
    } else if (a == "--help" || a == "-h")
      Usage(nullptr);
    else
      Usage(("unknown option " + a).c_str());
  }
  if (!o.screenshot.empty() && !o.autoplay) Usage("--screenshot needs --autoplay");
  if (o.autoplay && o.frames == 0) o.frames = 900;
  if (!o.record.empty() && !o.autoplay) Usage("--record needs --autoplay");
  if (o.recordEvery != 0 && o.record.empty()) Usage("--record-every needs --record");
  if (!o.record.empty()) {
    if (o.recordEvery == 0) o.recordEvery = 1;
    if (o.recordEvery > o.frames)
      Usage(("--record-every " + std::to_string(o.recordEvery) + " is more than the " +
             std::to_string(o.frames) + " frames: nothing would be recorded")
                .c_str());
    // The directory is made (with its parents) before the window opens, so a bad path is a
    // usage error, not a failure 900 frames in.
    std::error_code ec;
    std::filesystem::create_directories(o.record, ec);
    if (ec || !std::filesystem::is_directory(o.record))
      Usage(("--record: cannot make the directory " + o.record +
             (ec ? ": " + ec.message() : std::string()))
                .c_str());
  }
  // The autoplay is watched from the wide camera (station, ship and rocks in one frame).
  if (o.autoplay && !o.chase) o.wide = true;
  return o;
}

// The pilot's keys, held and pressed.
spacegame::ShipInput Keyboard(bool fire, bool dock) {
  const Uint8* k = SDL_GetKeyboardState(nullptr);
  auto axis = [k](SDL_Scancode plus, SDL_Scancode minus) {
    return double(k[plus]) - double(k[minus]);
  };
  spacegame::ShipInput in;
  in.thrust = axis(SDL_SCANCODE_W, SDL_SCANCODE_S);
  in.yaw = axis(SDL_SCANCODE_A, SDL_SCANCODE_D);
  in.pitch = axis(SDL_SCANCODE_DOWN, SDL_SCANCODE_UP);
  in.roll = axis(SDL_SCANCODE_E, SDL_SCANCODE_Q);
  in.strafe = axis(SDL_SCANCODE_LEFT, SDL_SCANCODE_RIGHT);
  in.lift = axis(SDL_SCANCODE_R, SDL_SCANCODE_V);
  in.laser = k[SDL_SCANCODE_SPACE];
  in.fireMissile = fire;
  in.dockToggle = dock;
  return in;
}

int Run(const Options& o) {
  spacegame::Window window("REngine space game", o.width, o.height, !o.autoplay);
  {
    spacegame::Game game(o.world);
    spacegame::Autoplay script(game);
    spacegame::Renderer renderer;
    spacegame::GameView view;
    spacegame::DrawList drawList;
    spacegame::Camera camera;
    spacegame::DebugDraw debug;
    debug.contacts = debug.bounds = o.debug;
    spacegame::HudState hud;
    hud.autoplay = o.autoplay;
    hud.wideCamera = o.wide;

    auto last = std::chrono::steady_clock::now();
    bool running = true;
    for (int frame = 0; running; ++frame) {
      bool fire = false, dock = false;
      SDL_Event e;
      while (SDL_PollEvent(&e)) {
        ImGui_ImplSDL2_ProcessEvent(&e);
        if (e.type == SDL_QUIT) running = false;
        if (e.type == SDL_KEYDOWN && !e.key.repeat) {
          switch (e.key.keysym.sym) {
            case SDLK_ESCAPE:
              running = false;
              break;
            case SDLK_f:
              fire = true;
              break;
            case SDLK_g:
              dock = true;
              break;
            case SDLK_c:
              hud.wideCamera = !hud.wideCamera;
              break;
            case SDLK_1:
              debug.contacts = !debug.contacts;
              break;
            case SDLK_2:
              debug.bounds = !debug.bounds;
              break;
            case SDLK_3:
              debug.sleeping = !debug.sleeping;
              break;
            case SDLK_4:
              debug.joints = !debug.joints;
              break;
            default:
              break;
          }
        }
      }
      const auto now = std::chrono::steady_clock::now();
      const double wall = std::chrono::duration<double>(now - last).count();
      last = now;
      hud.framesPerSecond = 0.9 * hud.framesPerSecond + 0.1 * (wall > 0 ? 1.0 / wall : 0);
      hud.frame = std::uint64_t(frame);

      // The autoplay's frames are of fixed length and its input scripted: the run repeats.
      if (o.autoplay) {
        game.Frame(spacegame::Autoplay::kFrameSeconds, script.Input(frame, game));
      } else {
        game.Frame(wall, Keyboard(fire, dock));
      }

      int w = 0, h = 0;
      window.DrawableSize(w, h);
      spacegame::GameView::Aim(
          camera, o.crew ? spacegame::CameraMode::kCrew
                         : hud.wideCamera ? spacegame::CameraMode::kWide : spacegame::CameraMode::kChase,
          game);
      view.Build(game, debug, drawList);
      renderer.Draw(drawList, camera, w, h);
      if (o.hud) {
        window.BeginHud();
        spacegame::DrawHud(game, hud, debug);
        window.EndHud();
      }
      const bool lastFrame = o.frames > 0 && frame + 1 >= o.frames;
      if (lastFrame && !o.screenshot.empty()) spacegame::WriteScreenshot(o.screenshot, w, h);
      // Only recorded frames read the framebuffer back (glReadPixels waits for the GPU).
      if (!o.record.empty() && (frame + 1) % o.recordEvery == 0) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%05d.png", (frame + 1) / o.recordEvery - 1);
        spacegame::WriteScreenshot(o.record + "/" + name, w, h);
      }
      window.Swap();
      if (lastFrame) {
        running = false;
        std::fprintf(stderr, "frames=%d steps=%llu physics_ms_per_step=%.4f hash=%s\n", frame + 1,
                     static_cast<unsigned long long>(game.Timing().steps),
                     game.Timing().MsPerStep(),
                     spacegame::HashHex(spacegame::HashState(game.World().Bodies())).c_str());
      }
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(Parse(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rengine-spacegame: %s\n", e.what());
    return 1;
  }
}
