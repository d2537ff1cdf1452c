#pragma once
// A discrimination trial on its graph (private to core/experiment): the two intervals set
// live on param/set, each explored for interval_s of the graph's clock, then the answer, all
// announced on task/event and recorded by the trial graph's logger.
#include <string>

#include "core/experiment/discrimination.h"

namespace enact::experiment {

struct GraphAnswer {
  enum class Outcome : std::uint8_t { answered, failed, interrupted } outcome = Outcome::failed;
  int chosen = 0;                // answered: the interval named
  double response_time_s = 0.0;  // answered: from the end of the last interval, graph clock
  std::string problem;           // failed: why (and where the log is)
};

// `trial` in its own graph (the spec's launch file), recorded to `folder`/<stem>.mcap, its
// nodes' output in <stem>.log; `answers` is asked once the intervals are over, `ui` told
// where a person is (with people)
GraphAnswer run_graph_trial(const DiscriminationSpec& spec, const Presentation& trial, const std::string& folder, AnswerSource& answers, RunnerUi& ui);

// a trial's recording and log, without the extension: s<subject>_<condition>_t<NNN>
std::string trial_stem(const Presentation& trial);

}  // namespace enact::experiment
