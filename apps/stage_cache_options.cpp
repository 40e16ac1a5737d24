#include "apps/stage_cache_options.hpp"

#include <stdexcept>

#include "core/content_hash.hpp"

namespace statebench::app {

std::unique_ptr<StageCache> OpenStageCache(const CliArgs& args) {
  const auto dir = args.Option("cache");
  const double limit_gb = args.Double("cache-limit-gb").value_or(kDefaultCacheLimitGb);
  if (!(limit_gb >= 0.0)) throw std::invalid_argument("--cache-limit-gb: must be >= 0");
  if (!dir) {
    if (args.Option("cache-limit-gb")) {
      throw std::invalid_argument("--cache-limit-gb: goes with --cache DIR");
    }
    return nullptr;
  }
  return std::make_unique<StageCache>(*dir, static_cast<std::uint64_t>(limit_gb * 1e9));
}

const std::string& BuildIdentity() {
  // A sweep hashes it once; the runs it forks inherit the value.
  static const std::string identity = Sha256OfFile("/proc/self/exe");
  return identity;
}

nlohmann::json CacheCountsJson(const StageCache& cache) {
  nlohmann::json counts = nlohmann::json::object();
  for (const auto& [stage, c] : cache.counts()) {
    counts[stage] = {{"hits", c.hits}, {"misses", c.misses}};
  }
  return counts;
}

}  // namespace statebench::app
