#pragma once
// The recording player (`enact play`): a recording's messages republished byte for byte from
// the endpoint of the node that published each (or of one node for all), topics filtered and
// remapped, each at its recorded time on a clock the caller gives (its rate, its pauses), with
// flow control (a full subscriber queue waits: nothing is dropped).
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/bus/bytes.h"
#include "core/record/reader.h"

namespace enact::graph {

class GraphSession;

struct PlayOptions {
  std::vector<std::string> topics;           // only these (empty: every topic)
  std::map<std::string, std::string> remap;  // topic -> published as
  double offset_s = 0.0;                     // skip the recording's first seconds
  double wait_s = 5.0;                       // for a subscriber of every topic before playing
  std::string as_node;                       // every message from this node ("": each its recorder's)

  bool wanted(std::string_view topic) const;
  std::string out_topic(const std::string& topic) const;
};

// when the player sends a message: restart(t) before the first of a pass (the recording's log
// time t), wait(t) before each (false: stop now)
struct PlayTiming {
  std::function<void(std::int64_t log_ns)> restart;
  std::function<bool(std::int64_t log_ns)> wait;
};

class Player {
 public:
  // publishers for every wanted channel of `r`, declared and announced: from the session's
  // endpoints when it plays as a graph of its own (`session`), else from the graph's
  // ($ENACT_GRAPH_DIR)
  Player(record::Reader& r, PlayOptions options, GraphSession* session);
  ~Player();

  // until every played topic has a subscriber (ZeroMQ drops what is sent before one
  // connects): a short grace, then up to wait_s, said on `log` with how it ended
  void wait_for_subscribers(const std::function<void(const std::string&)>& log) const;
  // the recording once from offset_s; `sent` after each message (its log time)
  void play_once(const PlayTiming& timing, const std::function<void(std::int64_t log_ns)>& sent);

 private:
  bus::BytePublisher& publisher(const record::Channel& c);
  bus::BytePublisher& of(const record::Channel& c);
  bool all_heard() const;

  record::Reader& r_;
  PlayOptions o_;
  GraphSession* session_;
  std::int64_t first_ns_;  // the recording's first log time (a pass starts offset_s after it)
  std::map<std::string, std::unique_ptr<bus::BytePublisher>> pubs_;  // by node
  std::map<std::uint16_t, bus::BytePublisher*> by_channel_;
};

}  // namespace enact::graph
