// JSON form of an estimator's diagnostics (diagnostics.json, docs/estimate-format.md).
#pragma once

#include <nlohmann/json.hpp>

#include "estimator/estimator_diagnostics.hpp"

namespace statebench::app {

nlohmann::json DiagnosticsJson(const est::EstimatorDiagnostics& diagnostics);

}  // namespace statebench::app
