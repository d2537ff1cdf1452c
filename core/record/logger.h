#pragma once
// The logger: an observer that attaches to a graph's attach point (locally or from another
// machine, at any time) and keeps every message of the topics asked for in an MCAP file
// (core/record). One MCAP channel per topic and publishing node, one schema per message
// type (the graph's own FileDescriptorSet, from GraphInfo); the launch file, the parameters
// in force and the files they name (scene, computer model, hand path) go in as metadata
// and attachments. Sequence gaps (header.seq) are counted per channel. It never slows the
// graph: the attach point queues deeply for it and drops (counted as gaps) if it stalls.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "core/bus/bytes.h"
#include "core/bus/disconnect.h"
#include "core/bus/client.h"
#include "core/record/writer.h"
#include "core/launch/launch_file.h"
#include "msgs/common.pb.h"
#include "msgs/graph.pb.h"

namespace enact::graph {

struct LoggerOptions {
  std::string attach;                    // the graph's attach endpoint (graph::find_graph resolves a name)
  bus::ClientKeys keys;                  // for a graph with an access file (bus::client_keys)
  std::string output = "recording.mcap";  // file; with splitting, NAME_000.mcap, NAME_001.mcap, ...
  std::vector<std::string> topics;       // topics to keep; empty = every topic of the graph
  std::string regex;                     // ... only those it matches (ECMAScript, anywhere); "" = all
  std::string exclude;                   // ... but none this matches; "" = none excluded
  record::WriterOptions writer;          // compression, chunk size and duration (the kill -9 loss bound)
  double split_size_mb = 0.0;            // start a new file past this size (0: never)
  double split_duration_s = 0.0;         // start a new file after this long (0: never)
  double wait_s = 10.0;                  // how long to wait for the graph to appear
};

// the components of a graph's containers (GraphInfo.components) as a recording keeps them,
// in the metadata record "enact.components": "NNN.node", "NNN.name", "NNN.plugin" and
// "NNN.library" for the NNN-th, in the launch file's order
struct RecordedComponent {
  std::string node, name, plugin, library;
};
record::StringMap components_metadata(const msgs::GraphInfo& info);
std::vector<RecordedComponent> recorded_components(const record::StringMap& metadata);

// which topics a logger keeps: those listed (none listed: every topic), matching regex,
// matching no exclude. Throws config::Error naming a pattern that is not a regular expression
class TopicFilter {
 public:
  TopicFilter() = default;
  explicit TopicFilter(const LoggerOptions& options);
  bool wants(const std::string& topic) const;

 private:
  std::vector<std::string> topics_;
  std::optional<std::regex> regex_, exclude_;
};

// sequence numbers of one publisher's topic (header.seq: +1 per message): a jump is a
// loss, a step back a restart of the publisher: a new stream whose first message is seq 1,
// so what came before the one received is lost too
struct SequenceCheck {
  std::uint64_t last = 0, messages = 0, gaps = 0, restarts = 0;
  std::int64_t last_stamp_ns = 0;  // header.stamp_ns of the last
  void add(std::uint64_t seq, std::int64_t stamp_ns = 0) {
    if (messages > 0 && seq > last + 1) gaps += seq - last - 1;
    if (messages > 0 && seq <= last) {
      ++restarts;
      gaps += seq - 1;
    }
    last = seq;
    last_stamp_ns = stamp_ns;
    ++messages;
  }
  // the same message again (an attach point repeats a state topic's last message for an
  // observer that came late): its seq and its stamp. Another message with the same seq (two
  // `enact param set` processes, each sending its first request as seq 1) is no repeat
  bool repeats(std::uint64_t seq, std::int64_t stamp_ns) const { return messages > 0 && seq != 0 && seq == last && stamp_ns == last_stamp_ns; }
};

// traffic of one channel (topic and publishing node)
struct ChannelReport {
  std::string topic, publisher, type;
  SequenceCheck seq;  // messages, gaps (missing by sequence number), restarts of the publisher
};

struct LoggerProgress {
  double elapsed_s = 0.0;
  std::uint64_t messages = 0, bytes = 0, gaps = 0;
  std::string file;
};

class Logger {
 public:
  explicit Logger(LoggerOptions options);
  ~Logger();

  // finds the graph (waits up to wait_s for its GraphInfo), subscribes, opens the first
  // file. Throws config::Error when no graph answers or a topic asked for is not in it.
  void attach();
  // receives and writes until `stop` returns true or the graph is gone (its attach point's
  // connection closed: the launcher ended, or was killed); calls `progress` about once a second
  void run(const std::function<bool()>& stop, const std::function<void(const LoggerProgress&)>& progress = {});
  // whether run() ended because the graph was gone
  bool graph_gone() const { return graph_gone_; }
  // writes the statistics metadata and closes the file (complete and indexed); after a
  // write failure, as much of that as the room left takes (the file stays readable)
  void close();
  // why writing stopped (a full disk, a file size limit: the writer's error), "" if it did not;
  // run() returns at the first failure
  const std::string& write_failure() const { return write_failure_; }
  // whether the last file was closed with its summary (false: readable, but `enact recover`
  // indexes it); valid after close()
  bool closed_whole() const { return closed_whole_; }

  const std::string& endpoint() const { return endpoint_; }
  std::vector<ChannelReport> report() const;
  std::vector<std::string> files() const { return files_; }
  std::uint64_t messages() const { return messages_.load(std::memory_order_relaxed); }

 private:
  struct Channel {
    std::uint16_t id = 0;  // in the current file
    ChannelReport report;  // across files
  };
  void open_file();
  void close_file();
  // run() until the first write failure, which it throws
  void receive(const std::function<bool()>& stop, const std::function<void(const LoggerProgress&)>& progress);
  void take(const bus::RawMessage& m, std::int64_t now_ns);
  void update_graph(const msgs::GraphInfo& info);
  std::uint16_t schema_for(const std::string& type);

  LoggerOptions options_;
  TopicFilter filter_;
  std::string endpoint_;
  bus::ByteSubscriber sub_;
  std::unique_ptr<bus::DisconnectWatch> watch_;  // on sub_, from attach()
  bool graph_gone_ = false;
  msgs::GraphInfo graph_;
  std::unique_ptr<record::Writer> writer_;
  std::map<std::string, std::uint16_t> schemas_;   // per file
  std::map<std::string, Channel> channels_;        // key: topic '\0' publisher
  std::vector<std::string> files_;
  std::string key_;
  msgs::Header header_;
  std::atomic<std::uint64_t> messages_{0};  // written by run()'s thread alone, read by any
  std::int64_t file_start_ns_ = 0, start_ns_ = 0;
  // wall clock - monotonic clock at the start: log times are dates (Foxglove shows them),
  // one offset for the whole recording so they never jump; publish times keep header.stamp_ns
  std::int64_t wall_offset_ns_ = 0;
  std::string write_failure_;
  bool closed_whole_ = false;
};

// what a logger says when its disk filled: the writer's error, and what the file holds now
// (closed with its summary, or readable without one: the `enact recover` line)
std::string format_write_failure(const Logger& logger);

// one line of progress: "12.0 s  61234 messages  1.2 MB  0 gaps  -> FILE"
std::string format(const LoggerProgress& p);
// the end-of-recording table: per channel, messages and gaps, then the totals
std::string format(const std::vector<ChannelReport>& channels);

}  // namespace enact::graph
