#pragma once
// The topics of a graph (DESIGN.md, "Topics") and their message types.
namespace enact::graph {

inline constexpr const char* kDeviceState = "ffd/state";      // DeviceState, FFD driver, loop rate
inline constexpr const char* kForceCommand = "ffd/force";     // ForceCommand, simulator, loop rate
inline constexpr const char* kTactileFrame = "tactile/frame"; // TactileFrame, simulator, down-sampled
inline constexpr const char* kTactileShown = "tactile/shown"; // TactileShown, tactile driver, device rate
inline constexpr const char* kSceneState = "sim/scene";       // SceneState, simulator, viewer rate
inline constexpr const char* kTaskEvent = "task/event";       // TaskEvent, simulator, on event
inline constexpr const char* kTaskState = "task/state";       // TaskState, simulator, 10 Hz and on change (latched)
inline constexpr const char* kParamSet = "param/set";         // ParamUpdate, viewer / CLI, on demand
inline constexpr const char* kParamAck = "param/ack";         // ParamAck, simulator, one per ParamUpdate
inline constexpr const char* kSimKeyframe = "sim/keyframe";  // SimKeyframe, simulator, 1 Hz: replay starts there
inline constexpr const char* kNodeStatus = "node/status";     // NodeStatus, every node, 1 Hz
// ParamValues, every node, 1 Hz and on a live change (latched): topic kParamValues + node name
inline constexpr const char* kParamValues = "param/values/";

// how often the simulator publishes a keyframe (sim/keyframe)
inline constexpr long long kKeyframePeriod_ns = 1'000'000'000;

// where a node's parameter board (param_board.h) publishes: node_endpoint(name + kParamBoardSuffix)
inline constexpr const char* kParamBoardSuffix = ":params";

// the topics observers may send on, through the attach point (the graph's nodes publish
// every other)
inline constexpr const char* kInboundTopics[] = {kParamSet};

// the attach point's inbound publisher (what observers send: param/set) is at
// node_endpoint(kInboundNode); ':' keeps it apart from every node name
inline constexpr const char* kInboundNode = "attach:in";

}  // namespace enact::graph
