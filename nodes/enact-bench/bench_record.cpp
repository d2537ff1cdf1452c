// enact bench record: the MCAP writer's throughput next to raw file writes, and the
// logger's headroom over a bridge graph's traffic.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/bus/attach.h"
#include "core/bus/client.h"
#include "core/bus/endpoints.h"
#include "core/bus/typed.h"
#include "core/record/compression.h"
#include "core/record/logger.h"
#include "core/record/mcap.h"
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
   machine's floor), each 5 times interleaved; medians and ranges (min..max) of messages/s
   and MB/s (of payload), and of each one's ratio to the raw write of the same round.
   A compressing writer's other floor, in the same rounds: its CPU work alone, no file,
   spread over every CPU: the messages made into the chunks' records on one thread (the
   writer's own thread's work), and the same chunks compressed in memory on one thread per
   CPU (as the writer's workers). It can be no faster than the slower of that and the raw
   write. Before each case's clock: the last file removed, what earlier cases left dirty
   written out. The machine line says whether freed memory goes back to a host (a VM's
   free page reporting), which makes the cases that take new pages vary.
2. Logger headroom, 3 times each: a publisher sends bridge-graph traffic (ffd/state +
   ffd/force, 5 kHz each, about 10,000 messages/s in all) at 10x its rate for 3 s through an
   attach point to the logger: none may be lost. Then as fast as it can for 3 s: the logger's
   rate is what it kept over the time to its last message (messages the attach point dropped
   past capacity are counted as lost, not waited for); median and range. The floor beside it:
   the same, with a subscriber that only counts in the logger's place (what the publisher and
   the attach point deliver on this machine). And alone: the publisher sends for 1 s with the
   logger stopped, then the logger takes the backlog.
JSON keys (medians): msgs_per_s_lz4, msgs_per_s_zstd, msgs_per_s_none, msgs_per_s_raw,
ratio_vs_raw_write (lz4; and ratio_vs_raw_write_zstd, _none; each with _min and _max),
mb_per_s_compress_zstd, mb_per_s_compress_lz4, mb_per_s_make_records, ratio_vs_floor (lz4;
and ratio_vs_floor_zstd, _none; each with _min and _max: the writer against the slower of
its two floors),
logger_msgs_per_s_at_10x, logger_gaps_at_10x, logger_lost_at_10x, logger_max_msgs_per_s
(with _min and _max), logger_floor_msgs_per_s and logger_max_ratio_to_floor (each with _min
and _max), logger_lost_flat_out, logger_headroom (max / bridge traffic),
logger_alone_msgs_per_s (with _min and _max), logger_lost_alone, free_page_reporting.

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

// the last round's file removed before the clock starts: giving its pages back is no cost of
// this case's (the zstd case truncated the none case's 294 MB file, inside its time); and the
// pages the cases before left dirty written out (syncfs), so that no case is timed while the
// kernel's writeback of another's takes one of the CPUs
void remove_before_timing(const std::string& path) {
  std::filesystem::remove(path);
  const int dir = ::open(std::filesystem::path(path).parent_path().c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::syncfs(dir);
    ::close(dir);
  }
}

// What this machine does with memory freed: a VM whose balloon reports free pages to its host
// hands them back within seconds, and the next touch of such a page faults in the host (on
// the 2-vCPU Firecracker VM of docs/performance.md a first touch of 1 GiB took 1410 ms against
// 320 ms for memory freed moments before, and the uncompressed writer, the case that takes
// the most new pages, ran at 0.51-0.57 of the raw write with reporting on, 0.91 with it off:
// medians of 3 runs).

// the order of the free pages reported to a host; -1: none (not a VM that reports them)
int page_reporting_order() {
  std::ifstream order("/sys/module/page_reporting/parameters/page_reporting_order");
  int o = -1;
  return order >> o ? o : -1;
}

// whether pages of `order` are reported: above the largest order the buddy allocator has
// (10), nothing ever is
bool pages_reported(int order) { return order >= 0 && order <= 10; }

std::string page_reporting_text(int o) {
  if (o < 0) return "no free page reporting to a host";
  if (!pages_reported(o)) return "free page reporting to the host off (order " + std::to_string(o) + ")";
  return "free page reporting to the host ON (order " + std::to_string(o) +
         "): the cases that take new pages vary with the host's faults (off, as root: echo 11 > "
         "/sys/module/page_reporting/parameters/page_reporting_order)";
}

// seconds to write n messages as MCAP
double write_mcap(const std::string& path, record::Compression c, std::uint64_t n) {
  record::WriterOptions o;
  o.compression = c;
  std::string p;
  remove_before_timing(path);
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
  remove_before_timing(path);
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

// the messages as the writer's chunks hold them: Message records in `chunk` (its room kept),
// handed to `full` each time it reaches a chunk's size, and at the end
template <class Full>
void make_records(std::uint64_t n, Full full) {
  const std::size_t chunk_bytes = record::WriterOptions{}.chunk_size_bytes;
  std::string chunk, p;
  chunk.reserve(chunk_bytes + record::message_record_size(kPayload));
  for (std::uint64_t i = 0; i < n; ++i) {
    fill_payload(p, i);
    const auto t = static_cast<std::uint64_t>(i) * 20'000;
    const std::size_t at = chunk.size();
    chunk.resize(at + record::message_record_size(p.size()));
    record::put_message(chunk.data() + at, 0, static_cast<std::uint32_t>(i), t, t, p);
    if (chunk.size() >= chunk_bytes || i + 1 == n) {
      full(chunk);
      chunk.clear();
    }
  }
}

// the chunks, made once, outside any clock
std::vector<std::string> message_chunks(std::uint64_t n) {
  std::vector<std::string> chunks;
  make_records(n, [&](const std::string& chunk) { chunks.push_back(chunk); });
  return chunks;
}

// the work of the writer's own thread, timed: seconds to make the messages and their
// records, chunk after chunk in one buffer, on one thread
double make_only(std::uint64_t n) {
  std::uint64_t bytes = 0;
  const std::int64_t t0 = rt::now_ns();
  make_records(n, [&](const std::string& chunk) { bytes += static_cast<unsigned char>(chunk[chunk.size() / 2]); });
  const double secs = seconds_since(t0);
  if (bytes == 1) std::fputs("", stderr);  // uses the records: the compiler keeps their making
  return secs;
}

// the compressing writers' other work: seconds to compress `chunks` in memory, no file, on
// `threads` threads (as many as the writer has workers) each with the writer's own compressor
double compress_only(const std::vector<std::string>& chunks, record::Compression c, unsigned threads) {
  const std::int64_t t0 = rt::now_ns();
  std::vector<std::thread> pool;
  for (unsigned k = 0; k < threads; ++k) {
    pool.emplace_back([&chunks, c, k, threads] {
      record::Compressor z(c);
      for (std::size_t i = k; i < chunks.size(); i += threads) z.compress(chunks[i]);
    });
  }
  for (std::thread& t : pool) t.join();
  return seconds_since(t0);
}

// the median and the range of some runs' figures
struct Spread {
  double median = 0.0, min = 0.0, max = 0.0;
  explicit Spread(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    median = v[v.size() / 2];
    min = v.front();
    max = v.back();
  }
};

// "1.23 (1.10..1.30)", each figure times `scale`
std::string spread_text(const Spread& s, double scale, const char* format) {
  char text[96], number[3][24];
  for (int k = 0; k < 3; ++k) std::snprintf(number[k], sizeof number[k], format, (k == 0 ? s.median : k == 1 ? s.min : s.max) * scale);
  std::snprintf(text, sizeof text, "%s (%s..%s)", number[0], number[1], number[2]);
  return text;
}

struct LoggerRun {
  double msgs_per_s = 0.0;
  std::uint64_t messages = 0, gaps = 0, sent = 0;  // gaps: by header.seq (a refused, retried send also skips one)
};

// what takes the messages at the attach point: the logger, or (the machine's floor) a bare
// subscriber that only counts them
class Sink {
 public:
  virtual ~Sink() = default;
  virtual void run(const std::atomic<bool>& done) = 0;  // on its own thread
  virtual std::uint64_t messages() const = 0;            // any thread
  virtual std::uint64_t gaps() const { return 0; }       // after run
};

class LoggerSink final : public Sink {
 public:
  LoggerSink(const std::string& attach, const std::string& file) {
    graph::LoggerOptions o;
    o.attach = attach;
    o.output = file;
    o.writer.compression = record::Compression::zstd;
    logger_.emplace(o);
    logger_->attach();
  }
  void run(const std::atomic<bool>& done) override {
    logger_->run([&] { return done.load(); });
    logger_->close();
    for (const auto& c : logger_->report()) gaps_ += c.seq.gaps;
  }
  std::uint64_t messages() const override { return logger_->messages(); }
  std::uint64_t gaps() const override { return gaps_; }

 private:
  std::optional<graph::Logger> logger_;
  std::uint64_t gaps_ = 0;
};

class CountingSink final : public Sink {
 public:
  explicit CountingSink(const std::string& attach) {
    bus::attach_connect(sub_.socket(), attach, {});
    sub_.subscribe("ffd/state");
    sub_.subscribe("ffd/force");
  }
  void run(const std::atomic<bool>& done) override {
    bus::RawMessage m;
    while (!done.load()) {
      for (int i = 0; i < 10000 && sub_.receive(m, i == 0 ? 50 : 0); ++i) count_.fetch_add(1, std::memory_order_relaxed);
    }
  }
  std::uint64_t messages() const override { return count_.load(std::memory_order_relaxed); }

 private:
  bus::ByteSubscriber sub_;
  std::atomic<std::uint64_t> count_{0};
};

// a publisher sends ffd/state and ffd/force (alternating) at `rate` messages/s (0: as fast
// as it can) for `seconds` through an attach point; the logger (or, `floor`, a subscriber
// that only counts) takes them. `backlog`: the logger starts once the publisher is done and
// its messages wait in the queues (a second later): its own rate, with no publisher beside
// it on the CPUs
LoggerRun run_logger(const std::string& dir, double rate, double seconds, int index, bool backlog = false, bool floor = false) {
  const std::string endpoint = bus::ipc_endpoint(dir, "bench" + std::to_string(index));
  bus::BytePublisher out(endpoint, {.node = "ffd", .send_hwm = 100000, .refuse_when_full = true});
  bus::Publisher<msgs::DeviceState> states(out, "ffd/state");
  bus::Publisher<msgs::ForceCommand> forces(out, "ffd/force");
  bus::AttachPoint attach("bench");
  attach.add_publisher("ffd", endpoint);
  attach.declare_topic<msgs::DeviceState>("ffd/state", "ffd");
  attach.declare_topic<msgs::ForceCommand>("ffd/force", "ffd");
  std::unique_ptr<Sink> sink;
  if (floor) sink = std::make_unique<CountingSink>(attach.endpoint());
  else sink = std::make_unique<LoggerSink>(attach.endpoint(), dir + "/logger" + std::to_string(index) + ".mcap");
  while (out.subscriber_count("ffd/state") < 1 || out.subscriber_count("ffd/force") < 1) rt::sleep_until_ns(rt::now_ns() + 1'000'000);
  std::atomic<bool> done{false};
  std::thread taker;
  const auto start_taking = [&] { taker = std::thread([&] { sink->run(done); }); };
  if (!backlog) start_taking();
  msgs::DeviceState s;
  msgs::ForceCommand f;
  LoggerRun r;
  const std::int64_t t0 = rt::now_ns(), end = t0 + static_cast<std::int64_t>(seconds * 1e9);
  const double period_ns = rate > 0 ? 1e9 / rate : 0.0;
  while (rt::now_ns() < end) {
    // paced: a sleep only when ahead (on a VM even a sleep already due costs a timer's tens of
    // microseconds: one per message held the 10x publisher near 35 000 messages/s)
    const std::int64_t due = t0 + static_cast<std::int64_t>(static_cast<double>(r.sent) * period_ns);
    if (period_ns > 0 && due > rt::now_ns()) rt::sleep_until_ns(due);
    s.mutable_position()->set_x(static_cast<double>(r.sent));
    // a full queue waits (flow control): what the publisher counts as sent, the logger must get
    while (!((r.sent % 2 == 0) ? states.publish(s) : forces.publish(f))) rt::sleep_until_ns(rt::now_ns() + 20'000);
    ++r.sent;
  }
  double sent_s = seconds_since(t0);
  std::int64_t from_ns = t0;
  if (backlog) {
    rt::sleep_until_ns(rt::now_ns() + 1'000'000'000);
    sent_s = 0.0;
    from_ns = rt::now_ns();
    start_taking();
  }
  // the taker takes what is on its way; what the attach point dropped never comes: it is
  // done with all of them, or once nothing came for half a second (waiting longer for the
  // lost ones made a run that lost a few look 4x slower: 214 k against 900 k messages/s)
  std::uint64_t kept = sink->messages();
  std::int64_t last_ns = rt::now_ns();
  while (kept < r.sent && rt::now_ns() - last_ns < 500'000'000) {
    rt::sleep_until_ns(rt::now_ns() + 1'000'000);
    if (sink->messages() != kept) {
      kept = sink->messages();
      last_ns = rt::now_ns();
    }
  }
  const double kept_s = static_cast<double>(last_ns - from_ns) * 1e-9;
  done.store(true);
  taker.join();
  r.messages = sink->messages();
  r.gaps = sink->gaps();
  r.msgs_per_s = static_cast<double>(r.messages) / std::max(sent_s, kept_s);
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
  // 1. writer: the four cases interleaved, 5 times; each one's ratio to the raw write of its
  // round, and to its floor: the slower of the raw write and (lz4, zstd) its CPU work alone,
  // spread over every CPU: making the records (one thread) and compressing them, no file,
  // timed in the same round
  const char* names[4] = {"zstd", "lz4", "none", "raw"};
  const std::vector<std::string> chunks = message_chunks(n);
  // the writer's workers: one per CPU
  const unsigned cpus = std::clamp(std::thread::hardware_concurrency(), 1u, record::kMaxWorkers);
  const int reporting_order = page_reporting_order();
  std::vector<double> rates[4], ratios[4], compress_rates[2], make_rates, writer_floor_ratios[3];
  for (int rep = 0; rep < 5; ++rep) {
    std::fprintf(stderr, "\rwriter: run %d of 5 ...", rep + 1);
    double secs[4];
    secs[0] = write_mcap(dir + "/w.mcap", record::Compression::zstd, n);
    secs[1] = write_mcap(dir + "/w.mcap", record::Compression::lz4, n);
    secs[2] = write_mcap(dir + "/w.mcap", record::Compression::none, n);
    secs[3] = write_raw(dir + "/w.raw", n);
    const double compress_secs[2] = {compress_only(chunks, record::Compression::zstd, cpus), compress_only(chunks, record::Compression::lz4, cpus)};
    const double make_secs = make_only(n);
    make_rates.push_back(static_cast<double>(n) / make_secs);
    for (int k = 0; k < 4; ++k) {
      rates[k].push_back(static_cast<double>(n) / secs[k]);
      ratios[k].push_back(secs[3] / secs[k]);
    }
    for (int k = 0; k < 3; ++k) {
      // the CPU work of a compressing writer on `cpus` CPUs at best: the records made on one
      // (make_secs of one CPU) and compressed on all (compress_secs of each)
      const double floor_secs = k < 2 ? std::max(secs[3], make_secs / cpus + compress_secs[k]) : secs[3];
      if (k < 2) compress_rates[k].push_back(static_cast<double>(n) / compress_secs[k]);
      writer_floor_ratios[k].push_back(floor_secs / secs[k]);
    }
  }
  std::fprintf(stderr, "\n");
  std::vector<Spread> rate, ratio, compress_rate, writer_floor_ratio;
  for (int k = 0; k < 4; ++k) {
    rate.emplace_back(rates[k]);
    ratio.emplace_back(ratios[k]);
  }
  for (int k = 0; k < 3; ++k) writer_floor_ratio.emplace_back(writer_floor_ratios[k]);
  for (int k = 0; k < 2; ++k) compress_rate.emplace_back(compress_rates[k]);
  const Spread make_rate(make_rates);
  std::printf("writer: %llu messages of %zu bytes, 5 interleaved runs: median (min..max)\n", static_cast<unsigned long long>(n), kPayload);
  std::printf("  %-5s %-26s %-24s %s\n", "", "messages/s (M)", "MB/s of payload", "ratio to the raw write of its run");
  for (int k = 0; k < 4; ++k) {
    std::printf("  %-5s %-26s %-24s %s\n", names[k], spread_text(rate[k], 1e-6, "%.2f").c_str(), spread_text(rate[k], kPayload * 1e-6, "%.0f").c_str(),
                k == 3 ? "1 (the machine's floor)" : spread_text(ratio[k], 1.0, "%.3f").c_str());
  }
  std::printf("  compressing the same chunks on %u threads, no file (MB/s of payload): zstd %s, lz4 %s\n", cpus,
              spread_text(compress_rate[0], kPayload * 1e-6, "%.0f").c_str(), spread_text(compress_rate[1], kPayload * 1e-6, "%.0f").c_str());
  std::printf("  making the messages' records on one thread, no file (MB/s of payload): %s\n", spread_text(make_rate, kPayload * 1e-6, "%.0f").c_str());
  std::printf("  each writer against its floor (the slower of the raw write and, compressed, its CPU work alone on %u CPUs): zstd %s, lz4 %s, none %s\n", cpus,
              spread_text(writer_floor_ratio[0], 1.0, "%.3f").c_str(), spread_text(writer_floor_ratio[1], 1.0, "%.3f").c_str(), spread_text(writer_floor_ratio[2], 1.0, "%.3f").c_str());
  // 2. the logger at 10x the bridge graph's traffic, then flat out, 3 times each
  std::fprintf(stderr, "logger: 3 s at 10x the bridge traffic, 3 s flat out, the floor flat out, a backlog alone; 3 times ...\n");
  std::vector<double> at10_rates, flat_rates, floor_rates, floor_ratios, backlog_rates;
  std::uint64_t at10_sent = 0, at10_kept = 0, at10_gaps = 0, flat_sent = 0, flat_kept = 0, backlog_sent = 0, backlog_kept = 0;
  for (int rep = 0; rep < 3; ++rep) {
    const LoggerRun at10 = run_logger(dir, 10.0 * kBridgeMsgsPerS, 3.0, 4 * rep);
    const LoggerRun flat = run_logger(dir, 0.0, 3.0, 4 * rep + 1);
    const LoggerRun bare = run_logger(dir, 0.0, 3.0, 4 * rep + 2, false, true);
    const LoggerRun backlog = run_logger(dir, 0.0, 1.0, 4 * rep + 3, true);
    floor_rates.push_back(bare.msgs_per_s);
    floor_ratios.push_back(flat.msgs_per_s / bare.msgs_per_s);
    at10_rates.push_back(at10.msgs_per_s);
    flat_rates.push_back(flat.msgs_per_s);
    backlog_rates.push_back(backlog.msgs_per_s);
    backlog_sent += backlog.sent;
    backlog_kept += backlog.messages;
    at10_sent += at10.sent;
    at10_kept += at10.messages;
    at10_gaps += at10.gaps;
    flat_sent += flat.sent;
    flat_kept += flat.messages;
  }
  const Spread at10(at10_rates), flat(flat_rates), floor(floor_rates), floor_ratio(floor_ratios), alone(backlog_rates);
  std::printf("logger (zstd, through an attach point), 3 runs each: median (min..max)\n");
  std::printf("  at 10x the bridge traffic (%.0f messages/s offered): %s k messages/s kept, %llu of %llu (lost %llu), sequence gaps %llu\n",
              10 * kBridgeMsgsPerS, spread_text(at10, 1e-3, "%.1f").c_str(), static_cast<unsigned long long>(at10_kept),
              static_cast<unsigned long long>(at10_sent), static_cast<unsigned long long>(at10_sent - at10_kept), static_cast<unsigned long long>(at10_gaps));
  std::printf("  flat out: %s k messages/s kept (%.0fx the bridge traffic), %llu of %llu (lost %llu at the attach point: past capacity)\n",
              spread_text(flat, 1e-3, "%.0f").c_str(), flat.median / kBridgeMsgsPerS, static_cast<unsigned long long>(flat_kept),
              static_cast<unsigned long long>(flat_sent), static_cast<unsigned long long>(flat_sent - flat_kept));
  std::printf("  the floor: a subscriber that only counts, flat out at the same attach point: %s k messages/s; the logger's ratio to it %s\n",
              spread_text(floor, 1e-3, "%.0f").c_str(), spread_text(floor_ratio, 1.0, "%.3f").c_str());
  std::printf("  alone, through a backlog (1 s flat out, then the logger): %s k messages/s kept, %llu of %llu (lost %llu)\n",
              spread_text(alone, 1e-3, "%.0f").c_str(), static_cast<unsigned long long>(backlog_kept), static_cast<unsigned long long>(backlog_sent),
              static_cast<unsigned long long>(backlog_sent - backlog_kept));
  std::printf("machine: %u cores; %s; files in %s\n", std::thread::hardware_concurrency(), page_reporting_text(reporting_order).c_str(), dir.c_str());
  if (a.has("json")) {
    Json j;
    j.begin_object();
    j.field("messages", static_cast<long long>(n)).field("message_bytes", static_cast<long long>(kPayload));
    const char* keys[4] = {"zstd", "lz4", "none", "raw"};
    for (int k = 0; k < 4; ++k) {
      j.field(std::string("msgs_per_s_") + keys[k], rate[k].median).field(std::string("mb_per_s_") + keys[k], rate[k].median * kPayload * 1e-6);
      j.field(std::string("mb_per_s_") + keys[k] + "_min", rate[k].min * kPayload * 1e-6).field(std::string("mb_per_s_") + keys[k] + "_max", rate[k].max * kPayload * 1e-6);
    }
    const std::pair<const char*, int> ratio_keys[3] = {{"ratio_vs_raw_write", 1}, {"ratio_vs_raw_write_zstd", 0}, {"ratio_vs_raw_write_none", 2}};
    for (const auto& [key, k] : ratio_keys) {
      j.field(key, ratio[k].median).field(std::string(key) + "_min", ratio[k].min).field(std::string(key) + "_max", ratio[k].max);
    }
    j.field("mb_per_s_compress_zstd", compress_rate[0].median * kPayload * 1e-6).field("mb_per_s_compress_lz4", compress_rate[1].median * kPayload * 1e-6);
    j.field("mb_per_s_make_records", make_rate.median * kPayload * 1e-6);
    const std::pair<const char*, int> floor_keys[3] = {{"ratio_vs_floor", 1}, {"ratio_vs_floor_zstd", 0}, {"ratio_vs_floor_none", 2}};
    for (const auto& [key, k] : floor_keys) {
      j.field(key, writer_floor_ratio[k].median).field(std::string(key) + "_min", writer_floor_ratio[k].min).field(std::string(key) + "_max", writer_floor_ratio[k].max);
    }
    j.field("bridge_msgs_per_s", kBridgeMsgsPerS);
    j.field("logger_msgs_per_s_at_10x", at10.median).field("logger_gaps_at_10x", static_cast<long long>(at10_gaps));
    j.field("logger_lost_at_10x", static_cast<long long>(at10_sent - at10_kept));
    j.field("logger_max_msgs_per_s", flat.median).field("logger_max_msgs_per_s_min", flat.min).field("logger_max_msgs_per_s_max", flat.max);
    j.field("logger_floor_msgs_per_s", floor.median).field("logger_floor_msgs_per_s_min", floor.min).field("logger_floor_msgs_per_s_max", floor.max);
    j.field("logger_max_ratio_to_floor", floor_ratio.median).field("logger_max_ratio_to_floor_min", floor_ratio.min).field("logger_max_ratio_to_floor_max", floor_ratio.max);
    j.field("logger_lost_flat_out", static_cast<long long>(flat_sent - flat_kept)).field("logger_headroom", flat.median / kBridgeMsgsPerS);
    j.field("logger_alone_msgs_per_s", alone.median).field("logger_alone_msgs_per_s_min", alone.min).field("logger_alone_msgs_per_s_max", alone.max);
    j.field("logger_lost_alone", static_cast<long long>(backlog_sent - backlog_kept));
    j.field("cores", static_cast<int>(std::thread::hardware_concurrency())).field("free_page_reporting", pages_reported(reporting_order));
    j.end_object();
    std::ofstream(a.get("json")) << j.str() << "\n";
  }
  return 0;
}

}  // namespace enact::cli
