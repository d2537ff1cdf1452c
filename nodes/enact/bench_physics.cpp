// enact bench physics: placeholder until the benchmark lands
#include "nodes/enact/commands.h"
namespace enact::cli {
int bench(int, char**) { return 2; }
}  // namespace enact::cli
