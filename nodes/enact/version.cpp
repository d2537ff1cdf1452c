// The version and the commit this enact was built from: the one file that includes the
// header cmake/git_commit.cmake writes at every build, so a new commit recompiles it alone.
#include "enact_git_commit.h"
#include "nodes/enact/commands.h"

namespace enact::cli {

const char* version() { return "enact " ENACT_VERSION; }
const char* git_commit() { return ENACT_GIT_COMMIT; }

}  // namespace enact::cli
