#include "core/experiment/discrimination.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/config/format.h"
#include "core/config/share.h"
#include "core/config/yaml.h"
#include "core/experiment/discrimination_graph.h"
#include "core/experiment/trial_graph.h"
#include "core/experiment/plan_file.h"
#include "core/experiment/results.h"
#include "core/math/random.h"
#include "core/sim/params.h"

namespace enact::experiment {
namespace {

namespace fs = std::filesystem;
using psychophysics::Placement;
using psychophysics::StepType;

// the live parameters a discrimination may compare: the simulator's live numbers that change
// what the hand feels (its force law), in the words of a refusal's fix
const sim::LiveNumber* comparable(const std::string& name) {
  const sim::LiveNumber* n = sim::find_live_number(name);
  return n && n->law != sim::LawChange::none ? n : nullptr;
}
std::string comparable_names() {
  std::string out;
  for (const sim::LiveNumber& n : sim::live_numbers()) {
    if (n.law != sim::LawChange::none) out += std::string(out.empty() ? "" : ", ") + n.name;
  }
  return out;
}

std::vector<double> numbers_of(const config::Map& m, const char* key) {
  const YAML::Node node = m.get(key);
  if (!node.IsSequence() || node.size() == 0) m.fail(key, std::string(key) + " must be a list of numbers", std::string("write ") + key + ": [a, b, c]");
  return config::numbers(m.file(), node, node.size(), key);
}

ProcedureSpec read_procedure(const std::string& path, const YAML::Node& node, std::size_t index) {
  if (!node.IsMap()) config::fail(path, node, "a procedure must be a mapping", "write e.g. - {kind: quest, guess: 90, trials: 60}");
  const std::string kind = node["kind"] && node["kind"].IsScalar() ? node["kind"].Scalar() : "";
  ProcedureSpec p;
  if (kind == "quest") {
    const config::Map m(node, path, "procedure", {"kind", "label", "guess", "prior_sd_log10", "p_threshold", "beta", "delta", "gamma", "grain_log10",
                                                   "range_log10", "placement", "quantile", "trials", "stop_interval_log10", "min", "max"});
    p.kind = ProcedureSpec::Kind::quest;
    auto& q = p.quest;
    q.guess_level = m.positive("guess");
    q.prior_sd_log10 = m.positive("prior_sd_log10", q.prior_sd_log10);
    q.p_threshold = m.positive("p_threshold", q.p_threshold);
    q.beta = m.positive("beta", q.beta);
    q.delta = m.positive("delta", q.delta, true);
    q.gamma = m.positive("gamma", q.gamma, true);
    q.grain_log10 = m.positive("grain_log10", q.grain_log10);
    q.range_log10 = m.positive("range_log10", q.range_log10);
    const std::string placement = m.text("placement", "mean");
    if (placement != "mean" && placement != "mode" && placement != "quantile") m.fail("placement", "placement '" + placement + "' is not mean, mode or quantile", "write placement: mean (King-Smith 1994), mode (Watson & Pelli 1983) or quantile");
    q.placement = placement == "mean" ? Placement::mean : placement == "mode" ? Placement::mode : Placement::quantile;
    q.quantile = m.positive("quantile", q.quantile);
    q.max_trials = m.integer("trials", q.max_trials, 1, 100000);
    q.stop_interval_log10 = m.positive("stop_interval_log10", 0.0, true);
    q.min_level = m.positive("min", q.min_level, true);
    q.max_level = m.positive("max", q.max_level);
    p.label = m.text("label", "quest");
    try {
      psychophysics::make_quest(q);
    } catch (const std::invalid_argument& e) {
      config::fail(path, node, std::string("QUEST: ") + e.what(), "give 0 < gamma < p_threshold < 1, delta < 1, quantile in (0, 1) and range_log10 > grain_log10");
    }
  } else if (kind == "staircase") {
    const config::Map m(node, path, "procedure", {"kind", "label", "start", "up", "down", "step_sizes", "step_type", "initial_one_down", "min", "max",
                                                   "reversals", "max_trials", "average_reversals"});
    p.kind = ProcedureSpec::Kind::staircase;
    auto& s = p.staircase;
    s.start = m.positive("start");
    s.up = m.integer("up", 1, 1, 10);
    s.down = m.integer("down", 2, 1, 10);
    s.step_sizes = numbers_of(m, "step_sizes");
    for (double step : s.step_sizes) {
      if (!(step > 0.0)) m.fail("step_sizes", "step sizes must be > 0", "write e.g. step_sizes: [0.2, 0.1, 0.05] (log10) or [40, 20, 10] (linear)");
    }
    const std::string type = m.text("step_type", "log10");
    if (type != "log10" && type != "linear") m.fail("step_type", "step_type '" + type + "' is not log10 or linear", "write step_type: log10 (level x 10^step) or linear (level + step)");
    s.step_type = type == "log10" ? StepType::log10 : StepType::linear;
    s.initial_one_down = m.flag("initial_one_down", true);
    s.min_level = m.positive("min", 0.0, true);
    s.max_level = m.positive("max", s.max_level);
    s.stop_reversals = m.integer("reversals", 12, 1, 10000);
    s.max_trials = m.integer("max_trials", 400, 1, 100000);
    s.average_reversals = m.integer("average_reversals", std::min(6, s.stop_reversals), 1, s.stop_reversals);
    p.label = m.text("label", "staircase");
  } else if (kind == "constant") {
    const config::Map m(node, path, "procedure", {"kind", "label", "levels", "repetitions"});
    p.kind = ProcedureSpec::Kind::constant;
    p.constant.levels = numbers_of(m, "levels");
    for (double level : p.constant.levels) {
      if (!(level > 0.0)) m.fail("levels", "levels must be > 0 (the comparison's excess over the reference)", "write e.g. levels: [20, 40, 80]");
    }
    p.constant.repetitions = m.integer("repetitions", 10, 1, 10000);
    p.label = m.text("label", "constant");
  } else {
    config::fail(path, node, "procedure " + std::to_string(index + 1) + ": kind '" + kind + "' is not quest, staircase or constant",
                 "write kind: quest, kind: staircase or kind: constant");
  }
  return p;
}

VirtualObservers read_observers(const config::Map& parent, const std::vector<Condition>& conditions) {
  const config::Map m(parent.get("virtual_observers"), parent.file(), "virtual_observers", {"weber_fraction", "weber_sd_log", "exponent", "lapse"});
  VirtualObservers o;
  // one for all conditions, or one per condition in their order
  const YAML::Node w = m.get("weber_fraction");
  if (!w.IsScalar() && (!w.IsSequence() || w.size() != conditions.size())) {
    m.fail("weber_fraction", "weber_fraction must be one number, or one per condition (" + std::to_string(conditions.size()) + ")",
           "write e.g. weber_fraction: 0.15, or [0.16, 0.12] for conditions [CM0, CM1]");
  }
  const std::vector<double> weber = w.IsScalar() ? std::vector<double>(conditions.size(), m.positive("weber_fraction"))
                                                 : config::numbers(parent.file(), w, conditions.size(), "weber_fraction (one per condition)");
  for (std::size_t i = 0; i < conditions.size(); ++i) {
    if (!(weber[i] > 0.0)) m.fail("weber_fraction", "a Weber fraction must be > 0", "write e.g. weber_fraction: 0.15, or [0.16, 0.12] for conditions [CM0, CM1]");
    o.weber_fraction[conditions[i].label] = weber[i];
  }
  o.weber_sd_log = m.positive("weber_sd_log", o.weber_sd_log, true);
  o.exponent = m.positive("exponent", o.exponent);
  o.lapse = m.positive("lapse", o.lapse, true);
  if (o.lapse >= 0.5) m.fail("lapse", "a lapse rate must be below 0.5", "write e.g. lapse: 0.02");
  return o;
}

// a level as trials.csv stores it: full precision, so a resumed procedure finds its own levels
std::string exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

const char* const kDiscriminationTrialsHeader =
    "subject,condition,order,procedure,trial,parameter,reference,comparison,level,reference_interval,chosen_interval,correct,response_time_s";
const char* const kDiscriminationSummaryHeader =
    "subject,condition,order,trials,jnd,jnd_low,jnd_high,bootstrap_low,bootstrap_high,weber_fraction,lapse,spread,true_jnd";

bool is_discrimination(const std::string& path) {
  const YAML::Node root = config::load_file(config::find_file(path));
  return root.IsMap() && root["kind"] && root["kind"].IsScalar() && root["kind"].Scalar() == "discrimination";
}

DiscriminationSpec load_discrimination(const std::string& given) {
  const std::string path = config::find_file(given);
  const YAML::Node root = config::load_file(path);
  const config::Map m(root, path, "discrimination experiment",
                      {"name", "description", "kind", "seed", "subjects", "conditions", "order", "parameter", "reference", "procedures",
                       "virtual_observers", "analysis", "graph", "launch_args", "interval_s", "answer_limit_s"});
  DiscriminationSpec s;
  s.file = fs::absolute(path).lexically_normal().string();
  s.name = m.text("name", fs::path(path).stem().string());
  s.seed = static_cast<std::uint64_t>(m.integer("seed", 1, 0, 2147483647));
  s.subjects = read_subjects(m);
  s.conditions = read_conditions(m);
  s.order = read_order(m);
  // the compared parameter: a numeric live parameter of the simulator
  s.parameter = m.text("parameter");
  if (!comparable(s.parameter)) {
    m.fail("parameter", "'" + s.parameter + "' is not a numeric live parameter of the simulator", "write parameter: one of " + comparable_names());
  }
  s.reference = m.positive("reference");
  // the procedures, interleaved; labels unique
  const YAML::Node procedures = m.get("procedures");
  if (!procedures.IsSequence() || procedures.size() == 0) m.fail("procedures", "procedures must be a list", "write procedures: [{kind: quest, guess: 90, trials: 60}]");
  for (std::size_t i = 0; i < procedures.size(); ++i) {
    ProcedureSpec p = read_procedure(path, procedures[i], i);
    for (const ProcedureSpec& other : s.procedures) {
      if (other.label == p.label) config::fail(path, procedures[i], "procedure label '" + p.label + "' is used twice", "give each procedure its own label: (e.g. label: ascending)");
    }
    s.procedures.push_back(p);
  }
  // who answers: virtual observers, or people
  s.virtual_observers = m.has("virtual_observers");
  if (s.virtual_observers) s.observers = read_observers(m, s.conditions);
  // where: each trial in its graph (the default), or no graph at all (virtual observers only)
  if (!m.has("graph")) {
    m.fail("kind", "a discrimination experiment names its trials' graph",
           "write graph: trial_rt.yaml (each trial in the co-located trial graph, a launch file relative to this file), or graph: false (virtual observers, no graph)");
  }
  if (m.text("graph") == "false") {
    if (!s.virtual_observers) m.fail("graph", "graph: false runs virtual observers only: people explore the intervals on a graph", "write graph: trial_rt.yaml, or give virtual_observers");
  } else {
    read_trial_graph(m, {"model", "recording", "limit_s"}, s.launch, s.launch_args);
  }
  s.interval_s = m.positive("interval_s", s.interval_s);
  s.answer_limit_s = m.positive("answer_limit_s", s.answer_limit_s);
  // the analysis
  if (m.has("analysis")) {
    const config::Map a(m.get("analysis"), path, "analysis", {"shape", "exponent", "max_lapse", "bootstrap"});
    const std::string shape = a.text("shape", "weibull");
    const auto named = psychophysics::shape_named(shape);
    if (!named) a.fail("shape", "shape '" + shape + "' is not weibull or gaussian", "write shape: weibull or shape: gaussian");
    s.fit.shape = *named;
    s.fit.spread = a.positive("exponent", 0.0, true);
    if (s.fit.spread > 0.0 && s.fit.shape == psychophysics::Shape::gaussian) a.fail("exponent", "a cumulative Gaussian has no exponent", "remove exponent, or write shape: weibull");
    s.fit.max_lapse = a.positive("max_lapse", s.fit.max_lapse, true);
    s.fit.free_lapse = s.fit.max_lapse > 0.0;
    s.bootstrap_replicates = a.integer("bootstrap", s.bootstrap_replicates, 0, 100000);
  } else {
    s.fit.shape = psychophysics::Shape::weibull;
    s.fit.spread = 3.5;
  }
  return s;
}

std::vector<DiscriminationBlock> make_blocks(const DiscriminationSpec& spec) {
  std::vector<DiscriminationBlock> blocks;
  for (std::size_t s = 0; s < spec.subjects.size(); ++s) {
    const std::uint64_t subject_stream = math::derive_seed(spec.seed, 2 * s + 1);
    math::Random traits(math::derive_seed(subject_stream, 0));
    const double z = traits.normal();
    const std::vector<std::size_t> order = condition_order(spec.order, spec.conditions.size(), s, spec.seed);
    for (std::size_t i = 0; i < order.size(); ++i) {
      DiscriminationBlock b;
      b.subject = spec.subjects[s];
      b.subject_index = s;
      b.condition_index = order[i];
      b.condition = spec.conditions[order[i]];
      b.order = static_cast<int>(i + 1);
      b.seed = math::derive_seed(subject_stream, 1 + order[i]);
      // people: no observer (its JND unknown)
      const double weber = spec.virtual_observers ? spec.observers.weber_fraction.at(b.condition.label) * std::exp(spec.observers.weber_sd_log * z) : NAN;
      b.observer.function = {psychophysics::Shape::weibull, weber * spec.reference, spec.observers.exponent, 0.5, spec.observers.lapse};
      b.observer.seed = math::derive_seed(b.seed, 1);
      blocks.push_back(b);
    }
  }
  return blocks;
}

psychophysics::Interleaved make_procedures(const DiscriminationSpec& spec, const DiscriminationBlock& block) {
  psychophysics::Interleaved set;
  set.seed = math::derive_seed(block.seed, 2);
  for (std::size_t i = 0; i < spec.procedures.size(); ++i) {
    const ProcedureSpec& p = spec.procedures[i];
    if (p.kind == ProcedureSpec::Kind::quest) set.procedures.push_back(psychophysics::make_quest(p.quest));
    if (p.kind == ProcedureSpec::Kind::staircase) set.procedures.push_back(psychophysics::make_staircase(p.staircase));
    if (p.kind == ProcedureSpec::Kind::constant) {
      psychophysics::ConstantStimuliSettings c = p.constant;
      c.seed = math::derive_seed(block.seed, 3 + i);
      set.procedures.push_back(psychophysics::make_constant_stimuli(c));
    }
  }
  return set;
}

namespace {

// trials.csv's rows of each block (subject/condition), in order: (procedure index, level,
// correct) triples; throws config::Error on a damaged file or an unknown procedure
struct Told {
  std::size_t procedure = 0;
  double level = 0.0;
  bool correct = false;
};
std::map<std::string, std::vector<Told>> read_trials(const std::string& path, const DiscriminationSpec& spec) {
  std::map<std::string, std::vector<Told>> out;
  std::ifstream in(path);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (n == 1) {
      if (line != kDiscriminationTrialsHeader) throw config::Error(path + ":1: not a discrimination trials file\n  fix: give a new --out folder, or restore the file");
      continue;
    }
    const std::vector<std::string> c = cells(line);
    const auto procedure = std::find_if(spec.procedures.begin(), spec.procedures.end(), [&](const ProcedureSpec& p) { return c.size() == 13 && p.label == c[3]; });
    if (c.size() != 13 || procedure == spec.procedures.end()) {
      throw config::Error(path + ":" + std::to_string(n) + ": a damaged row (" + line + ")\n  fix: delete this row and those after it: their trials run again");
    }
    out[c[0] + "," + c[1]].push_back({static_cast<std::size_t>(procedure - spec.procedures.begin()), std::stod(c[8]), c[11] == "1"});
  }
  return out;
}

// the manifest: everything that decides the trials and their analysis, written before the
// first trial (the study pre-registered by construction) and the same for a resumed run
std::string manifest_text(const DiscriminationSpec& spec, const std::string& file_text, const std::vector<DiscriminationBlock>& blocks) {
  char hash[32];
  std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(fnv1a64(file_text)));
  using config::number;
  std::string m = "experiment: " + spec.file + "\nexperiment_fnv1a64: " + hash + "\nseed: " + std::to_string(spec.seed) + "\nparameter: " +
                  spec.parameter + "\nreference: " + number(spec.reference) + "\nprocedures:";
  for (const ProcedureSpec& p : spec.procedures) m += " " + p.label;
  m += std::string("\nanalysis: ") + psychophysics::to_string(spec.fit.shape) + ", exponent " + (spec.fit.spread > 0.0 ? number(spec.fit.spread) : "fitted") +
       ", lapse in [0, " + number(spec.fit.free_lapse ? spec.fit.max_lapse : 0.0) + "], bootstrap " + std::to_string(spec.bootstrap_replicates) +
       ", 95 % profile-likelihood and bootstrap intervals\ntrials: " +
       (spec.on_graph() ? "each in its graph " + spec.launch + ", clock " + (spec.clock ? rt::to_string(*spec.clock) : "of the launch file") +
                              ", intervals of " + number(spec.interval_s) + " s"
                        : std::string("no graph")) +
       ", answered by " + (spec.virtual_observers ? "virtual observers" : "people") + "\nblocks: subject,condition,order,seed,observer_jnd\n";
  for (const DiscriminationBlock& b : blocks) {
    m += b.subject + "," + b.condition.label + "," + std::to_string(b.order) + "," + std::to_string(b.seed) + "," + number(b.observer.function.threshold) + "\n";
  }
  return m;
}

// the folder's manifest and experiment file: written by the first run; a run of another
// plan (file, --subjects) is refused
void check_same_plan(const DiscriminationSpec& spec, const std::string& out, const std::vector<DiscriminationBlock>& blocks) {
  std::ifstream file(spec.file);
  std::stringstream text;
  text << file.rdbuf();
  keep_or_check(out + "/manifest.txt", manifest_text(spec, text.str(), blocks), "experiment file or --subjects differ");
  keep_or_check(out + "/experiment.yaml", text.str(), "experiment file differs");
}

}  // namespace

std::string script_fit_options(const psychophysics::FitSettings& fit) {
  std::string o = std::string(" --shape ") + psychophysics::to_string(fit.shape);
  if (fit.spread > 0.0) o += " --exponent " + config::number(fit.spread);
  return o + " --max-lapse " + config::number(fit.free_lapse ? fit.max_lapse : 0.0);
}

namespace {

// the summary row of a finished block
std::string summarise(const DiscriminationSpec& spec, const DiscriminationBlock& block, const psychophysics::Interleaved& set) {
  std::vector<psychophysics::Response> all;
  for (const auto& p : set.procedures) all.insert(all.end(), p->history().begin(), p->history().end());
  const std::vector<psychophysics::LevelCount> data = psychophysics::tally(all);
  const psychophysics::Fit fit = psychophysics::fit_ml(data, spec.fit);
  const psychophysics::Interval profile = psychophysics::profile_threshold(data, spec.fit, fit);
  psychophysics::Interval bootstrap{NAN, NAN};
  if (spec.bootstrap_replicates > 0) {
    // the bootstrap runs the block's procedures again with the fitted observer
    const psychophysics::Resample again = [&](const psychophysics::PsychometricFunction& f, std::uint64_t seed) {
      psychophysics::Interleaved fresh = make_procedures(spec, block);
      const psychophysics::VirtualObserver o{f, seed};
      while (!fresh.finished()) fresh.tell(o.correct(fresh.trials, fresh.procedures[fresh.next()]->next_level()));
      std::vector<psychophysics::Response> answers;
      for (const auto& p : fresh.procedures) answers.insert(answers.end(), p->history().begin(), p->history().end());
      return psychophysics::tally(answers);
    };
    bootstrap = psychophysics::bootstrap_threshold(again, spec.fit, fit, spec.bootstrap_replicates, math::derive_seed(block.seed, 4));
  }
  using config::number;
  return block.subject + "," + block.condition.label + "," + std::to_string(block.order) + "," + std::to_string(all.size()) + "," +
         number(fit.function.threshold) + "," + number(profile.low) + "," + number(profile.high) + "," + number(bootstrap.low) + "," +
         number(bootstrap.high) + "," + number(fit.function.threshold / spec.reference) + "," + number(std::round(fit.function.lapse / kLapsePrecision) * kLapsePrecision) + "," +
         number(fit.function.spread) + "," + number(block.observer.function.threshold);
}

}  // namespace

AnswerSource::~AnswerSource() = default;

int ObserverAnswers::answer(const Presentation& trial, std::uint32_t) {
  return trial.block->observer.chosen_interval(trial.trial, trial.level, trial.larger_interval());
}

int PersonAnswers::answer(const Presentation&, std::uint32_t buttons) {
  // a button counts when pressed, not while held
  const std::uint32_t pressed = buttons & ~last_buttons_;
  last_buttons_ = buttons;
  const int key = ui_.interval_answer();
  if (key == 1 || key == 2) return key;
  return (pressed & 1u) ? 1 : (pressed & 2u) ? 2 : 0;
}

namespace {

// the block as a trial of the runner's user interface (its prompt before the block)
Trial prompt_of(const DiscriminationBlock& b) {
  Trial t;
  t.subject = b.subject;
  t.subject_index = b.subject_index;
  t.condition = b.condition;
  t.order = b.order;
  return t;
}

// the next trial of a block: its procedure's level, and the reference's interval drawn from
// the block's seed and the trial's index
Presentation present(const DiscriminationSpec& spec, const DiscriminationBlock& b, psychophysics::Interleaved& set) {
  Presentation p;
  p.block = &b;
  p.trial = set.trials;
  const std::size_t k = set.next();
  p.procedure = spec.procedures[k].label;
  p.level = set.procedures[k]->next_level();
  math::Random coin(math::derive_seed(b.seed, 1000 + set.trials));
  p.reference_interval = 1 + static_cast<int>(coin.below(2));
  return p;
}


}  // namespace

DiscriminationRun run_discrimination(const DiscriminationSpec& spec, const std::string& out, RunnerUi& ui, std::size_t max_trials) {
  fs::create_directories(out + (spec.on_graph() ? "/trials" : ""));
  const std::vector<DiscriminationBlock> blocks = make_blocks(spec);
  check_same_plan(spec, out, blocks);
  DiscriminationRun run;
  run.trials = out + "/trials.csv";
  run.summary = out + "/summary.csv";
  const std::map<std::string, std::vector<Told>> told = read_trials(run.trials, spec);
  std::string summary = std::string(kDiscriminationSummaryHeader) + "\n";
  // whoever answers, through the one interface
  ObserverAnswers observers;
  PersonAnswers people(ui);
  AnswerSource& answers = spec.virtual_observers ? static_cast<AnswerSource&>(observers) : people;
  bool complete = true;
  int failures = 0;
  for (const DiscriminationBlock& b : blocks) {
    psychophysics::Interleaved set = make_procedures(spec, b);
    // resume: replay what trials.csv holds for this block
    const auto held = told.find(b.subject + "," + b.condition.label);
    if (held != told.end()) {
      std::vector<std::string> saved(set.procedures.size());
      for (const Told& t : held->second) saved[t.procedure] += exact(t.level) + (t.correct ? " 1\n" : " 0\n");
      try {
        for (std::size_t k = 0; k < saved.size(); ++k) set.procedures[k]->restore(saved[k]);
      } catch (const std::invalid_argument& e) {
        throw config::Error(run.trials + ": subject " + b.subject + ", " + b.condition.label + ": " + e.what() +
                            "\n  fix: this folder holds another run: give another --out");
      }
      set.trials = held->second.size();
      if (set.finished()) ++run.blocks_done_before;
    }
    // with people, the experimenter starts each block
    if (!set.finished() && !run.interrupted && !spec.virtual_observers && !ui.start_trial(prompt_of(b))) run.interrupted = true;
    // the block's trials, each recorded before the next
    while (!set.finished() && !run.interrupted) {
      if (take_stop_signal() || (max_trials > 0 && run.trials_run >= max_trials)) {
        run.interrupted = true;
        break;
      }
      const Presentation p = present(spec, b, set);
      const GraphAnswer a = spec.on_graph() ? run_graph_trial(spec, p, out + "/trials", answers, ui)
                                            : GraphAnswer{GraphAnswer::Outcome::answered, answers.answer(p, 0), NAN, ""};
      if (a.outcome == GraphAnswer::Outcome::interrupted) {
        run.interrupted = true;
        break;
      }
      if (a.outcome == GraphAnswer::Outcome::failed) {
        ++run.failed;
        ui.note("subject " + b.subject + ", " + b.condition.label + ", trial " + std::to_string(p.trial + 1) + ": " + a.problem + "; it runs again");
        if (++failures >= kMaxFailures) {
          ui.note("stopping: " + std::to_string(failures) + " trials failed in a row");
          run.interrupted = true;
        }
        continue;
      }
      failures = 0;
      const bool correct = a.chosen == p.larger_interval();
      append_line(run.trials, kDiscriminationTrialsHeader,
                  b.subject + "," + b.condition.label + "," + std::to_string(b.order) + "," + p.procedure + "," + std::to_string(p.trial + 1) + "," +
                      spec.parameter + "," + config::number(spec.reference) + "," + config::number(spec.reference + p.level) + "," + exact(p.level) + "," +
                      std::to_string(p.reference_interval) + "," + std::to_string(a.chosen) + "," + (correct ? "1" : "0") + "," +
                      config::number(a.response_time_s));
      set.tell(correct);
      ++run.trials_run;
    }
    if (!set.finished()) {
      complete = false;
      break;
    }
    summary += summarise(spec, b, set) + "\n";
    if (set.trials < static_cast<std::uint64_t>(kMinTrialsForFit)) {
      ui.note("warning: subject " + b.subject + ", " + b.condition.label + ": its fit rests on " + std::to_string(set.trials) + " trials, fewer than " +
              std::to_string(kMinTrialsForFit) + ": its JND is unreliable\n  fix: give the procedures more trials (trials:, max_trials:, reversals:)");
    }
    ui.note("subject " + b.subject + ", " + b.condition.label + ": " + std::to_string(set.trials) + " trials done");
  }
  // the summary, once every block is done
  if (complete) std::ofstream(run.summary) << summary;
  return run;
}

}  // namespace enact::experiment
