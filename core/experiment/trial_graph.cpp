#include "core/experiment/trial_graph.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <sstream>
#include <thread>

#include "core/config/yaml.h"
#include "core/session/registry.h"
#include "core/graph/topics.h"
#include "core/launch/realtime.h"
#include "core/launch/supervisor.h"
#include "core/rt/profile.h"
#include "msgs/task_event.pb.h"

namespace enact::experiment {
namespace {

// stdout and stderr (fds 1 and 2) go to a file while this lives: the graph's processes
// inherit them
struct OutputTo {
  int saved_out = -1, saved_err = -1;
  explicit OutputTo(const std::string& path) {
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    const int fd = open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0) throw config::Error(path + ": cannot write the trial's log\n  fix: check the folder's permissions");
    saved_out = fcntl(1, F_DUPFD_CLOEXEC, 3);
    saved_err = fcntl(2, F_DUPFD_CLOEXEC, 3);
    dup2(fd, 1);
    dup2(fd, 2);
    close(fd);
  }
  ~OutputTo() {
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    dup2(saved_out, 1);
    dup2(saved_err, 2);
    close(saved_out);
    close(saved_err);
  }
  OutputTo(const OutputTo&) = delete;
  OutputTo& operator=(const OutputTo&) = delete;
};

}  // namespace

launch::LaunchDescription load_trial_graph(const std::string& launch_file, const std::map<std::string, std::string>& args,
                                           const std::optional<rt::GraphClock>& clock) {
  launch::LaunchDescription graph = launch::load_launch(launch_file, args);
  if (clock) launch::choose_clock(graph, *clock);
  return graph;
}

int run_trial_graph(const std::string& name, const std::string& launch_file, launch::LaunchDescription graph, const std::string& log,
                    const std::function<void(GraphRun&)>& watch) {
  // the real-time profile, before the trial's threads start (they inherit it); said in the
  // trial's log
  std::ostringstream realtime_said;
  graph.realtime.other_loops = graph::running_loops();
  const auto realtime = launch::apply_realtime(graph, realtime_said);
  // the trial's graph: watched and adjusted live like any other, by its name (numbered when
  // the same experiment runs twice on this machine)
  graph::SessionOptions session_options;
  session_options.numbered = true;
  session_options.loop_cpus = rt::cpu_list(realtime->loop_cpus());
  graph::GraphSession session(name, launch_file, session_options);
  // the runner's publisher, bound before the attach point connects to it
  bus::BytePublisher out(session.node_endpoint(kRunnerNode), {.node = kRunnerNode});
  session.attach().add_publisher(kRunnerNode, out.endpoint());
  session.attach().declare_topic<msgs::TaskEvent>(graph::kTaskEvent, kRunnerNode);
  GraphRun run(out, session);

  launch::SupervisorOptions options;
  options.ready_timeout_s = 20.0;
  std::atomic<bool>* ready = &run.ready_;
  options.on_ready = [ready] { ready->store(true); };
  std::atomic<std::int64_t>* clean_exit = &run.clean_exit_ns_;
  options.on_exit = [clean_exit](const launch::NodeSpec&, int status) {
    std::int64_t none = 0;
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) clean_exit->compare_exchange_strong(none, rt::now_ns());
  };
  const OutputTo to_log(log);
  std::cerr << realtime_said.str();
  std::thread watching([&] { watch(run); });
  const int code = session.run(graph, launch_file, options, std::cerr);
  run.finished_.store(true);
  watching.join();
  return code;
}

}  // namespace enact::experiment
