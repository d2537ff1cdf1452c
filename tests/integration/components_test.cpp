// enact-rt's component list is data: a container that names its components (sim, ffd,
// tactile, each with its parameters) runs exactly as one that names none and gets the
// default three, its components' parameters given as the container's (sim.scene, ...).
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "core/record/reader.h"
#include "msgs/force_command.pb.h"
#include "tests/integration/integration_util.h"

namespace enact::test {
namespace {

// every recorded ffd/force, serialized, by the device state it answers
std::map<std::uint64_t, std::string> forces(const std::string& recording) {
  std::map<std::uint64_t, std::string> out;
  msgs::ForceCommand force;
  record::Reader(recording).for_each([&](const record::Message& m) {
    if (m.topic == "ffd/force" && force.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      out[force.answered_seq()] = force.force().SerializeAsString();
    }
    return true;
  });
  return out;
}

// a logger, then the container: 1 s of the bridge under a scripted hand, in simulated time
std::string graph(const std::string& recording, const std::string& container) {
  return "launch:\n"
         "  - node: {name: logger, exec: enact-logger, param: [{name: output, value: " + recording + "}]}\n"
         "  - container:\n"
         "      name: rt\n"
         "      required: false\n"
         "      param:\n"
         "        - {name: duration_s, value: \"1\"}\n"
         "        - {name: observers, value: \"1\"}\n" + container;
}

TEST(ContainerComponents, NamedExplicitlyRunsAsTheDefault) {
  TempDir dir;
  const std::string scene = source_path("launch/scenes/bridge.yaml"), path = source_path("launch/paths/bridge_walk.csv");
  const std::string named = dir.file("named.yaml"), defaulted = dir.file("default.yaml");
  write_file(named, graph(dir.file("named.mcap"), "      component:\n"
                                                  "        - {name: sim, plugin: sim, param: [{name: scene, value: " + scene + "}, {name: model, value: CM2}]}\n"
                                                  "        - {name: ffd, plugin: ffd, param: [{name: hand_path, value: " + path + "}, {name: start_scene, value: " + scene + "}]}\n"
                                                  "        - {name: tactile, plugin: tactile}\n"));
  write_file(defaulted, graph(dir.file("default.mcap"), "        - {name: sim.scene, value: " + scene + "}\n"
                                                        "        - {name: sim.model, value: CM2}\n"
                                                        "        - {name: ffd.hand_path, value: " + path + "}\n"
                                                        "        - {name: ffd.start_scene, value: " + scene + "}\n"));
  for (const std::string& file : {named, defaulted}) {
    const RunResult r = run(std::string(ENACT_CLI) + " launch " + file + " --clock simulated --duration 6");
    EXPECT_NE(r.out.find("the hand felt"), std::string::npos) << file << "\n" << r.out << r.err;
  }
  const std::map<std::uint64_t, std::string> a = forces(dir.file("named.mcap")), b = forces(dir.file("default.mcap"));
  EXPECT_GT(a.size(), 4000u) << "1 s at 5 kHz, all but the last in flight";
  std::size_t common = 0;
  for (const auto& [seq, force] : a) {
    const auto other = b.find(seq);
    if (other == b.end()) continue;
    ++common;
    EXPECT_EQ(other->second, force) << "the force answering state " << seq;
  }
  EXPECT_GT(common, 4000u);
}

}  // namespace
}  // namespace enact::test
