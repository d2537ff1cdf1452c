// enact bench record: the MCAP writer's throughput next to raw file writes, and the
// logger's headroom over a bridge graph's traffic.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/bus/attach.h"
#include "core/bus/endpoints.h"
#include "core/bus/typed.h"
#include "core/record/logger.h"
#include "core/graph/temp_folder.h"
#include "core/record/writer.h"
#include "core/rt/clock.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "nodes/enact/commands.h"
#include "nodes/enact/json.h"

namespace enact::cli {
namespace {

constexpr const char* kBenchRecordHelp = R"(usage: enact bench record [--json FILE] [--messages N] [--dir DIR]

1. Writer throughput, side by side in one run: N messages of 100 bytes written as MCAP with
   zstd, lz4 and no compression, and the same payload bytes written raw to a file (the
   floor), each 5 times interleaved; medians of messages/s and MB/s (of payload), and each
   one's ratio to the raw write.
2. Logger headroom: a publisher sends bridge-graph traffic (ffd/state + ffd/force, 5 kHz
   each, about 10,000 messages/s in all) at 10x its rate for 3 s through an attach point
   to the logger: gaps must be 0. Then as fast as it can: the logger's maximum rate.
JSON keys: msgs_per_s_lz4, msgs_per_s_zstd, msgs_per_s_none, msgs_per_s_raw,
ratio_vs_raw_write (lz4; and ratio_vs_raw_write_zstd, _none), logger_msgs_per_s_at_10x,
logger_gaps_at_10x, logger_lost_at_10x, logger_max_msgs_per_s, logger_headroom (max / bridge traffic).

options:
  --messages N   messages per writer run (default 2000000)
  --dir DIR      where the files go (default: a temporary folder, removed)
)";

constexpr std::size_t kPayload = 100;
constexpr double kBridgeMsgsPerS = 10'000.0;  // ffd/state + ffd/force at 5 kHz; the rest is < 5 %

// a payload that compresses like real messages: a counter and slowly varying numbers
void fill_payload(std::string& p, std::uint64_t i) {
  p.assign(kPayload, '\0');
  for (std::size_t k = 0; k < kPayload; k += 8) {
    const std::uint64_t v = (i + k) * 0x9E3779B97F4A7C15ull >> (k % 48);
    std::memcpy(&p[k], &v, std::min<std::size_t>(8, kPayload - k));
  }
}

double seconds_since(std::int64_t t0) { return static_cast<double>(rt::now_ns() - t0) * 1e-9; }

// seconds to write n messages as MCAP
double write_mcap(const std::string& path, record::Compression c, std::uint64_t n) {
  record::WriterOptions o;
  o.compression = c;
  std::string p;
  const std::int64_t t0 = rt::now_ns();
  {
    record::Writer w(path, o);
    const auto ch = w.add_channel(w.add_schema("bench.Payload", "protobuf", ""), "bench", "protobuf");
    for (std::uint64_t i = 0; i < n; ++i) {
      fill_payload(p, i);
      w.write(ch, static_cast<std::uint32_t>(i), static_cast<std::int64_t>(i) * 20'000, static_cast<std::int64_t>(i) * 20'000, p);
    }
    w.close();
  }
  return seconds_since(t0);
}

// seconds to write the same payload bytes raw, in 1 MiB blocks
double write_raw(const std::string& path, std::uint64_t n) {
  std::string p, block;
  const std::int64_t t0 = rt::now_ns();
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  bool ok = fd >= 0;
  for (std::uint64_t i = 0; i < n && ok; ++i) {
    fill_payload(p, i);
    block += p;
    if (block.size() >= (1u << 20) || i + 1 == n) {
      ok = ::write(fd, block.data(), block.size()) == static_cast<ssize_t>(block.size());
      block.clear();
    }
  }
  if (fd >= 0) ::close(fd);
  if (!ok) throw std::runtime_error(path + ": cannot write the raw file");
  return seconds_since(t0);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct LoggerRun {
  double msgs_per_s = 0.0;
  std::uint64_t messages = 0, gaps = 0, sent = 0;  // gaps: by header.seq (a refused, retried send also skips one)
};

// a publisher sends ffd/state and ffd/force (alternating) at `rate` messages/s (0: as fast
// as it can) for `seconds` through an attach point; the logger records them
LoggerRun run_logger(const std::string& dir, double rate, double seconds, int index) {
  const std::string endpoint = bus::ipc_endpoint(dir, "bench" + std::to_string(index));
  bus::BytePublisher out(endpoint, {.node = "ffd", .send_hwm = 100000, .refuse_when_full = true});
  bus::Publisher<msgs::DeviceState> states(out, "ffd/state");
  bus::Publisher<msgs::ForceCommand> forces(out, "ffd/force");
  bus::AttachPoint attach("bench");
  attach.add_publisher("ffd", endpoint);
  attach.declare_topic<msgs::DeviceState>("ffd/state", "ffd");
  attach.declare_topic<msgs::ForceCommand>("ffd/force", "ffd");
  graph::LoggerOptions o;
  o.attach = attach.endpoint();
  o.output = dir + "/logger" + std::to_string(index) + ".mcap";
  o.writer.compression = record::Compression::zstd;
  graph::Logger logger(o);
  logger.attach();
  while (out.subscriber_count("ffd/state") < 1 || out.subscriber_count("ffd/force") < 1) rt::sleep_until_ns(rt::now_ns() + 1'000'000);
  std::atomic<bool> done{false};
  std::thread recorder([&] { logger.run([&] { return done.load(); }); });
  msgs::DeviceState s;
  msgs::ForceCommand f;
  LoggerRun r;
  const std::int64_t t0 = rt::now_ns(), end = t0 + static_cast<std::int64_t>(seconds * 1e9);
  const double period_ns = rate > 0 ? 1e9 / rate : 0.0;
  while (rt::now_ns() < end) {
    if (period_ns > 0) rt::sleep_until_ns(t0 + static_cast<std::int64_t>(static_cast<double>(r.sent) * period_ns));
    s.mutable_position()->set_x(static_cast<double>(r.sent));
    // a full queue waits (flow control): what the publisher counts as sent, the logger must get
    while (!((r.sent % 2 == 0) ? states.publish(s) : forces.publish(f))) rt::sleep_until_ns(rt::now_ns() + 20'000);
    ++r.sent;
  }
  const double sent_s = seconds_since(t0);
  // the logger catches up (or gives up after 10 s)
  const std::int64_t give_up = rt::now_ns() + 10'000'000'000;
  while (logger.messages() < r.sent && rt::now_ns() < give_up) rt::sleep_until_ns(rt::now_ns() + 1'000'000);
  const double total_s = seconds_since(t0);
  done.store(true);
  recorder.join();
  logger.close();
  r.messages = logger.messages();
  for (const auto& c : logger.report()) r.gaps += c.seq.gaps;
  r.msgs_per_s = static_cast<double>(r.messages) / std::max(sent_s, total_s);
  return r;
}

}  // namespace

int bench_record(int argc, char** argv) {
  const Args a = parse(argc, argv, 3, {"json", "messages", "dir"}, {});
  if (a.flag("help")) {
    std::fputs(kBenchRecordHelp, stdout);
    return 0;
  }
  const auto n = static_cast<std::uint64_t>(a.number("messages", 2e6));
  if (n < 1000) throw UsageError("--messages must be >= 1000");
  // the files go to --dir, else to a temporary folder removed at the end
  std::optional<graph::TempFolder> temporary;
  if (!a.has("dir")) temporary.emplace((std::filesystem::temp_directory_path() / "enact-bench-").string());
  const std::string dir = temporary ? temporary->path() : a.get("dir");
  // 1. writer: the four cases interleaved, 5 times
  const char* names[4] = {"zstd", "lz4", "none", "raw"};
  std::vector<double> secs[4];
  for (int rep = 0; rep < 5; ++rep) {
    std::fprintf(stderr, "\rwriter: run %d of 5 ...", rep + 1);
    secs[0].push_back(write_mcap(dir + "/w.mcap", record::Compression::zstd, n));
    secs[1].push_back(write_mcap(dir + "/w.mcap", record::Compression::lz4, n));
    secs[2].push_back(write_mcap(dir + "/w.mcap", record::Compression::none, n));
    secs[3].push_back(write_raw(dir + "/w.raw", n));
  }
  std::fprintf(stderr, "\n");
  double rate[4];
  for (int k = 0; k < 4; ++k) rate[k] = static_cast<double>(n) / median(secs[k]);
  std::printf("writer: %llu messages of %zu bytes, median of 5 interleaved runs (payload MB/s)\n", static_cast<unsigned long long>(n), kPayload);
  std::printf("  %-6s %14s %10s %14s\n", "", "messages/s", "MB/s", "ratio vs raw");
  for (int k = 0; k < 4; ++k) {
    std::printf("  %-6s %14.0f %10.1f %14.3f\n", names[k], rate[k], rate[k] * kPayload * 1e-6, rate[k] / rate[3]);
  }
  // 2. the logger at 10x the bridge graph's traffic, then flat out
  std::fprintf(stderr, "logger: 3 s at 10x the bridge traffic, then 3 s flat out ...\n");
  const LoggerRun at10 = run_logger(dir, 10.0 * kBridgeMsgsPerS, 3.0, 0);
  const LoggerRun flat = run_logger(dir, 0.0, 3.0, 1);
  std::printf("logger (zstd, through an attach point):\n");
  std::printf("  at 10x the bridge traffic (%.0f messages/s offered): %.0f messages/s kept, %llu of %llu (lost %llu), sequence gaps %llu\n",
              10 * kBridgeMsgsPerS, at10.msgs_per_s, static_cast<unsigned long long>(at10.messages), static_cast<unsigned long long>(at10.sent),
              static_cast<unsigned long long>(at10.sent - at10.messages), static_cast<unsigned long long>(at10.gaps));
  std::printf("  flat out: %.0f messages/s kept, %llu of %llu (lost %llu at the attach point: past capacity): %.1fx the bridge traffic\n",
              flat.msgs_per_s, static_cast<unsigned long long>(flat.messages), static_cast<unsigned long long>(flat.sent),
              static_cast<unsigned long long>(flat.sent - flat.messages), flat.msgs_per_s / kBridgeMsgsPerS);
  std::printf("machine: %u cores; files in %s\n", std::thread::hardware_concurrency(), dir.c_str());
  if (a.has("json")) {
    Json j;
    j.begin_object();
    j.field("messages", static_cast<long long>(n)).field("message_bytes", static_cast<long long>(kPayload));
    j.field("msgs_per_s_zstd", rate[0]).field("msgs_per_s_lz4", rate[1]).field("msgs_per_s_none", rate[2]).field("msgs_per_s_raw", rate[3]);
    j.field("mb_per_s_zstd", rate[0] * kPayload * 1e-6).field("mb_per_s_lz4", rate[1] * kPayload * 1e-6);
    j.field("mb_per_s_none", rate[2] * kPayload * 1e-6).field("mb_per_s_raw", rate[3] * kPayload * 1e-6);
    j.field("ratio_vs_raw_write", rate[1] / rate[3]).field("ratio_vs_raw_write_zstd", rate[0] / rate[3]).field("ratio_vs_raw_write_none", rate[2] / rate[3]);
    j.field("bridge_msgs_per_s", kBridgeMsgsPerS);
    j.field("logger_msgs_per_s_at_10x", at10.msgs_per_s).field("logger_gaps_at_10x", static_cast<long long>(at10.gaps));
    j.field("logger_max_msgs_per_s", flat.msgs_per_s).field("logger_headroom", flat.msgs_per_s / kBridgeMsgsPerS);
    j.field("cores", static_cast<int>(std::thread::hardware_concurrency()));
    j.end_object();
    std::ofstream(a.get("json")) << j.str() << "\n";
  }
  return 0;
}

}  // namespace enact::cli
