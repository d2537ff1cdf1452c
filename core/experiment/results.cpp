#include "core/experiment/results.h"

#include <algorithm>
#include <fstream>
#include <optional>
#include <sstream>

#include "core/config/format.h"
#include "core/config/yaml.h"
#include "core/record/logger.h"
#include "core/graph/topics.h"
#include "core/physics/scene.h"
#include "core/record/reader.h"
#include "core/replay/replay.h"
#include "msgs/device_state.pb.h"
#include "msgs/node_status.pb.h"
#include "msgs/task_event.pb.h"
#include "msgs/sim_keyframe.pb.h"

namespace enact::experiment {
namespace {

using config::number;

double seconds(std::int64_t ns) { return static_cast<double>(ns) * 1e-9; }

}  // namespace

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

void append_line(const std::string& path, const char* header, const std::string& line) {
  std::ifstream probe(path);
  const bool fresh = !probe || probe.peek() == std::ifstream::traits_type::eof();
  probe.close();
  std::ofstream out(path, std::ios::app);
  if (fresh) out << header << '\n';
  out << line << '\n';
  out.flush();
  if (!out) throw config::Error(path + ": cannot write\n  fix: check the folder's permissions and free space");
}

void keep_or_check(const std::string& path, const std::string& text, const std::string& differs) {
  std::ifstream in(path);
  if (!in) {
    std::ofstream(path) << text;
    return;
  }
  std::stringstream held;
  held << in.rdbuf();
  if (held.str() != text) {
    throw config::Error(path + ": this folder holds a run of another plan (" + differs + ")\n"
                        "  fix: run with the same file and options to resume it, or give another --out");
  }
}

const char* const kResultsHeader = "subject,condition,order,falls,time_total_s,time_out_s,ratio,completed,missed_deadlines";
const char* const kPracticeHeader = "subject,condition,order,falls,time_total_s,time_out_s,ratio,completed,missed_deadlines,kind";

namespace {

// the bridge task's metrics of a recorded trial from its events (with their publishers),
// the simulator `sim`, the keyframe it is taken up from (if any) and its device states' span
task::Metrics metrics_of(const std::vector<std::pair<std::string, msgs::TaskEvent>>& events, const std::string& sim, const std::optional<msgs::SimKeyframe>& from,
                         std::int64_t first_ns, std::int64_t last_ns) {
  // the simulator's events, in the order it reported them; the runner's own (trial start,
  // reset, condition) carry no metric. A live `sim.trial start` or `sim.reset` begins a new
  // trial there, `sim.trial stop` ends it (not completed). A fall that begins or ends on the
  // very step that completes the bridge is not reported (BridgeTask keeps it): then falls
  // can be one short.
  task::Metrics metrics;
  std::int64_t start_ns = first_ns, end_ns = -1, fall_ns = -1, out_ns = 0;
  if (from) {
    start_ns = from->trial_start_ns();
    metrics.falls = from->falls();
    out_ns = from->closed_out_ns();
    fall_ns = from->fall_since_ns() != 0 ? from->fall_since_ns() : -1;
    end_ns = from->trial_end_ns() != 0 ? from->trial_end_ns() : -1;
    metrics.completed = end_ns >= 0 && !from->stopped();
  }
  for (const auto& [publisher, e] : events) {
    const bool restart = e.kind() == msgs::TaskEvent::TRIAL_START || (e.kind() == msgs::TaskEvent::RESET && e.detail() == "reset");
    if (publisher == sim && restart) {
      metrics = {};
      start_ns = e.time_ns();
      end_ns = fall_ns = -1;
      out_ns = 0;
    }
    if (end_ns >= 0) continue;
    if (e.kind() == msgs::TaskEvent::FALL_START) {
      ++metrics.falls;
      fall_ns = e.time_ns();
    } else if (e.kind() == msgs::TaskEvent::FALL_END && fall_ns >= 0) {
      out_ns += e.time_ns() - fall_ns;
      fall_ns = -1;
    } else if (e.kind() == msgs::TaskEvent::TRIAL_END) {
      end_ns = e.time_ns();
      metrics.completed = e.detail() != "stopped";
    }
  }
  // a fall still open counts up to the end: the completion, or the last device state
  const std::int64_t stop_ns = end_ns >= 0 ? end_ns : last_ns;
  if (fall_ns >= 0) out_ns += stop_ns - fall_ns;
  metrics.time_total_s = seconds(stop_ns - start_ns);
  metrics.time_out_s = seconds(out_ns);
  metrics.ratio = metrics.time_total_s > 0.0 ? metrics.time_out_s / metrics.time_total_s : 0.0;
  return metrics;
}

}  // namespace

RecordedTrial read_trial(const std::string& mcap_path, std::int64_t keyframe_stamp_ns) {
  record::Reader reader(mcap_path);
  RecordedTrial out;
  std::int64_t first_ns = 0, last_ns = 0;
  graph::SequenceCheck seq;
  msgs::DeviceState state;
  msgs::TaskEvent event;
  msgs::NodeStatus status;
  msgs::SimKeyframe keyframe;
  std::vector<std::pair<std::string, msgs::TaskEvent>> events;  // with their publisher
  std::optional<msgs::SimKeyframe> from;  // the keyframe the trial is taken up from
  std::string sim;  // the simulator: the publisher of ffd/force
  reader.for_each([&](const record::Message& m) {
    const auto pub = m.channel->metadata.find("publisher");
    const std::string publisher = pub == m.channel->metadata.end() ? "" : pub->second;
    if (m.topic == graph::kDeviceState && state.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      if (out.states == 0) {
        out.first_state_seq = state.header().seq();
        first_ns = state.header().stamp_ns();
      }
      seq.add(state.header().seq());
      out.state_gaps = seq.gaps;
      last_ns = state.header().stamp_ns();
      ++out.states;
    } else if (m.topic == graph::kTaskEvent && event.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      events.emplace_back(publisher, event);
    } else if (keyframe_stamp_ns != 0 && !from && m.topic == graph::kSimKeyframe && keyframe.ParseFromArray(m.data.data(), static_cast<int>(m.data.size())) &&
               keyframe.header().stamp_ns() == keyframe_stamp_ns) {
      // the simulator's events before its keyframe are in the trial it carries
      from = keyframe;
      std::erase_if(events, [&](const auto& e) { return e.first == publisher; });
    } else if (m.topic == graph::kForceCommand) {
      sim = publisher;
    } else if (m.topic == graph::kNodeStatus && status.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      out.missed_deadlines = std::max<std::uint64_t>(out.missed_deadlines, status.deadlines_missed());
    }
    return true;
  });
  if (out.states == 0) throw config::Error(mcap_path + ": holds no device state (ffd/state)\n  fix: record the trial's graph with its logger");
  out.metrics = metrics_of(events, sim, from, first_ns, last_ns);
  out.duration_s = seconds(last_ns - first_ns);
  // the recorded scene: one without a task has no falls or completion to count
  try {
    graph::TempFolder files;
    out.task = !physics::load_scene(graph::recorded_sim_param(mcap_path, "scene", files)).task_surface.empty();
  } catch (const config::Error&) {
    // no scene recorded (a graph not started by enact launch): taken to have the task
  }
  return out;
}

std::string trial_key(const std::string& subject, const std::string& condition, TrialKind kind) {
  return subject + '\n' + condition + '\n' + to_string(kind);
}

void append_result(const std::string& path, const Trial& t, const RecordedTrial& recorded) {
  const task::Metrics& m = recorded.metrics;
  std::string line = t.subject + ',' + t.condition.label + ',' + std::to_string(t.order) + ',' + std::to_string(m.falls) + ',' +
                     number(m.time_total_s) + ',' + number(m.time_out_s) + ',' + number(m.ratio) + ',' + (m.completed ? "1" : "0") + ',' +
                     std::to_string(recorded.missed_deadlines);
  const bool measured = t.kind == TrialKind::measured;
  if (!measured) line += std::string(",") + to_string(t.kind);
  append_line(path, measured ? kResultsHeader : kPracticeHeader, line);
}

std::set<std::string> done_trials(const std::string& path) {
  std::set<std::string> done;
  std::ifstream in(path);
  if (!in) return done;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (n == 1) {
      if (line != kResultsHeader && line != kPracticeHeader) {
        throw config::Error(path + ":1: not an enact results file (header: " + line + ")\n  fix: give a new --out folder, or restore the file");
      }
      continue;
    }
    if (line.empty()) continue;
    const std::vector<std::string> c = cells(line);
    if (c.size() < 9) throw config::Error(path + ":" + std::to_string(n) + ": a damaged row (" + line + ")\n  fix: delete the row: its trial runs again");
    const TrialKind kind = c.size() > 9 ? (c[9] == "practice" ? TrialKind::practice : TrialKind::familiarisation) : TrialKind::measured;
    done.insert(trial_key(c[0], c[1], kind));
  }
  return done;
}

void append_ranking(const std::string& path, const std::string& subject, const std::map<std::string, int>& ranks) {
  for (const auto& [condition, rank] : ranks) append_line(path, "subject,condition,rank", subject + ',' + condition + ',' + std::to_string(rank));
}

std::set<std::string> ranked_subjects(const std::string& path) {
  std::set<std::string> out;
  std::ifstream in(path);
  std::string line;
  for (int n = 0; std::getline(in, line); ++n) {
    if (n > 0 && !line.empty()) out.insert(cells(line).front());
  }
  return out;
}

std::string plan_text(const std::vector<Trial>& plan) {
  std::string out = "index,subject,condition,model,order,kind,limit_s,subject_seed,noise_seed,recording\n";
  for (const Trial& t : plan) {
    out += std::to_string(t.index) + ',' + t.subject + ',' + t.condition.label + ',' + t.condition.model + ',' + std::to_string(t.order) + ',' +
           to_string(t.kind) + ',' + number(t.limit_s) + ',' + std::to_string(t.subject_seed) + ',' + std::to_string(t.noise_seed) + ',' +
           t.file_stem + ".mcap\n";
  }
  return out;
}

}  // namespace enact::experiment
