#pragma once
// A node process's own setup and lines: the launcher's real-time profile applied to a loop
// process, the graph clock it was given, and "<node>: <text>" on stderr.
#include <string>

#include "core/rt/clock.h"

namespace enact::graph {

// a loop process of the graph (launch file `realtime:`): applies the profile the launcher
// put in ENACT_RT_PROFILE to this thread and to the I/O threads of the bus, and says what
// it applied. Call it first, before any socket. Nothing when the variable is not set.
void apply_rt_profile(const std::string& node);

// whether apply_rt_profile pinned this process to CPUs of its own: the graph's other
// processes run elsewhere, and no other loop process shares them (the distributed graph's
// simulator, pinned beside the FFD driver, does: the driver's loop must then sleep every tick)
bool loop_cpu_own();

// the graph clock the launcher gave this node (ENACT_CLOCK; unset: real time); throws
// config::Error for a value that names no clock
rt::GraphClock graph_clock();

// print "<node>: <text>" on stderr, flushed (nodes' lines interleave under the launcher)
void say(const std::string& node, const std::string& text);

}  // namespace enact::graph
