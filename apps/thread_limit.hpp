// How many threads a command's parallel sections may use: TBB's, i.e. the lidar simulation's
// blocks of columns (sensors/lidar_simulator.cpp) and the ICP's reductions
// (estimator/icp_registration.cpp). Their results do not depend on it (fixed blocks with random
// streams of their own, deterministic reductions over fixed grains): only the CPU time does. A
// run that shares the machine with other runs (a suite, a sweep) gains nothing from a second
// thread but pays for its spinning and for the smaller pieces of work.
#pragma once

#include <oneapi/tbb/global_control.h>

#include <cstddef>
#include <cstdint>
#include <optional>

#include "apps/cli_args.hpp"

namespace statebench::app {

// Holds the limit for its lifetime (a tbb::global_control: process-wide).
class ThreadLimit {
 public:
  // threads: at most this many (at least 1); nullopt: TBB's default, every core the process may
  // run on.
  explicit ThreadLimit(std::optional<std::uint64_t> threads);
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

  // The limit in effect (TBB's max_allowed_parallelism).
  static std::size_t Threads();

 private:
  std::optional<tbb::global_control> control_;
};

// --threads of a command; throws std::invalid_argument when it is 0.
std::optional<std::uint64_t> ThreadsOption(const CliArgs& args);

// Threads for each of `jobs` runs at once on this machine: max(1, cores / jobs).
std::uint64_t ThreadsPerJob(std::uint64_t jobs);

// The machine's cores (online processors).
std::uint64_t OnlineCores();

}  // namespace statebench::app
