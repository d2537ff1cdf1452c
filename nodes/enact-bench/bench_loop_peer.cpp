// enact bench loop, the distributed arm's second process: a simulator answering DeviceStates
// on the bus and a raw ZeroMQ echo, on ipc and tcp, like the graph's simulator process.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "core/config/env.h"
#include "core/bus/context.h"
#include "core/bus/loop_link.h"
#include "core/bus/typed.h"
#include "core/graph/messages.h"
#include "core/graph/process.h"
#include "core/graph/stop.h"
#include "core/rt/clock.h"
#include "core/rt/profile.h"
#include "core/rt/spsc_queue.h"
#include "core/sim/simulator.h"
#include "nodes/enact/args.h"
#include "nodes/enact-bench/bench_loop.h"

namespace enact::cli::loop {

int run_peer(const std::string& dir, const std::string& scene, const PeerSetup& setup) {
  graph::install_stop_handlers();
  graph::apply_rt_profile("peer");
  std::vector<std::string> parent;
  std::stringstream in(setup.parent_list);
  for (std::string e; std::getline(in, e, ',');) parent.push_back(e);
  if (parent.size() != 4) throw UsageError("--peer-of needs 4 endpoints");
  sim::SimParams p;
  p.scene = scene;
  sim::Simulator simulator;
  simulator.configure(p);
  simulator.activate(0);
  struct Side {
    std::unique_ptr<bus::BytePublisher> out;
    std::unique_ptr<bus::Publisher<msgs::ForceCommand>> forces;
    bus::ByteSubscriber in;
    std::unique_ptr<bus::Subscriber<msgs::DeviceState>> states;
    zmq::socket_t raw_pub{bus::context(), zmq::socket_type::pub}, raw_sub{bus::context(), zmq::socket_type::sub};
  } sides[2];
  const std::string binds[2][2] = {{"ipc://" + dir + "/peer-bus", "ipc://" + dir + "/peer-raw"}, {"tcp://127.0.0.1:*", "tcp://127.0.0.1:*"}};
  for (int i = 0; i < 2; ++i) {
    Side& s = sides[i];
    s.out = std::make_unique<bus::BytePublisher>(binds[i][0], bus::PublisherOptions{.node = "sim", .send_hwm = 10000});
    s.forces = std::make_unique<bus::Publisher<msgs::ForceCommand>>(*s.out, "ffd/force");
    s.states = std::make_unique<bus::Subscriber<msgs::DeviceState>>(s.in, "ffd/state");
    s.in.connect(parent[2 * i]);
    for (zmq::socket_t* z : {&s.raw_pub, &s.raw_sub}) z->set(zmq::sockopt::linger, 0);
    s.raw_pub.bind(binds[i][1]);
    s.raw_sub.set(zmq::sockopt::subscribe, "");
    s.raw_sub.connect(parent[2 * i + 1]);
  }
  std::printf("%s %s %s %s\n", sides[0].out->endpoint().c_str(), sides[0].raw_pub.get(zmq::sockopt::last_endpoint).c_str(),
              sides[1].out->endpoint().c_str(), sides[1].raw_pub.get(zmq::sockopt::last_endpoint).c_str());
  std::fflush(stdout);
  // the local arms, each on a thread of its own that waits on its one descriptor as the
  // graph's simulator waits on its link (the process's CPU and priority, inherited)
  std::atomic<bool> done{false};
  std::thread link_arm([&] {
    // answered like the graph's simulator (node::Sim): a step of its own simulator, the answer
    // over the link at once, the step handed to a second thread that publishes it on a bus
    // without subscribers (node::SimFeed: every millisecond, or at once when woken)
    sim::Simulator own;
    own.configure(p);
    own.activate(0);
    bus::BytePublisher link_out("ipc://" + dir + "/peer-link-bus", {.node = "sim", .send_hwm = 10000});
    bus::Publisher<msgs::ForceCommand> link_forces(link_out, "ffd/force");
    bus::ByteSubscriber link_in;
    bus::Subscriber<msgs::DeviceState> link_states(link_in, "ffd/state");
    bus::LoopLink link = bus::LoopLink::connect(setup.link_path, rt::now_ns() + 10'000'000'000);
    struct Step {
      std::uint64_t seq;
      math::Vec3 force_n;
      bool fault;
    };
    rt::SpscQueue<Step, 16384> steps;
    std::atomic<bool> link_done{false};
    std::thread feed([&] {
      msgs::ForceCommand published;
      for (Step s; !link_done.load();) {
        while (steps.try_pop(s)) {
          graph::fill(published, s.seq, s.force_n, s.fault);
          link_forces.publish(published, s.seq);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    });
    char buffer[bus::LoopLink::kMaxMessage];
    std::uint8_t answer[bus::LoopLink::kMaxMessage];
    bus::ReusedMessage<msgs::DeviceState> state;
    msgs::ForceCommand command;
    command.mutable_header()->set_source("sim");
    while (!done.load() && !graph::stop_requested() && link.connected()) {
      const long n = link.receive(buffer, sizeof buffer, bus::LoopLink::kNoDeadline, graph::stop_fd());
      if (n <= 0 || !link_states.accept_payload(buffer, static_cast<std::size_t>(n), state.fresh())) continue;
      const sim::StepOutput& o = own.step(state->header().stamp_ns(), graph::get(state->position()));
      graph::fill(command, state->header().seq(), o.force_n, o.fault);
      command.mutable_header()->set_seq(state->header().seq());
      command.mutable_header()->set_stamp_ns(rt::now_ns());
      bus::send_over(link, command, answer);
      steps.try_push({state->header().seq(), o.force_n, o.fault});
    }
    link_done.store(true);
    feed.join();
  });
  std::thread pipe_arm([&] {
    char buffer[4096];
    for (ssize_t n; !done.load() && (n = read(setup.pipe_in, buffer, sizeof buffer)) > 0;) {
      if (write(setup.pipe_out, buffer, static_cast<std::size_t>(n)) != n) break;
    }
  });
  msgs::DeviceState state;
  msgs::ForceCommand command;
  zmq::message_t m;
  zmq::pollitem_t items[4] = {{sides[0].in.socket().handle(), 0, ZMQ_POLLIN, 0}, {sides[0].raw_sub.handle(), 0, ZMQ_POLLIN, 0},
                              {sides[1].in.socket().handle(), 0, ZMQ_POLLIN, 0}, {sides[1].raw_sub.handle(), 0, ZMQ_POLLIN, 0}};
  // answer until told to stop (SIGTERM) or the parent is gone
  while (!graph::stop_requested() && getppid() != 1) {
    try {
      if (zmq::poll(items, 4, std::chrono::milliseconds(100)) == 0) continue;
    } catch (const zmq::error_t&) {
      continue;
    }
    for (int i = 0; i < 2; ++i) {
      Side& s = sides[i];
      while (s.states->receive(state, 0)) {
        const sim::StepOutput& o = simulator.step(state.header().stamp_ns(), graph::get(state.position()));
        graph::fill(command, state.header().seq(), o.force_n, o.fault);
        s.forces->publish(command);
      }
      while (s.raw_sub.recv(m, zmq::recv_flags::dontwait)) s.raw_pub.send(zmq::buffer(m.data(), m.size()), zmq::send_flags::dontwait);
    }
  }
  // the threads end with the process: the pipe's reader may be blocked in read (its writer,
  // the parent, closes it on exit)
  done.store(true);
  link_arm.detach();
  pipe_arm.detach();
  std::fflush(stdout);
  _exit(0);
}

Peer::Peer(const std::string& dir, const std::string& scene, const PeerSetup& setup, const std::string& profile_env) {
  // its command line and environment, made before fork (the child only execs)
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  std::vector<std::string> args = {self,     "bench", "loop",          "--peer",       dir,
                                   "--scene", scene,   "--peer-of",     setup.parent_list, "--peer-link",
                                   setup.link_path,    "--peer-pipes",  std::to_string(setup.pipe_in) + "," + std::to_string(setup.pipe_out)};
  std::vector<std::string> env;
  const std::string profile_key = std::string(env::kRtProfile) + "=";
  for (char** e = environ; *e; ++e) {
    if (std::strncmp(*e, profile_key.c_str(), profile_key.size()) != 0) env.emplace_back(*e);
  }
  if (!profile_env.empty()) env.push_back(profile_key + profile_env);
  std::vector<char*> argv, envp;
  for (std::string& s : args) argv.push_back(s.data());
  for (std::string& s : env) envp.push_back(s.data());
  argv.push_back(nullptr);
  envp.push_back(nullptr);
  int out[2];
  if (pipe(out) != 0) throw std::runtime_error("bench loop: pipe failed");
  pid_ = fork();
  if (pid_ == 0) {
    dup2(out[1], STDOUT_FILENO);
    close(out[0]);
    close(out[1]);
    execve(self.c_str(), argv.data(), envp.data());
    _exit(127);
  }
  close(out[1]);
  // the peer's endpoints: the first line it prints, once bound
  FILE* f = fdopen(out[0], "r");
  char line[4096] = {};
  const bool got = f && std::fgets(line, sizeof line, f);
  if (f) std::fclose(f);
  std::stringstream words(got ? line : "");
  words >> ends_.bus[0] >> ends_.raw[0] >> ends_.bus[1] >> ends_.raw[1];
  if (ends_.raw[1].empty()) throw std::runtime_error("bench loop: the peer process did not start (see above)");
}

Peer::~Peer() {
  kill(pid_, SIGTERM);
  int status = 0;
  waitpid(pid_, &status, 0);
}

}  // namespace enact::cli::loop
