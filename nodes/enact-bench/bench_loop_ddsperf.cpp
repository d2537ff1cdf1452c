// enact bench loop, the peer arm: Cyclone DDS's own ping/pong (ddsperf, Debian
// cyclonedds-tools) at the loop's rate, reported beside ours, when installed.
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/launch/launch_file.h"
#include "nodes/enact-bench/bench_loop.h"

namespace enact::cli::loop {
namespace {

// the number after `key` in a ddsperf report line ("50% 16.6us", "cnt 1370"), -1 if absent
double after(const std::string& line, const std::string& key) {
  const std::size_t at = line.find(key);
  return at == std::string::npos ? -1.0 : std::atof(line.c_str() + at + key.size());
}

}  // namespace

DdsPerf ddsperf(double seconds) {
  DdsPerf r;
  const std::string exe = launch::default_resolver()("ddsperf");
  if (exe.empty()) return r;
  const int s = static_cast<int>(std::ceil(seconds));
  FILE* pong = popen((exe + " -D " + std::to_string(s + 3) + " pong >/dev/null 2>&1").c_str(), "r");
  FILE* ping = popen((exe + " -D " + std::to_string(s) + " -Qminmatch:1 ping 5000Hz size 100 2>&1").c_str(), "r");
  std::vector<double> p50, p99;
  char buf[1024];
  while (ping && std::fgets(buf, sizeof buf, ping)) {
    const std::string line = buf;
    if (line.find(" size 100 mean ") == std::string::npos) continue;
    p50.push_back(after(line, " 50% "));
    p99.push_back(after(line, " 99% "));
    r.round_trips += static_cast<std::uint64_t>(std::max(0.0, after(line, " cnt ")));
  }
  if (ping) pclose(ping);
  if (pong) pclose(pong);
  r.ran = !p50.empty();
  r.p50_us = quantile(p50, 0.5);
  r.p99_us = quantile(p99, 0.5);
  r.expected = static_cast<std::uint64_t>(kRate_hz * static_cast<double>(p50.size()));
  return r;
}

}  // namespace enact::cli::loop
