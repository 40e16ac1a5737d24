#include "apps/thread_limit.hpp"

#include <unistd.h>

#include <algorithm>
#include <stdexcept>

namespace statebench::app {

ThreadLimit::ThreadLimit(std::optional<std::uint64_t> threads) {
  if (threads) {
    control_.emplace(tbb::global_control::max_allowed_parallelism,
                     static_cast<std::size_t>(std::max<std::uint64_t>(1, *threads)));
  }
}

std::size_t ThreadLimit::Threads() {
  return tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
}

std::optional<std::uint64_t> ThreadsOption(const CliArgs& args) {
  const std::optional<std::uint64_t> threads = args.Unsigned("threads");
  if (threads && *threads < 1) throw std::invalid_argument("--threads: must be at least 1");
  return threads;
}

std::uint64_t OnlineCores() {
  return static_cast<std::uint64_t>(std::max(1L, sysconf(_SC_NPROCESSORS_ONLN)));
}

std::uint64_t ThreadsPerJob(std::uint64_t jobs) {
  return std::max<std::uint64_t>(1, OnlineCores() / std::max<std::uint64_t>(1, jobs));
}

}  // namespace statebench::app
