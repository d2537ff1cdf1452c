#include "core/record/logger.h"

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <tuple>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>

#include "core/bus/attach.h"
#include "core/bus/endpoints.h"
#include "core/bus/schema.h"
#include "core/config/yaml.h"
#include "core/graph/graph_dir.h"
#include "core/graph/stop.h"
#include "core/graph/topics.h"
#include "core/rt/clock.h"

namespace enact::graph {
namespace {

constexpr std::uint16_t kNoChannel = 0xFFFF;

// the header of a stream message: field 1 (length-delimited) of the payload
bool parse_header(const bus::RawMessage& m, msgs::Header& out) {
  const auto* p = static_cast<const unsigned char*>(m.payload());
  const std::size_t n = m.payload_size();
  if (n < 2 || p[0] != 0x0a) return false;
  std::size_t len = 0, at = 1;
  for (int shift = 0; at < n && shift < 35; shift += 7) {
    len |= static_cast<std::size_t>(p[at] & 0x7F) << shift;
    if (!(p[at++] & 0x80)) break;
  }
  return len <= n - at && out.ParseFromArray(p + at, static_cast<int>(len));
}

std::string numbered(const std::string& output, int index) {
  const std::filesystem::path p(output);
  char suffix[16];
  std::snprintf(suffix, sizeof suffix, "_%03d", index);
  return (p.parent_path() / (p.stem().string() + suffix + p.extension().string())).string();
}

}  // namespace

Logger::Logger(LoggerOptions options) : options_(std::move(options)) {}

Logger::~Logger() {
  try {
    close();
  } catch (...) {
  }
}

void Logger::attach() {
  filter_ = TopicFilter(options_);  // checked before anything connects
  if (options_.attach.empty()) throw config::Error("no attach endpoint given\n  fix: give the graph's (LoggerOptions::attach: graph::find_graph finds it by name)");
  endpoint_ = options_.attach;
  bus::validate_endpoint(endpoint_, "attach endpoint");
  // deep receive queue: the logger must keep up with bursts while it compresses a chunk
  sub_.set_receive_hwm(1'000'000);
  bus::attach_connect(sub_.socket(), endpoint_, options_.keys);
  // attach_connect's own monitor is stopped by now: the socket can take this one
  watch_ = std::make_unique<bus::DisconnectWatch>(sub_.socket());
  sub_.subscribe(std::string(bus::kGraphTopic));
  const std::int64_t give_up = rt::now_ns() + static_cast<std::int64_t>(options_.wait_s * 1e9);
  bus::RawMessage m;
  // a topic asked for by name may be one a node still starting has not declared yet
  const auto unlisted = [&] {
    return std::any_of(options_.topics.begin(), options_.topics.end(), [&](const std::string& t) {
      return std::none_of(graph_.topics().begin(), graph_.topics().end(), [&](const auto& d) { return d.name() == t; });
    });
  };
  while (!graph_.ByteSizeLong() || (unlisted() && !nodes_not_announced(graph_).empty())) {
    const std::int64_t left_ms = (give_up - rt::now_ns()) / 1'000'000;
    if (left_ms <= 0) {
      if (graph_.ByteSizeLong()) break;
      throw config::Error("no graph answers at " + endpoint_ + " (waited " + std::to_string(options_.wait_s) +
                          " s)\n  fix: start the graph first (`enact launch FILE`), or check the endpoint");
    }
    if (sub_.receive(m, static_cast<int>(std::min<std::int64_t>(left_ms, 200))) && m.topic() == bus::kGraphTopic) {
      graph_.ParseFromArray(m.payload(), static_cast<int>(m.payload_size()));
    }
  }
  for (const std::string& t : options_.topics) {
    bool found = false;
    for (const auto& d : graph_.topics()) found |= d.name() == t;
    if (!found) {
      std::string known;
      for (const auto& d : graph_.topics()) known += (known.empty() ? "" : ", ") + d.name();
      throw config::Error("topic '" + t + "' is not in graph '" + graph_.graph() + "'\n  fix: choose among " + known);
    }
  }
  update_graph(graph_);
  start_ns_ = rt::now_ns();
  wall_offset_ns_ = rt::wall_ns() - start_ns_;
  open_file();
}

record::StringMap components_metadata(const msgs::GraphInfo& info) {
  record::StringMap out;
  for (int i = 0; i < info.components_size(); ++i) {
    char index[16];
    std::snprintf(index, sizeof index, "%03d.", i);
    const msgs::GraphInfo::Component& c = info.components(i);
    out[std::string(index) + "node"] = c.node();
    out[std::string(index) + "name"] = c.name();
    out[std::string(index) + "plugin"] = c.plugin();
    out[std::string(index) + "library"] = c.library();
  }
  return out;
}

std::vector<RecordedComponent> recorded_components(const record::StringMap& metadata) {
  std::map<std::string, RecordedComponent> by_index;  // "000" < "001": the launch file's order
  for (const auto& [key, value] : metadata) {
    const std::size_t dot = key.find('.');
    if (dot == std::string::npos) continue;
    RecordedComponent& c = by_index[key.substr(0, dot)];
    const std::string field = key.substr(dot + 1);
    if (field == "node") c.node = value;
    if (field == "name") c.name = value;
    if (field == "plugin") c.plugin = value;
    if (field == "library") c.library = value;
  }
  std::vector<RecordedComponent> out;
  for (auto& [index, c] : by_index) out.push_back(std::move(c));
  return out;
}

TopicFilter::TopicFilter(const LoggerOptions& options) : topics_(options.topics) {
  for (auto [text, out, what] : {std::tuple{&options.regex, &regex_, "regex"}, std::tuple{&options.exclude, &exclude_, "exclude"}}) {
    if (text->empty()) continue;
    try {
      out->emplace(*text, std::regex::ECMAScript);
    } catch (const std::regex_error& e) {
      throw config::Error(std::string(what) + " '" + *text + "' is not a regular expression: " + e.what() + "\n  fix: e.g. '^ffd/' or 'state$'");
    }
  }
}

bool TopicFilter::wants(const std::string& topic) const {
  const bool listed = topics_.empty() || std::find(topics_.begin(), topics_.end(), topic) != topics_.end();
  return listed && (!regex_ || std::regex_search(topic, *regex_)) && !(exclude_ && std::regex_search(topic, *exclude_));
}

void Logger::update_graph(const msgs::GraphInfo& info) {
  for (const auto& d : info.topics()) {
    if (filter_.wants(d.name())) sub_.subscribe(d.name());
  }
}

void Logger::open_file() {
  const int index = static_cast<int>(files_.size());
  const bool split = options_.split_size_mb > 0.0 || options_.split_duration_s > 0.0;
  const std::string path = split ? numbered(options_.output, index) : options_.output;
  // a file size limit (ulimit -f) then fails the write as a full disk does, instead of
  // killing the logger before it closes its file
  std::signal(SIGXFSZ, SIG_IGN);
  writer_ = std::make_unique<record::Writer>(path, options_.writer);
  files_.push_back(path);
  file_start_ns_ = rt::now_ns();
  schemas_.clear();
  for (auto& [key, c] : channels_) c.id = kNoChannel;
  // how the graph was started: metadata and the files its parameters name
  writer_->add_metadata("enact.graph", {{"graph", graph_.graph()},
                                        {"attach", endpoint_},
                                        {"launch_file", graph_.launch_file()},
                                        {"clock", graph_.clock().empty() ? "real" : graph_.clock()},
                                        {"launch_text", graph_.launch_text()},
                                        {"part", std::to_string(index)}});
  record::StringMap params;
  for (const auto& p : graph_.params()) params[p.name()] = p.value();
  writer_->add_metadata("enact.params", params);
  writer_->add_metadata("enact.components", components_metadata(graph_));
  for (const auto& f : graph_.files()) writer_->add_attachment(f.name(), f.media_type(), f.data(), rt::now_ns() + wall_offset_ns_);
}

std::uint16_t Logger::schema_for(const std::string& type) {
  const auto it = schemas_.find(type);
  if (it != schemas_.end()) return it->second;
  // the type's file and its imports, from the graph's own descriptor set
  google::protobuf::FileDescriptorSet set;
  google::protobuf::DescriptorPool pool;
  std::string data;
  if (set.ParseFromString(graph_.descriptor_set())) {
    for (const auto& f : set.file()) pool.BuildFile(f);
    if (const auto* d = pool.FindMessageTypeByName(type)) data = bus::descriptor_set_of(*d);
  }
  const std::uint16_t id = writer_->add_schema(type, data.empty() ? "" : "protobuf", data);
  schemas_.emplace(type, id);
  return id;
}

void Logger::take(const bus::RawMessage& m, std::int64_t now_ns) {
  if (m.topic() == bus::kGraphTopic) {
    msgs::GraphInfo info;
    if (info.ParseFromArray(m.payload(), static_cast<int>(m.payload_size()))) update_graph(info);
    return;
  }
  header_.Clear();
  const bool has_header = parse_header(m, header_);
  key_.assign(m.topic());
  key_ += '\0';
  key_ += header_.source();
  auto it = channels_.find(key_);
  if (it == channels_.end()) {
    Channel c;
    c.id = kNoChannel;
    c.report = {std::string(m.topic()), header_.source(), std::string(m.type()), {}};
    it = channels_.emplace(key_, std::move(c)).first;
  }
  Channel& c = it->second;
  if (has_header && c.report.seq.repeats(header_.seq(), header_.stamp_ns())) return;
  if (c.id == kNoChannel) {
    c.id = writer_->add_channel(schema_for(c.report.type), c.report.topic, "protobuf", {{"publisher", c.report.publisher}});
  }
  // sequence: +1 per message per publisher and topic; a jump is a loss
  c.report.seq.add(has_header ? header_.seq() : c.report.seq.last + 1, header_.stamp_ns());
  messages_.store(messages_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  const std::int64_t publish_ns = has_header && header_.stamp_ns() > 0 ? header_.stamp_ns() : now_ns;
  writer_->write(c.id, static_cast<std::uint32_t>(c.report.seq.last), now_ns + wall_offset_ns_, publish_ns,
                 std::string_view(static_cast<const char*>(m.payload()), m.payload_size()));
}

// after a stop: take messages until none came for this long, at most kDrainMax_s (the
// supervisor's SIGKILL comes 3 s after its SIGTERM)
constexpr int kDrainQuiet_ms = 100;
constexpr double kDrainMax_s = 2.0;

void Logger::run(const std::function<bool()>& stop, const std::function<void(const LoggerProgress&)>& progress) {
  try {
    receive(stop, progress);
  } catch (const record::Error& e) {
    // the disk is full: stop here, close what the file holds
    write_failure_ = e.what();
  }
}

void Logger::receive(const std::function<bool()>& stop, const std::function<void(const LoggerProgress&)>& progress) {
  bus::RawMessage m;
  std::int64_t next_progress = rt::now_ns() + 1'000'000'000;
  while (!stop()) {
    // drain what is queued, then wait a little; a graph gone sends nothing more. A stop is
    // seen within a batch: behind a long backlog on a busy machine a batch of 10000 took
    // seconds, and the stop's grace (graph::kStopGrace_s) ended the process before its file
    // was closed
    for (int i = 0; i < 10000 && (i % 256 != 255 || !stop()) && sub_.receive(m, i == 0 ? 50 : 0); ++i) take(m, rt::now_ns());
    if (watch_ && watch_->disconnected()) {
      graph_gone_ = true;
      break;
    }
    const std::int64_t now = rt::now_ns();
    writer_->flush_if_due(now);
    const bool too_big = options_.split_size_mb > 0.0 && static_cast<double>(writer_->bytes_written()) >= options_.split_size_mb * 1e6;
    const bool too_long = options_.split_duration_s > 0.0 && static_cast<double>(now - file_start_ns_) >= options_.split_duration_s * 1e9;
    if (too_big || too_long) {
      close_file();
      if (!write_failure_.empty()) return;
      open_file();
    }
    if (progress && now >= next_progress) {
      next_progress = now + 1'000'000'000;
      LoggerProgress p;
      p.elapsed_s = static_cast<double>(now - start_ns_) * 1e-9;
      p.messages = messages();
      for (const auto& [k, c] : channels_) p.gaps += c.report.seq.gaps;
      std::uint64_t bytes = 0;
      for (std::size_t i = 0; i + 1 < files_.size(); ++i) bytes += std::filesystem::file_size(files_[i]);
      p.bytes = bytes + writer_->bytes_written();
      p.file = files_.back();
      progress(p);
    }
  }
  // what is already queued or on its way still goes in: the graph's nodes stop first, so the
  // stream goes quiet soon (a logger behind a graph in simulated time may still have many)
  const std::int64_t give_up = rt::now_ns() + static_cast<std::int64_t>(kDrainMax_s * 1e9);
  while (sub_.receive(m, kDrainQuiet_ms) && rt::now_ns() < give_up) take(m, rt::now_ns());
}

void Logger::close_file() {
  if (!writer_) return;
  record::StringMap stats;
  std::uint64_t gaps = 0;
  for (const auto& [k, c] : channels_) {
    stats[c.report.topic + " (" + c.report.publisher + ")"] =
        "messages " + std::to_string(c.report.seq.messages) + ", gaps " + std::to_string(c.report.seq.gaps);
    gaps += c.report.seq.gaps;
  }
  stats["messages"] = std::to_string(messages());
  stats["gaps"] = std::to_string(gaps);
  // after a write failure each part is tried on its own: the summary may still fit
  closed_whole_ = false;
  try {
    writer_->add_metadata("enact.recording", stats);
  } catch (const record::Error& e) {
    if (write_failure_.empty()) write_failure_ = e.what();
  }
  try {
    writer_->close();
    closed_whole_ = true;
  } catch (const record::Error& e) {
    if (write_failure_.empty()) write_failure_ = e.what();
  }
  writer_.reset();
}

void Logger::close() { close_file(); }

std::string format_write_failure(const Logger& logger) {
  const std::string file = logger.files().back();
  return logger.write_failure() + "\nrecording stopped; " + file +
         (logger.closed_whole() ? " is closed: it holds every message up to its last whole chunk (enact info " + file + ")"
                                : " is readable but has no summary: enact recover " + file + " -o FIXED.mcap");
}

std::vector<ChannelReport> Logger::report() const {
  std::vector<ChannelReport> out;
  for (const auto& [k, c] : channels_) out.push_back(c.report);
  return out;
}

std::string format(const LoggerProgress& p) {
  char line[256];
  std::snprintf(line, sizeof line, "%7.1f s  %10llu messages  %8.2f MB  %llu gaps  -> %s", p.elapsed_s,
                static_cast<unsigned long long>(p.messages), static_cast<double>(p.bytes) * 1e-6,
                static_cast<unsigned long long>(p.gaps), p.file.c_str());
  return line;
}

std::string format(const std::vector<ChannelReport>& channels) {
  std::string out;
  char line[256];
  std::uint64_t messages = 0, gaps = 0;
  for (const ChannelReport& c : channels) {
    std::snprintf(line, sizeof line, "  %-16s %-10s %10llu messages  %llu gaps%s\n", c.topic.c_str(), c.publisher.c_str(),
                  static_cast<unsigned long long>(c.seq.messages), static_cast<unsigned long long>(c.seq.gaps),
                  c.seq.restarts ? "  (publisher restarted)" : "");
    out += line;
    messages += c.seq.messages;
    gaps += c.seq.gaps;
  }
  std::snprintf(line, sizeof line, "  total: %llu messages, %llu gaps\n", static_cast<unsigned long long>(messages),
                static_cast<unsigned long long>(gaps));
  return out + line;
}

}  // namespace enact::graph
