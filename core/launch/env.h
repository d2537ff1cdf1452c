#pragma once
// The environment a launcher gives the processes of its graph: one name each, here.
namespace enact::launch {

inline constexpr const char* kGraphDirEnv = "ENACT_GRAPH_DIR";  // the graph's folder (its sockets)
inline constexpr const char* kAttachEnv = "ENACT_ATTACH";       // the graph's attach point
inline constexpr const char* kGraphEnv = "ENACT_GRAPH";         // the graph's name
inline constexpr const char* kReadyFdEnv = "ENACT_READY_FD";    // where a node says "ready"
inline constexpr const char* kRespawnEnv = "ENACT_RESPAWN";     // how many times the node was restarted
inline constexpr const char* kClockEnv = "ENACT_CLOCK";         // the graph clock: simulated (unset: real)
inline constexpr const char* kRegistryEnv = "ENACT_REGISTRY";   // the folder of running graphs (tests)

}  // namespace enact::launch
