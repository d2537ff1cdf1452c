// enact-sim: the simulator of a distributed graph (core/node/sim.h)
#include "core/node/sim.h"

int main(int argc, char** argv) { return enact::node::host_main<enact::node::Sim>(enact::node::kSim, argc, argv); }
