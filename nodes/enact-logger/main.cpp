// enact-logger: the logger as a node of a launch file (core/node/recorder.h)
#include "core/node/recorder.h"

int main(int argc, char** argv) { return enact::node::host_main<enact::node::LoggerNode>(enact::node::kLogger, argc, argv); }
