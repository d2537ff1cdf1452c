#include "core/viewer/window.h"

#include <GL/gl.h>
#include <backends/imgui_impl_opengl3.h>
#include <backends/imgui_impl_sdl.h>
#include <imgui.h>
#include <stb_image_write.h>

#include <cstdlib>
#include <stdexcept>

#include "core/viewer/draw.h"

namespace enact::viewer {
namespace {

[[noreturn]] void sdl_failed(const std::string& what) { throw std::runtime_error(what + ": " + SDL_GetError()); }

}  // namespace

Window::Window(const char* title, int width, int height, bool offscreen_ok) {
  // no display: render offscreen (snapshots only), else refuse a window nobody would see
  const bool display = std::getenv("DISPLAY") || std::getenv("WAYLAND_DISPLAY") || std::getenv("SDL_VIDEODRIVER");
  if (!display && !offscreen_ok) {
    throw std::runtime_error("no display ($DISPLAY and $WAYLAND_DISPLAY are unset): the window would be invisible\n"
                             "  fix: run it on a desktop (or ssh -X), under xvfb-run, or take a picture with --snapshot FILE.png");
  }
  if (!display) setenv("SDL_VIDEODRIVER", "offscreen", 1);
  if (SDL_Init(SDL_INIT_VIDEO) != 0) sdl_failed("cannot start SDL video (no display? run under Xvfb, or set DISPLAY)");
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_MAJOR_VERSION, 3);
  SDL_GL_SetAttribute(SDL_GL_CONTEXT_MINOR_VERSION, 0);
  SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
  window_ = SDL_CreateWindow(title, SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, width, height, SDL_WINDOW_OPENGL);
  if (!window_) {
    SDL_Quit();
    sdl_failed("cannot open a window");
  }
  gl_ = SDL_GL_CreateContext(window_);
  if (!gl_) {
    SDL_DestroyWindow(window_);
    SDL_Quit();
    sdl_failed("cannot create an OpenGL 3 context");
  }
  SDL_GL_MakeCurrent(window_, gl_);
  SDL_GL_SetSwapInterval(0);  // the viewer paces itself
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui_ImplSDL2_InitForOpenGL(window_, gl_);
  ImGui_ImplOpenGL3_Init("#version 130");
}

Window::~Window() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplSDL2_Shutdown();
  ImGui::DestroyContext();
  SDL_GL_DeleteContext(gl_);
  SDL_DestroyWindow(window_);
  SDL_Quit();
}

bool Window::poll(std::vector<char>& keys) {
  SDL_Event e;
  bool open = true;
  while (SDL_PollEvent(&e)) {
    ImGui_ImplSDL2_ProcessEvent(&e);
    if (e.type == SDL_QUIT) open = false;
    if (e.type == SDL_WINDOWEVENT && e.window.event == SDL_WINDOWEVENT_CLOSE) open = false;
    if (e.type == SDL_TEXTINPUT && !ImGui::GetIO().WantTextInput && e.text.text[0] != '\0' && e.text.text[1] == '\0') keys.push_back(e.text.text[0]);
  }
  return open;
}

void Window::begin_frame() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplSDL2_NewFrame();
  ImGui::NewFrame();
}

int Window::width() const {
  int w = 0, h = 0;
  SDL_GL_GetDrawableSize(window_, &w, &h);
  return w;
}

int Window::height() const {
  int w = 0, h = 0;
  SDL_GL_GetDrawableSize(window_, &w, &h);
  return h;
}

void Window::skip_frame() { ImGui::Render(); }

bool Window::end_frame(const std::string& png_path) {
  ImGui::Render();
  const int w = width(), h = height();
  glViewport(0, 0, w, h);
  const ImVec4 bg = ImGui::ColorConvertU32ToFloat4(palette::kBackground);
  glClearColor(bg.x, bg.y, bg.z, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  bool saved = true;
  if (!png_path.empty()) {
    // the back buffer, bottom row first in OpenGL: flipped while writing
    std::vector<unsigned char> pixels(static_cast<std::size_t>(w) * h * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
    stbi_flip_vertically_on_write(1);
    saved = stbi_write_png(png_path.c_str(), w, h, 3, pixels.data(), w * 3) != 0;
  }
  SDL_GL_SwapWindow(window_);
  return saved;
}

}  // namespace enact::viewer
