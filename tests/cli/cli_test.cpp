// enact --help / check / simulate / path on the bridge scene.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_support.h"

namespace enact::test {
namespace {

constexpr const char* kPython = "/usr/bin/python3";
constexpr const char* kCsvHeader = "t_s,x_m,y_m,z_m,fx_n,fy_n,fz_n,contacts,pins,on_top,progress,fault";

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string line;
  while (std::getline(ss, line)) out.push_back(line);
  return out;
}

std::vector<std::string> cells_of(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream ss(row);
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(cell);
  return out;
}

TEST(Cli, HelpExitsZero) {
  const RunResult r = enact("--help");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("usage: enact"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("simulate"), std::string::npos) << r.out;
}

// every subcommand a command's own help gives (its "enact COMMAND SUB" usage lines) is in
// `enact --help`, on that command's lines
TEST(Cli, HelpListsEverySubcommand) {
  const std::string usage = enact("--help").out;
  for (const std::string command : {"param", "topic", "node", "keys", "graph"}) {
    std::string listed;  // the synopses of `command` in enact --help
    for (const std::string& line : lines_of(usage)) {
      if (line.rfind("  " + command + " ", 0) == 0) listed += line.substr(0, line.find("  ", 2)) + "\n";
    }
    for (const std::string& line : lines_of(enact(command + " --help").out)) {
      const std::size_t at = line.find("enact " + command + " ");
      if (at == std::string::npos || line.find_first_not_of(' ', line.rfind("usage:", 0) == 0 ? 6 : 0) != at) continue;
      const std::string sub = line.substr(at + 7 + command.size(), line.find(' ', at + 7 + command.size()) - (at + 7 + command.size()));
      EXPECT_NE(listed.find(sub), std::string::npos) << "enact --help does not list `enact " << command << " " << sub << "`:\n" << listed;
    }
  }
}

TEST(Cli, NoArgumentsIsAUsageError) { EXPECT_EQ(enact("").exit_code, 2); }

// docs/cli.md is what the code generates: a command or parameter added, renamed or
// re-documented without regenerating it fails here
TEST(Cli, TheCheckedInReferenceIsWhatTheCodeGenerates) {
  const RunResult r = enact("help --markdown");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("| `enact simulate SCENE` |"), std::string::npos);
  EXPECT_NE(r.out.find("| `stiffness_n_per_m` |"), std::string::npos) << "the simulator's live parameters are listed";
  EXPECT_EQ(r.out, read_file(source_path("docs/cli.md"))) << "docs/cli.md is out of date: regenerate it with `enact help --markdown > docs/cli.md`";
}

TEST(Cli, UnknownCommandExitsTwo) { EXPECT_EQ(enact("frobnicate").exit_code, 2); }

TEST(Cli, UnknownOptionExitsTwo) {
  const RunResult r = enact("check " + bridge_scene() + " --bogus");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--bogus"), std::string::npos) << r.err;
  EXPECT_EQ(enact("simulate " + bridge_scene() + " --frobnicate 3").exit_code, 2);
}

TEST(CliCheck, BridgeIsStable) {
  const RunResult r = enact("check " + bridge_scene());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("verdict     stable\n"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("UNSTABLE"), std::string::npos) << r.out;
}

// the figure live changes are held to is the one the simulator's planner refuses with (and
// the viewer shows): the bridge on the ERGOS at 5 kHz, 17 body points at 6000 N/m and 0.02 N s/m
TEST(CliCheck, SaysTheLiveChangeBoundTheRefusalsGive) {
  const RunResult r = enact("check " + bridge_scene());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("at most 10.54 N s/m"), std::string::npos) << r.out;
  const RunResult fast = enact("check " + bridge_scene() + " --rate 44000");
  EXPECT_NE(fast.out.find("at most 6.00 N s/m"), std::string::npos) << "passive at 44 kHz: the device damping bounds it\n" << fast.out;
}

TEST(CliCheck, JsonHasTheGeometry) {
  const RunResult r = enact("check " + bridge_scene() + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* key : {"\"centerline_m\"", "\"width_m\"", "\"top_z_m\"", "\"offsets_m\""}) {
    EXPECT_NE(r.out.find(key), std::string::npos) << key;
  }
  if (!std::filesystem::exists(kPython)) GTEST_SKIP() << "no " << kPython << ": string checks only";
  // parse it for real and check the bridge's figures
  const TempDir dir;
  write_file(dir.file("check.json"), r.out);
  const RunResult py = run(std::string(kPython) + " -c '"
                           "import json, sys\n"
                           "d = json.load(open(sys.argv[1]))\n"
                           "b = [o for o in d[\"objects\"] if o[\"name\"] == \"bridge\"][0]\n"
                           "assert len(b[\"centerline_m\"]) == 4, b\n"
                           "assert abs(b[\"width_m\"] - 0.010) < 1e-12, b\n"
                           "assert abs(b[\"top_z_m\"] - 0.012) < 1e-12, b\n"
                           "assert len(d[\"bodies\"][0][\"offsets_m\"]) == 16\n"
                           "assert d[\"stable\"] is True\n"
                           "' " + dir.file("check.json"));
  EXPECT_EQ(py.exit_code, 0) << py.err;
}

// the example scene of objects beyond boxes: stable and passive, each object named by its type
TEST(CliCheck, AcceptsMeshesHeightMapsSpheresAndCapsules) {
  const RunResult r = enact("check " + source_path("launch/scenes/shapes.yaml") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* type : {"heightmap", "mesh", "sphere", "capsule", "plane"}) {
    EXPECT_NE(r.out.find(std::string("\"type\": \"") + type + "\""), std::string::npos) << type;
  }
  EXPECT_NE(r.out.find("\"triangles\": 320"), std::string::npos) << r.out;  // 8 x 8 cells: 4 a cell, 4 a boundary edge
  EXPECT_NE(r.out.find("\"stable\": true"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"passive\": true"), std::string::npos) << r.out;
}

// a scene without a task (two boxes with a gap) is summarised without the task's columns,
// and its metrics file has no task metrics; the bridge keeps them
TEST(CliSimulate, ASceneWithoutATaskHasNoTaskColumns) {
  const TempDir dir;
  const std::string scene = source_path("launch/scenes/two_boxes.yaml"), path = dir.file("path.csv");
  write_file(path, "t_s,x_m,y_m,z_m\n0,-0.012,0.003,0.0115\n1,0.018,0.003,0.0098\n");
  const RunResult r = enact("simulate " + scene + " --input " + path + " --metrics " + dir.file("m.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = lines_of(r.out);
  ASSERT_GE(lines.size(), 4u) << r.out;
  EXPECT_EQ(lines[0].find("falls"), std::string::npos) << r.out;
  EXPECT_EQ(lines[0].find("done"), std::string::npos) << r.out;
  EXPECT_NE(lines[0].find("faults"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("no task in this scene"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("live, a simulated hand tracks it behind a spring"), std::string::npos) << "the offline/live difference is said where it shows\n" << r.out;
  const std::string json = read_file(dir.file("m.json"));
  EXPECT_NE(json.find("\"task\": false"), std::string::npos) << json;
  EXPECT_EQ(json.find("\"falls\""), std::string::npos) << json;
  const RunResult bridge = enact("simulate " + bridge_scene());
  EXPECT_NE(lines_of(bridge.out)[0].find("falls"), std::string::npos) << bridge.out;
  EXPECT_NE(lines_of(bridge.out)[0].find("done"), std::string::npos) << bridge.out;
}

TEST(CliSimulate, WritesCsvAndMetrics) {
  const TempDir dir;
  const RunResult r = enact("simulate " + bridge_scene() + " --out " + dir.file("x.csv") + " --metrics " + dir.file("m.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> rows = lines_of(read_file(dir.file("x.csv")));
  ASSERT_GT(rows.size(), 1u);
  EXPECT_EQ(rows[0], kCsvHeader);
  EXPECT_EQ(cells_of(rows[1]).size(), 12u);
  EXPECT_EQ(cells_of(rows[1])[8].size(), 16u);  // one 0/1 per pin
  const std::string json = read_file(dir.file("m.json"));
  EXPECT_EQ(json_value(json, "falls"), "1") << json;
  EXPECT_EQ(json_value(json, "completed"), "true") << json;
  for (const char* key : {"time_total_s", "time_out_s", "ratio"}) EXPECT_FALSE(json_value(json, key).empty()) << key;
  EXPECT_EQ(json_value(json, "steps"), std::to_string(rows.size() - 1));
}

TEST(CliSimulate, TwoRunsAreByteIdentical) {
  const TempDir dir;
  for (const char* run_name : {"a", "b"}) {
    const std::string n(run_name);
    const RunResult r =
        enact("simulate " + bridge_scene() + " --out " + dir.file(n + ".csv") + " --metrics " + dir.file(n + ".json"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const std::string csv = read_file(dir.file("a.csv"));
  EXPECT_GT(csv.size(), 100000u);
  EXPECT_TRUE(csv == read_file(dir.file("b.csv")));
  EXPECT_EQ(read_file(dir.file("a.json")), read_file(dir.file("b.json")));
}

TEST(CliSimulate, InputAlongTheFirstSegment) {
  // a straight line along the top of the first segment, pressed 0.1 mm, over 2 s
  const TempDir dir;
  write_file(dir.file("line.csv"),
             "t_s,x_m,y_m,z_m\n"
             "0,-0.0074246,-0.0222739,0.0119\n"
             "2,0.0074246,-0.0074246,0.0119\n");
  const RunResult r = enact("simulate " + bridge_scene() + " --input " + dir.file("line.csv") + " --out " + dir.file("x.csv") +
                            " --metrics " + dir.file("m.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> rows = lines_of(read_file(dir.file("x.csv")));
  ASSERT_EQ(rows.size(), 1u + 10001u);  // header + 2 s at 5 kHz, both ends
  const auto first = cells_of(rows[1]);
  const auto last = cells_of(rows.back());
  EXPECT_EQ(first[0], "0");
  EXPECT_EQ(first[1], "-0.0074246");
  EXPECT_EQ(last[0], "2");
  EXPECT_EQ(last[2], "-0.0074246");
  EXPECT_NEAR(std::stod(last[10]), 1.0 / 3.0, 0.01);  // progress: end of the 1st of 3 equal segments
  for (std::size_t i = 1; i < rows.size(); ++i) ASSERT_EQ(cells_of(rows[i])[9], "1") << "off the top at row " << i;
  const std::string json = read_file(dir.file("m.json"));
  EXPECT_EQ(json_value(json, "falls"), "0") << json;
  EXPECT_EQ(json_value(json, "completed"), "false") << json;
}

TEST(CliPath, FedBackGivesTheSameMetrics) {
  const TempDir dir;
  const RunResult path = enact("path " + bridge_scene() + " -o " + dir.file("path.csv"));
  ASSERT_EQ(path.exit_code, 0) << path.err;
  EXPECT_EQ(lines_of(read_file(dir.file("path.csv")))[0], "t_s,x_m,y_m,z_m");
  ASSERT_EQ(enact("simulate " + bridge_scene() + " --metrics " + dir.file("builtin.json")).exit_code, 0);
  const RunResult fed = enact("simulate " + bridge_scene() + " --input " + dir.file("path.csv") + " --metrics " + dir.file("fed.json"));
  ASSERT_EQ(fed.exit_code, 0) << fed.err;
  const std::string builtin = read_file(dir.file("builtin.json"));
  const std::string from_file = read_file(dir.file("fed.json"));
  for (const char* key : {"steps", "falls", "time_total_s", "time_out_s", "ratio", "completed", "progress"}) {
    EXPECT_EQ(json_value(from_file, key), json_value(builtin, key)) << key;
  }
  EXPECT_EQ(json_value(builtin, "falls"), "1");
}

TEST(CliPath, StdoutWhenNoOutputFile) {
  const RunResult r = enact("path " + bridge_scene());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> rows = lines_of(r.out);
  ASSERT_GT(rows.size(), 100u);
  EXPECT_EQ(rows[0], "t_s,x_m,y_m,z_m");
  EXPECT_EQ(cells_of(rows[1]).size(), 4u);
}

}  // namespace
}  // namespace enact::test
