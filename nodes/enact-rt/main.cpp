// enact-rt: the co-located real-time container (core/node/container.h)
#include "core/node/container.h"

int main(int argc, char** argv) { return enact::node::host_main<enact::node::Container>(enact::node::kContainer, argc, argv); }
