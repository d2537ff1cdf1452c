// enact record | info | export | recover: make, inspect, flatten and repair MCAP recordings.
#include <unistd.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/dynamic_message.h>

#include "core/config/suggest.h"
#include "core/config/yaml.h"
#include "core/record/logger.h"
#include "core/graph/stop.h"
#include "core/replay/replay.h"
#include "core/graph/topics.h"
#include "core/record/reader.h"
#include "core/rt/clock.h"
#include "core/record/writer.h"
#include "nodes/enact/attach_target.h"
#include "nodes/enact/commands.h"
#include "nodes/enact/mcap_copy.h"

namespace enact::cli {
namespace {

constexpr const char* kRecordHelp = R"(usage: enact record [-o FILE] [--all | --topics T...] [--regex RE] [--exclude RE] [--split-size MB | --split-duration S]
                    [--compression zstd|lz4|none] [--chunk-duration S]
                    [--graph NAME | --attach ENDPOINT] [--duration S] [--wait S]
                    [--key FILE.key --server-key FILE.pub]

Attach to a running graph (--graph NAME, the only one running here, or --attach ENDPOINT,
also on another machine) and keep every message of its topics in an MCAP file, until the
graph ends (stopped or killed: within a second), Ctrl-C / SIGTERM or
--duration: the file is then complete and indexed, exit 0. Started before its graph, it
waits for it (saying so). A kill -9 loses at most the last chunk
(--chunk-duration, 1 s by default); `enact recover` rebuilds the rest. Sequence gaps are
counted per topic and reported at the end. A full disk (or a file size limit) stops it
with exit 1, saying so: the file ends at its last whole chunk, closed with its summary if
the room left holds one, else readable by `enact info` and `enact recover`.

options:
  -o, --out FILE         default enact_YYYYmmdd_HHMMSS.mcap
  --all                  every topic (the default)
  --topics T...          only these topics
  --regex RE             only topics RE matches (ECMAScript, anywhere in the name)
  --exclude RE           no topic RE matches
  --split-size MB        start a new file (FILE_000.mcap, FILE_001.mcap, ...) past this size
  --split-duration S     ... or after this long
  --compression C        zstd (default), lz4 or none
  --chunk-duration S     a chunk reaches the file at least this often (default 1)
  --duration S           stop after S seconds
)";

constexpr const char* kInfoHelp = R"(usage: enact info FILE

Duration, topics (publisher, type, messages, rate, sequence gaps), metadata and attachments
of an MCAP recording, and any damage (everything readable before it is still counted).
Exit status 1 when the file is damaged or was not closed.
)";

constexpr const char* kExportHelp = R"(usage: enact export FILE --topic T --csv OUT.csv|- [--publisher NODE] [--relative-time]
       enact export FILE --foxglove OUT.mcap

One topic of a recording as a flat CSV table for analysis: log_time_ns, then every field of
the message (nested fields as a.b, repeated ones as a.0, a.1, ...), decoded with the schema
stored in the recording. --csv -: to standard output. --relative-time: the first column
is time_s, seconds from the first row, instead of log_time_ns.
--foxglove: a copy of the recording with one more channel, foxglove/scene
(foxglove.SceneUpdate: the bridge, the body's grid coloured by contact, the force arrow),
made from sim/scene and the scene file kept with the recording, so Foxglove's 3D panel
shows it (layout: docs/foxglove-layout.json).
)";

constexpr const char* kRecoverHelp = R"(usage: enact recover BROKEN.mcap -o FIXED.mcap [--compression zstd|lz4|none]

Rebuild a complete, indexed recording from everything readable in a damaged or unclosed one
(a logger killed with kill -9, a truncated copy, a corrupted chunk). Reports what was lost.
)";

std::string default_output() {
  char name[64];
  const std::time_t t = std::time(nullptr);
  std::strftime(name, sizeof name, "enact_%Y%m%d_%H%M%S.mcap", std::localtime(&t));
  return name;
}

// per channel: counts, time span and sequence gaps of a recording
struct ChannelStats {
  graph::SequenceCheck seq;
  std::int64_t first = 0, last = 0;
};

std::string human_bytes(std::uint64_t n) {
  char s[32];
  if (n >= 1'000'000) std::snprintf(s, sizeof s, "%.1f MB", static_cast<double>(n) * 1e-6);
  else if (n >= 1000) std::snprintf(s, sizeof s, "%.1f kB", static_cast<double>(n) * 1e-3);
  else std::snprintf(s, sizeof s, "%llu B", static_cast<unsigned long long>(n));
  return s;
}

// decoding with the schema stored in a recording
class Decoder {
 public:
  const google::protobuf::Message* prototype(const record::Schema& schema) {
    auto it = prototypes_.find(schema.id);
    if (it != prototypes_.end()) return it->second;
    const google::protobuf::Message* proto = nullptr;
    google::protobuf::FileDescriptorSet set;
    if (schema.encoding == "protobuf" && set.ParseFromString(schema.data)) {
      for (const auto& f : set.file()) pool_.BuildFile(f);
      if (const auto* d = pool_.FindMessageTypeByName(schema.name)) proto = factory_.GetPrototype(d);
    }
    prototypes_.emplace(schema.id, proto);
    return proto;
  }

 private:
  google::protobuf::DescriptorPool pool_;
  google::protobuf::DynamicMessageFactory factory_{&pool_};
  std::map<std::uint16_t, const google::protobuf::Message*> prototypes_;
};

// the leaves of a message as (column, value) in field order; repeated fields by index
void flatten(const google::protobuf::Message& m, const std::string& prefix, std::vector<std::pair<std::string, std::string>>& out) {
  using FD = google::protobuf::FieldDescriptor;
  const auto* r = m.GetReflection();
  const auto* d = m.GetDescriptor();
  for (int i = 0; i < d->field_count(); ++i) {
    const FD* f = d->field(i);
    const std::string name = prefix + f->name();
    const int n = f->is_repeated() ? r->FieldSize(m, f) : 1;
    for (int k = 0; k < n; ++k) {
      const std::string col = f->is_repeated() ? name + "." + std::to_string(k) : name;
      const bool rep = f->is_repeated();
      char v[64];
      switch (f->cpp_type()) {
        case FD::CPPTYPE_MESSAGE: flatten(rep ? r->GetRepeatedMessage(m, f, k) : r->GetMessage(m, f), col + ".", out); continue;
        case FD::CPPTYPE_DOUBLE: std::snprintf(v, sizeof v, "%.17g", rep ? r->GetRepeatedDouble(m, f, k) : r->GetDouble(m, f)); break;
        case FD::CPPTYPE_FLOAT: std::snprintf(v, sizeof v, "%.9g", static_cast<double>(rep ? r->GetRepeatedFloat(m, f, k) : r->GetFloat(m, f))); break;
        case FD::CPPTYPE_INT32: std::snprintf(v, sizeof v, "%d", rep ? r->GetRepeatedInt32(m, f, k) : r->GetInt32(m, f)); break;
        case FD::CPPTYPE_INT64: std::snprintf(v, sizeof v, "%" PRId64, rep ? r->GetRepeatedInt64(m, f, k) : r->GetInt64(m, f)); break;
        case FD::CPPTYPE_UINT32: std::snprintf(v, sizeof v, "%u", rep ? r->GetRepeatedUInt32(m, f, k) : r->GetUInt32(m, f)); break;
        case FD::CPPTYPE_UINT64: std::snprintf(v, sizeof v, "%" PRIu64, rep ? r->GetRepeatedUInt64(m, f, k) : r->GetUInt64(m, f)); break;
        case FD::CPPTYPE_BOOL: std::snprintf(v, sizeof v, "%d", (rep ? r->GetRepeatedBool(m, f, k) : r->GetBool(m, f)) ? 1 : 0); break;
        case FD::CPPTYPE_ENUM: std::snprintf(v, sizeof v, "%s", (rep ? r->GetRepeatedEnum(m, f, k) : r->GetEnum(m, f))->name().c_str()); break;
        case FD::CPPTYPE_STRING: {
          std::string s = rep ? r->GetRepeatedString(m, f, k) : r->GetString(m, f);
          if (f->type() == FD::TYPE_BYTES) s = std::to_string(s.size()) + " bytes";
          out.emplace_back(col, "\"" + s + "\"");
          continue;
        }
      }
      out.emplace_back(col, v);
    }
  }
}

// a recording started on a running graph: said, with where a replay can begin (resim, metrics)
void say_replay_start(const std::string& file) {
  record::Reader r(file);
  const auto& channels = r.channels();
  if (std::none_of(channels.begin(), channels.end(), [](const auto& c) { return c.second.topic == graph::kDeviceState; })) return;
  const graph::ReplayStart start = graph::replay_start(r);
  if (start.mid_run) std::printf("the recording %s\n", graph::describe(start).c_str());
}

}  // namespace

int record(int argc, char** argv) {
  std::vector<std::string> topics = take_list(argc, argv, "--topics");
  for (std::string& t : topics) t = topic_name(t);
  const Args a = parse(argc, argv, 2, {"out", "split-size", "split-duration", "compression", "chunk-duration", "graph", "attach", "duration", "wait", "regex", "exclude", "key", "server-key"}, {"all"});
  if (a.flag("help")) {
    std::fputs(kRecordHelp, stdout);
    std::fputs(kAttachOptionsHelp, stdout);
    return 0;
  }
  if (!a.positional.empty()) throw UsageError("unexpected argument '" + a.positional[0] + "' (the file goes after -o)");
  if (a.flag("all") && !topics.empty()) throw UsageError("give --all or --topics, not both");
  if (a.has("split-size") && a.has("split-duration")) throw UsageError("give --split-size or --split-duration, not both");
  graph::LoggerOptions o;
  o.output = a.get("out", default_output());
  o.topics = topics;
  o.regex = a.get("regex");
  o.exclude = a.get("exclude");
  try {
    o.writer.compression = record::parse_compression(a.get("compression", "zstd"));
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  o.writer.chunk_duration_ns = static_cast<std::int64_t>(a.number("chunk-duration", 1.0) * 1e9);
  o.split_size_mb = a.number("split-size", 0.0);
  o.split_duration_s = a.number("split-duration", 0.0);
  o.keys = attach_keys(a);
  const double duration_s = a.number("duration", 0.0);
  if (o.writer.chunk_duration_ns <= 0 || o.split_size_mb < 0 || o.split_duration_s < 0 || duration_s < 0) {
    throw UsageError("--chunk-duration must be > 0; sizes and durations >= 0");
  }
  graph::install_stop_handlers();
  const graph::GraphEntry target = attach_target(a, "record");
  o.attach = target.endpoint;
  graph::Logger logger(o);
  logger.attach();
  std::fprintf(stderr, "enact record: recording %s to %s (Ctrl-C stops)\n", topics.empty() ? "every topic" : "the topics given", logger.files().back().c_str());
  const std::int64_t end_ns = duration_s > 0 ? rt::now_ns() + static_cast<std::int64_t>(duration_s * 1e9) : INT64_MAX;
  const bool tty = isatty(2);
  logger.run([&] { return graph::stop_requested() || rt::now_ns() >= end_ns; },
             [&](const graph::LoggerProgress& p) { std::fprintf(stderr, tty ? "\r%s   " : "%s\n", graph::format(p).c_str()); });
  logger.close();
  if (tty) std::fputs("\n", stderr);
  // its attach point closed the connection: the graph stopped, or its launcher was killed
  if (logger.graph_gone()) {
    std::fprintf(stderr, "enact record: graph %s ended; file closed\n", (target.name.empty() ? target.endpoint : target.name).c_str());
  }
  std::string files;
  for (const auto& f : logger.files()) files += " " + f;
  std::printf("recorded%s\n%s", files.c_str(), graph::format(logger.report()).c_str());
  // out before the teardown: a socket still holding a long backlog may take the rest of the
  // stop's grace to close, and a buffered report would go with the process
  std::fflush(stdout);
  if (logger.write_failure().empty()) say_replay_start(logger.files().front());
  if (!logger.write_failure().empty()) {
    std::fprintf(stderr, "enact record: %s\n", graph::format_write_failure(logger).c_str());
    return 1;
  }
  return 0;
}

int info(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {}, {});
  if (a.flag("help")) {
    std::fputs(kInfoHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw UsageError("give exactly one recording");
  record::Reader r(a.positional[0]);
  std::map<std::uint16_t, ChannelStats> stats;
  std::uint64_t total = 0;
  std::int64_t first = INT64_MAX, last = 0;
  r.for_each([&](const record::Message& m) {
    ChannelStats& s = stats[m.channel->id];
    if (s.seq.messages == 0) s.first = m.log_time_ns;
    s.last = m.log_time_ns;
    s.seq.add(m.sequence);
    first = std::min(first, m.log_time_ns);
    last = std::max(last, m.log_time_ns);
    ++total;
    return true;
  });
  const double duration_s = total ? static_cast<double>(last - first) * 1e-9 : 0.0;
  std::printf("file        %s (%s, %s)\n", r.path().c_str(), human_bytes(r.size_bytes()).c_str(),
              r.complete() ? "complete" : "NOT closed: no summary");
  std::printf("written by  %s%s%s\n", r.library().c_str(), r.profile().empty() ? "" : ", profile ", r.profile().c_str());
  std::printf("duration    %.3f s\nmessages    %llu\n", duration_s, static_cast<unsigned long long>(total));
  std::printf("topics:\n  %-16s %-10s %-28s %10s %10s %8s\n", "topic", "publisher", "type", "messages", "rate Hz", "gaps");
  for (const auto& [id, s] : stats) {
    const record::Channel& c = r.channels().at(id);
    const auto schema = r.schemas().find(c.schema_id);
    const double span = static_cast<double>(s.last - s.first) * 1e-9;
    const auto pub = c.metadata.find("publisher");
    std::printf("  %-16s %-10s %-28s %10llu %10.1f %8llu%s\n", c.topic.c_str(), pub == c.metadata.end() ? "" : pub->second.c_str(),
                schema == r.schemas().end() ? "(no schema)" : schema->second.name.c_str(), static_cast<unsigned long long>(s.seq.messages),
                span > 0 ? static_cast<double>(s.seq.messages - 1) / span : 0.0, static_cast<unsigned long long>(s.seq.gaps),
                s.seq.restarts ? "  (publisher restarted)" : "");
  }
  if (!r.metadata_records().empty()) std::printf("metadata:\n");
  for (const auto& m : r.metadata_records()) {
    std::printf("  %s\n", m.name.c_str());
    for (const auto& [k, v] : m.values) {
      if (v.find('\n') == std::string::npos) std::printf("    %s = %s\n", k.c_str(), v.c_str());
      else std::printf("    %s = (%zu characters of text)\n", k.c_str(), v.size());
    }
  }
  if (!r.attachments().empty()) std::printf("attachments:\n");
  for (const auto& at : r.attachments()) std::printf("  %s (%s, %s)\n", at.name.c_str(), at.media_type.c_str(), human_bytes(at.data.size()).c_str());
  if (!r.damage().empty()) {
    std::printf("damage (everything readable before and around it is counted above):\n");
    for (const auto& d : r.damage()) std::printf("  %s\n", d.c_str());
    std::printf("  fix: enact recover %s -o FIXED.mcap\n", r.path().c_str());
    return 1;
  }
  return 0;
}

int export_csv(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {"topic", "csv", "publisher", "foxglove"}, {"relative-time"});
  if (a.flag("help")) {
    std::fputs(kExportHelp, stdout);
    return 0;
  }
  if (a.has("foxglove")) return export_foxglove(a);
  if (a.positional.size() != 1 || !a.has("topic") || !a.has("csv")) throw UsageError("give FILE, --topic T and --csv OUT.csv");
  const std::string topic = topic_name(a.get("topic")), publisher = a.get("publisher", "");
  record::Reader r(a.positional[0]);
  Decoder decoder;
  std::vector<std::string> columns;
  std::map<std::string, std::size_t> column_of;
  std::vector<std::vector<std::pair<std::string, std::string>>> rows;
  std::vector<std::int64_t> times;
  std::unique_ptr<google::protobuf::Message> msg;
  std::uint64_t undecodable = 0;
  // one pass: rows of (column, value); the columns are the union in first-seen order
  r.for_each([&](const record::Message& m) {
    if (m.topic != topic) return true;
    if (!publisher.empty() && m.channel->metadata.count("publisher") && m.channel->metadata.at("publisher") != publisher) return true;
    const google::protobuf::Message* proto = m.schema ? decoder.prototype(*m.schema) : nullptr;
    if (!proto) {
      ++undecodable;
      return true;
    }
    msg.reset(proto->New());
    if (!msg->ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      ++undecodable;
      return true;
    }
    rows.emplace_back();
    flatten(*msg, "", rows.back());
    times.push_back(m.log_time_ns);
    for (const auto& [col, v] : rows.back()) {
      if (column_of.emplace(col, columns.size()).second) columns.push_back(col);
    }
    return true;
  });
  if (rows.empty()) {
    std::string known;
    std::vector<std::string> names;
    for (const auto& [id, c] : r.channels()) known += (known.empty() ? "" : ", ") + c.topic, names.push_back(c.topic);
    throw config::Error(r.path() + ": no decodable message on topic '" + topic + "'" + config::did_you_mean(topic, names) + "\n  fix: choose among " + known);
  }
  // "-": standard output (the summary line then goes to standard error)
  const bool to_stdout = a.get("csv") == "-";
  std::ofstream file;
  if (!to_stdout) file.open(a.get("csv"));
  if (!to_stdout && !file) throw config::Error(a.get("csv") + ": cannot create the file\n  fix: check the folder exists and is writable");
  std::ostream& out = to_stdout ? std::cout : file;
  // --relative-time: seconds from the first row instead of the log time
  const bool relative = a.flag("relative-time");
  out << (relative ? "time_s" : "log_time_ns");
  for (const auto& c : columns) out << "," << c;
  out << "\n";
  std::vector<const std::string*> line(columns.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    std::fill(line.begin(), line.end(), nullptr);
    for (const auto& [col, v] : rows[i]) line[column_of[col]] = &v;
    if (relative) {
      char t[32];
      std::snprintf(t, sizeof t, "%.9f", static_cast<double>(times[i] - times[0]) * 1e-9);
      out << t;
    } else {
      out << times[i];
    }
    for (const std::string* v : line) out << "," << (v ? *v : "");
    out << "\n";
  }
  out.flush();
  std::fprintf(to_stdout ? stderr : stdout, "%zu rows x %zu columns of %s -> %s%s\n", rows.size(), columns.size() + 1, topic.c_str(), a.get("csv").c_str(),
              undecodable ? (" (" + std::to_string(undecodable) + " messages could not be decoded)").c_str() : "");
  for (const auto& d : r.damage()) std::fprintf(stderr, "enact export: %s: %s\n", r.path().c_str(), d.c_str());
  return 0;
}

int recover(int argc, char** argv) {
  const Args a = parse(argc, argv, 2, {"out", "compression"}, {});
  if (a.flag("help")) {
    std::fputs(kRecoverHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1 || !a.has("out")) throw UsageError("give BROKEN.mcap and -o FIXED.mcap");
  if (a.get("out") == a.positional[0]) throw UsageError("write the recovered file next to the broken one, not over it");
  record::WriterOptions wo;
  try {
    wo.compression = record::parse_compression(a.get("compression", "zstd"));
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  record::Reader r(a.positional[0]);
  record::Writer w(a.get("out"), wo);
  const CopyCount n = copy_recording(r, w);
  w.close();
  std::printf("recovered %llu messages on %zu channels, %zu metadata records, %zu attachments -> %s\n", static_cast<unsigned long long>(n.messages),
              n.channels, r.metadata_records().size(), r.attachments().size(), a.get("out").c_str());
  if (r.damage().empty()) std::printf("the source had no damage\n");
  for (const auto& d : r.damage()) std::printf("  lost or skipped at %s\n", d.c_str());
  return 0;
}

}  // namespace enact::cli
