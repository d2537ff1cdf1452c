#include "core/experiment/experiment.h"

#include "core/experiment/plan_file.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <string_view>

#include "core/config/number.h"
#include "core/config/share.h"
#include "core/config/yaml.h"
#include "core/math/random.h"
#include "core/devices/virtual_subject.h"
#include "core/haptics/computer_model.h"
#include "core/launch/launch_file.h"

namespace enact::experiment {
namespace {

namespace fs = std::filesystem;

// seeds are below this: a node parameter carries whole numbers up to 1e9
constexpr std::uint64_t kSeedRange = 1'000'000'000;

// a preset, or a computer-model file relative to the experiment file; errors at its line
Condition condition(const std::string& file, const YAML::Node& at, const std::string& written) {
  const bool preset = haptics::preset(written).has_value();
  const std::string model = preset ? written : beside(file, written);
  try {
    return {haptics::resolve_computer_model(model).name, model};
  } catch (const config::Error& e) {
    config::fail(file, at, "condition '" + written + "': " + e.what(),
                 "use a computer model preset (CM0, CM1, CM2, CM3, P, T, PT) or a model file relative to the experiment file");
  }
}


std::vector<std::string> numbered(int count) {
  std::vector<std::string> ids;
  for (int i = 1; i <= count; ++i) ids.push_back(std::to_string(i));
  return ids;
}

}  // namespace

std::string substitute(const std::string& file, std::string value) {
  for (const std::string_view name : {"$(dirname)", "$(share)"}) {
    if (value.find(name) == std::string::npos) continue;
    const std::string folder = name == "$(share)" ? config::share_dir() : fs::absolute(file).parent_path().lexically_normal().string();
    for (std::size_t at = value.find(name); at != std::string::npos; at = value.find(name, at + folder.size())) value.replace(at, name.size(), folder);
  }
  return value;
}

std::string beside(const std::string& file, const std::string& written_path) {
  const std::string path = substitute(file, written_path);
  const fs::path p(path);
  const std::string written = (p.is_absolute() ? p : fs::absolute(fs::path(file).parent_path() / p)).lexically_normal().string();
  return config::locate(path, file).value_or(written);
}

std::vector<std::string> read_subjects(const config::Map& m) {
  const std::string& path = m.file();
  std::vector<std::string> subjects;
  const YAML::Node node = m.get("subjects");
  if (node.IsScalar()) return numbered(m.integer("subjects", 0, 1, 10000));
  if (!node.IsSequence() || node.size() == 0) m.fail("subjects", "subjects must be a count or a list of ids", "write subjects: 12, or subjects: [P01, P02]");
  for (const auto& id : node) {
    if (!id.IsScalar() || id.Scalar().empty()) config::fail(path, id, "a subject id must be a word", "write e.g. subjects: [P01, P02]");
    if (std::find(subjects.begin(), subjects.end(), id.Scalar()) != subjects.end()) {
      config::fail(path, id, "subject '" + id.Scalar() + "' is listed twice", "give each subject once");
    }
    subjects.push_back(id.Scalar());
  }
  return subjects;
}

std::vector<Condition> read_conditions(const config::Map& m) {
  const std::string& path = m.file();
  std::vector<Condition> out;
  const YAML::Node conditions = m.get("conditions");
  if (!conditions.IsSequence() || conditions.size() == 0) m.fail("conditions", "conditions must be a list", "write conditions: [CM0, CM1, CM2, CM3]");
  for (const auto& c : conditions) {
    if (!c.IsScalar()) config::fail(path, c, "a condition must be a preset name or a file", "write e.g. CM1 or models/mine.yaml");
    out.push_back(condition(path, c, c.Scalar()));
    for (std::size_t i = 0; i + 1 < out.size(); ++i) {
      if (out[i].label == out.back().label) config::fail(path, c, "condition '" + out.back().label + "' is listed twice", "give each condition once");
    }
  }
  return out;
}

Order read_order(const config::Map& m) {
  const std::string order = m.text("order", "random");
  if (order != "random" && order != "balanced") m.fail("order", "order '" + order + "' is not random or balanced", "write order: random (seeded per subject) or order: balanced (Latin square)");
  return order == "random" ? Order::random : Order::balanced;
}

const char* to_string(TrialKind kind) {
  switch (kind) {
    case TrialKind::familiarisation: return "familiarisation";
    case TrialKind::practice: return "practice";
    case TrialKind::measured: return "measured";
  }
  return "measured";
}

ExperimentSpec load_experiment(const std::string& given) {
  const std::string path = config::find_file(given);
  const YAML::Node root = config::load_file(path);
  const config::Map m(root, path, "experiment",
                      {"name", "description", "kind", "seed", "subjects", "virtual_subject", "conditions", "order", "limit_s",
                       "familiarisation_s", "practice_s", "graph", "launch_args"});
  if (m.text("kind", "bridge") != "bridge") m.fail("kind", "a bridge experiment's kind is bridge", "write kind: bridge, or kind: discrimination with its own keys (" + config::shipped("docs/experiments.md") + ", \"Discrimination experiments\")");
  ExperimentSpec s;
  s.file = fs::absolute(path).lexically_normal().string();
  s.name = m.text("name", fs::path(path).stem().string());
  s.seed = static_cast<std::uint64_t>(m.integer("seed", 1, 0, 2147483647));
  s.subjects = read_subjects(m);
  // who holds the device: a virtual subject (checked now), or people
  if (m.has("virtual_subject")) {
    s.virtual_subject = beside(path, m.text("virtual_subject"));
    if (!fs::is_regular_file(s.virtual_subject)) m.fail("virtual_subject", "no subject file " + s.virtual_subject, "give a virtual subject's YAML file, relative to the experiment file");
    devices::load_subject(s.virtual_subject);
  }
  s.conditions = read_conditions(m);
  // the protocol
  s.order = read_order(m);
  s.limit_s = m.positive("limit_s", s.limit_s);
  s.familiarisation_s = m.positive("familiarisation_s", 0.0, true);
  s.practice_s = m.positive("practice_s", 0.0, true);
  // the graph of a trial: a launch file, checked now with the arguments the runner gives it
  std::vector<std::string> needed{"model", "recording", "limit_s"};
  if (s.virtual_subjects()) needed.insert(needed.end(), {"subject", "subject_seed", "noise_seed"});
  read_trial_graph(m, needed, s.launch, s.launch_args);
  return s;
}

void read_trial_graph(const config::Map& m, const std::vector<std::string>& needed, std::string& launch,
                      std::vector<std::pair<std::string, std::string>>& args) {
  const std::string& path = m.file();
  launch = beside(path, m.text("graph"));
  if (!fs::is_regular_file(launch)) m.fail("graph", "no launch file " + launch, "give the trial's launch file, relative to the experiment file (e.g. trial_rt.yaml: co-located, trial.yaml: distributed)");
  if (m.has("launch_args")) {
    const YAML::Node given = m.get("launch_args");
    if (!given.IsMap()) m.fail("launch_args", "launch_args must be a mapping", "write launch_args: {rate_hz: 5000}");
    for (const auto& kv : given) {
      if (!kv.second.IsScalar()) config::fail(path, kv.second, "launch argument '" + kv.first.Scalar() + "' must be a single value", "write NAME: VALUE");
      // files beside the experiment, or shipped ones
      const std::string value = substitute(path, kv.second.Scalar());
      args.emplace_back(kv.first.Scalar(), value);
    }
  }
  try {
    // the arguments only: the executables are found when a trial starts
    const launch::LaunchDescription declared = launch::load_launch(launch, {}, [](const std::string& exec) { return exec; });
    std::vector<std::string> all = needed;
    for (const auto& [name, value] : args) all.push_back(name);
    for (const std::string& name : all) {
      const bool has = std::any_of(declared.args.begin(), declared.args.end(), [&](const launch::ArgSpec& a) { return a.name == name; });
      if (!has) m.fail("graph", "the launch file " + launch + " declares no argument '" + name + "'",
                       "give a trial launch file declaring model, recording and limit_s (and subject, subject_seed, noise_seed for virtual subjects)");
    }
  } catch (const config::Error& e) {
    const std::string what = e.what();
    if (what.rfind(path, 0) == 0) throw;
    m.fail("graph", "the launch file does not load: " + what, "fix the launch file");
  }
}

std::uint64_t fnv1a64(const std::string& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ULL;
  return h;
}

std::string file_safe(const std::string& text) {
  std::string out;
  for (char c : text) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
  return out;
}

std::vector<std::string> subjects_numbered(int count) {
  if (count < 1) throw config::Error("--subjects " + std::to_string(count) + " is not a count\n  fix: give a number from 1");
  return numbered(count);
}

void override_subjects(ExperimentSpec& spec, int count) { spec.subjects = subjects_numbered(count); }

const std::vector<std::string>& runner_launch_args() {
  static const std::vector<std::string> names{"model", "recording", "limit_s", "subject", "subject_seed", "noise_seed"};
  return names;
}

void override_launch_args(ExperimentSpec& spec, const std::vector<std::pair<std::string, std::string>>& args) {
  if (args.empty()) return;
  // the arguments only: the executables are found when a trial starts
  const launch::LaunchDescription declared = launch::load_launch(spec.launch, {}, [](const std::string& exec) { return exec; });
  for (const auto& arg : args) {
    const std::string& name = arg.first;  // a lambda cannot capture a structured binding in C++20 (clang 14)
    const auto& runner = runner_launch_args();
    if (std::find(runner.begin(), runner.end(), name) != runner.end()) {
      throw config::Error("'" + name + "' is set by the experiment runner for each trial\n  fix: give another launch argument (for the model: the conditions)");
    }
    const bool has = std::any_of(declared.args.begin(), declared.args.end(), [&](const launch::ArgSpec& a) { return a.name == name; });
    if (!has) throw config::Error("the trial graph " + spec.launch + " declares no launch argument '" + name + "'\n  fix: give one it declares (`enact launch " + spec.launch + " --check` lists them)");
    std::erase_if(spec.launch_args, [&](const auto& kv) { return kv.first == name; });
    spec.launch_args.emplace_back(name, arg.second);
  }
}

void override_conditions(ExperimentSpec& spec, const std::vector<std::string>& conditions) {
  if (conditions.empty()) throw config::Error("--conditions is empty\n  fix: give e.g. --conditions CM0,CM1");
  std::vector<Condition> out;
  for (const std::string& c : conditions) {
    // a file given relative to here, else the name as it is (a preset, or an unknown one)
    const std::string model = fs::exists(c) ? fs::absolute(c).string() : c;
    try {
      out.push_back({haptics::resolve_computer_model(model).name, model});
    } catch (const config::Error& e) {
      throw config::Error("--conditions: '" + c + "': " + e.what());
    }
  }
  spec.conditions = out;
}

std::vector<std::size_t> condition_order(Order order, std::size_t n, std::size_t subject_index, std::uint64_t seed) {
  std::vector<std::size_t> out(n);
  if (order == Order::random) {
    // Fisher-Yates with the subject's own stream
    for (std::size_t i = 0; i < n; ++i) out[i] = i;
    math::Random r(math::derive_seed(seed, 2 * subject_index));
    for (std::size_t i = n; i > 1; --i) std::swap(out[i - 1], out[r.below(i)]);
    return out;
  }
  // Williams (1949): first row 0, 1, n-1, 2, n-2, ...; row r adds r (mod n); with n odd the
  // mirrored rows follow, so each condition follows each other equally often
  std::vector<std::size_t> first{0};
  for (std::size_t lo = 1, hi = n - 1; first.size() < n;) {
    first.push_back(lo++);
    if (first.size() < n) first.push_back(hi--);
  }
  const std::size_t rows = n % 2 == 0 ? n : 2 * n;
  const std::size_t row = subject_index % rows;
  for (std::size_t j = 0; j < n; ++j) out[j] = (first[j] + row) % n;
  if (row >= n) std::reverse(out.begin(), out.end());
  return out;
}

std::vector<Trial> make_plan(const ExperimentSpec& spec) {
  std::vector<Trial> plan;
  const int width = spec.subjects.size() < 10 ? 1 : spec.subjects.size() < 100 ? 2 : 3;
  for (std::size_t s = 0; s < spec.subjects.size(); ++s) {
    const std::string& id = spec.subjects[s];
    const bool number = std::all_of(id.begin(), id.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
    char padded[16];
    std::snprintf(padded, sizeof padded, "%0*lld", width, number ? config::parse_integer(id).value_or(0) : 0LL);
    const std::string subject_stem = "s" + (number ? std::string(padded) : file_safe(id));
    const std::uint64_t subject_stream = math::derive_seed(spec.seed, 2 * s + 1);
    const std::vector<std::size_t> order = condition_order(spec.order, spec.conditions.size(), s, spec.seed);
    auto add = [&](std::size_t c, int position, TrialKind kind, double limit_s) {
      Trial t;
      t.index = plan.size();
      t.subject = id;
      t.subject_index = s;
      t.condition = spec.conditions[c];
      t.order = position;
      t.kind = kind;
      t.limit_s = limit_s;
      t.subject_seed = static_cast<std::uint32_t>(subject_stream % kSeedRange);
      t.noise_seed = static_cast<std::uint32_t>(math::derive_seed(subject_stream, 3 * c + static_cast<std::size_t>(kind)) % kSeedRange);
      t.file_stem = subject_stem + "_" + file_safe(t.condition.label) + "_" + to_string(kind);
      plan.push_back(t);
    };
    if (spec.familiarisation_s > 0.0) add(order.front(), 0, TrialKind::familiarisation, spec.familiarisation_s);
    for (std::size_t i = 0; i < order.size(); ++i) {
      if (spec.practice_s > 0.0) add(order[i], static_cast<int>(i + 1), TrialKind::practice, spec.practice_s);
      add(order[i], static_cast<int>(i + 1), TrialKind::measured, spec.limit_s);
    }
  }
  return plan;
}

}  // namespace enact::experiment
