// enact bench loop, round-trip arms: ffd -> sim -> ffd at 5 kHz with the simulator in a
// second process (bench_loop_peer.cpp), like the graph: the bus (DeviceState, a simulator
// step, ForceCommand) and a raw ZeroMQ ping-pong of the same sizes and socket layout,
// alternating tick by tick, over ipc then tcp; replies matched by sequence number.
#include <array>
#include <cstring>
#include <stdexcept>

#include "core/bus/context.h"
#include "core/bus/typed.h"
#include "core/graph/messages.h"
#include "core/graph/node.h"
#include "core/rt/clock.h"
#include "core/rt/scheduler.h"
#include "nodes/enact/bench_loop.h"

namespace enact::cli::loop {
namespace {

constexpr std::size_t kRawSize = 64;  // raw payload: seq (8 bytes) then filler

// one transport: the bus and the raw ping-pong, alternating tick by tick
class RttCase {
 public:
  RttCase(const std::string& bus_bind, const std::string& raw_bind)
      : out_(bus_bind, {.node = "ffd", .send_hwm = 10000}), states_(out_, "ffd/state"), forces_(in_, "ffd/force") {
    for (zmq::socket_t* z : {&raw_pub_, &raw_sub_}) z->set(zmq::sockopt::linger, 0);
    raw_pub_.bind(raw_bind);
    raw_sub_.set(zmq::sockopt::subscribe, "");
    graph::set(*state_.mutable_position(), {-0.0074246, -0.0222739, 0.0119});
    std::fill(raw_.begin(), raw_.end(), 'a');
  }
  std::string bus_endpoint() const { return out_.endpoint(); }
  std::string raw_endpoint() { return raw_pub_.get(zmq::sockopt::last_endpoint); }

  // connect to the peer, then ping both arms until each has answered (at most 10 s)
  void handshake(const std::string& peer_bus, const std::string& peer_raw) {
    in_.connect(peer_bus);
    raw_sub_.connect(peer_raw);
    const std::int64_t give_up = rt::now_ns() + 10'000'000'000;
    bool ok[2] = {false, false};
    while (!(ok[0] && ok[1]) && rt::now_ns() < give_up) {
      for (int a = 0; a < 2; ++a) ok[a] = ok[a] || exchange(a, rt::now_ns(), rt::now_ns() + 2'000'000, handshake_[a]);
    }
    if (!(ok[0] && ok[1])) throw std::runtime_error("bench loop: the peer did not answer within 10 s");
    // replies to the handshake's unanswered pings come back as stale: let them arrive now
    rt::sleep_until_ns(rt::now_ns() + 20'000'000);
    for (int a = 0; a < 2; ++a) exchange(a, rt::now_ns(), rt::now_ns(), handshake_[a]);
  }

  RttResult run(double seconds, bool fifo) {
    RttResult r;
    rt::LatencyHistogram block[2];
    loop_thread([&] {
      rt::PeriodicScheduler s({.rate_hz = kRate_hz, .spin_ns = 50'000, .sleep_every_tick = fifo});
      const std::int64_t start = rt::now_ns() + 1'000'000;
      const std::int64_t end = start + static_cast<std::int64_t>(seconds * 1e9);
      s.start(start);
      for (std::int64_t n = 0;; ++n) {
        const std::int64_t now = s.wait();
        if (now >= end) break;
        const int a = arm_of(n, 1);
        // the answer to this tick's request, until just before the next tick
        if (exchange(a, now, s.next_deadline_ns() - s.spin_ns(), r.arm[a])) block[a].record(r.arm[a].last_rtt_ns());
        if (n % (2 * kBlockTicks) == 2 * kBlockTicks - 1) r.p50.add_block(block[0], block[1]);
      }
    });
    r.p50.overall = ratio(r.arm[0].rtt().percentile(50.0), r.arm[1].rtt().percentile(50.0));
    r.lost = forces_.counters().lost;
    return r;
  }

 private:
  // arm 0 (bus) or 1 (raw): send request, wait for the reply carrying its number until
  // answer_by; replies to earlier requests are counted stale by `trip`
  bool exchange(int arm, std::int64_t now, std::int64_t answer_by, rt::RoundTrip& trip) {
    if (arm == 0) {
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
  rt::RoundTrip handshake_[2];
};

}  // namespace

RttResults round_trips(const std::string& dir, const std::string& scene, const std::string& peer_profile_env, double seconds, bool fifo) {
  RttCase ipc("ipc://" + dir + "/ffd-bus", "ipc://" + dir + "/ffd-raw");
  RttCase tcp("tcp://127.0.0.1:*", "tcp://127.0.0.1:*");
  const std::string parent = ipc.bus_endpoint() + "," + ipc.raw_endpoint() + "," + tcp.bus_endpoint() + "," + tcp.raw_endpoint();
  const Peer peer(dir, scene, parent, peer_profile_env);
  ipc.handshake(peer.endpoints().bus[0], peer.endpoints().raw[0]);
  tcp.handshake(peer.endpoints().bus[1], peer.endpoints().raw[1]);
  RttResults r;
  r.ipc = ipc.run(seconds, fifo);
  r.tcp = tcp.run(seconds, fifo);
  return r;
}

}  // namespace enact::cli::loop
