// enact-ffd: the force-feedback device driver and clock master of a distributed graph
// (core/node/ffd.h)
#include "core/node/ffd.h"

int main(int argc, char** argv) { return enact::node::host_main<enact::node::Ffd>(enact::node::kFfd, argc, argv); }
