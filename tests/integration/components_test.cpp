// enact-rt's component list is data: a container that names its components (sim, ffd,
// tactile, each with its parameters) runs exactly as one that names none and gets the
// default three, its components' parameters given as the container's (sim.scene, ...); one
// without a tactile display runs the same loop, its pins written nowhere.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "core/record/reader.h"
#include "msgs/force_command.pb.h"
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

}  // namespace
}  // namespace enact::test
