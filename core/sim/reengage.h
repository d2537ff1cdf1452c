#pragma once
// Re-synchronising the model with the device after an interruption of the force path (a
// watchdog episode, a simulator (re)start, a long overrun): while the force was cut, the hand
// may have pushed the device deep into an object, and stepping there at once would answer
// with a jolt (hundreds of N). Instead, the first step after the interruption places the
// body just out of every object along the contact normals (the contacts' memory of the
// faces they entered through is kept), and that offset shrinks smoothly (zero speed at both
// ends) to zero over duration_s: the force grows from zero back to the model's.
// A late sample (the device held the last force for longer than kLateSample_ns, yet not long
// enough for its watchdog to cut it) is held instead: meanwhile the hand may have pushed the
// device deeper than the body was, and the full answer at once would jolt (a 5 kHz walk, 9 ms
// late: 8.6 -> 21 N in one tick). Its first step places the body no deeper into the objects
// than the body of the sample before it was, so the force goes on from the force of the step
// before it, and that offset shrinks the same way. Allocates nothing after construction;
// never throws.
#include <cstdint>

#include "core/math/vec3.h"
#include "core/physics/model.h"
#include "core/physics/state.h"

namespace enact::sim {

class Simulator;

// the simulator node's default duration (parameter reengage_s)
constexpr double kReengageDefault_s = 0.100;

// a sample this long after the last (and more than two of the model's steps) is late: the
// device held a stale force long enough for the hand to move it (the device profiles' force
// step limits count per millisecond too)
constexpr std::int64_t kLateSample_ns = 1'000'000;

class Reengagement {
 public:
  // duration_s >= 0: how long the body takes to return from out of the objects to the device
  explicit Reengagement(double duration_s = kReengageDefault_s);

  // the force path was interrupted: the next position() re-synchronises
  void interrupt() { pending_ = Pending::cut; }
  // the next sample is late by gap_ns (the force path was whole): the next position() holds
  // the body no deeper than it was at body_m, the position of the step before (a cut pending
  // wins)
  void late(const math::Vec3& body_m, std::int64_t gap_ns);

  // the position to give Simulator::step for the device at device_m at time_ns: the
  // device's own, plus an offset that keeps the body's points out of the objects at the
  // first step after interrupt() and shrinks smoothly to zero over duration_s
  math::Vec3 position(const Simulator& sim, std::int64_t time_ns, const math::Vec3& device_m);

  // re-synchronisations so far, and the largest offset they needed (m)
  std::uint64_t count() const { return count_; }
  double largest_offset_m() const { return largest_m_; }
  // late samples held so far, the longest gap (ns) and the largest offset they needed (m)
  std::uint64_t late_count() const { return late_count_; }
  std::int64_t longest_gap_ns() const { return longest_gap_ns_; }
  double largest_late_offset_m() const { return largest_late_m_; }

 private:
  enum class Pending : std::uint8_t { none, cut, late };
  // what is left at time_ns of the offset the last re-synchronisation needed
  math::Vec3 offset_at(std::int64_t time_ns) const;
  std::int64_t duration_ns_;
  Pending pending_ = Pending::none;
  math::Vec3 body_m_;  // a late sample's: the body's position at the step before it
  math::Vec3 offset_m_;
  std::int64_t from_ns_ = 0;
  std::uint64_t count_ = 0;
  double largest_m_ = 0.0;
  std::uint64_t late_count_ = 0;
  std::int64_t longest_gap_ns_ = 0;
  double largest_late_m_ = 0.0;
};

// the smallest offset (found by a few projections along the contact normals) that brings
// every point of proxy 0's body at device_m out of the objects it would penetrate, given the
// state's contact memory; zero when nothing penetrates
math::Vec3 resync_offset(const physics::Model& model, const physics::State& state, const math::Vec3& device_m);

}  // namespace enact::sim
