#pragma once
// Two observers as nodes of a launch file: the logger (enact-logger; `enact record` is the
// same from the shell), recording to an MCAP file until stopped, then closing it complete
// and indexed; and the Foxglove bridge (enact-foxglove; `enact foxglove`), serving the graph
// over WebSocket. Both attach through the graph's attach point ($ENACT_ATTACH, set by
// `enact launch`).
#include <memory>

#include "core/foxglove/bridge.h"
#include "core/record/logger.h"
#include "core/node/host.h"

namespace enact::node {

extern const NodeKind kLogger;
extern const NodeKind kFoxglove;

class Logger {
 public:
  explicit Logger(Host& host);
  int run();

 private:
  Host& host_;
  graph::LoggerOptions options_;
};

class Foxglove {
 public:
  explicit Foxglove(Host& host);
  int run();

 private:
  Host& host_;
  foxglove::BridgeOptions options_;
};

}  // namespace enact::node
