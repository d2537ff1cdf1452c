// The one writer of the launcher's pipe: whole lines, and nothing after "ready" (the pipe is
// closed then, and its descriptor's number may be another file's).
#include <fcntl.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "core/config/env.h"
#include "core/graph/launcher_pipe.h"

namespace enact::graph {
namespace {

// all that can be read from `fd` without waiting
std::string drain(int fd) {
  fcntl(fd, F_SETFL, O_NONBLOCK);
  std::string out;
  char buffer[256];
  for (ssize_t n; (n = read(fd, buffer, sizeof buffer)) > 0;) out.append(buffer, static_cast<std::size_t>(n));
  return out;
}

TEST(LauncherPipe, LinesGoOutWholeUntilReadyThenNothingMore) {
  int launcher[2], other[2];
  ASSERT_EQ(pipe(launcher), 0);
  ASSERT_EQ(pipe(other), 0);
  setenv(env::kReadyFd, std::to_string(launcher[1]).c_str(), 1);
  tell_launcher("topic ffd/state enact.msgs.DeviceState");
  tell_launcher("wait 60");
  report_ready();
  // the number the pipe had now names another file, as it may in a node after "ready"
  ASSERT_EQ(dup2(other[1], launcher[1]), launcher[1]);
  tell_launcher("wait 60");
  report_ready();
  EXPECT_EQ(drain(launcher[0]), "topic ffd/state enact.msgs.DeviceState\nwait 60\nready\n");
  EXPECT_EQ(drain(other[0]), "") << "a line written after ready went to whatever file took the pipe's number";
  for (int fd : {launcher[0], launcher[1], other[0], other[1]}) close(fd);
  unsetenv(env::kReadyFd);
}

}  // namespace
}  // namespace enact::graph
