// enact bench loop, timer arms: a bare periodic thread against the co-located tick at 5 kHz
// (how late the sleep ends, before any spin), then the co-located tick at 44 kHz.
#include <memory>

#include "core/devices/safety.h"
#include "core/devices/simulated_force.h"
#include "core/devices/simulated_tactile.h"
#include "core/node/colocated.h"
#include "core/rt/clock.h"
#include "core/rt/scheduler.h"
#include "core/rt/probe.h"
#include "core/rt/profile.h"
#include "nodes/enact-bench/bench_loop.h"

namespace enact::cli::loop {
namespace {

// the co-located loop on the bridge scene: simulated ERGOS (resting on the bridge's start) and cells
struct Colocated {
  sim::Simulator simulator;
  std::unique_ptr<devices::SafeForceDevice> force;
  devices::SimulatedTactileDevice tactile;
  std::unique_ptr<graph::ColocatedLoop> loop;

  Colocated(const std::string& scene, double rate_hz) {
    sim::SimParams p;
    p.scene = scene;
    p.rate_hz = rate_hz;
    simulator.configure(p);
    devices::SimulatedForceParams f;
    f.start_m = {-0.0074246, -0.0222739, 0.0119};
    force = std::make_unique<devices::SafeForceDevice>(std::make_unique<devices::SimulatedForceDevice>(f));
    force->configure();
    tactile.configure();
    loop = std::make_unique<graph::ColocatedLoop>(simulator, *force, &tactile, &rt::now_ns);
    loop->activate();
  }
  ~Colocated() { loop->deactivate(); }
  // one tick at `now`: its sample-to-force latency, ns
  std::int64_t tick(std::int64_t now) {
    const graph::Observation& o = loop->tick(now);
    return o.force_ns - o.sample.time_ns;
  }
};

}  // namespace

TimerResult timer_5khz(const std::string& scene, std::int64_t ticks, bool fifo) {
  TimerResult r;
  Colocated col(scene, kRate_hz);
  loop_thread([&] {
    rt::PeriodicScheduler s({.rate_hz = kRate_hz, .spin_ns = 50'000, .sleep_every_tick = fifo});
    r.spin_ns = s.spin_ns();
    s.start(rt::now_ns() + 1'000'000);
    for (std::int64_t n = 0; n < ticks; ++n) {
      const std::int64_t woke = s.wait();
      TimerArm& arm = r.arm[arm_of(n, kBlockTicks)];
      const std::int64_t late = s.last_sleep_late_ns();
      if (late >= 0) {
        arm.sleep_late.record(late);
        arm.block.record(late);
        ++arm.slept;
        arm.overshoot += late > s.spin_ns() ? 1 : 0;
      }
      if (&arm == &r.arm[1]) arm.latency.record(col.tick(woke));
      if (n % (2 * kBlockTicks) == 2 * kBlockTicks - 1) r.p50.add_block(r.arm[1].block, r.arm[0].block);
    }
  });
  r.p50.overall = ratio(r.arm[1].sleep_late.percentile(50.0), r.arm[0].sleep_late.percentile(50.0));
  return r;
}

Rate44 colocated_44khz(const std::string& scene, double seconds, bool fifo, bool own_cpu) {
  Rate44 r;
  Colocated col(scene, 44000.0);
  // waiting as enact-rt does on this machine (the probe's plan: a period under twice the
  // wake-up lateness is spun whole, under normal scheduling)
  const rt::WaitPlan wait = rt::loop_wait(-1.0, static_cast<std::int64_t>(1e9 / 44000.0), fifo, false, own_cpu);
  r.how = wait.why;
  loop_thread([&] {
    if (fifo && !wait.fifo) rt::system_calls().set_fifo(0);
    rt::PeriodicScheduler s({.rate_hz = 44000.0, .spin_ns = wait.spin_ns, .sleep_every_tick = !wait.spin_whole_period});
    rt::LoopStats stats;
    const std::int64_t start = rt::now_ns() + 1'000'000;
    const std::int64_t end = start + static_cast<std::int64_t>(seconds * 1e9);
    s.start(start);
    for (std::int64_t now = s.wait(); now < end; now = s.wait()) stats.latency.record(col.tick(now));
    rt::take_timing(s, stats);
    r.loop = rt::summarize(stats, 44000.0);
    r.deadlines = s.ticks() + s.skipped();
    r.missed = s.overruns();
  });
  return r;
}

}  // namespace enact::cli::loop
