#pragma once
// Sweeps (docs/experiments.md, "Sweeps"): a file naming an experiment, a grid over its
// parameters (the trial graph's launch arguments, and `model`: one condition) and the
// replicates. Each grid point x replicate is one job: the whole experiment in simulated time
// (`enact experiment FILE --clock simulated --seed S --arg NAME=VALUE ...`), its seed derived
// from the sweep's seed and the job's coordinates alone, into its own folder. A job is (sweep
// file, coordinates, seed) -> a folder: where and when it ran changes no byte of it, and the
// merge sorts by coordinates, so every executor (local processes, Slurm, Dask) gives the same
// merged table.
//
// The folder of a sweep (--out DIR):
//   DIR/sweep.txt            what the jobs' results depend on besides their coordinates
//   DIR/jobs/<name>.partial/ a job running, failed or killed: never merged, run again
//   DIR/jobs/<name>/         a job done: the experiment's results.csv, trials/, experiment.log
//                            and job.json (exit code, duration, host, sha256 of results.csv);
//                            renamed from .partial only once it succeeded
//   DIR/results.csv          every done job's rows, the coordinates first, sorted by them
//   DIR/manifest.json        the enact version and git commit, the sweep file's sha256 and
//                            each job
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/experiment/experiment.h"

namespace enact::experiment {

// one axis of the grid: a launch argument of the trial graph (or `model`) and its values
struct SweepAxis {
  std::string name;
  std::vector<std::string> values;
  std::vector<std::string> seed_texts;  // each value in its jobs' seeds: as the sweep file writes it, an
                                        // absolute path relative to the sweep file's folder
  std::vector<int> lines;  // each value's line in the sweep file (1-based)
};

struct SweepSpec {
  std::string file;        // the sweep file (absolute)
  std::string name;
  std::string experiment;  // the experiment file (absolute)
  std::uint64_t seed = 1;
  int replicates = 1;
  int subjects = 0;        // > 0: --subjects over the experiment's
  std::vector<std::string> conditions;  // not empty: --conditions over the experiment's (model files absolute)
  std::vector<SweepAxis> grid;          // in the file's order: the first varies slowest
  std::string sha256;      // of the sweep file's bytes
};

// one job: a grid point and a replicate
struct SweepJob {
  std::size_t index = 0;            // in the sweep's order, from 0 (a Slurm array's task id)
  std::vector<std::string> values;  // one per axis, as the job uses it ($(dirname) and $(share) resolved)
  std::vector<std::string> written; // one per axis, as the sweep file writes it (SweepAxis::seed_texts):
                                    // the merged table's coordinates, the same wherever the files are
  int replicate = 1;                // from 1
  std::uint64_t seed = 0;           // the experiment's seed (under 10^9), from the values as written
                                    // (SweepAxis::seed_texts): the same wherever the sweep's files are
  std::string name;                 // its folder under DIR/jobs: <axis>-<value>_..._r<NNN>
};

// the grid's axis `model` sets the one condition of each job's experiment
inline constexpr const char* kModelAxis = "model";

// read a sweep file; throws config::Error with file:line and the fix (unknown keys, an axis
// that is not one of the trial graph's launch arguments, an empty axis, a value twice)
SweepSpec load_sweep(const std::string& path);

// every job, the first axis varying slowest and the replicate fastest
std::vector<SweepJob> sweep_jobs(const SweepSpec& spec);

// job `index`'s experiment: the experiment file with the sweep's overrides and the job's values
ExperimentSpec job_experiment(const SweepSpec& spec, const SweepJob& job);

// every value of the grid checked before any job runs: the experiment with that one value is
// planned and its trial graphs' nodes check their parameters (graph::check_graph); the
// problems, each "SWEEPFILE:LINE: AXIS: VALUE: what the node said"; empty when all pass
std::vector<std::string> check_sweep(const SweepSpec& spec, const std::string& out);

// the job's command after the enact executable: experiment FILE --clock simulated --seed S
// --out DIR [--subjects N] [--conditions ...] --arg NAME=VALUE ...
std::vector<std::string> experiment_command(const SweepSpec& spec, const SweepJob& job, const std::string& dir);

// what makes a job's result besides its coordinates: the experiment file (its path and
// sha256), the sweep's seed, subjects and conditions; kept in DIR/sweep.txt, a resumed run
// must have the same (its grid and replicates may grow or shrink: the jobs keep their seeds)
std::string sweep_identity(const SweepSpec& spec);

// where a job's folders are
std::string job_dir(const std::string& out, const SweepJob& job);
std::string partial_dir(const std::string& out, const SweepJob& job);

// what a job's job.json says
struct JobRecord {
  bool present = false;
  int exit_code = -1;
  double duration_s = 0.0;
  std::string host;
  std::string results_sha256;
};
JobRecord read_job_record(const std::string& dir);
void write_job_record(const std::string& dir, const SweepJob& job, const JobRecord& record);

// the state of each job as its folders say
enum class JobState : std::uint8_t { missing, running, failed, done };
JobState job_state(const std::string& out, const SweepJob& job);

// DIR/results.csv from every done job (rows sorted by coordinates: the jobs' order, then each
// job's own order) and DIR/manifest.json (with the enact `version` and the git `commit` it
// was built from); the number of jobs merged. Throws config::Error when a done job's
// results.csv does not match its recorded sha256.
std::size_t merge_sweep(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out, const std::string& version,
                        const std::string& commit);

// every file a job reads, so that it can travel with the job by content (Dask): the sweep
// file, the experiment file, the conditions' and the grid's files, and each file a YAML file
// among them names (a value that is a file: absolute, relative to the naming file or in
// enact's share, $(dirname) and $(share) substituted), and so on; absolute, sorted
std::vector<std::string> sweep_inputs(const SweepSpec& spec);

// SHA-256 (FIPS 180-4) of a file's bytes, lowercase hex; throws config::Error when unreadable
std::string sha256_file(const std::string& path);
std::string sha256_hex(const std::string& bytes);

}  // namespace enact::experiment
