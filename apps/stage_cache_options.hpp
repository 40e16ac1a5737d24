// The command-line side of the stage cache: --cache DIR and --cache-limit-gb G, the build's
// identity that goes into every cache key, and the hit counts for run.json.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "apps/cli_args.hpp"
#include "core/stage_cache.hpp"

namespace statebench::app {

constexpr double kDefaultCacheLimitGb = 20.0;

// nullptr without --cache. Throws std::invalid_argument on a bad limit.
std::unique_ptr<StageCache> OpenStageCache(const CliArgs& args);

// SHA-256 of the running executable: a cached stage is reused only by the very build that made
// it. Computed once per process.
const std::string& BuildIdentity();

// {"sumo": {"hits": 1, "misses": 0}, "sensors": {...}}
nlohmann::json CacheCountsJson(const StageCache& cache);

}  // namespace statebench::app
