#pragma once
// The viewer's window: SDL2 + an OpenGL 3 context + Dear ImGui with its SDL2 and OpenGL 3
// backends (Debian's libimgui-dev ships both), as one owning object. Without a display
// (no $DISPLAY, no $WAYLAND_DISPLAY) an offscreen window can still render snapshots
// (SDL's "offscreen" video driver, EGL).
#include <string>
#include <vector>

#include <SDL2/SDL.h>

namespace enact::viewer {

class Window {
 public:
  // opens a width x height window (offscreen when there is no display and `offscreen_ok`);
  // throws std::runtime_error naming what SDL or OpenGL refused, or when there is no display
  // and not `offscreen_ok` (a window nobody would see)
  Window(const char* title, int width, int height, bool offscreen_ok);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // handles the window's events; false once it was closed (or SIGINT / SIGTERM came).
  // Characters typed outside ImGui's text fields are appended to `keys`.
  bool poll(std::vector<char>& keys);
  // starts an ImGui frame
  void begin_frame();
  // renders the frame and shows it; with a path, first saves it there as an RGB PNG (false
  // when it could not be written)
  bool end_frame(const std::string& png_path = "");
  // ends the frame without drawing it (the windows are still laid out): for frames nobody
  // sees, as before a snapshot, where software OpenGL would only burn processor time
  void skip_frame();
  // the drawable's size, px
  int width() const;
  int height() const;

 private:
  SDL_Window* window_ = nullptr;
  SDL_GLContext gl_ = nullptr;
};

}  // namespace enact::viewer
