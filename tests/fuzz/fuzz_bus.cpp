// The bus decode path on any multipart message: a publisher's frames (any count, any bytes)
// through a ByteSubscriber into the typed subscribers of every stream topic, which count
// what they refuse and never throw.
#include <algorithm>
#include <array>
#include <cstring>
#include <string>
#include <string_view>

#include <zmq.hpp>

#include "core/bus/context.h"
#include "core/bus/typed.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/graph.pb.h"
#include "msgs/node_status.pb.h"
#include "msgs/param_update.pb.h"
#include "msgs/scene_state.pb.h"
#include "msgs/tactile_frame.pb.h"
#include "msgs/task_event.pb.h"
#include "tests/fuzz/fuzz.h"

namespace {

using namespace enact;

constexpr const char* kEnd = "fuzz/end";
constexpr std::array<std::string_view, 10> kTopics = {"ffd/state",  "ffd/force",   "tactile/frame", "tactile/shown", "sim/scene",
                                                      "task/event", "node/status", "param/set",     "param/ack",     "graph/topics"};

// a typed subscriber and the message it decodes into
template <class Msg>
struct Typed {
  bus::Subscriber<Msg> subscriber;
  Msg message;
  Typed(bus::ByteSubscriber& bytes, const char* topic) : subscriber(bytes, topic) {}
  void accept(const bus::RawMessage& raw) { subscriber.accept(raw, message); }
};

// one subscriber socket with a typed subscriber per topic, fed by a raw PUB socket
struct Bus {
  zmq::socket_t pub = bus::make_socket(zmq::socket_type::pub);
  bus::ByteSubscriber bytes;
  Typed<msgs::DeviceState> state{bytes, "ffd/state"};
  Typed<msgs::ForceCommand> force{bytes, "ffd/force"};
  Typed<msgs::TactileFrame> frame{bytes, "tactile/frame"};
  Typed<msgs::TactileShown> shown{bytes, "tactile/shown"};
  Typed<msgs::SceneState> scene{bytes, "sim/scene"};
  Typed<msgs::TaskEvent> event{bytes, "task/event"};
  Typed<msgs::NodeStatus> status{bytes, "node/status"};
  Typed<msgs::ParamUpdate> set{bytes, "param/set"};
  Typed<msgs::ParamAck> ack{bytes, "param/ack"};
  Typed<msgs::GraphInfo> info{bytes, "graph/topics"};
  std::uint64_t ends = 0;

  Bus() {
    pub.bind("inproc://fuzz-bus");
    bytes.subscribe(kEnd);
    bytes.connect("inproc://fuzz-bus");
    // the subscription reaches the publisher asynchronously: send end markers until one arrives
    bus::RawMessage raw;
    do send_end();
    while (!bytes.receive(raw, 10));
    drain();
  }

  // an end marker numbered `ends` (an input may itself look like an older marker)
  void send_end() {
    ++ends;
    pub.send(zmq::buffer(std::string_view(kEnd)), zmq::send_flags::sndmore);
    pub.send(zmq::buffer(std::string_view("end")), zmq::send_flags::sndmore);
    pub.send(zmq::const_buffer(&ends, sizeof ends), zmq::send_flags::none);
  }

  bool is_last_end(const bus::RawMessage& raw) const {
    return raw.topic() == kEnd && raw.payload_size() == sizeof ends && std::memcmp(raw.payload(), &ends, sizeof ends) == 0;
  }

  // every message up to the last end marker, handed to every typed subscriber
  void drain() {
    bus::RawMessage raw;
    while (bytes.receive(raw, 1000) && !is_last_end(raw)) {
      state.accept(raw), force.accept(raw), frame.accept(raw), shown.accept(raw), scene.accept(raw);
      event.accept(raw), status.accept(raw), set.accept(raw), ack.accept(raw), info.accept(raw);
    }
  }
};

}  // namespace

// received or refused on `topic`, as the byte subscriber counts
std::uint64_t counted(const bus::ByteSubscriber& bytes, std::string_view topic) {
  const bus::TopicCounters c = bytes.counters(topic);
  return c.received + c.malformed;
}

// input: [frame count - 1, mod 7] then the frames, each but the last as [length: 1 byte][bytes],
// the last taking the rest (frames past the input's end are empty). A three-frame message on
// a subscribed topic must be counted there, received or refused.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Bus bus_;
  if (size == 0) return 0;
  const int frames = 1 + data[0] % 7;
  std::size_t at = 1;
  std::string_view topic;
  for (int f = 0; f < frames; ++f) {
    const bool last = f + 1 == frames;
    std::size_t n = size - at;
    if (!last && at < size) {
      n = std::min<std::size_t>(data[at], size - at - 1);
      ++at;
    }
    if (f == 0) topic = std::string_view(reinterpret_cast<const char*>(data + at), n);
    bus_.pub.send(zmq::const_buffer(data + at, n), last ? zmq::send_flags::none : zmq::send_flags::sndmore);
    at += n;
  }
  const bool counts = frames == 3 && std::find(kTopics.begin(), kTopics.end(), topic) != kTopics.end();
  const std::uint64_t before = counted(bus_.bytes, topic);
  bus_.send_end();
  bus_.drain();
  if (counts && counted(bus_.bytes, topic) != before + 1) __builtin_trap();
  return 0;
}
