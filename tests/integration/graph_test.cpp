// Integration: the real graphs of launch/ (bridge_rt.yaml: the co-located container
// enact-rt; bridge.yaml: enact-sim, enact-tactile and enact-ffd over ZeroMQ ipc), started with
// the real `enact launch` and observed from this process through the graph's attach point,
// like any viewer or logger would.
//
// Machine assumptions: 2 noisy shared cores. No timing assertions except generous bounds.
// The attach point is lossy for slow observers by design (core/bus/README.md, "Delivery"):
// a test process descheduled for a while may lose messages, so sequence gaps seen here are
// reported and only bounded (< 1 %), not forbidden.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>

#include <cstdio>
#include <map>
#include <set>
#include <string>

#include "core/bus/typed.h"
#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

constexpr double kGraphDuration_s = 15.0;  // a safety net: every test stops its graph itself

// the topics every graph publishes, with their message types
const std::map<std::string, std::string> kTopics = {
    {"ffd/state", "enact.msgs.DeviceState"},   {"ffd/force", "enact.msgs.ForceCommand"},    {"tactile/frame", "enact.msgs.TactileFrame"},
    {"tactile/shown", "enact.msgs.TactileShown"}, {"sim/scene", "enact.msgs.SceneState"}, {"task/event", "enact.msgs.TaskEvent"},
    {"node/status", "enact.msgs.NodeStatus"},
};

// every topic arrived (task/event is on event only: not required), each message of the
// right type name and parseable (the typed layer counts anything else as malformed)
void expect_every_topic(Observer& obs, const Observed& seen) {
  EXPECT_FALSE(seen.states.empty()) << "ffd/state";
  EXPECT_FALSE(seen.forces.empty()) << "ffd/force";
  EXPECT_FALSE(seen.frames.empty()) << "tactile/frame";
  EXPECT_FALSE(seen.shown.empty()) << "tactile/shown";
  EXPECT_FALSE(seen.scenes.empty()) << "sim/scene";
  EXPECT_FALSE(seen.statuses.empty()) << "node/status";
  for (const auto& [topic, c] : obs.bytes().all_counters()) EXPECT_EQ(c.malformed, 0u) << topic << ": messages of a wrong type or not parseable";
  // the graph's own description lists them all with their types
  ASSERT_FALSE(seen.graphs.empty()) << "no GraphInfo on graph/topics";
  std::map<std::string, std::string> listed;
  for (const auto& t : seen.graphs.back().topics()) listed[t.name()] = t.type();
  for (const auto& [topic, type] : kTopics) EXPECT_EQ(listed[topic], type) << topic;
  EXPECT_FALSE(seen.graphs.back().descriptor_set().empty());
  // a little content sanity
  for (const auto& f : seen.frames) {
    ASSERT_EQ(f.rows() * f.cols(), static_cast<std::uint32_t>(f.level_size()));
    for (float l : f.level()) ASSERT_TRUE(l == 0.0f || l == 1.0f) << f.ShortDebugString();
  }
  for (const auto& s : seen.shown) {
    ASSERT_EQ(s.rows() * s.cols(), static_cast<std::uint32_t>(s.level_size()));
    for (float l : s.level()) ASSERT_TRUE(l >= 0.0f && l <= 1.0f) << s.ShortDebugString();
  }
  for (const auto& s : seen.statuses) EXPECT_EQ(s.node(), s.header().source());
}

// ffd/state: seq strictly increasing at the observer, and messages lost in gaps a small
// fraction (the attach point drops for a slow observer by design: see the top of the file)
void expect_few_state_gaps(Observer& obs, const Observed& seen) {
  ASSERT_GE(seen.states.size(), 2u);
  for (std::size_t i = 1; i < seen.states.size(); ++i) ASSERT_GT(seen.states[i].header().seq(), seen.states[i - 1].header().seq()) << "at " << i;
  const bus::TopicCounters c = obs.states->counters();
  const std::uint64_t span = seen.states.back().header().seq() - seen.states.front().header().seq() + 1;
  std::printf("[ observer ] ffd/state: %llu received over a seq span of %llu, %llu lost in %llu gaps\n", static_cast<unsigned long long>(c.received),
              static_cast<unsigned long long>(span), static_cast<unsigned long long>(c.lost), static_cast<unsigned long long>(c.gaps));
  EXPECT_EQ(c.received + c.lost, span);
  EXPECT_LT(c.lost * 100, span) << "more than 1 % of ffd/state lost at the observer";
}

// every ffd/force answers a DeviceState that exists: one the observer saw, or one it lost in
// a gap (forces and states may arrive in either order: only answers inside the observed
// range of states are checked); each sample is answered once, in order
void expect_answers_refer_to_states(Observer& obs, const Observed& seen, const std::string& state_source, const std::string& force_source) {
  ASSERT_FALSE(seen.forces.empty());
  ASSERT_FALSE(seen.states.empty());
  std::set<std::uint64_t> state_seqs;
  for (const auto& s : seen.states) {
    ASSERT_EQ(s.header().source(), state_source);
    state_seqs.insert(s.header().seq());
  }
  const std::uint64_t first = *state_seqs.begin(), last = *state_seqs.rbegin();
  std::uint64_t previous = 0, not_seen = 0, checked = 0;
  for (const auto& f : seen.forces) {
    ASSERT_EQ(f.header().source(), force_source);
    const std::uint64_t a = f.answered_seq();
    ASSERT_GT(a, previous) << "answers out of order or repeated: " << f.ShortDebugString();
    previous = a;
    if (a < first || a > last) continue;  // at the edges of the observed window
    ++checked;
    not_seen += !state_seqs.contains(a);
  }
  EXPECT_GT(checked, seen.forces.size() / 2);
  EXPECT_LE(not_seen, obs.states->counters().lost) << "answers to DeviceState seqs that were never published";
}

// sim/scene follows the scripted contact: on the top the resultant pushes up, with no mass in
// contact it is zero; pins follow the computer model (CM1: pin i up iff mass i touches; CM3:
// the inverse)
void expect_scene_follows_contact(const std::vector<msgs::SceneState>& scenes, const std::string& model, bool inverted) {
  ASSERT_GE(scenes.size(), 30u) << "sim/scene at 60 Hz over about 2 s";
  int on_top = 0, touching = 0, free = 0, bad_force = 0, bad_pins = 0;
  std::string first_bad;
  for (const auto& s : scenes) {
    ASSERT_EQ(s.in_contact_size(), 16);
    ASSERT_EQ(s.pin_level_size(), 16);
    ASSERT_EQ(s.contact_force_size(), 16);
    EXPECT_EQ(s.model(), model);
    bool any = false, pins_ok = true;
    for (int i = 0; i < 16; ++i) {
      any = any || s.in_contact(i);
      const float want = s.in_contact(i) != inverted ? 1.0f : 0.0f;
      pins_ok = pins_ok && s.pin_level(i) == want;
    }
    bool force_ok = true;
    if (s.on_top()) {
      ++on_top;
      force_ok = s.resultant_force().z() > 0.0;
    }
    if (any) {
      ++touching;
    } else {
      ++free;
      force_ok = force_ok && s.resultant_force().x() == 0.0 && s.resultant_force().y() == 0.0 && s.resultant_force().z() == 0.0;
    }
    bad_force += !force_ok;
    bad_pins += !pins_ok;
    if ((!force_ok || !pins_ok) && first_bad.empty()) first_bad = s.ShortDebugString();
  }
  std::printf("[ observer ] sim/scene (%s): %zu snapshots, %d on the top, %d touching, %d free\n", model.c_str(), scenes.size(), on_top, touching, free);
  EXPECT_EQ(bad_force, 0) << "snapshots whose resultant does not follow the contact; first: " << first_bad;
  EXPECT_EQ(bad_pins, 0) << "snapshots whose pins do not follow " << model << "; first: " << first_bad;
  EXPECT_GT(on_top, 0) << "the scripted hand never touched the top of the bridge: the checks above were vacuous";
}

TEST(IntegrationColocated, LateObserverSeesEveryTopicAndForcesAndPinsFollowContact) {
  const auto t0 = Clock::now();
  TempDir dir;
  Launcher launcher(dir, source_path("launch/bridge_rt.yaml"), kGraphDuration_s);
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  EXPECT_NE(launcher.log().find("rt ready"), std::string::npos) << launcher.log();
  // a late observer: connects after the graph is ready
  Observer obs(launcher.endpoint());
  obs.all_topics();
  Observed seen;
  obs.observe(2.5, seen);
  expect_every_topic(obs, seen);
  expect_few_state_gaps(obs, seen);
  expect_scene_follows_contact(seen.scenes, "CM1", false);
  bool rt_status = false;
  for (const auto& s : seen.statuses) rt_status = rt_status || s.node() == "rt";
  EXPECT_TRUE(rt_status) << "no node/status from the container 'rt'";
  // co-located: each ffd/force answers the ffd/state of the same tick
  expect_answers_refer_to_states(obs, seen, "rt", "rt");
  EXPECT_EQ(seen.graphs.back().loop_hop(), "co-located");
  EXPECT_EQ(launcher.stop(), 0) << launcher.log();
  std::printf("[ timing ] %.1f s\n", seconds_since(t0));
}

TEST(IntegrationColocated, ComputerModelCM3InvertsThePins) {
  const auto t0 = Clock::now();
  TempDir dir;
  Launcher launcher(dir, source_path("launch/bridge_rt.yaml"), kGraphDuration_s, {"model=CM3"});
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  Observer obs(launcher.endpoint());
  obs.scenes.emplace(obs.bytes(), "sim/scene");
  Observed seen;
  obs.observe(2.0, seen);
  EXPECT_EQ(obs.scenes->counters().malformed, 0u);
  expect_scene_follows_contact(seen.scenes, "CM3", true);
  EXPECT_EQ(launcher.stop(), 0) << launcher.log();
  std::printf("[ timing ] %.1f s\n", seconds_since(t0));
}

// the distributed graph, its loop's hop on the same-host link (the default) or forced onto
// ZeroMQ (the launch file's switch): observers see every topic either way, every answer refers
// to its sample, and the hop taken is said at start and in graph/topics
class IntegrationDistributed : public ::testing::TestWithParam<const char*> {};

TEST_P(IntegrationDistributed, ScenesFollowContactAndAnswersReferToSamples) {
  const auto t0 = Clock::now();
  const std::string transport = GetParam();
  TempDir dir;
  Launcher launcher(dir, source_path("launch/bridge.yaml"), kGraphDuration_s, {"loop_transport=" + transport});
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  for (const char* node : {"sim", "tactile", "ffd"}) EXPECT_NE(launcher.log().find(std::string(node) + " ready"), std::string::npos) << node;
  Observer obs(launcher.endpoint());
  obs.all_topics();
  Observed seen;
  obs.observe(2.5, seen);
  expect_every_topic(obs, seen);
  expect_few_state_gaps(obs, seen);
  expect_scene_follows_contact(seen.scenes, "CM1", false);

  expect_answers_refer_to_states(obs, seen, "ffd", "sim");
  const bool local = transport == "auto";
  EXPECT_EQ(seen.graphs.back().loop_hop(), local ? "local" : "zeromq");
  EXPECT_NE(launcher.log().find(local ? "ffd: loop hop to sim: local (Unix link" : "ffd: loop hop to sim: ZeroMQ (loop_transport=zeromq)"),
            std::string::npos)
      << launcher.log();

  // the driver measures its loop latency, counts its deadlines and gives its verdict. The
  // latency is that of the answers in time: a machine where the ZeroMQ hop is slower than the
  // period less the spin window (a VM whose threads wake 40 us late: 85 us a ZeroMQ round
  // trip) has none, every deadline missed and said so
  bool ffd_status = false;
  for (const auto& s : seen.statuses) {
    if (s.node() != "ffd") continue;
    ffd_status = true;
    if (local || s.deadlines_missed() < s.deadlines()) EXPECT_GT(s.latency_p50_ns(), 0) << s.ShortDebugString();
    EXPECT_GT(s.deadlines(), 0u) << s.ShortDebugString();
    EXPECT_LE(s.deadlines_missed(), s.deadlines()) << s.ShortDebugString();
    EXPECT_NE(s.verdict().find("this machine"), std::string::npos) << s.ShortDebugString();
  }
  EXPECT_TRUE(ffd_status) << "no node/status from ffd";
  for (const char* node : {"sim", "tactile"}) {
    bool found = false;
    for (const auto& s : seen.statuses) found = found || s.node() == node;
    EXPECT_TRUE(found) << "no node/status from " << node;
  }
  EXPECT_EQ(launcher.stop(), 0) << launcher.log();
  EXPECT_NE(launcher.log().find("ffd: verdict: this machine"), std::string::npos) << launcher.log();
  std::printf("[ timing ] %.1f s\n", seconds_since(t0));
}

INSTANTIATE_TEST_SUITE_P(Hop, IntegrationDistributed, ::testing::Values("auto", "zeromq"));

TEST(IntegrationDistributedFaults, KillingARequiredNodeStopsTheWholeGraph) {
  const auto t0 = Clock::now();
  // orphans of the graph would be re-parented to this process (and reaped below), not
  // linger as zombies of init that kill(pid, 0) still finds
  ASSERT_EQ(prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  TempDir dir;
  Launcher launcher(dir, source_path("launch/bridge.yaml"), 60.0);
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  const pid_t sim = launcher.pid_of("sim"), tactile = launcher.pid_of("tactile"), ffd = launcher.pid_of("ffd");
  ASSERT_GT(sim, 0) << launcher.log();
  ASSERT_GT(tactile, 0) << launcher.log();
  ASSERT_GT(ffd, 0) << launcher.log();
  const std::size_t before = launcher.log().size();
  ASSERT_EQ(kill(sim, SIGKILL), 0);
  const auto killed = Clock::now();
  const std::optional<int> code = launcher.wait_exit(10.0);
  ASSERT_TRUE(code.has_value()) << "the launcher still runs 10 s after its required node was killed\n" << launcher.log();
  std::printf("[ timing ] launcher exited %.2f s after SIGKILL of sim\n", seconds_since(killed));
  EXPECT_EQ(*code, 1) << launcher.log();
  const std::string after_kill = launcher.log().substr(before);
  EXPECT_NE(after_kill.find("'sim'"), std::string::npos) << after_kill;
  // nothing of the graph is left (reap whatever was re-parented to us first)
  const auto end = after(2.0);
  while (Clock::now() < end && !(process_gone(sim) && process_gone(tactile) && process_gone(ffd))) {
    while (waitpid(-1, nullptr, WNOHANG) > 0) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_TRUE(process_gone(sim)) << "sim pid " << sim;
  EXPECT_TRUE(process_gone(tactile)) << "tactile pid " << tactile;
  EXPECT_TRUE(process_gone(ffd)) << "ffd pid " << ffd;
  std::printf("[ timing ] %.1f s\n", seconds_since(t0));
}

TEST(IntegrationDistributedFaults, StalledSimulatorTripsTheDriverWatchdog) {
  const auto t0 = Clock::now();
  TempDir dir;
  Launcher launcher(dir, source_path("launch/bridge.yaml"), kGraphDuration_s);
  ASSERT_TRUE(launcher.wait_log("enact launch: graph ready", kReadyTimeout_s)) << launcher.log();
  const pid_t sim = launcher.pid_of("sim");
  ASSERT_GT(sim, 0) << launcher.log();
  Observer obs(launcher.endpoint());
  obs.states.emplace(obs.bytes(), "ffd/state");
  obs.statuses.emplace(obs.bytes(), "node/status");
  Observed seen;
  constexpr std::uint32_t kWatchdog = msgs::DEVICE_FAULT_WATCHDOG;

  // healthy first: samples without the watchdog bit (one may trip now and then on a busy
  // machine: 10 ms without an answer)
  std::size_t healthy = 0;
  obs.observe(5.0, seen, [&](std::string_view) {
    healthy += (seen.states.back().faults() & kWatchdog) == 0;
    return healthy < 200;
  });
  ASSERT_GE(healthy, 200u) << "no healthy ffd/state before the stall";

  // and 2 s of the loop without the stall, counted: what the machine misses on its own
  const auto clean_start = obs.status_after(seen, "ffd", rt::now_ns(), 5.0);
  ASSERT_TRUE(clean_start) << "no node/status from ffd";
  const auto before = obs.status_after(seen, "ffd", clean_start->header().stamp_ns() + 2'000'000'000, 5.0);
  ASSERT_TRUE(before) << "no node/status from ffd";

  // stall the simulator: within 2 s, samples taken after the stall carry the watchdog bit
  // (the watchdog trips after 10 ms; the stopped simulator loses the driver's ffd/state
  // alone, the attach point still gets it: core/bus/README.md, "Delivery")
  Continue guard{sim};
  const std::int64_t stop_ns = rt::now_ns();
  ASSERT_EQ(kill(sim, SIGSTOP), 0);
  bool tripped = false;
  const auto stopped = Clock::now();
  obs.observe(2.0, seen, [&](std::string_view) {
    const auto& s = seen.states.back();
    tripped = s.header().stamp_ns() > stop_ns && (s.faults() & kWatchdog) != 0;
    return !tripped;
  });
  EXPECT_TRUE(tripped) << "no ffd/state with DEVICE_FAULT_WATCHDOG within 2 s of stopping the simulator";
  std::printf("[ timing ] watchdog bit seen %.3f s after SIGSTOP\n", seconds_since(stopped));
  // stalled well past the tactile driver's watchdog (0.25 s) too
  std::this_thread::sleep_for(std::chrono::milliseconds(600));

  // resume it: within 2 s, samples taken after that are healthy again
  const std::int64_t cont_ns = rt::now_ns();
  ASSERT_EQ(kill(sim, SIGCONT), 0);
  bool cleared = false;
  const auto continued = Clock::now();
  obs.observe(2.0, seen, [&](std::string_view) {
    const auto& s = seen.states.back();
    cleared = s.header().stamp_ns() > cont_ns && (s.faults() & kWatchdog) == 0;
    return !cleared;
  });
  EXPECT_TRUE(cleared) << "the watchdog bit did not clear within 2 s of resuming the simulator";
  std::printf("[ timing ] watchdog bit cleared %.3f s after SIGCONT\n", seconds_since(continued));

  // the driver counted each sample of the stall once: the simulator, resumed, answered the
  // samples it had queued, too late to apply (stale, not samples without an answer again)
  const auto after_stall = obs.status_after(seen, "ffd", rt::now_ns(), 5.0);
  ASSERT_TRUE(after_stall) << "no node/status from ffd after the stall";
  const double window_samples = static_cast<double>(after_stall->header().stamp_ns() - before->header().stamp_ns()) * 1e-9 * 5000.0;
  const double stall_samples = static_cast<double>(cont_ns - stop_ns) * 1e-9 * 5000.0;
  const double unanswered = static_cast<double>(after_stall->faults() - before->faults());
  const double clean_fraction = static_cast<double>(before->faults() - clean_start->faults()) /
                                (static_cast<double>(before->header().stamp_ns() - clean_start->header().stamp_ns()) * 1e-9 * 5000.0);
  std::printf("[ measure ] stalled %.0f samples' time: %.0f of %.0f samples in the window without an answer in time (without the stall %.3f %%)\n",
              stall_samples, unanswered, window_samples, 100.0 * clean_fraction);
  EXPECT_GE(unanswered, 0.9 * stall_samples) << "the stall's samples were not counted unanswered";
  // the stall's samples, what the machine misses on its own in the rest of the window (the
  // bound of tests/integration/faults_test.cpp) and 50 ms of the simulator catching up
  EXPECT_LE(unanswered, stall_samples + (window_samples - stall_samples) * (3.0 * clean_fraction + 0.02) + 250.0)
      << "more samples unanswered than the stall left: one counter counts something else";
  EXPECT_EQ(launcher.stop(), 0) << launcher.log();
  // both drivers said when their watchdog began and ended (the tactile driver lowered the
  // pins: no frame for 0.25 s), and counted it in their summaries
  const std::string log = launcher.log();
  for (const char* line : {"ffd: watchdog: episode 1 began", "tactile: watchdog: episode 1 began, no tactile/frame: pins lowered",
                           "tactile: watchdog: episode 1 ended after"}) {
    EXPECT_NE(log.find(line), std::string::npos) << line << "\n" << log;
  }
  EXPECT_NE(log.find("watchdog episode"), std::string::npos) << log;
  std::printf("[ timing ] %.1f s\n", seconds_since(t0));
}

}  // namespace
}  // namespace enact::test
