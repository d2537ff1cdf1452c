// Sweep files and their jobs (core/experiment/sweep.h): the grid's order, seeds that depend on
// a job's coordinates only, the job's command, the merged table sorted by coordinates, a
// changed results.csv refused, SHA-256 against the standard's vectors, and bad files refused
// with file:line. No job runs here (tests/sweep runs them on real executors).
#include "core/experiment/sweep.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "tests/support/refusal.h"
#include "tests/support/test_util.h"

namespace enact::experiment {
namespace {

const std::string kHead = "experiment: " + test::source_path("launch/experiments/bridge_quick.yaml") + "\n";

std::string write_sweep(const test::TempDir& dir, const std::string& body, int seed = 3) {
  const std::string path = dir.file("sweep.yaml");
  test::write_file(path, kHead + "seed: " + std::to_string(seed) + "\n" + body);
  return path;
}

std::string sweep_error(const std::string& body) {
  return test::error_of_file("bad.yaml", kHead + body, [](const std::string& path) { load_sweep(path); });
}

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(Sweep, Sha256IsTheStandardsOnItsVectors) {
  // FIPS 180-4's examples, and the empty message
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"), "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sweep, JobsFollowTheGridOrderAndTheirSeedsTheirCoordinatesOnly) {
  const test::TempDir dir;
  const SweepSpec spec = load_sweep(write_sweep(dir, "replicates: 2\ngrid:\n  rate_hz: [1000, 2000]\n  model: [CM0, CM2, CM3]\n"));
  const std::vector<SweepJob> jobs = sweep_jobs(spec);
  ASSERT_EQ(jobs.size(), 12u);
  EXPECT_EQ(jobs[0].name, "rate_hz-1000_model-CM0_r001");
  EXPECT_EQ(jobs[1].name, "rate_hz-1000_model-CM0_r002");
  EXPECT_EQ(jobs[2].name, "rate_hz-1000_model-CM2_r001");
  EXPECT_EQ(jobs[11].name, "rate_hz-2000_model-CM3_r002");
  std::set<std::uint64_t> seeds;
  for (const SweepJob& j : jobs) {
    EXPECT_LT(j.seed, 1'000'000'000u);
    seeds.insert(j.seed);
  }
  EXPECT_EQ(seeds.size(), jobs.size()) << "every job its own seed";
  // another value in an axis: every job already there keeps its seed (another index)
  const std::vector<SweepJob> more = sweep_jobs(load_sweep(write_sweep(dir, "replicates: 2\ngrid:\n  rate_hz: [500, 1000, 2000]\n  model: [CM0, CM2, CM3]\n")));
  for (const SweepJob& j : jobs) {
    const auto it = std::find_if(more.begin(), more.end(), [&](const SweepJob& m) { return m.name == j.name; });
    ASSERT_NE(it, more.end()) << j.name;
    EXPECT_EQ(it->seed, j.seed) << j.name;
    EXPECT_NE(it->index, j.index) << j.name;
  }
  // another sweep seed: other seeds
  const std::vector<SweepJob> reseeded = sweep_jobs(load_sweep(write_sweep(dir, "replicates: 2\ngrid:\n  rate_hz: [1000, 2000]\n  model: [CM0, CM2, CM3]\n", 4)));
  EXPECT_NE(reseeded[0].seed, jobs[0].seed);
}

TEST(Sweep, AJobIsTheExperimentWithItsValues) {
  const test::TempDir dir;
  const SweepSpec spec = load_sweep(write_sweep(dir, "subjects: 2\ngrid:\n  rate_hz: [1000]\n  model: [CM2]\n  scene: [$(dirname)/b.yaml]\n"));
  const SweepJob job = sweep_jobs(spec)[0];
  const std::vector<std::string> c = experiment_command(spec, job, "/out/x");
  const std::vector<std::string> expected{"experiment", spec.experiment, "--clock", "simulated", "--seed", std::to_string(job.seed), "--out", "/out/x",
                                          "--subjects", "2", "--arg", "rate_hz=1000", "--arg", "scene=" + dir.file("b.yaml"), "--conditions", "CM2"};
  EXPECT_EQ(c, expected);
  EXPECT_EQ(job.name, "rate_hz-1000_model-CM2_scene-b_r001") << "a path by its stem";
}

TEST(Sweep, TheMergedTableIsSortedByCoordinatesAndRefusesAChangedJob) {
  const test::TempDir dir;
  const SweepSpec spec = load_sweep(write_sweep(dir, "replicates: 2\ngrid:\n  rate_hz: [1000, 2000]\n"));
  const std::vector<SweepJob> jobs = sweep_jobs(spec);
  const std::string out = dir.file("out");
  // the jobs done in another order than the grid's; job 2 not done (a partial folder)
  for (std::size_t k : {3u, 0u, 1u}) {
    std::filesystem::create_directories(job_dir(out, jobs[k]));
    const std::string results = "subject,condition\n" + std::to_string(k) + ",CM1\n";
    test::write_file(job_dir(out, jobs[k]) + "/results.csv", results);
    write_job_record(job_dir(out, jobs[k]), jobs[k], {true, 0, 1.5, "h", sha256_hex(results)});
  }
  std::filesystem::create_directories(partial_dir(out, jobs[2]));
  test::write_file(partial_dir(out, jobs[2]) + "/results.csv", "subject,condition\n2,CM1\n");
  EXPECT_EQ(merge_sweep(spec, jobs, out, "enact test", "0123abc-dirty"), 3u);
  const std::string s0 = std::to_string(jobs[0].seed), s1 = std::to_string(jobs[1].seed), s3 = std::to_string(jobs[3].seed);
  EXPECT_EQ(read(out + "/results.csv"), "rate_hz,replicate,seed,subject,condition\n1000,1," + s0 + ",0,CM1\n1000,2," + s1 + ",1,CM1\n2000,2," + s3 + ",3,CM1\n");
  EXPECT_EQ(job_state(out, jobs[2]), JobState::missing) << "a partial folder without a record: a killed job";
  const std::string manifest = read(out + "/manifest.json");
  EXPECT_NE(manifest.find("\"sweep_sha256\": \"" + spec.sha256 + "\""), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("\"enact\": \"enact test\",\n  \"enact_commit\": \"0123abc-dirty\""), std::string::npos) << manifest;
  EXPECT_NE(manifest.find("\"state\": \"not done\""), std::string::npos) << manifest;
  // a done job's results changed after it: refused, naming the file and the fix
  test::write_file(job_dir(out, jobs[3]) + "/results.csv", "subject,condition\n9,CM1\n");
  const std::string e = test::error_of([&] { merge_sweep(spec, jobs, out, "enact test", "0123abc-dirty"); });
  EXPECT_NE(e.find(job_dir(out, jobs[3]) + "/results.csv"), std::string::npos) << e;
  EXPECT_NE(e.find("fix:"), std::string::npos) << e;
}

TEST(Sweep, AJobsSeedIsTheSameWhereverTheSweepAndItsFilesAre) {
  // a scene axis written three ways (beside the sweep, absolute, relative); the same sweep
  // and files in another folder: the same seeds, though every path differs
  const auto seeds = [](const test::TempDir& dir) {
    std::filesystem::create_directories(dir.file("scenes"));
    for (const char* f : {"scenes/a.yaml", "scenes/b.yaml", "scenes/c.yaml"}) test::write_file(dir.file(f), "x: 1\n");
    const SweepSpec spec = load_sweep(write_sweep(dir, "grid:\n  scene: [$(dirname)/scenes/a.yaml, " + dir.file("scenes/b.yaml") + ", scenes/c.yaml]\n"));
    std::vector<std::uint64_t> out;
    for (const SweepJob& j : sweep_jobs(spec)) out.push_back(j.seed);
    EXPECT_EQ(sweep_jobs(spec)[1].values[0], dir.file("scenes/b.yaml"));
    return out;
  };
  const test::TempDir here, there;
  const std::vector<std::uint64_t> a = seeds(here), b = seeds(there);
  ASSERT_EQ(a.size(), 3u);
  EXPECT_EQ(a, b);
  EXPECT_EQ(std::set<std::uint64_t>(a.begin(), a.end()).size(), 3u) << "each point its own seed";
}

TEST(Sweep, ItsInputsAreEveryFileItsJobsRead) {
  // an experiment beside the sweep naming its subject (relative) and the shipped trial graph
  // (absolute), which names its scene by $(dirname); a model file in the conditions; a scene
  // in the grid naming a mesh beside it
  const test::TempDir dir;
  std::filesystem::create_directories(dir.file("subjects"));
  test::write_file(dir.file("subjects/s.yaml"), test::read_file(test::source_path("launch/experiments/subjects/quick.yaml")));
  test::write_file(dir.file("experiment.yaml"), "name: e\nsubjects: 1\nvirtual_subject: subjects/s.yaml\nconditions: [CM1]\nlimit_s: 2\ngraph: " +
                                                    test::source_path("launch/experiments/trial_rt.yaml") + "\n");
  test::write_file(dir.file("mine.yaml"), "name: edges-only\nforce: [0, 3, 12, 15]\npins: contact\n");
  test::write_file(dir.file("mesh.obj"), "v 0 0 0\n");
  test::write_file(dir.file("scene.yaml"), "objects:\n  - {mesh: mesh.obj, note: $(var x)}\n");
  test::write_file(dir.file("sweep.yaml"), "experiment: experiment.yaml\nconditions: [mine.yaml]\ngrid:\n  scene: [$(dirname)/scene.yaml]\n  rate_hz: [1000]\n");
  const std::vector<std::string> expected{dir.file("experiment.yaml"), dir.file("mesh.obj"), dir.file("mine.yaml"), dir.file("scene.yaml"),
                                          dir.file("subjects/s.yaml"), dir.file("sweep.yaml"),
                                          std::filesystem::weakly_canonical(test::source_path("launch/scenes/bridge.yaml")).string(),
                                          test::source_path("launch/experiments/trial_rt.yaml")};
  std::vector<std::string> inputs = sweep_inputs(load_sweep(dir.file("sweep.yaml")));
  for (std::string& f : inputs) f = std::filesystem::weakly_canonical(f).string();
  std::vector<std::string> sorted = expected;
  for (std::string& f : sorted) f = std::filesystem::weakly_canonical(f).string();
  std::sort(sorted.begin(), sorted.end());
  std::sort(inputs.begin(), inputs.end());
  EXPECT_EQ(inputs, sorted);
}

TEST(Sweep, TheBodysStiffnessIsSweptFromTheStartAndABadValueIsRefusedAtItsLine) {
  // a live number of the simulator's as a grid axis: each job's trial graph is given it at
  // start (launch/experiments/trial_rt.yaml: stiffness_n_per_m); the whole grid is checked
  // against the parameter table before any job runs
  const test::TempDir dir, out;
  // the trial graph's nodes are found as the enact beside them finds them
  const std::filesystem::path nodes = std::filesystem::path(ENACT_CLI).parent_path().parent_path();
  std::string path = std::getenv("PATH") ? std::getenv("PATH") : "/usr/bin:/bin";
  for (const char* exec : {"enact-logger", "enact-rt"}) path = (nodes / exec).string() + ":" + path;
  setenv("PATH", path.c_str(), 1);
  const SweepSpec good = load_sweep(write_sweep(dir, "grid:\n  stiffness_n_per_m: [800, 1600]\n"));
  const std::vector<std::string> none = check_sweep(good, out.path());
  EXPECT_TRUE(none.empty()) << (none.empty() ? "" : none[0]);
  const std::vector<std::string> c = experiment_command(good, sweep_jobs(good)[1], "/out/x");
  EXPECT_NE(std::find(c.begin(), c.end(), "stiffness_n_per_m=1600"), c.end());
  const SweepSpec bad = load_sweep(write_sweep(dir, "grid:\n  stiffness_n_per_m: [800,\n    -5]\n"));
  const std::vector<std::string> problems = check_sweep(bad, out.path());
  ASSERT_GE(problems.size(), 1u);
  for (const std::string& p : problems) EXPECT_NE(p.find("sweep.yaml:5: stiffness_n_per_m: -5"), std::string::npos) << p;
  EXPECT_NE(problems[0].find("sweep.yaml:5: stiffness_n_per_m: -5"), std::string::npos) << problems[0];
  EXPECT_NE(problems[0].find("out of range"), std::string::npos) << problems[0];
}

TEST(Sweep, BadFilesAreRefusedAtTheirLine) {
  const auto refused = [](const std::string& body, const std::string& at, const std::string& what) {
    const std::string e = sweep_error(body);
    EXPECT_NE(e.find("bad.yaml:" + at + ":"), std::string::npos) << e;
    EXPECT_NE(e.find(what), std::string::npos) << e;
    EXPECT_NE(e.find("fix:"), std::string::npos) << e;
  };
  refused("grid:\n  rate_hz: [1000]\nreplicate: 2\n", "4", "replicate");                      // an unknown key
  refused("grid:\n  stiffness: [1, 2]\n", "3", "stiffness");                                // not a launch argument
  refused("grid:\n  noise_seed: [1, 2]\n", "3", "set by the experiment runner");             // the runner's
  refused("grid:\n  rate_hz: []\n", "3", "needs a list");                                    // empty
  refused("grid:\n  rate_hz: [1000, 2000, 1000]\n", "3", "listed twice");                   // twice
  refused("grid:\n  rate_hz: [1000]\nreplicates: 0\n", "4", "replicates");                    // no replicate
  refused("conditions: [CM1, CM9]\ngrid:\n  rate_hz: [1000]\n", "2", "CM9");                  // not a model
  const std::string e = test::error_of_file("bad.yaml", "experiment: nowhere.yaml\ngrid: {rate_hz: [1]}\n", [](const std::string& p) { load_sweep(p); });
  EXPECT_NE(e.find("bad.yaml:1:"), std::string::npos) << e;
  EXPECT_NE(e.find("nowhere.yaml"), std::string::npos) << e;
}

}  // namespace
}  // namespace enact::experiment
