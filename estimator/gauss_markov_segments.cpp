#include "estimator/gauss_markov_segments.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "core/error.hpp"

namespace statebench::est {

GaussMarkovTransition::GaussMarkovTransition(double sigma, double rho) : rho_(rho) {
  if (!(sigma > 0.0) || !std::isfinite(sigma) || !(rho >= 0.0 && rho < 1.0)) {
    throw InputError("Gauss-Markov transition: sigma must be positive and rho in [0, 1)");
  }
  inv_sigma_w_ = 1.0 / (sigma * std::sqrt(1.0 - rho * rho));
}

bool GaussMarkovTransition::Evaluate(double const* const* parameters, double* residuals,
                                     double** jacobians) const {
  residuals[0] = inv_sigma_w_ * (parameters[1][0] - rho_ * parameters[0][0]);
  if (jacobians != nullptr) {
    if (jacobians[0] != nullptr) jacobians[0][0] = -inv_sigma_w_ * rho_;
    if (jacobians[1] != nullptr) jacobians[1][0] = inv_sigma_w_;
  }
  return true;
}

double GaussMarkovSegments::SegmentLength(double tau_s, double span_s, int max_segments) {
  return std::max(tau_s / 10.0, span_s / std::max(max_segments, 1));
}

namespace {

bool Uses(const FactorRecord& f, const double* value) {
  return std::find(f.blocks.begin(), f.blocks.end(), value) != f.blocks.end();
}

}  // namespace

GaussMarkovSegments::GaussMarkovSegments(const std::vector<TimeNs>& times,
                                         const std::vector<GaussMarkovGlobal>& processes,
                                         int max_segments, std::vector<ChainState>* chain,
                                         std::vector<double*>* globals) {
  if (times.size() != chain->size()) {
    throw InputError("Gauss-Markov segments: one stamp per chain state");
  }
  // The records rewritten here (a factor may use several processes: east, north and up).
  std::unordered_map<const FactorRecord*, FactorRecord*> owned;
  for (const GaussMarkovGlobal& p : processes) {
    // The first state whose factors use the process: its segments start there.
    std::size_t first = chain->size();
    for (std::size_t k = 0; k < chain->size() && first == chain->size(); ++k) {
      for (const FactorRecord* f : (*chain)[k].factors) {
        if (Uses(*f, p.value)) {
          first = k;
          break;
        }
      }
    }
    if (first == chain->size()) {
      segments_.push_back(0);
      continue;
    }
    const double span_s = ToSeconds(times.back() - times[first]);
    const double length_s = SegmentLength(p.tau_s, span_s, max_segments);
    std::vector<std::size_t> starts{first};
    std::vector<std::size_t> segment_of(chain->size(), 0);
    for (std::size_t k = first + 1; k < chain->size(); ++k) {
      if (ToSeconds(times[k] - times[starts.back()]) >= length_s &&
          static_cast<int>(starts.size()) < max_segments) {
        starts.push_back(k);
      }
      segment_of[k] = starts.size() - 1;
    }
    segments_.push_back(static_cast<int>(starts.size()));
    if (starts.size() == 1) continue;

    // Every segment but the newest gets its own value; the newest keeps the live one.
    std::vector<double*> value(starts.size(), p.value);
    for (std::size_t s = 0; s + 1 < starts.size(); ++s) {
      values_.push_back(0.0);
      value[s] = &values_.back();
      globals->push_back(value[s]);
    }
    for (std::size_t k = first; k < chain->size(); ++k) {
      double* const mine = value[segment_of[k]];
      if (mine == p.value) continue;
      for (const FactorRecord*& f : (*chain)[k].factors) {
        if (!Uses(*f, p.value)) continue;
        FactorRecord* record = nullptr;
        if (const auto it = owned.find(f); it != owned.end()) {
          record = it->second;
        } else {
          records_.push_back(*f);
          record = &records_.back();
          owned.emplace(record, record);
          f = record;
        }
        std::replace(record->blocks.begin(), record->blocks.end(), p.value, mine);
      }
    }
    for (std::size_t s = 0; s + 1 < starts.size(); ++s) {
      const double dt_s = ToSeconds(times[starts[s + 1]] - times[starts[s]]);
      transitions_.push_back(
          std::make_unique<GaussMarkovTransition>(p.sigma, std::exp(-dt_s / p.tau_s)));
      records_.push_back(
          FactorRecord{transitions_.back().get(), nullptr, {value[s], value[s + 1]}});
      (*chain)[starts[s + 1]].factors.push_back(&records_.back());
    }
  }
}

}  // namespace statebench::est
