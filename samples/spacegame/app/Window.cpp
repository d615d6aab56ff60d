#include "Window.h"

#include <imgui.h>
#include <imgui_impl_opengl3.h>
#include <imgui_impl_sdl.h>

#include <stdexcept>
#include <string>

namespace spacegame {

namespace {
[[noreturn]] void Fail(const char* what) {
  throw std::runtime_error(std::string(what) + ": " + SDL_GetError());
}
}  // namespace

Window::Window(const char* title, int width, int height, bool vsync) {
  if (SDL_Init(SDL_INIT_VIDEO) != 0) Fail("SDL_Init");
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_MAJOR_VERSION, 3);
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_MINOR_VERSION, 3);
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_PROFILE_MASK, SDL_GL_CONTEXT_PROFILE_CORE);
  SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
  SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
  m_window = SDL_CreateWindow(title, SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, width, height,
                              SDL_WINDOW_OPENGL | SDL_WINDOW_RESIZABLE);
  if (!m_window) {
    SDL_Quit();
    Fail("SDL_CreateWindow");
  }
  m_gl = SDL_GL_CreateContext(m_window);
  if (!m_gl) {
    SDL_DestroyWindow(m_window);
    SDL_Quit();
    Fail("OpenGL 3.3 core context");
  }
  SDL_GL_SetSwapInterval(vsync ? 1 : 0);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini beside the screenshots
  ImGui::StyleColorsDark();
  ImGui_ImplSDL2_InitForOpenGL(m_window, m_gl);
  ImGui_ImplOpenGL3_Init("#version 330 core");
}

Window::~Window() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplSDL2_Shutdown();
  ImGui::DestroyContext();
  SDL_GL_DeleteContext(m_gl);
  SDL_DestroyWindow(m_window);
  SDL_Quit();
}

void Window::DrawableSize(int& width, int& height) const {
  SDL_GL_GetDrawableSize(m_window, &width, &height);
}

void Window::BeginHud() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplSDL2_NewFrame();
  ImGui::NewFrame();
}

void Window::EndHud() {
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

}  // namespace spacegame
