#pragma once
// A recording's loop, tick by tick: each device state's stamp and position and the force that
// answered it, to compare two runs bit for bit. Header-only: the tests that use it link
// enact_record and enact_msgs.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/record/reader.h"
#include "msgs/device_state.pb.h"
#include "msgs/force_command.pb.h"

namespace enact::test {

struct RecordedTick {
  std::int64_t stamp_ns = 0;
  double position[3] = {};
  double force[3] = {};
  bool answered = false;  // the recording holds its force (a real-time observer may lose one)
};

// the ticks from the first device state up to the first gap in their seq, each with the force
// that answered it (the first answer the recording holds: in a distributed graph an answer
// may be logged before the state it answers)
inline std::vector<RecordedTick> recorded_ticks(const std::string& recording) {
  std::vector<RecordedTick> ticks;
  std::map<std::uint64_t, msgs::Vec3> answers;
  record::Reader r(recording);
  msgs::DeviceState state;
  msgs::ForceCommand force;
  r.for_each([&](const record::Message& m) {
    if (m.topic == "ffd/state" && state.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      if (state.header().seq() != ticks.size() + 1) return true;  // a gap: compared up to it
      const auto& p = state.position();
      ticks.push_back({state.header().stamp_ns(), {p.x(), p.y(), p.z()}, {}});
    } else if (m.topic == "ffd/force" && force.ParseFromArray(m.data.data(), static_cast<int>(m.data.size()))) {
      answers.emplace(force.answered_seq(), force.force());
    }
    return true;
  });
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    const auto it = answers.find(i + 1);
    if (it == answers.end()) continue;
    ticks[i].force[0] = it->second.x(), ticks[i].force[1] = it->second.y(), ticks[i].force[2] = it->second.z();
    ticks[i].answered = true;
  }
  return ticks;
}

// the ticks before the first missed deadline: a tick's stamp is its deadline, so a missed one
// (skipped by the scheduler) is a step of more than a period between two stamps (and before
// the first whose force the recording lost)
inline std::size_t ticks_before_first_miss(const std::vector<RecordedTick>& ticks, std::int64_t period_ns) {
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    if (!ticks[i].answered || (i > 0 && ticks[i].stamp_ns - ticks[i - 1].stamp_ns != period_ns)) return i;
  }
  return ticks.size();
}

}  // namespace enact::test
