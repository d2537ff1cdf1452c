#include "core/graph/launcher_pipe.h"

#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <mutex>

#include "core/config/env.h"
#include "core/config/number.h"

namespace enact::graph {
namespace {

// the pipe's descriptor: read from the environment once; -1 when there is none or after
// "ready" closed it (a closed descriptor's number may be another file's by then)
std::mutex g_pipe_mutex;
int g_pipe_fd = -2;  // -2: not read yet

int pipe_fd() {
  if (g_pipe_fd != -2) return g_pipe_fd;
  g_pipe_fd = -1;
  if (const char* text = std::getenv(env::kReadyFd)) {
    const auto fd = config::parse_integer(text);
    if (fd && *fd >= 0 && *fd <= INT_MAX) g_pipe_fd = static_cast<int>(*fd);
  }
  return g_pipe_fd;
}

// the whole line in one write: the launcher reads lines, and a pipe keeps a write of up to
// PIPE_BUF bytes whole
void write_line(int fd, const std::string& line) {
  const std::string text = line + "\n";
  (void)!write(fd, text.data(), text.size());
}

}  // namespace

void tell_launcher(const std::string& line) {
  std::lock_guard<std::mutex> lock(g_pipe_mutex);
  if (const int fd = pipe_fd(); fd >= 0) write_line(fd, line);
}

void announce_topics(const bus::BytePublisher& out) {
  for (const auto& [topic, type] : out.declared()) tell_launcher("topic " + topic + " " + type);
}

void report_ready() {
  std::lock_guard<std::mutex> lock(g_pipe_mutex);
  const int fd = pipe_fd();
  if (fd < 0) return;
  write_line(fd, "ready");
  close(fd);
  g_pipe_fd = -1;
}

}  // namespace enact::graph
