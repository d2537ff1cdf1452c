// enact-tactile: the tactile display driver of a distributed graph (core/node/tactile.h)
#include "core/node/tactile.h"

int main(int argc, char** argv) { return enact::node::host_main<enact::node::Tactile>(enact::node::kTactile, argc, argv); }
