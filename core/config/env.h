#pragma once
// The environment variables enact reads: one name each, here. A launcher gives the first ones
// to the processes of its graph; the others are a user's or a launcher's settings.
namespace enact::env {

inline constexpr const char* kGraphDir = "ENACT_GRAPH_DIR";     // the graph's folder (its sockets)
inline constexpr const char* kAttach = "ENACT_ATTACH";          // the graph's attach point
inline constexpr const char* kGraph = "ENACT_GRAPH";            // the graph's name
inline constexpr const char* kReadyFd = "ENACT_READY_FD";       // the launcher's pipe: a node's topics, waits and "ready"
inline constexpr const char* kRespawn = "ENACT_RESPAWN";        // how many times the node was restarted
inline constexpr const char* kClock = "ENACT_CLOCK";            // the graph clock: simulated (unset: real)
inline constexpr const char* kRtProfile = "ENACT_RT_PROFILE";   // a loop process's real-time profile (launch file realtime:)
inline constexpr const char* kRegistry = "ENACT_REGISTRY";      // the folder of running graphs (tests)
inline constexpr const char* kKey = "ENACT_KEY";                // a client's key file (graphs with keys)
inline constexpr const char* kServerKey = "ENACT_SERVER_KEY";   // the graph's public key file

}  // namespace enact::env
