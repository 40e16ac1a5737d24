// statebench suite [DIR] --out OUT [--jobs N] [--threads T] [--seed N] [--duration S] [--quiet]
//
// Runs every scenario DIR/*.yaml (default scenarios/paper) as its own `statebench run` process
// (this same binary), N at a time, each with --threads T (default max(1, cores / N): the runs
// are the parallelism) into OUT/<scenario name>/ with its output in run.log there; a failing
// scenario is reported and the others go on. Then reads every run.json and builds Table I of
// the paper side by side with ours (reports/paper_table.hpp): printed, and written to
// OUT/table1.md and OUT/table1.json, with OUT/suite.json holding each scenario's status, wall
// time and real-time factor. Exit code 1 when a scenario failed.
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/process_pool.hpp"
#include "apps/thread_limit.hpp"
#include "core/error.hpp"
#include "reports/paper_table.hpp"
#include "simulator/scenario.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* kUsage =
    "usage: statebench suite [DIR] --out OUT [--jobs N] [--threads T] [--seed N] [--duration S]\n"
    "                        [--quiet]\n"
    "  Runs every scenario DIR/*.yaml (default scenarios/paper) with `statebench run`, N at a\n"
    "  time (default 2), into OUT/<scenario>/ (log in run.log there), then prints Table I of the\n"
    "  paper side by side with ours and writes OUT/table1.md, OUT/table1.json, OUT/suite.json.\n"
    "  --seed, --duration and --threads (default: max(1, cores / N)) are passed to every run.\n"
    "  Exit code 1 if a scenario failed.\n";

const std::set<std::string> kFlags = {"quiet"};
const std::set<std::string> kOptions = {"out", "jobs", "threads", "seed", "duration"};

// scenarios/paper of the working folder, else of the source tree.
std::string DefaultDir() {
  const char* source_dir = std::getenv("STATEBENCH_SOURCE_DIR");
  if (fs::is_directory("scenarios/paper") || source_dir == nullptr) return "scenarios/paper";
  return (fs::path(source_dir) / "scenarios" / "paper").string();
}

// DIR is optional: CliArgs takes an exact count, so the default is filled in first.
std::vector<std::string> WithDefaultDir(std::vector<std::string> argv) {
  std::size_t positional = 0;
  for (std::size_t i = 0; i < argv.size(); ++i) {
    if (argv[i].rfind("--", 0) == 0) {
      if (kOptions.count(argv[i].substr(2))) ++i;
    } else {
      ++positional;
    }
  }
  if (positional == 0) argv.insert(argv.begin(), DefaultDir());
  return argv;
}

struct Job {
  fs::path file;
  std::string name;
  fs::path dir;
  pid_t pid = -1;
  Clock::time_point start;
  double wall_s = 0.0;
  double cpu_s = 0.0;  // user + system time of the run process (what an idle machine needs)
  int exit_code = -1;  // -1: not finished
  std::string failure;
  std::string no_estimate;  // kExitNoEstimate: the run's lines naming the estimators without one
  std::optional<nlohmann::json> run;
};

// The scenario's name (its output folder); the file stem when it does not load (its run will
// then fail with the loader's message in its log).
std::string ScenarioName(const fs::path& file) {
  try {
    return sim::LoadScenario(file).name;
  } catch (const InputError&) {
    return file.stem().string();
  }
}

std::vector<Job> ListJobs(const fs::path& dir, const fs::path& out) {
  if (!fs::is_directory(dir)) {
    throw std::invalid_argument("no such scenario folder: " + dir.string());
  }
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file() && entry.path().extension() == ".yaml") {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) throw std::invalid_argument("no *.yaml scenario in " + dir.string());
  std::vector<Job> jobs;
  std::map<std::string, fs::path> seen;
  for (const fs::path& file : files) {
    Job job;
    job.file = file;
    job.name = ScenarioName(file);
    if (const auto it = seen.find(job.name); it != seen.end()) {
      throw InputError(file.string() + ": scenario name '" + job.name + "' is also the name of " +
                       it->second.string() + " (each scenario gets the folder OUT/<name>)");
    }
    seen[job.name] = file;
    job.dir = out / job.name;
    jobs.push_back(job);
  }
  return jobs;
}

// Forks `statebench run FILE --out DIR [passed options] ` with stdout and stderr in DIR/run.log.
pid_t Launch(const Job& job, const std::vector<std::string>& passed) {
  fs::create_directories(job.dir);
  const std::string log = (job.dir / "run.log").string();
  std::vector<std::string> args = {"statebench", "run", job.file.string(), "--out",
                                   job.dir.string()};
  args.insert(args.end(), passed.begin(), passed.end());
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, STDOUT_FILENO);
      dup2(fd, STDERR_FILENO);
      close(fd);
    }
    std::vector<char*> cargs;
    for (std::string& a : args) cargs.push_back(a.data());
    cargs.push_back(nullptr);
    execv("/proc/self/exe", cargs.data());
    _exit(127);
  }
  return pid;
}

// Last non-empty line of a text file (a child's progress or its error message).
std::string LastLine(const fs::path& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  }
  const auto cr = last.rfind('\r');  // a progress bar redrawn in place
  return cr == std::string::npos ? last : last.substr(cr + 1);
}

// Lines of the log starting with "error:" or "statebench run:" (the run's messages).
std::string ErrorLines(const Job& job) {
  std::ifstream in(job.dir / "run.log");
  std::string line, errors;
  while (std::getline(in, line)) {
    if (!errors.empty() && line.rfind("  ", 0) == 0) errors += "\n" + line;  // continuation
    if (line.rfind("error:", 0) == 0 || line.rfind("statebench run:", 0) == 0) {
      errors += (errors.empty() ? "" : "\n") + line;
    }
  }
  return errors;
}

// The run's error lines, else its last line, after the exit code.
std::string FailureOf(const Job& job) {
  const std::string errors = ErrorLines(job);
  const std::string what = errors.empty() ? LastLine(job.dir / "run.log") : errors;
  const std::string code = job.exit_code >= 128
                               ? "killed by signal " + std::to_string(job.exit_code - 128)
                               : "exit code " + std::to_string(job.exit_code);
  return code + (what.empty() ? "" : ": " + what);
}

std::string Elapsed(const Clock::time_point& start) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.0fs",
                std::chrono::duration<double>(Clock::now() - start).count());
  return text;
}

void Finish(Job* job, int status, const rusage& usage) {
  job->wall_s = std::chrono::duration<double>(Clock::now() - job->start).count();
  job->cpu_s = CpuSeconds(usage);
  job->exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  // kExitNoEstimate: the run is complete but an estimator never initialised; its metrics are
  // unavailable (Table I shows the availability), the others' are there.
  if (job->exit_code == kExitNoEstimate) {
    // "error: LABEL never initialised: WHY" lines -> "no estimate: LABEL ...; LABEL ..."
    std::istringstream lines(ErrorLines(*job));
    std::string line;
    while (std::getline(lines, line)) {
      if (line.rfind("error: ", 0) == 0) line = line.substr(7);
      job->no_estimate += (job->no_estimate.empty() ? "no estimate: " : "; ") + line;
    }
  }
  if (job->exit_code == 0 || job->exit_code == kExitNoEstimate) {
    try {
      job->run = nlohmann::json::parse(std::ifstream(job->dir / "run.json"));
    } catch (const std::exception& e) {
      job->exit_code = 1;
      job->failure = "no readable run.json: " + std::string(e.what());
      return;
    }
  } else {
    job->failure = FailureOf(*job);
  }
}

// Runs the jobs `jobs_at_once` at a time; reports each end and, every `status_every`, the
// running ones with the last progress line of their logs.
void RunAll(std::vector<Job>* jobs, std::size_t jobs_at_once,
            const std::vector<std::string>& passed, bool quiet) {
  const bool tty = isatty(fileno(stderr)) != 0;
  const auto status_every = std::chrono::seconds(tty ? 2 : 30);
  auto last_status = Clock::now();
  std::size_t next = 0, running = 0, done = 0;
  const auto suite_start = Clock::now();
  while (done < jobs->size()) {
    while (running < jobs_at_once && next < jobs->size()) {
      Job& job = (*jobs)[next++];
      job.start = Clock::now();
      job.pid = Launch(job, passed);
      ++running;
      if (!quiet) {
        std::fprintf(stderr, "%ssuite: started %s (%s)\n", tty ? "\r\033[K" : "", job.name.c_str(),
                     job.file.string().c_str());
      }
    }
    int status = 0;
    rusage usage{};
    const pid_t pid = wait4(-1, &status, WNOHANG, &usage);
    if (pid > 0) {
      for (Job& job : *jobs) {
        if (job.pid != pid || job.exit_code >= 0) continue;
        Finish(&job, status, usage);
        --running;
        ++done;
        if (quiet) break;
        if (job.run) {
          std::fprintf(stderr, "%ssuite: [%zu/%zu] %s done in %.1f s (%.2fx real time)%s%s\n",
                       tty ? "\r\033[K" : "", done, jobs->size(), job.name.c_str(), job.wall_s,
                       job.run->value("real_time_factor", 0.0), job.no_estimate.empty() ? "" : "; ",
                       job.no_estimate.c_str());
        } else {
          std::fprintf(stderr, "%ssuite: [%zu/%zu] %s FAILED after %.1f s (%s): %s\n",
                       tty ? "\r\033[K" : "", done, jobs->size(), job.name.c_str(), job.wall_s,
                       (job.dir / "run.log").string().c_str(), job.failure.c_str());
        }
        break;
      }
      continue;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    if (quiet || Clock::now() - last_status < status_every) continue;
    last_status = Clock::now();
    std::string line = "suite " + Elapsed(suite_start) + " [" + std::to_string(done) + "/" +
                       std::to_string(jobs->size()) + " done]";
    for (const Job& job : *jobs) {
      if (job.pid < 0 || job.exit_code >= 0) continue;
      std::string progress = LastLine(job.dir / "run.log");
      if (progress.size() > 60) progress = progress.substr(0, 60);
      line += " | " + (progress.empty() ? job.name + " starting" : progress);
    }
    std::fprintf(stderr, tty ? "\r%s\033[K" : "%s\n", line.c_str());
  }
  if (tty && !quiet) std::fprintf(stderr, "\r\033[K");
}

// "    CPU s: lidar_raycast 60.1, lidar_odometry 30.2, ..." from the run's cpu split, largest first.
void PrintStages(const nlohmann::json& run) {
  if (!run.contains("cpu") || !run["cpu"].contains("stages_s")) return;
  std::vector<std::pair<double, std::string>> stages;
  for (const auto& [name, seconds] : run["cpu"]["stages_s"].items()) {
    stages.emplace_back(seconds.get<double>(), name);
  }
  stages.emplace_back(run["cpu"].value("child_processes_s", 0.0), "child processes");
  std::sort(stages.rbegin(), stages.rend());
  std::string line = "      CPU s:";
  for (const auto& [seconds, name] : stages) {
    char part[64];
    std::snprintf(part, sizeof(part), " %s %.1f,", name.c_str(), seconds);
    line += part;
  }
  line.pop_back();
  std::printf("%s\n", line.c_str());
}

nlohmann::json SuiteJson(const std::vector<Job>& jobs, const fs::path& dir,
                         std::size_t jobs_at_once, std::uint64_t threads, double wall_s) {
  nlohmann::json scenarios = nlohmann::json::array();
  for (const Job& job : jobs) {
    nlohmann::json j = {{"name", job.name},
                        {"file", job.file.string()},
                        {"status", job.run ? "ok" : "failed"},
                        {"exit_code", job.exit_code},
                        {"wall_time_s", job.wall_s},
                        {"cpu_time_s", job.cpu_s},
                        {"log", (job.dir / "run.log").string()}};
    if (job.run) {
      j["simulated_s"] = job.run->value("simulated_s", 0.0);
      j["distance_m"] = job.run->value("distance_m", 0.0);
      j["run_wall_time_s"] = job.run->value("wall_time_s", 0.0);
      j["real_time_factor"] = job.run->value("real_time_factor", 0.0);
      // Simulated seconds per CPU second: the real-time factor of a machine with a free core.
      j["real_time_factor_cpu"] =
          job.cpu_s > 0 ? job.run->value("simulated_s", 0.0) / job.cpu_s : 0.0;
      if (job.run->contains("cpu")) j["cpu"] = (*job.run)["cpu"];  // per stage and estimator
    } else {
      j["failure"] = job.failure;
    }
    if (!job.no_estimate.empty()) j["no_estimate"] = job.no_estimate;
    scenarios.push_back(j);
  }
  return {{"dir", dir.string()},
          {"jobs", jobs_at_once},
          {"threads_per_run", threads},
          {"wall_time_s", wall_s},
          {"scenarios", scenarios}};
}

}  // namespace

int RunSuite(const std::vector<std::string>& argv) {
  const auto parsed =
      ParseCommand({"suite", kUsage, kFlags, kOptions, 1, {"out"}}, WithDefaultDir(argv));
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs& args = std::get<CliArgs>(parsed);
  try {
    const auto wall_start = Clock::now();
    const fs::path out = *args.Option("out");
    const fs::path dir = args.positional().at(0);
    const std::uint64_t jobs_at_once = args.Unsigned("jobs").value_or(2);
    if (jobs_at_once < 1) throw std::invalid_argument("--jobs: must be at least 1");
    // Checked once here rather than failing in every run. The runs are not --quiet: their
    // progress goes to their logs, where the suite reads it.
    if (const auto duration = args.Double("duration"); duration && !(*duration > 0.0)) {
      throw std::invalid_argument("--duration: must be positive");
    }
    args.Unsigned("seed");
    const std::uint64_t threads = ThreadsOption(args).value_or(ThreadsPerJob(jobs_at_once));
    std::vector<std::string> passed = {"--threads", std::to_string(threads)};
    for (const char* option : {"seed", "duration"}) {
      if (const auto v = args.Option(option)) {
        passed.push_back(std::string("--") + option);
        passed.push_back(*v);
      }
    }

    std::vector<Job> jobs = ListJobs(dir, out);
    fs::create_directories(out);
    RunAll(&jobs, jobs_at_once, passed, args.Flag("quiet"));
    const double wall_s = std::chrono::duration<double>(Clock::now() - wall_start).count();

    std::vector<reports::ScenarioRun> runs;
    for (const Job& job : jobs) runs.push_back({job.name, job.run, job.failure});
    const reports::PaperTable table = reports::BuildPaperTable(runs);
    const std::string markdown = reports::ToMarkdown(table);
    std::ofstream(out / "table1.md") << markdown;
    std::ofstream(out / "table1.json") << reports::ToJson(table).dump(2) << "\n";
    std::ofstream(out / "suite.json")
        << SuiteJson(jobs, dir, jobs_at_once, threads, wall_s).dump(2) << "\n";
    std::printf("%s\n", markdown.c_str());
    std::size_t failed = 0;
    std::printf("Suite: %zu scenarios in %.1f s wall (%llu at a time, %llu thread%s each):\n",
                jobs.size(), wall_s, static_cast<unsigned long long>(jobs_at_once),
                static_cast<unsigned long long>(threads), threads == 1 ? "" : "s");
    for (const Job& job : jobs) {
      if (job.run) {
        const double simulated_s = job.run->value("simulated_s", 0.0);
        std::printf(
            "  %-22s ok  %5.0f s simulated in %6.1f s wall (%.2fx real time), %6.1f s CPU "
            "(%.2fx)\n",
            job.name.c_str(), simulated_s, job.wall_s, job.run->value("real_time_factor", 0.0),
            job.cpu_s, job.cpu_s > 0 ? simulated_s / job.cpu_s : 0.0);
        PrintStages(*job.run);
        if (!job.no_estimate.empty()) std::printf("      %s\n", job.no_estimate.c_str());
      } else {
        ++failed;
        std::printf("  %-22s FAILED  %s\n", job.name.c_str(), job.failure.c_str());
      }
    }
    std::printf("Written: %s, %s, %s\n", (out / "table1.md").string().c_str(),
                (out / "table1.json").string().c_str(), (out / "suite.json").string().c_str());
    return failed == 0 ? 0 : 1;
  } catch (...) {
    return ExitCodeForCurrentException("suite");
  }
}

}  // namespace statebench::app
