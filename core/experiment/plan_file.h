#pragma once
// The keys bridge and discrimination experiment files share, read the same way (private to
// core/experiment): file:line errors with the fix.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/config/yaml.h"
#include "core/experiment/experiment.h"

namespace enact::experiment {

// `subjects`: a count (ids 1..N) or a list of ids
std::vector<std::string> read_subjects(const config::Map& m);
// `conditions`: presets or computer-model files relative to the file
std::vector<Condition> read_conditions(const config::Map& m);
// `order`: random (default) or balanced
Order read_order(const config::Map& m);
// a value written in `file` (an experiment or sweep file) with $(dirname) (the file's folder, as
// in launch files: files beside it) and $(share) (enact's shipped files, config/share.h)
// substituted
std::string substitute(const std::string& file, std::string value);
// a path written in `file`, relative to it (else in enact's share, config/share.h), absolute
std::string beside(const std::string& file, const std::string& written_path);
// FNV-1a, 64 bits (Fowler, Noll, Vo): a file's fingerprint, a sweep job's seed stream
std::uint64_t fnv1a64(const std::string& bytes);
// `text` with letters, digits, '-' and '_' only (others become '_'): safe in a file name
std::string file_safe(const std::string& text);
// `graph` (the trial's launch file, relative to the file, absolute in `launch`) and
// `launch_args` (into `args`), checked: the launch file loads and declares the arguments
// `needed` and every one of launch_args
void read_trial_graph(const config::Map& m, const std::vector<std::string>& needed, std::string& launch,
                      std::vector<std::pair<std::string, std::string>>& args);

}  // namespace enact::experiment
