// enact bench loop, round-trip arms: ffd -> sim -> ffd at 5 kHz with the simulator in a
// second process (bench_loop_peer.cpp), like the graph: the bus over ZeroMQ (DeviceState, a
// simulator step, ForceCommand) and a raw ZeroMQ ping-pong of the same sizes and socket
// layout, over ipc then tcp; on ipc also the loop's local link (the same messages and step,
// as the graph's FFD driver and simulator exchange them) and its floor, a raw ping-pong
// through two pipes. The arms alternate tick by tick; replies are matched by sequence number.
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <array>
#include <cstring>
#include <stdexcept>

#include "core/bus/context.h"
#include "core/bus/loop_link.h"
#include "core/bus/typed.h"
#include "core/graph/messages.h"
#include "core/graph/sockets.h"
#include "core/rt/clock.h"
#include "core/rt/scheduler.h"
#include "nodes/enact-bench/bench_loop.h"

namespace enact::cli::loop {
namespace {

constexpr std::size_t kRawSize = 64;  // raw payload: seq (8 bytes) then filler

// one transport: the bus and the raw ping-pong, alternating tick by tick
class RttCase {
 public:
  // `local_dir`: where the local arms' link and bus live ("": no local arms)
  RttCase(const std::string& bus_bind, const std::string& raw_bind, const std::string& local_dir = "")
      : out_(bus_bind, {.node = "ffd", .send_hwm = 10000}),
        states_(out_, "ffd/state"),
        forces_(in_, "ffd/force"),
        link_out_(local_dir.empty() ? "inproc://bench-link-" + std::to_string(reinterpret_cast<std::uintptr_t>(this)) : "ipc://" + local_dir + "/ffd-link-bus",
                  {.node = "ffd", .send_hwm = 10000}),
        link_states_(link_out_, "ffd/state"),
        link_forces_(link_in_, "ffd/force"),
        arms_(local_dir.empty() ? 2 : kArms) {
    for (zmq::socket_t* z : {&raw_pub_, &raw_sub_}) z->set(zmq::sockopt::linger, 0);
    raw_pub_.bind(raw_bind);
    raw_sub_.set(zmq::sockopt::subscribe, "");
    graph::set(*state_.mutable_position(), {-0.0074246, -0.0222739, 0.0119});
    std::fill(raw_.begin(), raw_.end(), 'a');
    if (arms_ == kArms) {
      link_ = bus::LoopLink::listen(bus::loop_link_path(local_dir, "bench"));
      link_states_.also_over(&link_);
      int to_peer[2], from_peer[2];
      if (pipe2(to_peer, O_CLOEXEC) != 0 || pipe2(from_peer, O_CLOEXEC) != 0) throw std::runtime_error("bench loop: pipe failed");
      // the peer inherits its ends alone
      fcntl(to_peer[0], F_SETFD, 0);
      fcntl(from_peer[1], F_SETFD, 0);
      pipe_out_ = to_peer[1];
      pipe_in_ = from_peer[0];
      peer_pipe_in_ = to_peer[0];
      peer_pipe_out_ = from_peer[1];
    }
  }
  ~RttCase() {
    for (int fd : {pipe_in_, pipe_out_, peer_pipe_in_, peer_pipe_out_}) {
      if (fd >= 0) close(fd);
    }
  }
  RttCase(const RttCase&) = delete;
  RttCase& operator=(const RttCase&) = delete;
  // what the peer needs of the local arms (empty without them)
  PeerSetup local_setup() const { return {"", arms_ == kArms ? link_.path() : "", peer_pipe_in_, peer_pipe_out_}; }
  // the peer has the pipes' other ends: this process closes its copies
  void peer_started() {
    for (int* fd : {&peer_pipe_in_, &peer_pipe_out_}) {
      if (*fd >= 0) close(*fd);
      *fd = -1;
    }
  }
  std::string bus_endpoint() const { return out_.endpoint(); }
  std::string raw_endpoint() { return raw_pub_.get(zmq::sockopt::last_endpoint); }

  // connect to the peer, then ping both arms until each has answered (at most 10 s)
  void handshake(const std::string& peer_bus, const std::string& peer_raw) {
    in_.connect(peer_bus);
    raw_sub_.connect(peer_raw);
    const std::int64_t give_up = rt::now_ns() + 10'000'000'000;
    if (arms_ == kArms && !link_.wait_for_peer(give_up)) throw std::runtime_error("bench loop: the peer did not connect to the local link within 10 s");
    bool ok[kArms] = {};
    const auto all_ok = [&] { return std::all_of(ok, ok + arms_, [](bool b) { return b; }); };
    while (!all_ok() && rt::now_ns() < give_up) {
      for (int a = 0; a < arms_; ++a) ok[a] = ok[a] || exchange(a, rt::now_ns(), rt::now_ns() + 2'000'000, {rt::now_ns() + 2'000'000, -1}, handshake_[a]);
    }
    if (!all_ok()) throw std::runtime_error("bench loop: the peer did not answer within 10 s");
    // replies to the handshake's unanswered pings come back as stale: let them arrive now
    rt::sleep_until_ns(rt::now_ns() + 20'000'000);
    for (int a = 0; a < arms_; ++a) exchange(a, rt::now_ns(), rt::now_ns(), {rt::now_ns(), -1}, handshake_[a]);
  }

  RttResult run(double seconds, bool fifo) {
    RttResult r;
    rt::LatencyHistogram block[kArms];
    loop_thread([&] {
      rt::PeriodicScheduler s({.rate_hz = kRate_hz, .spin_ns = 50'000, .sleep_every_tick = fifo, .wake_fd = true});
      const std::int64_t start = rt::now_ns() + 1'000'000;
      const std::int64_t end = start + static_cast<std::int64_t>(seconds * 1e9);
      s.start(start);
      for (std::int64_t n = 0;; ++n) {
        const std::int64_t now = s.wait();
        if (now >= end) break;
        // tick by tick, the order of each round of arms flipped every other round
        const int a = arms_ == 2 ? arm_of(n, 1) : (n / kArms) % 2 == 0 ? static_cast<int>(n % kArms) : kArms - 1 - static_cast<int>(n % kArms);
        // the answer to this tick's request, until just before the next tick
        const std::int64_t answer_by = s.next_deadline_ns() - s.spin_ns();
        if (exchange(a, now, answer_by, s.reply_wait(answer_by), r.arm[a])) block[a].record(r.arm[a].last_rtt_ns());
        if (n % (arms_ * kBlockTicks) == arms_ * kBlockTicks - 1) {
          r.p50.add_block(block[kBus], block[kRaw]);
          if (arms_ == kArms) r.floor.add_block(block[kLink], block[kPipe]);
        }
      }
    });
    r.p50.overall = ratio(r.arm[kBus].rtt().percentile(50.0), r.arm[kRaw].rtt().percentile(50.0));
    if (arms_ == kArms) r.floor.overall = ratio(r.arm[kLink].rtt().percentile(50.0), r.arm[kPipe].rtt().percentile(50.0));
    r.lost = forces_.counters().lost;
    return r;
  }

 private:
  // one arm: send request, wait for the reply carrying its number until answer_by; replies
  // to earlier requests are counted stale by `trip`. The local arms wait as the graph's FFD
  // driver does: until the scheduler's timer where it is armed for answer_by (`local`), so
  // their wait sets no timer of its own
  bool exchange(int arm, std::int64_t now, std::int64_t answer_by, rt::PeriodicScheduler::ReplyWait local, rt::RoundTrip& trip) {
    const std::int64_t local_by = local.until;
    const int stop_fd = local.stop_fd;
    if (arm == kLink) {
      // as the graph's FFD driver: published over the link, answered there, then on the bus
      state_.mutable_header()->set_stamp_ns(now);
      link_states_.publish(state_);
      trip.sent(link_states_.last_seq(), now);
      bool answered = false;
      for (long n; !answered && (n = link_.receive(link_buffer_, sizeof link_buffer_, local_by, stop_fd)) > 0;) {
        answered = link_forces_.accept_payload(link_buffer_, static_cast<std::size_t>(n), command_) && trip.reply(command_.answered_seq(), rt::now_ns());
      }
      link_states_.send_held();  // the observers' copy, after the answer (as the driver)
      if (answered) return true;
    } else if (arm == kPipe) {
      ++pipe_seq_;
      std::memcpy(raw_.data(), &pipe_seq_, sizeof pipe_seq_);
      trip.sent(pipe_seq_, now);
      if (write(pipe_out_, raw_.data(), raw_.size()) == static_cast<ssize_t>(raw_.size())) {
        for (;;) {
          const std::int64_t left_ns = local_by - rt::now_ns();
          pollfd p[2] = {{pipe_in_, POLLIN, 0}, {stop_fd, POLLIN, 0}};
          const timespec left{static_cast<time_t>(left_ns / 1'000'000'000), static_cast<long>(left_ns % 1'000'000'000)};
          if (left_ns <= 0 || ppoll(p, stop_fd >= 0 ? 2 : 1, &left, nullptr) <= 0 || p[0].revents == 0) break;
          std::array<char, kRawSize> reply{};
          if (read(pipe_in_, reply.data(), reply.size()) != static_cast<ssize_t>(reply.size())) break;
          std::uint64_t seq = 0;
          std::memcpy(&seq, reply.data(), sizeof seq);
          if (trip.reply(seq, rt::now_ns())) return true;
        }
      }
    } else if (arm == kBus) {
      state_.mutable_header()->set_stamp_ns(now);
      states_.publish(state_);
      trip.sent(state_.header().seq(), now);
      while (graph::wait_readable(in_.socket(), answer_by)) {
        while (forces_.receive(command_, 0)) {
          if (trip.reply(command_.answered_seq(), rt::now_ns())) return true;
        }
      }
    } else {
      ++raw_seq_;
      std::memcpy(raw_.data(), &raw_seq_, sizeof raw_seq_);
      raw_pub_.send(zmq::buffer(raw_), zmq::send_flags::dontwait);
      trip.sent(raw_seq_, now);
      while (graph::wait_readable(raw_sub_, answer_by)) {
        while (raw_sub_.recv(reply_, zmq::recv_flags::dontwait)) {
          std::uint64_t seq = 0;
          if (reply_.size() >= sizeof seq) std::memcpy(&seq, reply_.data(), sizeof seq);
          if (trip.reply(seq, rt::now_ns())) return true;
        }
      }
    }
    trip.close();
    return false;
  }

  bus::BytePublisher out_;
  bus::Publisher<msgs::DeviceState> states_;
  bus::ByteSubscriber in_;
  bus::Subscriber<msgs::ForceCommand> forces_;
  zmq::socket_t raw_pub_{bus::context(), zmq::socket_type::pub}, raw_sub_{bus::context(), zmq::socket_type::sub};
  msgs::DeviceState state_;
  msgs::ForceCommand command_;
  std::array<char, kRawSize> raw_{};
  std::uint64_t raw_seq_ = 0;
  zmq::message_t reply_;
  rt::RoundTrip handshake_[kArms];
  // the local arms
  bus::BytePublisher link_out_;
  bus::Publisher<msgs::DeviceState> link_states_;
  bus::ByteSubscriber link_in_;
  bus::Subscriber<msgs::ForceCommand> link_forces_;
  bus::LoopLink link_;
  char link_buffer_[bus::LoopLink::kMaxMessage];
  int pipe_in_ = -1, pipe_out_ = -1, peer_pipe_in_ = -1, peer_pipe_out_ = -1;
  std::uint64_t pipe_seq_ = 0;
  int arms_;
};

}  // namespace

RttResults round_trips(const std::string& dir, const std::string& scene, const std::string& peer_profile_env, double seconds, bool fifo) {
  RttCase ipc("ipc://" + dir + "/ffd-bus", "ipc://" + dir + "/ffd-raw", dir);
  RttCase tcp("tcp://127.0.0.1:*", "tcp://127.0.0.1:*");
  PeerSetup setup = ipc.local_setup();
  setup.parent_list = ipc.bus_endpoint() + "," + ipc.raw_endpoint() + "," + tcp.bus_endpoint() + "," + tcp.raw_endpoint();
  const Peer peer(dir, scene, setup, peer_profile_env);
  ipc.peer_started();
  ipc.handshake(peer.endpoints().bus[0], peer.endpoints().raw[0]);
  tcp.handshake(peer.endpoints().bus[1], peer.endpoints().raw[1]);
  RttResults r;
  r.ipc = ipc.run(seconds, fifo);
  r.tcp = tcp.run(seconds, fifo);
  return r;
}

}  // namespace enact::cli::loop
