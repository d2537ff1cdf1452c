// enact sweep FILE: a grid of an experiment's parameters x replicates, each job a whole
// simulated-time experiment in its own process, run here, on Slurm or on Dask; merged the
// same whatever ran it (core/experiment/sweep.h).
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <thread>

#include "core/config/format.h"
#include "core/config/share.h"
#include "core/config/number.h"
#include "core/config/yaml.h"
#include "core/experiment/results.h"
#include "core/experiment/runner.h"
#include "core/experiment/sweep.h"
#include "core/launch/supervisor.h"
#include "core/rt/clock.h"
#include "nodes/enact/child_process.h"
#include "nodes/enact/commands.h"

namespace enact::cli {
namespace {

namespace fs = std::filesystem;
using experiment::JobState;
using experiment::SweepJob;
using experiment::SweepSpec;

constexpr const char* kSweepHelp = R"help(usage: enact sweep FILE [--out DIR] [--executor local|slurm|dask://HOST:PORT] [--jobs J]
                   [--slurm-opt NAME=VALUE]... [--dask-files content|shared] [--dry-run]

Run the sweep of FILE (format: docs/experiments.md, "Sweeps"): an experiment with virtual
subjects over a grid of its parameters (the trial graph's launch arguments, e.g. rate_hz,
and model: the condition) x replicates. Each grid point x replicate is one job: the whole
experiment in simulated time, its seed derived from the sweep's seed and the job's
coordinates alone. Every value of the grid is checked first (the trial graphs' nodes check
their parameters, as `enact experiment --plan` does); a bad one is refused with the sweep
file's line, before any job runs.

Each job is one process running `enact sweep FILE --out DIR --job K` (whatever the executor),
which runs `enact experiment EXPERIMENT --clock simulated --seed S --arg NAME=VALUE ...` into
DIR/jobs/<coords>.partial/ and renames it DIR/jobs/<coords>/ once it succeeded (results.csv,
trials/, experiment.log, job.json). Then DIR/results.csv holds every done job's rows, the
coordinates as the first columns, sorted by them: the same bytes whatever ran the jobs; and
DIR/manifest.json the enact version and the git commit it was built from, the sweep file's
sha256 and each job's seed, exit code, duration, host and results.csv's sha256. Run the same command again to resume: only the jobs
missing or failed (a killed worker's, a cancelled task's) run again; a partial job is never
merged.

executors:
  local               J processes on this machine (default)
  slurm               one job array through sbatch (each array task runs one job; the
                      folders must be shared with the nodes); waits for the array
  dask://HOST:PORT    a running Dask scheduler: one task per job (scripts/dask_sweep.py,
                      Debian's python3-distributed), each running the job on a worker;
                      the files the job reads travel with the task (DIR/inputs.txt lists
                      them) and its folder comes back: no folder shared with the workers
                      but the enact executable's; prints the dashboard's address

options:
  --out DIR           the sweep's folder (default: results/<name of the sweep>)
  --executor E        local, slurm or dask://HOST:PORT (default: local)
  --jobs J            local: J jobs at once (default: one per CPU); slurm: at most J array
                      tasks at once (default: Slurm's choice)
  --slurm-opt N=V     an sbatch option for the array (repeatable): partition=debug,
                      time=00:30:00, mem=2G, cpus-per-task=2 ...
  --dask-files M      content (default): the inputs and the job's folder travel with each
                      task; shared: the workers use the sweep's files and DIR at their
                      paths (a folder shared with them; a file missing on a worker is an
                      error naming that host and the path)
  --dry-run           print what would run (the jobs' commands, the Slurm script, the Dask
                      call) after the checks, and run nothing
  --job K             run job K only, here (what each executor runs)
Progress (done / running / failed, time left) goes to stderr. Then, a measure per grid point
with intervals: /usr/bin/python3 "$(enact share scripts/sweep_plot.py)" DIR
Exit status: 0 every job done, 1 jobs failed or did not finish (run again to resume them) or
an error, 2 bad arguments, 130 stopped (Ctrl-C).
)help";

std::string host_name() {
  char buf[256] = {};
  gethostname(buf, sizeof buf - 1);
  return buf;
}

std::string self_exe() { return fs::read_symlink("/proc/self/exe").string(); }

// a word for a shell script, in single quotes
std::string shell_word(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// ---- one job (--job K): what every executor runs ----

int run_job(const std::string& file, const std::string& out, long index) {
  const std::string host = host_name();
  // whoever started the job gone (a killed worker, a cancelled task): the job stops too
  const pid_t parent = getppid();
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != parent) return 143;
  // the shared files, named with this host when one is missing here
  for (const auto& [path, what] : {std::pair{file, "the sweep file"}, std::pair{out + "/jobs", "the sweep's folder (--out)"}}) {
    if (!fs::exists(path)) {
      std::fprintf(stderr, "enact sweep: on host %s: %s %s is missing here\n  fix: run the jobs where the sweep's files are on a folder shared with this host (the same path)\n",
                   host.c_str(), what, path.c_str());
      return 1;
    }
  }
  SweepSpec spec;
  std::vector<SweepJob> jobs;
  try {
    spec = experiment::load_sweep(file);
    jobs = experiment::sweep_jobs(spec);
  } catch (const config::Error& e) {
    std::fprintf(stderr, "enact sweep: on host %s: error: %s\n", host.c_str(), e.what());
    return 1;
  }
  if (index < 0 || index >= static_cast<long>(jobs.size())) throw UsageError("--job " + std::to_string(index) + ": the sweep has jobs 0 to " + std::to_string(jobs.size() - 1));
  const SweepJob& job = jobs[static_cast<std::size_t>(index)];
  const std::string done = experiment::job_dir(out, job), partial = experiment::partial_dir(out, job);
  // one process per job: another one's (a killed worker's still stopping) is waited for. The
  // experiment and its graph inherit the lock: it is held until the last of them is gone
  const std::string lock = out + "/jobs/" + job.name + ".lock";
  const int fd = open(lock.c_str(), O_RDWR | O_CREAT, 0644);
  if (fd < 0) throw config::Error(lock + ": cannot be created (" + std::strerror(errno) + ")\n  fix: the sweep's folder must be writable here (host " + host + ")");
  const std::int64_t wait_until = rt::now_ns() + 60'000'000'000;
  while (flock(fd, LOCK_EX | LOCK_NB) != 0) {
    if (rt::now_ns() > wait_until) {
      std::fprintf(stderr, "enact sweep: on host %s: job %ld (%s) is running in another process for over a minute; not run twice\n", host.c_str(), index, job.name.c_str());
      return 75;
    }
    rt::sleep_until_ns(rt::now_ns() + 200'000'000);
  }
  if (experiment::read_job_record(done).present) {
    std::fprintf(stderr, "enact sweep: job %ld (%s) was done before\n", index, job.name.c_str());
    return 0;
  }
  // a fresh start: what a killed or failed run left is not kept
  fs::remove_all(partial);
  fs::create_directories(partial);
  std::vector<std::string> args{self_exe()};
  for (const std::string& a : experiment::experiment_command(spec, job, partial)) args.push_back(a);
  std::fprintf(stderr, "enact sweep: on host %s: job %ld (%s, seed %llu):", host.c_str(), index, job.name.c_str(), static_cast<unsigned long long>(job.seed));
  for (const std::string& a : args) std::fprintf(stderr, " %s", a.c_str());
  std::fprintf(stderr, "\n");
  std::fflush(stderr);
  const std::int64_t start_ns = rt::now_ns();
  launch::block_supervisor_signals();
  const pid_t pid = start_logged(args, partial + "/experiment.log", true);
  int status = 0;
  bool stopped = false;
  while (true) {
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) break;
    if (!stopped && experiment::take_stop_signal()) {
      stopped = true;
      kill(pid, SIGTERM);
    }
    rt::sleep_until_ns(rt::now_ns() + 50'000'000);
  }
  if (stopped) {
    std::fprintf(stderr, "enact sweep: job %ld (%s) stopped; it runs again on the next run\n", index, job.name.c_str());
    return 130;
  }
  experiment::JobRecord record;
  record.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  record.duration_s = std::round(static_cast<double>(rt::now_ns() - start_ns) * 1e-6) * 1e-3;
  record.host = host;
  if (record.exit_code == 0) {
    try {
      record.results_sha256 = experiment::sha256_file(partial + "/results.csv");
    } catch (const config::Error& e) {
      std::fprintf(stderr, "enact sweep: job %ld: the experiment ended without results: %s\n", index, e.what());
      record.exit_code = 1;
    }
  }
  experiment::write_job_record(partial, job, record);
  if (record.exit_code != 0) {
    std::fprintf(stderr, "enact sweep: on host %s: job %ld (%s) failed (exit %d); see %s/experiment.log\n", host.c_str(), index, job.name.c_str(), record.exit_code,
                 partial.c_str());
    return 1;
  }
  fs::rename(partial, done);
  std::fprintf(stderr, "enact sweep: job %ld (%s) done in %s s on %s\n", index, job.name.c_str(), config::number(record.duration_s).c_str(), host.c_str());
  return 0;
}

// ---- the executors ----

// what executors are given: the pending jobs and how to run one
struct SweepRun {
  const SweepSpec& spec;
  const std::vector<SweepJob>& jobs;
  std::vector<std::size_t> pending;  // indices into jobs
  std::string out;                   // absolute
  std::string enact;                 // this executable
  // `enact sweep FILE --out DIR --job K`
  std::vector<std::string> job_command(std::size_t k) const { return {enact, "sweep", spec.file, "--out", out, "--job", std::to_string(k)}; }
  std::string log(std::size_t k) const { return out + "/logs/job_" + std::to_string(k) + ".log"; }
};

class Executor {
 public:
  virtual ~Executor() = default;
  // what would run, printed
  virtual void dry_run(const SweepRun& run) = 0;
  // runs every pending job and returns once none runs; `tick` about every second; false when
  // stopped by a signal
  virtual bool run(const SweepRun& run, const std::function<void()>& tick) = 0;
};

class LocalExecutor final : public Executor {
 public:
  explicit LocalExecutor(int jobs) : jobs_(jobs) {}

  void dry_run(const SweepRun& run) override {
    std::printf("# %d at once\n", jobs_);
    for (std::size_t k : run.pending) {
      std::string line;
      for (const std::string& a : run.job_command(k)) line += (line.empty() ? "" : " ") + shell_word(a);
      std::printf("%s\n", line.c_str());
    }
  }

  bool run(const SweepRun& run, const std::function<void()>& tick) override {
    std::map<pid_t, std::size_t> running;
    std::size_t next = 0;
    bool stopping = false;
    std::int64_t last_tick = 0;
    while ((next < run.pending.size() && !stopping) || !running.empty()) {
      while (!stopping && next < run.pending.size() && static_cast<int>(running.size()) < jobs_) {
        const std::size_t k = run.pending[next++];
        running[start_logged(run.job_command(k), run.log(k), true)] = k;
      }
      if (!stopping && experiment::take_stop_signal()) {
        stopping = true;
        for (const auto& [pid, k] : running) kill(pid, SIGTERM);
      }
      int status = 0;
      const pid_t pid = waitpid(-1, &status, WNOHANG);
      if (pid > 0) {
        running.erase(pid);
        continue;
      }
      if (rt::now_ns() - last_tick > 1'000'000'000) {
        tick();
        last_tick = rt::now_ns();
      }
      rt::sleep_until_ns(rt::now_ns() + 100'000'000);
    }
    return !stopping;
  }

 private:
  int jobs_;
};

// `text` into the file `path`; throws config::Error naming it when it cannot be written
void write_text(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  const bool written = f && std::fputs(text.c_str(), f) >= 0;
  if (f && std::fclose(f) != 0) throw config::Error(path + ": cannot be written (" + std::strerror(errno) + ")\n  fix: check the folder's space and permissions");
  if (!written) throw config::Error(path + ": cannot be written\n  fix: check the folder's space and permissions");
}

// a command's standard output (its exit status in `status`)
std::string capture(const std::string& command, int& status) {
  std::string out;
  FILE* p = popen(command.c_str(), "r");
  if (!p) {
    status = -1;
    return out;
  }
  char buf[512];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  status = pclose(p);
  return out;
}

class SlurmExecutor final : public Executor {
 public:
  SlurmExecutor(int jobs, std::vector<std::string> options) : jobs_(jobs), options_(std::move(options)) {}

  void dry_run(const SweepRun& run) override { std::fputs(script(run).c_str(), stdout); }

  bool run(const SweepRun& run, const std::function<void()>& tick) override {
    fs::create_directories(run.out + "/slurm");
    const std::string path = run.out + "/slurm/array.sbatch";
    write_text(path, script(run));
    int status = 0;
    const std::string answer = capture("sbatch --parsable " + shell_word(path) + " 2>&1", status);
    if (status != 0) throw config::Error("sbatch refused the array (" + path + "): " + answer + "  fix: is Slurm running (sinfo)? scripts/slurm_local.sh start starts one here");
    const std::string id = answer.substr(0, answer.find_first_of(";\n"));
    std::fprintf(stderr, "enact sweep: Slurm job array %s submitted (%zu tasks; script %s; logs %s/logs/job_K.log)\n", id.c_str(), run.pending.size(), path.c_str(),
                 run.out.c_str());
    int squeue_failures = 0;
    while (true) {
      if (experiment::take_stop_signal()) {
        capture("scancel " + shell_word(id) + " 2>&1", status);
        std::fprintf(stderr, "\nenact sweep: stopped: the array %s cancelled (run the same command again to resume)\n", id.c_str());
        return false;
      }
      const std::string queued = capture("squeue -h -j " + shell_word(id) + " -o %i 2>/dev/null", status);
      if (status != 0) {
        // a finished array is forgotten by squeue after a while (MinJobAge): an error then
        if (++squeue_failures > 5) break;
      } else if (queued.find_first_not_of(" \n") == std::string::npos) {
        break;
      } else {
        squeue_failures = 0;
      }
      tick();
      rt::sleep_until_ns(rt::now_ns() + 1'000'000'000);
    }
    return true;
  }

 private:
  std::string script(const SweepRun& run) const {
    // the pending jobs as ranges: 0-11,14,20-23
    std::string tasks;
    for (std::size_t i = 0; i < run.pending.size();) {
      std::size_t last = i;
      while (last + 1 < run.pending.size() && run.pending[last + 1] == run.pending[last] + 1) ++last;
      tasks += (tasks.empty() ? "" : ",") + std::to_string(run.pending[i]) + (last > i ? "-" + std::to_string(run.pending[last]) : "");
      i = last + 1;
    }
    std::string s = "#!/bin/sh\n# enact sweep " + run.spec.file + ": one array task per job (" + std::to_string(run.pending.size()) + " jobs)\n";
    s += "#SBATCH --job-name=enact-" + run.spec.name + "\n";
    s += "#SBATCH --array=" + tasks + (jobs_ > 0 ? "%" + std::to_string(jobs_) : "") + "\n";
    s += "#SBATCH --output=" + run.out + "/logs/job_%a.log\n#SBATCH --open-mode=append\n";
    for (const std::string& o : options_) s += "#SBATCH --" + o + "\n";
    std::string cmd;
    const std::vector<std::string> c = run.job_command(0);
    for (std::size_t i = 0; i + 1 < c.size(); ++i) cmd += shell_word(c[i]) + " ";
    s += "exec " + cmd + "\"$SLURM_ARRAY_TASK_ID\"\n";
    return s;
  }

  int jobs_;
  std::vector<std::string> options_;
};

class DaskExecutor final : public Executor {
 public:
  // by_content: the inputs travel with each task and the job's folder comes back (no folder
  // shared with the workers); else the workers run the jobs through the shared folder
  DaskExecutor(std::string scheduler, bool by_content) : scheduler_(std::move(scheduler)), by_content_(by_content) {}

  void dry_run(const SweepRun& run) override {
    std::string line;
    for (const std::string& a : command(run)) line += (line.empty() ? "" : " ") + shell_word(a);
    std::printf("%s\n", line.c_str());
  }

  bool run(const SweepRun& run, const std::function<void()>& tick) override {
    if (by_content_) {
      // the files each job reads, one a line: dask_sweep.py sends their bytes with the tasks
      std::string list;
      for (const std::string& f : experiment::sweep_inputs(run.spec)) list += f + "\n";
      write_text(inputs(run), list);
    }
    const pid_t pid = start_logged(command(run), "", true);
    bool stopped = false;
    std::int64_t last_tick = 0;
    while (true) {
      int status = 0;
      if (waitpid(pid, &status, WNOHANG) == pid) {
        if (!stopped && !(WIFEXITED(status) && (WEXITSTATUS(status) == 0 || WEXITSTATUS(status) == 1))) {
          throw config::Error("scripts/dask_sweep.py ended with status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status)) +
                              " (above)\n  fix: is the scheduler at " + scheduler_ + " running, and python3-distributed installed (scripts/setup.sh)?");
        }
        break;
      }
      if (!stopped && experiment::take_stop_signal()) {
        stopped = true;
        kill(pid, SIGTERM);
      }
      if (rt::now_ns() - last_tick > 1'000'000'000) {
        tick();
        last_tick = rt::now_ns();
      }
      rt::sleep_until_ns(rt::now_ns() + 100'000'000);
    }
    return !stopped;
  }

 private:
  static std::string inputs(const SweepRun& run) { return run.out + "/inputs.txt"; }

  std::vector<std::string> command(const SweepRun& run) const {
    const std::string script = fs::absolute(find_file("scripts/dask_sweep.py")).string();
    std::string tasks;
    for (std::size_t k : run.pending) tasks += (tasks.empty() ? "" : ",") + std::to_string(k);
    std::vector<std::string> c{script, "--scheduler", scheduler_, "--enact", run.enact, "--sweep", run.spec.file, "--out", run.out, "--jobs", tasks};
    if (by_content_) c.insert(c.end(), {"--inputs", inputs(run)});
    return c;
  }

  std::string scheduler_;
  bool by_content_;
};

// the states of the jobs, counted
struct Counts {
  std::size_t done = 0, running = 0, failed = 0, missing = 0;
};

Counts count(const SweepRun& run) {
  Counts c;
  for (const SweepJob& j : run.jobs) {
    switch (experiment::job_state(run.out, j)) {
      case JobState::done: ++c.done; break;
      case JobState::running: ++c.running; break;
      case JobState::failed: ++c.failed; break;
      case JobState::missing: ++c.missing; break;
    }
  }
  return c;
}

}  // namespace

int sweep_run(int argc, char** argv) {
  const std::vector<std::string> slurm_options = take_repeated(argc, argv, "--slurm-opt");
  const Args a = parse(argc, argv, 2, {"out", "executor", "jobs", "job", "dask-files"}, {"dry-run"});
  if (a.flag("help")) {
    std::fputs(kSweepHelp, stdout);
    return 0;
  }
  if (a.positional.size() != 1) throw UsageError("give exactly one sweep file");
  if (a.has("job")) {
    // as given: a job names a sweep file missing on its host itself
    const std::string file = fs::absolute(a.positional[0]).lexically_normal().string();
    const double k = a.number("job", -1.0);
    if (!a.has("out")) throw UsageError("--job needs the sweep's --out");
    if (k < 0 || k != std::floor(k)) throw UsageError("--job needs a job's number (from 0)");
    return run_job(file, fs::absolute(a.get("out")).lexically_normal().string(), static_cast<long>(k));
  }
  launch::block_supervisor_signals();
  const SweepSpec spec = experiment::load_sweep(fs::absolute(find_file(a.positional[0])).lexically_normal().string());
  const std::vector<SweepJob> jobs = experiment::sweep_jobs(spec);
  const std::string out = fs::absolute(a.get("out", "results/" + spec.name)).lexically_normal().string();
  // the executor, from its options
  const std::string executor = a.get("executor", "local");
  const double jobs_given = a.number("jobs", 0.0);
  if (jobs_given < 0 || jobs_given != std::floor(jobs_given)) throw UsageError("--jobs needs a whole number >= 1");
  if (!slurm_options.empty() && executor != "slurm") throw UsageError("--slurm-opt is for --executor slurm");
  const std::string dask_files = a.get("dask-files", "content");
  if (a.has("dask-files") && !executor.starts_with("dask://")) throw UsageError("--dask-files is for --executor dask://HOST:PORT");
  if (dask_files != "content" && dask_files != "shared") throw UsageError("--dask-files " + dask_files + ": give content or shared");
  for (const std::string& o : slurm_options) {
    if (o.empty() || o.find('\n') != std::string::npos || o[0] == '-') throw UsageError("--slurm-opt needs NAME=VALUE (an sbatch option without its dashes), got '" + o + "'");
  }
  std::unique_ptr<Executor> ex;
  if (executor == "local") ex = std::make_unique<LocalExecutor>(jobs_given > 0 ? static_cast<int>(jobs_given) : static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  else if (executor == "slurm") ex = std::make_unique<SlurmExecutor>(static_cast<int>(jobs_given), slurm_options);
  else if (executor.starts_with("dask://") && executor.size() > 7) ex = std::make_unique<DaskExecutor>(executor.substr(7), dask_files == "content");
  else throw UsageError("--executor " + executor + ": give local, slurm or dask://HOST:PORT");
  // every value of the grid, before anything runs
  std::fprintf(stderr, "enact sweep: %s: %zu jobs (%zu grid points x %d replicates) of %s; checking every value of the grid\n", spec.name.c_str(), jobs.size(),
               jobs.size() / static_cast<std::size_t>(spec.replicates), spec.replicates, spec.experiment.c_str());
  fs::create_directories(out + "/jobs");
  fs::create_directories(out + "/logs");
  const std::vector<std::string> problems = experiment::check_sweep(spec, out + "/jobs");
  for (const std::string& p : problems) std::fprintf(stderr, "enact sweep: %s\n", p.c_str());
  if (!problems.empty()) throw config::Error(spec.file + ": the grid has values the trial graphs refuse (above); no job ran");
  experiment::keep_or_check(out + "/sweep.txt", experiment::sweep_identity(spec), "another experiment, or the experiment file changed, or another seed, subjects or conditions");
  SweepRun run{spec, jobs, {}, out, self_exe()};
  for (const SweepJob& j : jobs) {
    if (experiment::job_state(out, j) != JobState::done) run.pending.push_back(j.index);
  }
  if (a.flag("dry-run")) {
    std::fprintf(stderr, "enact sweep: %zu of %zu jobs to run (dry run: nothing runs)\n", run.pending.size(), jobs.size());
    ex->dry_run(run);
    return 0;
  }
  const Counts before = count(run);
  std::fprintf(stderr, "enact sweep: %zu jobs to run (%zu done before), executor %s, into %s\n", run.pending.size(), before.done, executor.c_str(), out.c_str());
  // the progress line: done / running / failed, time left from this run's pace
  const bool tty = isatty(STDERR_FILENO) != 0;
  const std::int64_t start_ns = rt::now_ns();
  std::string last_counts;
  auto tick = [&] {
    const Counts c = count(run);
    const double elapsed_s = static_cast<double>(rt::now_ns() - start_ns) * 1e-9;
    const std::size_t finished = c.done - before.done;
    const std::size_t left = jobs.size() - c.done;
    const std::string eta = finished ? clock_text(elapsed_s / static_cast<double>(finished) * static_cast<double>(left)) : "?";
    char line[256];
    std::snprintf(line, sizeof line, "sweep %s: %zu/%zu done, %zu running, %zu failed, elapsed %s, left ~%s", spec.name.c_str(), c.done, jobs.size(), c.running, c.failed,
                  clock_text(elapsed_s).c_str(), eta.c_str());
    // on a terminal one line kept up to date; else a line when a count changes
    const std::string counts = std::string(line).substr(0, std::string(line).find(", elapsed"));
    if (tty) std::fprintf(stderr, "\r\033[K%s", line);
    else if (counts != last_counts) std::fprintf(stderr, "%s\n", line);
    last_counts = counts;
  };
  const bool finished = run.pending.empty() || ex->run(run, tick);
  tick();
  if (tty) std::fputs("\n", stderr);
  // the merged table and the manifest, from the jobs done (earlier runs' included)
  const std::size_t merged = experiment::merge_sweep(spec, jobs, out, version(), git_commit());
  // the jobs not done: those that started named with their logs, the others counted
  std::size_t not_done = 0, not_started = 0;
  std::string unstarted;  // their numbers, the first 20
  for (const SweepJob& j : jobs) {
    const JobState s = experiment::job_state(out, j);
    if (s == JobState::done) continue;
    ++not_done;
    if (s == JobState::missing && !fs::exists(experiment::partial_dir(out, j))) {
      if (++not_started <= 20) unstarted += (unstarted.empty() ? "" : ", ") + std::to_string(j.index);
      continue;
    }
    std::fprintf(stderr, "enact sweep: job %zu (%s) %s; logs: %s/logs/job_%zu.log, %s/experiment.log\n", j.index, j.name.c_str(),
                 s == JobState::failed ? "failed" : s == JobState::running ? "is still running elsewhere" : "did not finish", out.c_str(), j.index,
                 experiment::partial_dir(out, j).c_str());
  }
  if (not_started) std::fprintf(stderr, "enact sweep: %zu jobs did not start (%s%s)\n", not_started, unstarted.c_str(), not_started > 20 ? ", ..." : "");
  std::fprintf(stderr, "enact sweep: %zu of %zu jobs done; results: %s/results.csv, manifest: %s/manifest.json%s\nplot: /usr/bin/python3 %s %s\n", merged, jobs.size(),
               out.c_str(), out.c_str(), not_done ? "\n  run the same command again to run the jobs not done" : "", config::shipped("scripts/sweep_plot.py").c_str(), out.c_str());
  if (!finished) return 130;
  return not_done ? 1 : 0;
}

}  // namespace enact::cli
