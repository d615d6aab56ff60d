// A window with an OpenGL 3.3 core context (SDL2, epoxy loads the functions) and Dear
// ImGui on it: what rengine-spacegame and rengine-view share. Owns SDL, the context and
// ImGui's context; throws std::runtime_error (with SDL's reason) when any of them fails.
#pragma once

#include <SDL.h>

namespace spacegame {

class Window {
 public:
  // vsync off for runs that draw as fast as they can (the autoplay, the tests).
  Window(const char* title, int width, int height, bool vsync);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  SDL_Window* Sdl() const { return m_window; }
  // The drawable's size in pixels.
  void DrawableSize(int& width, int& height) const;
  // ImGui's frame around the HUD's calls.
  void BeginHud();
  void EndHud();
  void Swap() { SDL_GL_SwapWindow(m_window); }

 private:
  SDL_Window* m_window = nullptr;
  SDL_GLContext m_gl = nullptr;
};

}  // namespace spacegame
