#pragma once
// The launcher's side of a graph's real-time profile (launch entry `realtime:`, see
// core/rt/profile.h): applied once, before the launcher starts any thread or process.
#include <iosfwd>
#include <memory>

#include "core/launch/launch_file.h"
#include "core/rt/profile.h"

namespace enact::launch {

// in simulated time (graph.clock), gives every node the clock in its environment
// (ENACT_CLOCK) and turns the real-time profile off. Then applies graph.realtime in the
// calling (launcher) thread, gives each loop node its profile
// in its environment (ENACT_RT_PROFILE), and says once on `log` what was applied and what
// was refused. The CPU latency request lasts as long as the returned object.
std::unique_ptr<rt::LauncherProfile> apply_realtime(LaunchDescription& graph, std::ostream& log);

}  // namespace enact::launch
