// enact bench loop: the real-time loop measured against the machine's floor, each pair of
// arms in the same run, alternating, so that noise hits both arms alike:
//  - timer: a bare periodic thread and the co-located tick (bridge, simulated devices) at
//    5 kHz, in short blocks with the order flipped; jitter = how late the sleep ends, before
//    any spin; then the co-located tick at 44 kHz, every missed deadline counted;
//  - round trip: ffd -> sim -> ffd over the bus (DeviceState out, a simulator steps in a
//    second process, ForceCommand back) and a raw ZeroMQ ping-pong of the same sizes and
//    layout, alternating tick by tick, over ipc and tcp; replies matched by sequence number.
// The machine's state (cores, steal, load, CPU latency request, pinning, FIFO) is recorded.
// This file: the command, its options and profile, the order of the arms (bench_loop.h).
#include <cstdio>

#include "core/bus/context.h"
#include "core/graph/temp_folder.h"
#include "core/rt/probe.h"
#include "core/rt/profile.h"
#include "nodes/enact-bench/bench_loop.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

constexpr const char* kBenchLoopHelp = R"(usage: enact bench loop [--json FILE] [--seconds S] [--jitter-ticks N] [--scene PATH]
                        [--fifo PRIORITY] [--no-profile]

The real-time loop against the machine's floor; the arms of each comparison alternate in
the same run (noise hits both alike):
  timer     a bare periodic thread and the co-located tick (bridge scene, simulated ERGOS
            and cells) at 5 kHz, in blocks of 250 ticks with the order flipped; jitter = how
            late the sleep ends, before the spin (and the fraction of ticks it overshoots the
            spin window); then the co-located tick at 44 kHz, every missed deadline counted
  rtt       ffd -> sim -> ffd at 5 kHz with the simulator in a second process, like the
            graph: the bus (DeviceState, a simulator step, ForceCommand) and a raw ZeroMQ
            ping-pong of the same sizes and socket layout, alternating tick by tick, over ipc
            then tcp; replies matched by sequence number (stale and unanswered counted per arm)
  peer      when ddsperf is installed (Debian cyclonedds-tools): Cyclone DDS's ping/pong at
            5 kHz, 100 bytes, on the same CPU, reported beside ours
The shipped graphs' real-time profile applies (loop threads and the peer on one CPU, CPU
latency request held, SCHED_FIFO 80 ordered as in a launch file) unless --no-profile;
--fifo P changes the priority (0: normal scheduling). Refusals are said, the bench runs.

options:
  --seconds S       each round-trip case and the 44 kHz case (default 5)
  --jitter-ticks N  ticks of the 5 kHz timer comparison, both arms (default 100000: 20 s)
  --json FILE       every figure, with the machine's state
JSON: distributed_rtt_p50_ratio (bus / raw ZeroMQ, ipc; expected 0.7-1.3),
colocated_jitter_p99_ratio, colocated_latency_p99_us, colocated_44khz_missed_fraction, ...
Total time at the defaults: about 45 s. (--peer DIR --peer-of ENDPOINTS: the second
process, started by the bench itself.)
)";

}  // namespace

int bench_loop(int argc, char** argv) {
  const Args a = parse(argc, argv, 3, {"json", "seconds", "jitter-ticks", "scene", "fifo", "peer", "peer-of", "peer-link", "peer-pipes"}, {"no-profile"});
  if (a.flag("help")) {
    std::fputs(kBenchLoopHelp, stdout);
    return 0;
  }
  const std::string scene = find_file(a.get("scene", "launch/scenes/bridge.yaml"));
  if (a.has("peer")) {
    loop::PeerSetup setup{a.get("peer-of"), a.get("peer-link"), -1, -1};
    if (std::sscanf(a.get("peer-pipes").c_str(), "%d,%d", &setup.pipe_in, &setup.pipe_out) != 2) throw UsageError("--peer-pipes needs IN,OUT");
    return loop::run_peer(a.get("peer"), scene, setup);
  }
  const double seconds = a.number("seconds", 5.0);
  const auto jitter_ticks = static_cast<std::int64_t>(a.number("jitter-ticks", 100000.0));
  const int fifo = static_cast<int>(a.number("fifo", 80.0));
  if (seconds <= 0.0 || jitter_ticks < 2 * loop::kBlockTicks) throw UsageError("--seconds must be > 0 and --jitter-ticks at least 500");

  loop::LoopResults r;
  r.seconds = seconds;
  r.jitter_ticks = jitter_ticks;
  r.fifo_priority = fifo;
  // the graph's profile: the peer and this thread are the loop, ordered as the graph's [sim, ffd]: the
  // answering side above the clock master (it runs as soon as a request comes)
  loop::Machine& machine = r.machine;
  const rt::GraphProfile graph_profile{.enabled = !a.flag("no-profile"), .loop = {"peer", "bench"}, .fifo_priority = fifo, .cpu_latency = true, .other_loops = {}};
  const rt::LauncherProfile profile(graph_profile);
  const rt::NodeProfileReport self = rt::apply_node_profile(profile.node("bench"));
  bus::set_io_threads({self.io_cpus, self.io_fifo_priority});
  machine.profile = profile.summary() + (self.notes.empty() ? "" : "; this process: " + self.summary());
  machine.latency_held = profile.cpu_latency_held();
  machine.loop_cpus = profile.loop_cpus();
  machine.fifo = self.fifo;
  machine.probe = rt::cached_probe();
  std::fprintf(stderr, "enact bench loop: %s\nabout %.0f s: timer %lld ticks at 5 kHz, 44 kHz %.1f s, round trips ipc, tcp and ddsperf %.1f s each\n", machine.profile.c_str(),
               static_cast<double>(jitter_ticks) / loop::kRate_hz + 4.0 * seconds, static_cast<long long>(jitter_ticks), seconds, seconds);

  r.timer = loop::timer_5khz(scene, jitter_ticks, machine.fifo);
  r.r44 = loop::colocated_44khz(scene, seconds, machine.fifo, !machine.loop_cpus.empty());
  const graph::TempFolder dir("/tmp/enact-bench-");
  r.rtt = loop::round_trips(dir.path(), scene, profile.in_loop("peer") ? profile.node("peer").to_env() : "", seconds, machine.fifo);
  r.dds = loop::ddsperf(seconds);
  r.steal_pct = machine.steal_pct();
  loop::report(r, a.get("json", ""));
  return 0;
}

}  // namespace enact::cli
