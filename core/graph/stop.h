#pragma once
// Stopping a node process: SIGINT and SIGTERM ask it to stop (a flag its loops read), and a
// node stuck in its shutdown is ended after a grace period.

namespace enact::graph {

// seconds a node may take to stop after the first SIGINT/SIGTERM before it is killed
// (SIGALRM): a node stuck in its shutdown never outlives its launcher for long
inline constexpr unsigned kStopGrace_s = 5;

// SIGINT and SIGTERM set a flag instead of killing the process, and arm the grace period
void install_stop_handlers();
bool stop_requested();
// a descriptor readable once a stop was asked (-1 before install_stop_handlers): a loop that
// waits on it beside its own needs no timeout of its own to see the stop (on a VM a wait's
// timer costs each wait about a microsecond: enact bench loop)
int stop_fd();

}  // namespace enact::graph
