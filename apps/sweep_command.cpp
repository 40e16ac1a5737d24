// statebench sweep SWEEP.yaml --out DIR [--jobs N] [--threads T] [--shard I/N] [--resume]
//                  [--dry-run] [--duration S] [--cache DIR | --no-cache] [--cache-limit-gb G]
//
// Expands the sweep file (sweep_file.hpp, sweep_expansion.hpp) into runs and starts each as its
// own `statebench run` process, --jobs at a time with --threads each, in DIR/runs/<id>/; every
// finished run goes into the results store DIR/results.db in one transaction
// (reports/results_store.hpp).
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <utility>

#include "apps/cli_args.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/process_pool.hpp"
#include "apps/progress_bar.hpp"
#include "apps/stage_cache_options.hpp"
#include "apps/sweep_expansion.hpp"
#include "apps/sweep_run_record.hpp"
#include "apps/sweep_schedule.hpp"
#include "apps/thread_limit.hpp"
#include "core/error.hpp"
#include "reports/results_store.hpp"
#include "simulator/xml_scan.hpp"

namespace statebench::app {
namespace {

namespace fs = std::filesystem;

constexpr const char* kUsage =
    "usage: statebench sweep SWEEP.yaml --out DIR [--jobs N] [--threads T] [--shard I/N]\n"
    "                        [--resume] [--dry-run] [--duration S] [--cache DIR | --no-cache]\n"
    "                        [--cache-limit-gb G]\n"
    "  Expands the sweep file (docs/sweeps.md) into runs, each an independent `statebench run`\n"
    "  process in DIR/runs/<id>/, --jobs at a time (default: the number of cores) with --threads\n"
    "  threads each (default: max(1, cores / jobs); the results do not depend on it), and writes\n"
    "  every finished run into the results store DIR/results.db (docs/results-store.md).\n"
    "  --resume skips the runs already complete in the store and re-runs failed or interrupted\n"
    "  ones. --shard I/N runs the I-th of N deterministic parts (merge the stores with\n"
    "  `statebench results merge`). --dry-run lists the runs and their parameters.\n"
    "  --duration S shortens every run (smoke tests). The SUMO results and the sensor streams\n"
    "  are cached in --cache DIR (default $XDG_CACHE_HOME/statebench or ~/.cache/statebench,\n"
    "  at most G GB, default 20) and reused by every run that has the same inputs.\n"
    "  Exit code: 0 when every run succeeded, 1 when some failed, 2 on a bad sweep file.\n";

std::pair<int, int> ParseShard(const std::string& text) {
  int i = 0, n = 0;
  char slash = 0;
  std::istringstream in(text);
  if (!(in >> i >> slash >> n) || slash != '/' || !in.eof() || n < 1 || i < 1 || i > n) {
    throw std::invalid_argument("--shard: expected I/N with 1 <= I <= N, got '" + text + "'");
  }
  return {i, n};
}

fs::path DefaultCacheDir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) {
    return fs::path(xdg) / "statebench";
  }
  if (const char* home = std::getenv("HOME"); home && *home) {
    return fs::path(home) / ".cache" / "statebench";
  }
  return fs::temp_directory_path() / "statebench-cache";
}

std::string Hostname() {
  char name[256] = {};
  gethostname(name, sizeof(name) - 1);
  return name;
}

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof(text), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

void PrintDryRun(const std::vector<SweepRun>& runs, std::size_t total) {
  std::printf("%zu of %zu runs\n", runs.size(), total);
  std::printf("%-16s %-22s %8s  %-24s %s\n", "id", "scenario", "seed", "estimators",
              "parameters");
  for (const SweepRun& run : runs) {
    std::string estimators, parameters;
    for (const std::string& e : run.estimators) estimators += (estimators.empty() ? "" : ",") + e;
    for (const auto& [axis, value] : run.parameters) {
      parameters += (parameters.empty() ? "" : " ") + axis + "=" + value;
    }
    std::printf("%-16s %-22s %8llu  %-24s %s\n", run.id.c_str(), run.scenario.c_str(),
                static_cast<unsigned long long>(run.seed), estimators.c_str(),
                parameters.c_str());
  }
}

std::string Duration(double s) {
  char text[32];
  if (s >= 3600) {
    std::snprintf(text, sizeof(text), "%dh%02dm", static_cast<int>(s / 3600),
                  static_cast<int>(s / 60) % 60);
  } else {
    std::snprintf(text, sizeof(text), "%dm%02ds", static_cast<int>(s / 60),
                  static_cast<int>(s) % 60);
  }
  return text;
}

}  // namespace

int RunSweep(const std::vector<std::string>& argv) {
  const auto parsed =
      ParseCommand({"sweep",
                    kUsage,
                    {"resume", "dry-run", "no-cache"},
                    {"out", "jobs", "threads", "shard", "duration", "cache", "cache-limit-gb"},
                    1,
                    {"out"}},
                   argv);
  if (const int* code = std::get_if<int>(&parsed)) return *code;
  const CliArgs& args = std::get<CliArgs>(parsed);
  try {
    const fs::path sweep_file = args.positional().at(0);
    const fs::path out_dir = *args.Option("out");
    const int jobs = static_cast<int>(args.Unsigned("jobs").value_or(OnlineCores()));
    if (jobs < 1) throw std::invalid_argument("--jobs: must be at least 1");
    const std::uint64_t threads =
        ThreadsOption(args).value_or(ThreadsPerJob(static_cast<std::uint64_t>(jobs)));
    const auto [shard, shards] = ParseShard(args.Option("shard").value_or("1/1"));
    std::optional<double> duration = args.Double("duration");
    if (duration && !(*duration > 0.0)) throw std::invalid_argument("--duration: must be positive");
    if (args.Flag("no-cache") && (args.Option("cache") || args.Option("cache-limit-gb"))) {
      throw std::invalid_argument("--no-cache: not with --cache or --cache-limit-gb");
    }

    const double expand_start = MonotonicSeconds();
    const SweepSpec spec = LoadSweepFile(sweep_file);
    const std::string code_version = CodeVersion();
    const std::vector<SweepRun> all = ExpandSweep(spec, code_version, duration);
    const std::vector<SweepRun> runs = ShardOf(all, shard, shards);
    const double expand_s = MonotonicSeconds() - expand_start;
    if (args.Flag("dry-run")) {
      PrintDryRun(runs, all.size());
      return 0;
    }

    fs::create_directories(out_dir / "runs");
    const fs::path store_file = out_dir / "results.db";
    reports::ResultsStore store(store_file);
    const std::set<std::string> complete = store.CompletedRunIds();
    if (!store.Runs().empty() && !args.Flag("resume")) {
      throw std::invalid_argument(store_file.string() +
                                  " already holds runs: pass --resume to go on with this sweep, "
                                  "or choose another --out");
    }
    // A store holds one sweep: resuming it with another file (or another version of the file)
    // would mix runs of two definitions in one summary.
    const std::string definition = sim::ReadTextFile(sweep_file);
    for (const reports::SweepRecord& earlier : store.Sweeps()) {
      if (earlier.definition != definition) {
        throw std::invalid_argument(
            store_file.string() + " holds sweep '" + earlier.name + "' of " + earlier.file +
            " as it read then, not this file: --resume goes on with the same sweep file only "
            "(choose another --out for a changed sweep)");
      }
    }
    store.AddSweep({spec.name, fs::absolute(sweep_file).string(), definition,
                    code_version, Hostname(), shards > 1 ? args.Option("shard").value() : "",
                    UtcNow()});
    std::vector<const SweepRun*> todo;
    for (const SweepRun& run : runs) {
      if (!complete.count(run.id)) todo.push_back(&run);
    }

    const fs::path cache_dir =
        args.Option("cache") ? fs::path(*args.Option("cache")) : DefaultCacheDir();
    const std::string cache_limit =
        args.Option("cache-limit-gb").value_or(std::to_string(kDefaultCacheLimitGb));
    BuildIdentity();  // hashed once here, inherited by every run

    std::fprintf(stderr,
                 "sweep %s: %zu runs (%zu already complete), %d at a time, %llu thread%s each; "
                 "store %s\n",
                 spec.name.c_str(), runs.size(), runs.size() - todo.size(), jobs,
                 static_cast<unsigned long long>(threads), threads == 1 ? "" : "s",
                 store_file.c_str());
    ProgressBar bar("sweep " + spec.name);
    ProcessPool pool;
    // Without the cache nothing is shared: every run is its own group.
    std::vector<std::string> groups;
    for (const SweepRun* run : todo) {
      groups.push_back(args.Flag("no-cache") ? run->id : run->simulation_group);
    }
    SweepSchedule schedule(std::move(groups));
    std::size_t done = 0, failed = 0;
    double child_wall_s = 0.0, store_s = 0.0;
    std::vector<std::string> failures;
    std::map<std::string, StageCache::Counts> cache_totals;
    const double sweep_start = MonotonicSeconds();
    const auto detail = [&] {
      const double elapsed = MonotonicSeconds() - sweep_start;
      const std::size_t finished = done + failed;
      std::string eta = "?";
      if (finished > 0) {
        eta = Duration(elapsed / static_cast<double>(finished) *
                       static_cast<double>(todo.size() - finished));
      }
      return std::to_string(done) + " done, " + std::to_string(failed) + " failed, " +
             std::to_string(pool.running()) + " running of " + std::to_string(todo.size()) +
             ", ETA " + eta;
    };
    bar.Update(0.0, detail());
    while (!schedule.AllStarted() || pool.running() > 0) {
      while (pool.running() < static_cast<std::size_t>(jobs)) {
        const std::optional<std::size_t> next = schedule.Next();
        if (!next) break;
        const SweepRun& run = *todo[*next];
        const fs::path dir = out_dir / "runs" / run.id;
        std::error_code ec;
        fs::remove_all(dir, ec);  // an interrupted attempt
        fs::create_directories(dir);
        std::ofstream(dir / "scenario.yaml") << run.scenario_yaml;
        std::vector<std::string> run_args = {(dir / "scenario.yaml").string(), "--out",
                                             dir.string(), "--quiet"};
        run_args.insert(run_args.end(), {"--threads", std::to_string(threads)});
        if (!args.Flag("no-cache")) {
          run_args.insert(run_args.end(),
                          {"--cache", cache_dir.string(), "--cache-limit-gb", cache_limit});
        }
        // `statebench run` in a child process forked from this one (libsumo: one simulation
        // per process; a crash stays in its run), without loading the program again.
        pool.StartFunction(*next, [run_args] { return RunRun(run_args); }, dir / "stdout.log",
                           dir / "stderr.log");
      }
      const ChildExit exit = pool.WaitAny();
      schedule.Finished(exit.token);
      const SweepRun& run = *todo[exit.token];
      child_wall_s += exit.wall_s;
      const double store_start = MonotonicSeconds();
      reports::RunRecord record =
          RecordOfFinishedRun(run, spec.name, code_version, exit, out_dir / "runs" / run.id);
      record.host = Hostname();
      record.finished_at = UtcNow();
      store.WriteRun(record);
      store_s += MonotonicSeconds() - store_start;
      for (const auto& [stage, c] : record.cache.items()) {
        cache_totals[stage].hits += c.value("hits", 0);
        cache_totals[stage].misses += c.value("misses", 0);
      }
      if (record.status == "ok") {
        ++done;
      } else {
        ++failed;
        failures.push_back(run.id + ": " + record.error);
      }
      bar.Update(static_cast<double>(done + failed) / static_cast<double>(todo.size()), detail());
    }
    bar.Finish(detail());
    const double wall_s = MonotonicSeconds() - sweep_start;

    std::printf("sweep %s: %zu runs ok, %zu failed, %zu skipped (already complete); wall %.1f s\n",
                spec.name.c_str(), done, failed, runs.size() - todo.size(), wall_s);
    for (const auto& [stage, c] : cache_totals) {
      std::printf("  cache %-8s %d hits, %d misses\n", stage.c_str(), c.hits, c.misses);
    }
    if (!todo.empty()) {
      const double n = static_cast<double>(todo.size());
      std::printf("  overhead per run: expansion %.4f s, process start %.4f s, store %.4f s",
                  expand_s / static_cast<double>(all.size()), pool.start_s() / n, store_s / n);
      if (jobs == 1) std::printf(", outside the runs in all %.4f s", (wall_s - child_wall_s) / n);
      std::printf("\n");
    }
    std::printf("  store: %s\n", store_file.c_str());
    for (const std::string& f : failures) std::printf("  FAILED %s\n", f.c_str());
    return failed > 0 ? 1 : 0;
  } catch (...) {
    return ExitCodeForCurrentException("sweep");
  }
}

}  // namespace statebench::app
