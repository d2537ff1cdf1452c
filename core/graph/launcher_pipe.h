#pragma once
// The one writer of the launcher's pipe ($ENACT_READY_FD, set by `enact launch` for each
// node it starts): a node tells its launcher, one whole line at a time, the topics it
// publishes ("topic NAME TYPE"), that it needs longer to start ("wait SECONDS"), and that it
// is active ("ready", after which the pipe is closed and nothing more is written). A process
// not started by a launcher has no pipe: every call is then a no-op.
#include <string>

#include "core/bus/bytes.h"

namespace enact::graph {

// one line to the launcher, if it is still listening (before "ready")
void tell_launcher(const std::string& line);

// the topics `out` publishes, with their types: what its typed publishers declared. Call it
// once every publisher is made, before "ready".
void announce_topics(const bus::BytePublisher& out);

// "ready": the node is active; the pipe is closed (the node host says it for its component)
void report_ready();

}  // namespace enact::graph
