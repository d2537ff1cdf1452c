// enact-rt's component list is data: a container that names its components (sim, ffd,
// tactile, each with its parameters) runs exactly as one that names none and gets the
// default three, its components' parameters given as the container's (sim.scene, ...); one
// without a tactile display runs the same loop, its pins written nowhere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/math/vec3.h"
#include "core/record/reader.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"
#include "msgs/node_status.pb.h"
#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

// every recorded ffd/force, serialized, by the device state it answers; and how many
// messages each topic has
struct Recorded {
  std::map<std::uint64_t, std::string> forces;
  std::map<std::string, std::size_t> counts;
  std::size_t count(const std::string& topic) const {
    const auto it = counts.find(topic);
    return it == counts.end() ? 0 : it->second;
  }
};
Recorded recorded(const std::string& recording) {
  Recorded out;
  msgs::ForceCommand force;
  record::Reader(recording).for_each([&](const record::Message& m) {
    out.counts[std::string(m.topic)] += 1;
    if (m.topic == "ffd/force" && force.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      out.forces[force.answered_seq()] = force.force().SerializeAsString();
    }
    return true;
  });
  return out;
}

// the forces of b that answer the same device state as one of a's, each equal to a's; how many
std::size_t same_forces(const Recorded& a, const Recorded& b) {
  std::size_t common = 0;
  for (const auto& [seq, force] : a.forces) {
    const auto other = b.forces.find(seq);
    if (other == b.forces.end()) continue;
    ++common;
    EXPECT_EQ(other->second, force) << "the force answering state " << seq;
  }
  return common;
}

// a logger, then the container: 1 s of the bridge under a scripted hand, in simulated time
std::string graph(const std::string& recording, const std::string& container) {
  return "launch:\n"
         "  - node: {name: logger, exec: enact-logger, param: [{name: output, value: " + recording + "}]}\n"
         "  - container:\n"
         "      name: rt\n"
         "      required: true\n"
         "      param:\n"
         "        - {name: duration_s, value: \"1\"}\n"
         "        - {name: observers, value: \"1\"}\n" + container;
}

// the same 1 s of the bridge under a scripted hand, three ways: the three components named
// with their parameters, the default three with the container's, and sim and ffd alone (the
// tactile display is optional; the pins never push back on a scripted hand). The forces are
// the same tick for tick; without a display the model's frames are still observed and no
// pins are shown
TEST(ContainerComponents, NamedDefaultOrWithoutATactileDisplayTheLoopIsTheSame) {
  TempDir dir;
  const std::string scene = source_path("launch/scenes/bridge.yaml"), path = source_path("launch/paths/bridge_walk.csv");
  const std::string sim = "        - {name: sim, plugin: sim, param: [{name: scene, value: " + scene + "}, {name: model, value: CM2}]}\n";
  const std::string hand = "param: [{name: hand_path, value: " + path + "}, {name: start_scene, value: " + scene + "}]}\n";
  const std::string named = dir.file("named.yaml"), defaulted = dir.file("default.yaml"), two = dir.file("two.yaml");
  write_file(named, graph(dir.file("named.mcap"), "      component:\n" + sim + "        - {name: ffd, plugin: ffd, " + hand + "        - {name: tactile, plugin: tactile}\n"));
  write_file(defaulted, graph(dir.file("default.mcap"), "        - {name: sim.scene, value: " + scene + "}\n"
                                                        "        - {name: sim.model, value: CM2}\n"
                                                        "        - {name: ffd.hand_path, value: " + path + "}\n"
                                                        "        - {name: ffd.start_scene, value: " + scene + "}\n"));
  write_file(two, graph(dir.file("two.mcap"), "      component:\n" + sim + "        - {name: hand, plugin: ffd, " + hand));
  for (const std::string& file : {named, defaulted, two}) {
    const RunResult r = run(std::string(ENACT_CLI) + " launch " + file + " --clock simulated --duration 6");
    EXPECT_NE(r.out.find("the hand felt"), std::string::npos) << file << "\n" << r.out << r.err;
  }
  const Recorded a = recorded(dir.file("named.mcap")), b = recorded(dir.file("default.mcap")), c = recorded(dir.file("two.mcap"));
  EXPECT_GT(a.forces.size(), 4000u) << "1 s at 5 kHz, all but the last in flight";
  EXPECT_GT(same_forces(a, b), 4000u) << "named as the default";
  EXPECT_GT(same_forces(a, c), 4000u) << "without a tactile display as with one";
  EXPECT_GT(c.count("tactile/frame"), 0u) << "the model's frames are observed without a display";
  EXPECT_GE(10 * c.count("tactile/frame"), 9 * a.count("tactile/frame")) << "as many as with a display, but for the last in flight";
  EXPECT_EQ(c.count("tactile/shown"), 0u) << "no display, no pins shown";
  EXPECT_GT(a.count("tactile/shown"), 0u) << "a display shows its pins";
}

// the ffd/state seqs recorded, and the container's own count of what it published (its last
// node/status: the whole run's)
struct StatesRecorded {
  std::vector<std::uint64_t> seqs;
  std::uint64_t published = 0;
  std::size_t forces = 0;
};
StatesRecorded states_recorded(const std::string& recording) {
  StatesRecorded out;
  msgs::DeviceState state;
  msgs::NodeStatus status;
  record::Reader(recording).for_each([&](const record::Message& m) {
    if (m.topic == "ffd/state" && state.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) out.seqs.push_back(state.header().seq());
    if (m.topic == "ffd/force") ++out.forces;
    if (m.topic == "node/status" && status.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      for (const auto& t : status.topics()) {
        if (t.topic() == "ffd/state") out.published = t.sent();
      }
    }
    return true;
  });
  return out;
}

// a logger can be a component of the container itself (no process of its own, no observers
// parameter): in real time, stopped by the launcher as Ctrl-C stops it, it has every device
// state the loop published from the first tick and every force, and a second logger of one
// topic beside it has the same forces; its file is closed whole
TEST(ContainerComponents, ALoggerComponentRecordsEveryTickFromTheFirst) {
  TempDir dir;
  const std::string scene = source_path("launch/scenes/bridge.yaml"), path = source_path("launch/paths/bridge_walk.csv");
  const std::string file = dir.file("g.yaml"), all = dir.file("all.mcap"), forces = dir.file("forces.mcap"), states = dir.file("states.mcap");
  write_file(file, "launch:\n"
                   "  - container:\n"
                   "      name: rt\n"
                   "      required: true\n"
                   "      component:\n"
                   "        - {name: sim, plugin: sim, param: [{name: scene, value: " + scene + "}, {name: model, value: CM2}]}\n"
                   "        - {name: ffd, plugin: ffd, param: [{name: hand_path, value: " + path + "}, {name: start_scene, value: " + scene + "}]}\n"
                   "        - {name: tactile, plugin: tactile}\n"
                   "        - {name: rec, plugin: logger, param: [{name: output, value: " + all + "}]}\n"
                   "        - {name: forces, plugin: logger, param: [{name: output, value: " + forces + "}, {name: topics, value: ffd/force}]}\n"
                   "        - {name: states, plugin: logger, param: [{name: output, value: " + states + "}, {name: regex, value: \"^ffd/\"}, {name: exclude, value: force}]}\n");
  const RunResult r = run(std::string(ENACT_CLI) + " launch " + file + " --duration 2");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::string said = r.out + r.err;
  EXPECT_NE(said.find("rt: rec: recording every topic to " + all), std::string::npos) << said;
  EXPECT_NE(said.find("rt: rec: closed " + all), std::string::npos) << said;
  EXPECT_NE(said.find("rt: forces: closed " + forces), std::string::npos) << said;
  const StatesRecorded s = states_recorded(all);
  ASSERT_GT(s.seqs.size(), 1000u) << "about 2 s at 5 kHz";
  EXPECT_EQ(s.seqs.front(), 1u) << "from the first tick";
  for (std::size_t i = 1; i < s.seqs.size(); ++i) ASSERT_EQ(s.seqs[i], s.seqs[i - 1] + 1) << "no state lost after " << s.seqs[i - 1];
  EXPECT_EQ(s.seqs.size(), s.published) << "every state the loop published, by its own last count";
  EXPECT_EQ(s.forces, s.seqs.size()) << "every force";
  const Recorded a = recorded(all), b = recorded(forces);
  EXPECT_EQ(b.count("ffd/state"), 0u) << "the second keeps only ffd/force";
  EXPECT_EQ(same_forces(a, b), a.forces.size()) << "the same forces in both";
  // a logger told by patterns is waited for as one told by names: from the first tick
  const StatesRecorded by_pattern = states_recorded(states);
  ASSERT_FALSE(by_pattern.seqs.empty()) << said;
  EXPECT_EQ(by_pattern.seqs.front(), 1u) << "the regex logger records from the first tick";
  EXPECT_EQ(by_pattern.seqs.size(), s.seqs.size()) << "every state";
  EXPECT_EQ(by_pattern.forces, 0u) << "ffd/force excluded";
}

// a virtual subject feels the pins: without a tactile display the container refuses it,
// before anything moves, with the fix
TEST(ContainerComponents, AVirtualSubjectWithoutATactileDisplayIsRefused) {
  TempDir dir;
  const std::string scene = source_path("launch/scenes/bridge.yaml"), file = dir.file("subject.yaml");
  write_file(file, "launch:\n"
                   "  - container:\n"
                   "      name: rt\n"
                   "      component:\n"
                   "        - {name: sim, plugin: sim, param: [{name: scene, value: " + scene + "}]}\n"
                   "        - {name: hand, plugin: ffd, param: [{name: subject, value: " + source_path("launch/experiments/subjects/quick.yaml") +
                       "}, {name: start_scene, value: " + scene + "}]}\n");
  const RunResult r = run(std::string(ENACT_CLI) + " launch " + file + " --clock simulated --duration 6");
  EXPECT_NE(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.err.find("component 'hand' drives the device with a virtual subject, who feels the pins, and there is no tactile display"), std::string::npos)
      << r.out << r.err;
  EXPECT_NE(r.err.find("fix: add {name: tactile, plugin: tactile} to the component list"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("the hand felt"), std::string::npos) << "nothing ran\n" << r.out;
}


// the host of a user's stage: the co-located container's tick, or enact-sim's answer in a
// distributed graph (a process a component)
enum class StageHost { container, process };
std::string host_name(const ::testing::TestParamInfo<StageHost>& info) { return info.param == StageHost::container ? "InTheContainer" : "InEnactSim"; }

// a graph with the example guide spring (examples/plugins/guide_spring.cpp, loaded from its
// library) beside the model, and a logger that records from the first tick
std::string guided(StageHost host, const std::string& recording, const std::string& guide_params, const std::string& plugin = "guide_spring",
                   const std::string& library = ENACT_GUIDE_SPRING) {
  const std::string scene = source_path("launch/scenes/bridge.yaml");
  const std::string guide = "          - name: guide\n"
                            "            plugin: " + plugin + "\n"
                            "            library: " + library + "\n"
                            "            param: [" + guide_params + "]\n";
  if (host == StageHost::process) {
    return "launch:\n"
           "  - node: {name: rec, exec: enact-logger, param: [{name: output, value: " + recording + "}]}\n"
           "  - node:\n"
           "        name: sim\n"
           "        exec: enact-sim\n"
           "        required: true\n"
           "        param: [{name: scene, value: " + scene + "}, {name: rate_hz, value: \"5000\"}, {name: observers, value: \"1\"}]\n"
           "        component:\n" + guide +
           "  - node: {name: tactile, exec: enact-tactile, required: true}\n"
           "  - node:\n"
           "        name: ffd\n"
           "        exec: enact-ffd\n"
           "        required: true\n"
           "        param: [{name: start_scene, value: " + scene + "}, {name: rate_hz, value: \"5000\"}, {name: observers, value: \"1\"}]\n";
  }
  return "launch:\n"
         "  - container:\n"
         "      name: rt\n"
         "      required: true\n"
         "      component:\n"
         "        - {name: sim, plugin: sim, param: [{name: scene, value: " + scene + "}]}\n"
         "        - {name: ffd, plugin: ffd, param: [{name: start_scene, value: " + scene + "}]}\n"
         "        - {name: tactile, plugin: tactile}\n"
         "        - name: guide\n"
         "          plugin: " + plugin + "\n"
         "          library: " + library + "\n"
         "          param: [" + guide_params + "]\n"
         "        - {name: rec, plugin: logger, param: [{name: output, value: " + recording + "}]}\n";
}

// the user's stage runs in the tick: nobody holds the device but a hand that keeps it at the
// scene's start, above the bridge, where the model pushes nothing; the guide pulls it toward
// an anchor 8 mm away. Every recorded force is the guide's law of the state it answers
// (spring and damper, capped at max_force_n), and the device moved toward the anchor
class Stages : public ::testing::TestWithParam<StageHost> {};
INSTANTIATE_TEST_SUITE_P(EitherHost, Stages, ::testing::Values(StageHost::container, StageHost::process), host_name);

TEST_P(Stages, AStageFromAPluginLibraryGivesTheForceOfEveryTick) {
  TempDir dir;
  const std::string file = dir.file("g.yaml"), rec = dir.file("g.mcap");
  const math::Vec3 start{-0.0074246, -0.0222739, 0.013}, anchor{start.x + 0.008, start.y, start.z};
  const double k = 150.0, b = 2.0, cap = 1.0;
  char anchor_text[128];
  std::snprintf(anchor_text, sizeof anchor_text, "%.17g,%.17g,%.17g", anchor.x, anchor.y, anchor.z);
  write_file(file, guided(GetParam(), rec, "{name: anchor_m, value: \"" + std::string(anchor_text) +
                                   "\"}, {name: stiffness_n_per_m, value: \"150\"}, {name: damping_n_s_per_m, value: \"2\"}, {name: max_force_n, value: \"1\"}"));
  const RunResult r = run(std::string(ENACT_CLI) + " launch " + file + " --clock simulated --duration 1");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  std::map<std::uint64_t, msgs::DeviceState> states;
  std::map<std::uint64_t, math::Vec3> forces;
  msgs::DeviceState state;
  msgs::ForceCommand force;
  record::Reader(rec).for_each([&](const record::Message& m) {
    if (m.topic == "ffd/state" && state.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) states[state.header().seq()] = state;
    if (m.topic == "ffd/force" && force.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      forces[force.answered_seq()] = {force.force().x(), force.force().y(), force.force().z()};
    }
    return true;
  });
  ASSERT_GT(forces.size(), 4000u) << "1 s at 5 kHz";
  std::size_t compared = 0, capped = 0;
  double moved_m = 0.0;
  for (const auto& [seq, f] : forces) {
    const auto it = states.find(seq);
    if (it == states.end()) continue;
    const math::Vec3 x{it->second.position().x(), it->second.position().y(), it->second.position().z()};
    const math::Vec3 v{it->second.velocity().x(), it->second.velocity().y(), it->second.velocity().z()};
    math::Vec3 law = (x - anchor) * -k - v * b;
    if (math::norm(law) > cap) {
      law = law * (cap / math::norm(law));
      ++capped;
    }
    ASSERT_NEAR(math::norm(f - law), 0.0, 1e-9) << "the force answering state " << seq << " is the guide's";
    moved_m = std::max(moved_m, x.x - start.x);
    ++compared;
  }
  EXPECT_GT(compared, 4000u);
  EXPECT_GT(capped, 0u) << "at 8 mm the spring asks 1.2 N: capped at the start";
  EXPECT_LT(capped, compared) << "and not once the device came closer";
  EXPECT_GT(moved_m, 0.001) << "the guide moved the device toward its anchor";
}

// a recording of a loop with a stage a user wrote replays identically: enact resim and enact
// metrics step the recorded stage again after the model (from the library the recording
// names, with its recorded parameters); a library moved away is named with the fix, and
// --library gives it where it is now. A replay without the stage gives the model's force
// alone (none, where this hand holds the device) and diverges at the first tick
TEST_P(Stages, AReplayStepsTheRecordedStagesAgain) {
  TempDir dir;
  const std::string file = dir.file("g.yaml"), rec = dir.file("g.mcap"), moved = dir.file("libenact_guide_spring.so");
  std::filesystem::copy_file(ENACT_GUIDE_SPRING, moved);
  write_file(file, guided(GetParam(), rec, "{name: anchor_m, value: \"0.0006,-0.0222739,0.013\"}, {name: stiffness_n_per_m, value: \"120\"}", "guide_spring", moved));
  const RunResult r = run(std::string(ENACT_CLI) + " launch " + file + " --clock simulated --duration 1");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const RunResult resim = run(std::string(ENACT_CLI) + " resim " + rec);
  EXPECT_EQ(resim.exit_code, 0) << resim.out << resim.err;
  EXPECT_NE(resim.out.find("stage guide (plugin guide_spring, " + moved + ") stepped after the model at every tick"), std::string::npos) << resim.out;
  EXPECT_NE(resim.out.find("identical: every force and every pin frame"), std::string::npos) << resim.out;
  const RunResult metrics = run(std::string(ENACT_CLI) + " metrics --json " + rec);
  EXPECT_EQ(metrics.exit_code, 0) << metrics.out << metrics.err;
  EXPECT_NE(metrics.out.find("\"agree\": true"), std::string::npos) << metrics.out;
  // the library moved away: named, with the fix; given where it is now: identical again
  std::filesystem::remove(moved);
  const RunResult gone = run(std::string(ENACT_CLI) + " resim " + rec);
  EXPECT_EQ(gone.exit_code, 1) << gone.out << gone.err;
  EXPECT_NE(gone.err.find(moved + ": there is no plugin library here, and the recorded loop's stage 'guide' (plugin guide_spring) came from it"),
            std::string::npos) << gone.err;
  EXPECT_NE(gone.err.find("fix: give the library where it is now: --library PATH"), std::string::npos) << gone.err;
  const RunResult given = run(std::string(ENACT_CLI) + " resim " + rec + " --library " + ENACT_GUIDE_SPRING + " --json");
  EXPECT_EQ(given.exit_code, 0) << given.out << given.err;
  EXPECT_NE(given.out.find("\"stages\": 1"), std::string::npos) << given.out;
  EXPECT_NE(given.out.find("\"identical\": true"), std::string::npos) << given.out;
}

// a graph refused before anything ran: what it said, with the fix
struct Refusal {
  std::string graph, said, fix;
};
void expect_refused(const std::string& file, const std::vector<Refusal>& cases) {
  for (const Refusal& c : cases) {
    write_file(file, c.graph);
    const RunResult r = run(std::string(ENACT_CLI) + " launch " + file + " --clock simulated --duration 1");
    const std::string said = r.out + r.err;
    EXPECT_NE(r.exit_code, 0) << said;
    EXPECT_NE(said.find(c.said), std::string::npos) << "expected: " << c.said << "\n" << said;
    EXPECT_NE(said.find(c.fix), std::string::npos) << "expected: " << c.fix << "\n" << said;
    EXPECT_EQ(said.find(" ready"), std::string::npos) << "nothing started\n" << said;
  }
}

// a plugin library's stage is refused before anything moves, with the file and the fix: a
// library that is not there (the launch file's line), a file that is not a shared library, a
// plugin the library does not hold (the plugins it has named), a parameter out of range
TEST(ContainerStages, ABadPluginLibraryOrStageIsRefusedWithTheFix) {
  TempDir dir;
  const std::string file = dir.file("g.yaml"), rec = dir.file("g.mcap"), junk = dir.file("junk.so");
  write_file(junk, "not a shared library\n");
  expect_refused(file, {
      {guided(StageHost::container, rec, "", "guide_spring", dir.file("none.so")), file + ":9: node 'rt': component 'guide': there is no plugin library '" + dir.file("none.so") + "'",
       "fix: build it (" + source_path("docs/components.md") + ")"},  // the docs where they are (enact run from the build)
      {guided(StageHost::container, rec, "", "guide_spring", junk), junk + ": cannot load the plugin library", "fix: build it against this enact"},
      {guided(StageHost::container, rec, "", "guide_sprung"), "component 'guide': unknown plugin 'guide_sprung'", "guide_spring (guiding spring toward anchor_m"},
      {guided(StageHost::container, rec, "{name: stiffness_n_per_m, value: \"-1\"}"), "stiffness_n_per_m", "fix:"},
  });
}

// only enact-sim and enact-rt host components, and enact-sim only stages (it runs its own
// simulator; drivers and observers are nodes of their own): refused before anything starts,
// at the entry's line, with the fix
TEST(Stages, AComponentANodeCannotHostIsRefusedWithTheFix) {
  TempDir dir;
  const std::string file = dir.file("g.yaml"), scene = source_path("launch/scenes/bridge.yaml");
  expect_refused(file, {
      {"launch:\n  - node:\n      name: sim\n      exec: enact-sim\n      param: [{name: scene, value: " + scene +
           "}]\n      component:\n        - {name: rec, plugin: logger}\n",
       file + ":7: node 'sim': component 'rec' is a ", "fix: list only stages of a user's (plugin libraries) under enact-sim"},
      {"launch:\n  - node:\n      name: ffd\n      exec: enact-ffd\n      component:\n        - {name: guide, plugin: guide_spring, library: " +
           std::string(ENACT_GUIDE_SPRING) + "}\n",
       "node 'ffd': enact-ffd runs no components", "fix: a stage of your own runs in enact-sim (after its model's step) or in enact-rt's tick"},
  });
}

}  // namespace
}  // namespace enact::test
