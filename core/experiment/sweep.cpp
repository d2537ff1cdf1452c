#include "core/experiment/sweep.h"

#include <sys/file.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/config/number.h"
#include "core/config/yaml.h"
#include "core/experiment/plan_file.h"
#include "core/experiment/results.h"
#include "core/experiment/runner.h"
#include "core/math/random.h"

namespace enact::experiment {
namespace {

namespace fs = std::filesystem;

// an experiment's seed is at most this (a node parameter carries whole numbers up to 1e9)
constexpr std::uint64_t kJobSeedRange = 1'000'000'000;

// a value as a part of a folder name: a path by its stem, then letters, digits, '-', '_'
std::string value_name(const std::string& value) {
  const std::string v = value.find('/') != std::string::npos ? fs::path(value).stem().string() : value;
  return file_safe(v);
}

// the text of a JSON string
std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += std::string("\\") + c;
    else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw config::Error(path + ": cannot be read\n  fix: check that the file is there and readable");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// writes `text` to `path` through a temporary file renamed over it (never half a file)
void write_whole(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out.flush()) throw config::Error(tmp + ": cannot be written\n  fix: check the folder's space and permissions");
  }
  fs::rename(tmp, path);
}

// a condition as written in the sweep file: a model file relative to it made absolute, a
// preset (or anything else: refused later with its line) as it is
std::string model_value(const std::string& written, const std::string& sweep_file) {
  const fs::path beside = fs::absolute(fs::path(sweep_file).parent_path() / written);
  return !fs::path(written).is_absolute() && fs::is_regular_file(beside) ? beside.lexically_normal().string() : written;
}

// true when a process holds the job's lock (a job running)
bool lock_held(const std::string& path) {
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool held = flock(fd, LOCK_EX | LOCK_NB) != 0;
  close(fd);
  return held;
}

}  // namespace

SweepSpec load_sweep(const std::string& path) {
  const YAML::Node root = config::load_file(path);
  const config::Map m(root, path, "sweep", {"name", "description", "experiment", "seed", "replicates", "subjects", "conditions", "grid"});
  SweepSpec s;
  s.file = fs::absolute(path).lexically_normal().string();
  s.sha256 = sha256_file(path);
  s.name = m.text("name", fs::path(path).stem().string());
  s.experiment = beside(path, m.text("experiment"));
  if (!fs::is_regular_file(s.experiment)) m.fail("experiment", "no experiment file " + s.experiment, "give the experiment file, relative to the sweep file");
  s.seed = static_cast<std::uint64_t>(m.integer("seed", 1, 0, 2147483647));
  s.replicates = m.integer("replicates", 1, 1, 100000);
  if (m.has("subjects")) s.subjects = m.integer("subjects", 0, 1, 10000);
  if (m.has("conditions")) {
    const YAML::Node c = m.get("conditions");
    if (!c.IsSequence() || c.size() == 0) m.fail("conditions", "conditions must be a list", "write conditions: [CM0, CM1]");
    for (const auto& v : c) s.conditions.push_back(model_value(config::scalar(path, v, "a condition"), path));
  }
  // the experiment loads (its own file:line errors), and declares what the grid names
  const ExperimentSpec base = load_experiment(s.experiment);
  if (!s.conditions.empty()) {
    try {
      ExperimentSpec e = base;
      override_conditions(e, s.conditions);
    } catch (const config::Error& e) {
      const std::string what = e.what();
      m.fail("conditions", what.substr(0, what.find('\n')), "use computer model presets (CM0, CM1, CM2, CM3, P, T, PT) or model files relative to the sweep file");
    }
  }
  const YAML::Node grid = m.get("grid");
  if (!grid.IsMap() || grid.size() == 0) m.fail("grid", "grid must be a mapping of parameters to lists of values", "write grid: {rate_hz: [1000, 5000], model: [CM0, CM1]}");
  for (const auto& kv : grid) {
    SweepAxis axis;
    axis.name = config::scalar(path, kv.first, "a grid parameter");
    if (axis.name != kModelAxis) {
      // a launch argument the trial graph declares, not one the runner sets
      try {
        ExperimentSpec e = base;
        override_launch_args(e, {{axis.name, ""}});
      } catch (const config::Error& e) {
        const std::string what = e.what();
        config::fail(path, kv.first, "grid parameter: " + what.substr(0, what.find('\n')), "sweep a launch argument of the trial graph (e.g. rate_hz, scene), or model: the condition");
      }
    }
    if (!kv.second.IsSequence() || kv.second.size() == 0) config::fail(path, kv.second, "grid parameter '" + axis.name + "' needs a list of values", "write " + axis.name + ": [A, B]");
    for (const auto& v : kv.second) {
      // $(dirname): the sweep file's folder, $(share): enact's shipped files
      const std::string written = config::scalar(path, v, "a value of " + axis.name);
      std::string value = substitute(path, written);
      // the value in a job's seed: as written, an absolute path relative to the sweep file
      // (the same wherever the sweep and its files are moved together)
      const fs::path p(written);
      axis.seed_texts.push_back(p.is_absolute() ? p.lexically_normal().lexically_relative(fs::path(s.file).parent_path()).string() : written);
      if (axis.name == kModelAxis) value = model_value(value, path);
      if (value.find('/') != std::string::npos) value = fs::path(value).lexically_normal().string();
      if (value.find_first_of(",\n\r\"") != std::string::npos) config::fail(path, v, "a grid value cannot hold a comma, a quote or a line break", "write the value without them");
      for (std::size_t i = 0; i < axis.values.size(); ++i) {
        if (value_name(axis.values[i]) == value_name(value)) {
          config::fail(path, v, axis.name + ": '" + value + "' is listed twice (or names the same folder as '" + axis.values[i] + "')", "give each value once");
        }
      }
      axis.values.push_back(value);
      axis.lines.push_back(v.Mark().line + 1);
    }
    s.grid.push_back(axis);
  }
  return s;
}

std::vector<SweepJob> sweep_jobs(const SweepSpec& spec) {
  std::vector<SweepJob> jobs;
  std::size_t points = 1;
  for (const SweepAxis& a : spec.grid) points *= a.values.size();
  for (std::size_t p = 0; p < points; ++p) {
    // the point's value of each axis, the last axis varying fastest
    std::vector<std::string> values(spec.grid.size()), seed_texts(spec.grid.size());
    std::size_t rest = p;
    for (std::size_t i = spec.grid.size(); i-- > 0;) {
      const std::size_t v = rest % spec.grid[i].values.size();
      values[i] = spec.grid[i].values[v];
      seed_texts[i] = spec.grid[i].seed_texts[v];
      rest /= spec.grid[i].values.size();
    }
    for (int r = 1; r <= spec.replicates; ++r) {
      SweepJob j;
      j.index = jobs.size();
      j.values = values;
      j.written = seed_texts;
      j.replicate = r;
      std::string coords, name;
      for (std::size_t i = 0; i < values.size(); ++i) {
        coords += spec.grid[i].name + "=" + seed_texts[i] + ";";
        name += spec.grid[i].name + "-" + value_name(values[i]) + "_";
      }
      coords += "replicate=" + std::to_string(r);
      char rep[16];
      std::snprintf(rep, sizeof rep, "r%03d", r);
      j.name = name + rep;
      // from the sweep's seed and the coordinates alone (not where the files are, not the
      // job's place in the list)
      j.seed = math::derive_seed(spec.seed, fnv1a64(coords)) % kJobSeedRange;
      jobs.push_back(j);
    }
  }
  return jobs;
}

ExperimentSpec job_experiment(const SweepSpec& spec, const SweepJob& job) {
  ExperimentSpec e = load_experiment(spec.experiment);
  if (spec.subjects > 0) override_subjects(e, spec.subjects);
  if (!spec.conditions.empty()) override_conditions(e, spec.conditions);
  e.seed = job.seed;
  e.clock = rt::GraphClock::simulated;
  for (std::size_t i = 0; i < spec.grid.size(); ++i) {
    if (job.values[i].empty()) continue;  // check_sweep: the file's value
    if (spec.grid[i].name == kModelAxis) {
      override_conditions(e, {job.values[i]});
      continue;
    }
    override_launch_args(e, {{spec.grid[i].name, job.values[i]}});
  }
  return e;
}

std::vector<std::string> check_sweep(const SweepSpec& spec, const std::string& out) {
  std::vector<std::string> problems;
  for (std::size_t a = 0; a < spec.grid.size(); ++a) {
    const SweepAxis& axis = spec.grid[a];
    for (std::size_t v = 0; v < axis.values.size(); ++v) {
      // this value alone over the experiment's own (each value's line for its problems)
      SweepJob probe;
      probe.values.assign(spec.grid.size(), "");
      probe.values[a] = axis.values[v];
      const std::string at = spec.file + ":" + std::to_string(axis.lines[v]) + ": " + axis.name + ": " + axis.values[v] + ": ";
      try {
        const ExperimentSpec e = job_experiment(spec, probe);
        for (const std::string& p : check_trial_graphs(e, make_plan(e), out)) problems.push_back(at + p);
      } catch (const config::Error& err) {
        problems.push_back(at + err.what());
      }
    }
  }
  return problems;
}

std::vector<std::string> experiment_command(const SweepSpec& spec, const SweepJob& job, const std::string& dir) {
  std::vector<std::string> c{"experiment", spec.experiment, "--clock", "simulated", "--seed", std::to_string(job.seed), "--out", dir};
  if (spec.subjects > 0) c.insert(c.end(), {"--subjects", std::to_string(spec.subjects)});
  std::string conditions;
  for (const std::string& x : spec.conditions) conditions += (conditions.empty() ? "" : ",") + x;
  for (std::size_t i = 0; i < spec.grid.size(); ++i) {
    if (spec.grid[i].name == kModelAxis) conditions = job.values[i];
    else c.insert(c.end(), {"--arg", spec.grid[i].name + "=" + job.values[i]});
  }
  if (!conditions.empty()) c.insert(c.end(), {"--conditions", conditions});
  return c;
}

std::string sweep_identity(const SweepSpec& spec) {
  std::string t = "experiment " + spec.experiment + "\nexperiment_sha256 " + sha256_file(spec.experiment) + "\nseed " + std::to_string(spec.seed) + "\n";
  if (spec.subjects > 0) t += "subjects " + std::to_string(spec.subjects) + "\n";
  for (const std::string& c : spec.conditions) t += "condition " + c + "\n";
  return t;
}

std::string job_dir(const std::string& out, const SweepJob& job) { return out + "/jobs/" + job.name; }
std::string partial_dir(const std::string& out, const SweepJob& job) { return out + "/jobs/" + job.name + ".partial"; }

JobRecord read_job_record(const std::string& dir) {
  JobRecord r;
  const std::string path = dir + "/job.json";
  if (!fs::is_regular_file(path)) return r;
  try {
    const YAML::Node n = YAML::LoadFile(path);  // JSON is YAML
    r.exit_code = n["exit_code"].as<int>();
    r.duration_s = n["duration_s"].as<double>();
    r.host = n["host"].as<std::string>();
    r.results_sha256 = n["results_sha256"].as<std::string>();
    r.present = true;
  } catch (const YAML::Exception&) {
    // half written: as if absent (the job runs again)
  }
  return r;
}

void write_job_record(const std::string& dir, const SweepJob& job, const JobRecord& record) {
  std::string t = "{\n  \"index\": " + std::to_string(job.index) + ",\n  \"name\": " + json_string(job.name) + ",\n  \"replicate\": " +
                  std::to_string(job.replicate) + ",\n  \"seed\": " + std::to_string(job.seed) + ",\n  \"exit_code\": " + std::to_string(record.exit_code) +
                  ",\n  \"duration_s\": " + config::number(record.duration_s) + ",\n  \"host\": " + json_string(record.host) +
                  ",\n  \"results_sha256\": " + json_string(record.results_sha256) + "\n}\n";
  write_whole(dir + "/job.json", t);
}

JobState job_state(const std::string& out, const SweepJob& job) {
  if (read_job_record(job_dir(out, job)).present) return JobState::done;
  const std::string partial = partial_dir(out, job);
  if (lock_held(out + "/jobs/" + job.name + ".lock")) return JobState::running;
  if (!fs::exists(partial)) return JobState::missing;
  const JobRecord r = read_job_record(partial);
  return r.present && r.exit_code != 0 ? JobState::failed : JobState::missing;
}

std::size_t merge_sweep(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out, const std::string& version,
                        const std::string& commit) {
  std::string header;
  for (const SweepAxis& a : spec.grid) header += a.name + ",";
  header += "replicate,seed,";
  std::string table, experiment_header, manifest_jobs;
  std::size_t merged = 0;
  for (const SweepJob& j : jobs) {
    const std::string dir = job_dir(out, j);
    const JobRecord r = read_job_record(dir);
    std::string coords;
    for (std::size_t i = 0; i < j.values.size(); ++i) coords += (i ? ", " : "") + json_string(spec.grid[i].name) + ": " + json_string(j.values[i]);
    manifest_jobs += std::string(manifest_jobs.empty() ? "" : ",\n") + "    {\"index\": " + std::to_string(j.index) + ", \"name\": " + json_string(j.name) +
                     ", \"coords\": {" + coords + "}, \"replicate\": " + std::to_string(j.replicate) + ", \"seed\": " + std::to_string(j.seed);
    if (!r.present) {
      manifest_jobs += ", \"state\": " + json_string(job_state(out, j) == JobState::failed ? "failed" : "not done") + "}";
      continue;
    }
    const std::string results = dir + "/results.csv";
    const std::string text = read_all(results);
    if (sha256_hex(text) != r.results_sha256) {
      throw config::Error(results + ": its sha256 differs from the one its job recorded (job.json): the file changed after the job\n"
                          "  fix: delete the folder " + dir + " and run the sweep again (the job runs again)");
    }
    std::istringstream lines(text);
    std::string line;
    bool first = true;
    std::string prefix;
    for (const std::string& v : j.written) prefix += v + ",";
    prefix += std::to_string(j.replicate) + "," + std::to_string(j.seed) + ",";
    while (std::getline(lines, line)) {
      if (line.empty()) continue;
      if (first) {
        if (!experiment_header.empty() && line != experiment_header) throw config::Error(results + ":1: another header than the other jobs'\n  fix: delete the folder " + dir + " and run again");
        experiment_header = line;
        first = false;
        continue;
      }
      table += prefix + line + "\n";
    }
    ++merged;
    manifest_jobs += ", \"state\": \"done\", \"exit_code\": " + std::to_string(r.exit_code) + ", \"duration_s\": " + config::number(r.duration_s) +
                     ", \"host\": " + json_string(r.host) + ", \"results_sha256\": " + json_string(r.results_sha256) + "}";
  }
  write_whole(out + "/results.csv", header + (experiment_header.empty() ? std::string(kResultsHeader) : experiment_header) + "\n" + table);
  std::string axes;
  for (const SweepAxis& a : spec.grid) {
    std::string values;
    for (const std::string& v : a.values) values += (values.empty() ? "" : ", ") + json_string(v);
    axes += (axes.empty() ? "" : ", ") + json_string(a.name) + ": [" + values + "]";
  }
  write_whole(out + "/manifest.json", "{\n  \"enact\": " + json_string(version) + ",\n  \"enact_commit\": " + json_string(commit) + ",\n  \"sweep\": " + json_string(spec.file) + ",\n  \"sweep_sha256\": " +
                                          json_string(spec.sha256) + ",\n  \"experiment\": " + json_string(spec.experiment) + ",\n  \"seed\": " +
                                          std::to_string(spec.seed) + ",\n  \"replicates\": " + std::to_string(spec.replicates) + ",\n  \"grid\": {" + axes +
                                          "},\n  \"jobs_done\": " + std::to_string(merged) + ",\n  \"jobs\": [\n" + manifest_jobs + "\n  ]\n}\n");
  return merged;
}

namespace {

// each value in a YAML file's tree that names a file (beside the file, absolute or in
// enact's share) into `found`; values with $(var ...) and the like name none that exists
void named_files(const std::string& file, const YAML::Node& node, std::vector<std::string>& found) {
  if (node.IsMap()) {
    for (const auto& kv : node) named_files(file, kv.second, found);
  } else if (node.IsSequence()) {
    for (const auto& v : node) named_files(file, v, found);
  } else if (node.IsScalar() && !node.Scalar().empty() && node.Scalar().size() < 4096) {
    const std::string path = fs::path(beside(file, node.Scalar())).lexically_normal().string();
    if (fs::is_regular_file(path)) found.push_back(path);
  }
}

}  // namespace

std::vector<std::string> sweep_inputs(const SweepSpec& spec) {
  std::vector<std::string> files{spec.file, spec.experiment};
  for (const std::string& c : spec.conditions) files.push_back(c);
  for (const SweepAxis& a : spec.grid) files.insert(files.end(), a.values.begin(), a.values.end());
  // what each YAML file among them names, until no new file comes
  std::vector<std::string> inputs;
  while (!files.empty()) {
    const std::string f = files.back();
    files.pop_back();
    if (!fs::is_regular_file(f) || std::find(inputs.begin(), inputs.end(), f) != inputs.end()) continue;
    inputs.push_back(f);
    const std::string ext = fs::path(f).extension().string();
    if (ext == ".yaml" || ext == ".yml") named_files(f, config::load_file(f), files);
  }
  std::sort(inputs.begin(), inputs.end());
  return inputs;
}

// SHA-256 as FIPS 180-4 specifies it: 512-bit blocks, 64 rounds, big-endian words
std::string sha256_hex(const std::string& bytes) {
  static constexpr std::array<std::uint32_t, 64> k{
      0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5, 0xd807aa98, 0x12835b01, 0x243185be,
      0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174, 0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa,
      0x5cb0a9dc, 0x76f988da, 0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967, 0x27b70a85,
      0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85, 0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3,
      0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070, 0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f,
      0x682e6ff3, 0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};
  std::array<std::uint32_t, 8> h{0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a, 0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};
  // the message padded: a 1 bit, zeros, and its length in bits (64-bit big-endian)
  std::string m = bytes;
  const std::uint64_t bits = static_cast<std::uint64_t>(bytes.size()) * 8;
  m += static_cast<char>(0x80);
  while (m.size() % 64 != 56) m += '\0';
  for (int i = 7; i >= 0; --i) m += static_cast<char>((bits >> (8 * i)) & 0xff);
  auto rotr = [](std::uint32_t x, int n) { return (x >> n) | (x << (32 - n)); };
  for (std::size_t block = 0; block < m.size(); block += 64) {
    std::array<std::uint32_t, 64> w{};
    for (int t = 0; t < 16; ++t) {
      for (int b = 0; b < 4; ++b) w[t] = (w[t] << 8) | static_cast<unsigned char>(m[block + 4 * t + b]);
    }
    for (int t = 16; t < 64; ++t) {
      const std::uint32_t s0 = rotr(w[t - 15], 7) ^ rotr(w[t - 15], 18) ^ (w[t - 15] >> 3);
      const std::uint32_t s1 = rotr(w[t - 2], 17) ^ rotr(w[t - 2], 19) ^ (w[t - 2] >> 10);
      w[t] = w[t - 16] + s0 + w[t - 7] + s1;
    }
    std::array<std::uint32_t, 8> v = h;
    for (int t = 0; t < 64; ++t) {
      const std::uint32_t s1 = rotr(v[4], 6) ^ rotr(v[4], 11) ^ rotr(v[4], 25);
      const std::uint32_t ch = (v[4] & v[5]) ^ (~v[4] & v[6]);
      const std::uint32_t t1 = v[7] + s1 + ch + k[t] + w[t];
      const std::uint32_t s0 = rotr(v[0], 2) ^ rotr(v[0], 13) ^ rotr(v[0], 22);
      const std::uint32_t maj = (v[0] & v[1]) ^ (v[0] & v[2]) ^ (v[1] & v[2]);
      const std::uint32_t t2 = s0 + maj;
      v = {t1 + t2, v[0], v[1], v[2], v[3] + t1, v[4], v[5], v[6]};
    }
    for (int i = 0; i < 8; ++i) h[i] += v[i];
  }
  std::string hex;
  char buf[9];
  for (std::uint32_t x : h) {
    std::snprintf(buf, sizeof buf, "%08x", x);
    hex += buf;
  }
  return hex;
}

std::string sha256_file(const std::string& path) { return sha256_hex(read_all(path)); }

}  // namespace enact::experiment
