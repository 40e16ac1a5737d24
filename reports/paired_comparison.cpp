#include "reports/paired_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "core/yaml_node.hpp"
#include "reports/figure_format.hpp"

namespace statebench::reports {
namespace {

struct Row {
  std::string estimator, metric, pairs, base, candidate, difference, interval, p, threshold,
      verdict;
};

std::vector<Row> Rows(const Comparison& c) {
  std::vector<Row> rows;
  for (const MetricComparison& m : c.metrics) {
    char p[32];
    std::snprintf(p, sizeof(p), "%.3g", m.p_value);
    char interval[80];
    std::snprintf(interval, sizeof(interval), "[%s, %s]", FormatFigure(m.difference_interval.low).c_str(),
                  FormatFigure(m.difference_interval.high).c_str());
    rows.push_back({m.estimator, m.metric, std::to_string(m.pairs), FormatFigure(m.base_median),
                    FormatFigure(m.candidate_median), FormatFigure(m.median_difference), interval, p,
                    FormatFigure(m.threshold), VerdictName(m.verdict)});
  }
  return rows;
}

}  // namespace

RegressionThresholds LoadRegressionThresholds(const std::filesystem::path& file) {
  const YamlNode root = YamlNode::LoadFile(file);
  root.ExpectMap();
  root.ExpectOnlyKeys({"significance", "metrics"});
  RegressionThresholds t;
  t.significance = root.Get<double>("significance", t.significance);
  if (!(t.significance > 0.0 && t.significance < 1.0)) {
    root["significance"].Fail("expected a level between 0 and 1, e.g. 0.05");
  }
  const YamlNode metrics = root["metrics"];
  metrics.ExpectMap();
  if (metrics.size() == 0) metrics.Fail("name at least one metric");
  for (const std::string& name : metrics.Keys()) {
    const YamlNode m = metrics[name];
    m.ExpectOnlyKeys({"better", "target", "absolute", "relative"});
    MetricThreshold mt;
    mt.name = name;
    const std::string better = m.Get<std::string>("better", "lower");
    if (better != "lower" && better != "higher" && better != "closer") {
      m["better"].Fail("expected lower, higher or closer (to `target`)");
    }
    mt.lower_is_better = better != "higher";
    if (better == "closer") mt.target = m.Get<double>("target");
    if (better != "closer" && m.Has("target")) m["target"].Fail("goes with 'better: closer'");
    mt.absolute = m.Get<double>("absolute", 0.0);
    mt.relative = m.Get<double>("relative", 0.0);
    if (!(mt.absolute >= 0.0)) m["absolute"].Fail("expected a non-negative change");
    if (!(mt.relative >= 0.0)) m["relative"].Fail("expected a non-negative fraction");
    t.metrics.push_back(mt);
  }
  return t;
}

double WilcoxonSignedRankP(const std::vector<double>& differences) {
  std::vector<double> d;
  for (const double x : differences) {
    if (x != 0.0 && std::isfinite(x)) d.push_back(x);
  }
  const std::size_t n = d.size();
  if (n == 0) return 1.0;
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&d](std::size_t a, std::size_t b) { return std::abs(d[a]) < std::abs(d[b]); });
  // Doubled ranks (ties share the mean rank), so they stay integers.
  std::vector<int> rank2(n);
  double tie_term = 0.0;
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i;
    while (j + 1 < n && std::abs(d[order[j + 1]]) == std::abs(d[order[i]])) ++j;
    const int shared = static_cast<int>(i + j + 2);  // 2 * mean of ranks i+1 .. j+1
    for (std::size_t k = i; k <= j; ++k) rank2[order[k]] = shared;
    const double t = static_cast<double>(j - i + 1);
    tie_term += t * t * t - t;
    i = j + 1;
  }
  int w2 = 0;  // doubled W+
  for (std::size_t i = 0; i < n; ++i) {
    if (d[i] > 0.0) w2 += rank2[i];
  }
  if (n <= 20) {
    // Exact: the number of sign assignments giving each doubled rank sum.
    int total = 0;
    for (const int r : rank2) total += r;
    std::vector<double> count(static_cast<std::size_t>(total) + 1, 0.0);
    count[0] = 1.0;
    for (const int r : rank2) {
      for (int s = total; s >= r; --s) count[static_cast<std::size_t>(s)] += count[static_cast<std::size_t>(s - r)];
    }
    double below = 0.0, above = 0.0, all = 0.0;
    for (int s = 0; s <= total; ++s) {
      const double c = count[static_cast<std::size_t>(s)];
      all += c;
      if (s <= w2) below += c;
      if (s >= w2) above += c;
    }
    return std::min(1.0, 2.0 * std::min(below, above) / all);
  }
  const double nn = static_cast<double>(n);
  const double mean = nn * (nn + 1.0) / 4.0;
  const double var = nn * (nn + 1.0) * (2.0 * nn + 1.0) / 24.0 - tie_term / 48.0;
  const double w = 0.5 * w2;
  const double z = (std::abs(w - mean) - 0.5) / std::sqrt(std::max(var, 1e-300));
  return std::min(1.0, std::erfc(std::max(z, 0.0) / std::sqrt(2.0)));
}

Interval BootstrapMedianInterval(const std::vector<double>& values, std::uint64_t seed,
                                 int resamples) {
  return BootstrapInterval(values, Median, seed, resamples);
}

const char* VerdictName(Verdict v) {
  switch (v) {
    case Verdict::kBetter:
      return "better";
    case Verdict::kWorse:
      return "worse";
    case Verdict::kNoChange:
      return "no significant change";
    case Verdict::kNoData:
      return "no data";
  }
  return "?";
}

bool Comparison::AnyWorse() const {
  return std::any_of(metrics.begin(), metrics.end(),
                     [](const MetricComparison& m) { return m.verdict == Verdict::kWorse; });
}

std::vector<RunRecord> SelectEstimator(std::vector<RunRecord> runs, const std::string& estimator,
                                       const std::string& label, const std::string& where) {
  std::set<std::string> present;
  bool found = false;
  for (RunRecord& run : runs) {
    std::vector<MetricValue> kept;
    for (MetricValue& m : run.metrics) {
      present.insert(m.estimator);
      if (m.estimator != estimator) continue;
      found = true;
      m.estimator = label;
      kept.push_back(std::move(m));
    }
    run.metrics = std::move(kept);
  }
  if (!found) {
    std::string names;
    for (const std::string& name : present) names += (names.empty() ? "" : ", ") + name;
    throw InputError(where + ": no run has the estimator '" + estimator + "' (" +
                     (names.empty() ? std::string("no estimator at all") : "it has: " + names) +
                     ")");
  }
  return runs;
}

std::string PairingKey(const RunRecord& run) {
  std::vector<std::pair<std::string, std::string>> parameters = run.parameters;
  std::sort(parameters.begin(), parameters.end());
  std::string key = run.scenario + " seed " + std::to_string(run.seed);
  for (const auto& [axis, value] : parameters) key += " " + axis + "=" + value;
  return key;
}

Comparison CompareRuns(const std::vector<RunRecord>& base, const std::vector<RunRecord>& candidate,
                       const RegressionThresholds& thresholds) {
  Comparison c;
  std::map<std::string, const RunRecord*> base_by_key, candidate_by_key;
  for (const RunRecord& r : base) {
    if (r.status == "ok") base_by_key[PairingKey(r)] = &r;
  }
  for (const RunRecord& r : candidate) {
    if (r.status == "ok") candidate_by_key[PairingKey(r)] = &r;
  }
  c.base_runs = base_by_key.size();
  c.candidate_runs = candidate_by_key.size();
  std::vector<std::pair<const RunRecord*, const RunRecord*>> pairs;
  for (const auto& [key, run] : base_by_key) {
    const auto it = candidate_by_key.find(key);
    if (it == candidate_by_key.end()) {
      c.unpaired.push_back("base only: " + key);
    } else {
      pairs.emplace_back(run, it->second);
    }
  }
  for (const auto& [key, run] : candidate_by_key) {
    if (!base_by_key.count(key)) c.unpaired.push_back("candidate only: " + key);
  }
  c.pairs = pairs.size();
  if (pairs.empty()) {
    throw InputError("no run of the base pairs with a run of the candidate (same scenario, "
                     "parameters and seed): " + std::to_string(c.base_runs) + " base runs, " +
                     std::to_string(c.candidate_runs) + " candidate runs");
  }
  // A metric of an estimator that compared no epoch (never started) is unavailable, not 0.
  const auto value_of = [](const RunRecord& r, const std::string& estimator,
                           const std::string& metric) {
    double value = std::nan("");
    for (const MetricValue& m : r.metrics) {
      if (m.estimator != estimator) continue;
      if (m.name == "compared" && !(m.value > 0.0)) return std::nan("");
      if (m.name == metric) value = m.value;
    }
    return value;
  };
  std::set<std::string> estimators;
  for (const auto& [b, k] : pairs) {
    for (const MetricValue& m : b->metrics) estimators.insert(m.estimator);
  }
  for (const std::string& estimator : estimators) {
    for (const MetricThreshold& t : thresholds.metrics) {
      MetricComparison m;
      m.estimator = estimator;
      m.metric = t.name;
      m.better = t.target ? "closer" : t.lower_is_better ? "lower" : "higher";
      m.target = t.target;
      std::vector<double> b, k, d;
      for (const auto& [br, kr] : pairs) {
        const double x = value_of(*br, estimator, t.name);
        const double y = value_of(*kr, estimator, t.name);
        if (!std::isfinite(x) || !std::isfinite(y)) continue;
        b.push_back(x);
        k.push_back(y);
        d.push_back(t.target ? std::abs(y - *t.target) - std::abs(x - *t.target) : y - x);
        m.paired.push_back({PairingKey(*br), x, y, d.back()});
      }
      m.pairs = d.size();
      if (d.empty()) {
        c.metrics.push_back(m);
        continue;
      }
      m.base_median = Median(b);
      m.candidate_median = Median(k);
      m.median_difference = Median(d);
      m.difference_interval = BootstrapMedianInterval(d);
      m.p_value = WilcoxonSignedRankP(d);
      m.threshold = std::max(
          t.absolute, t.relative * std::abs(t.target ? m.base_median - *t.target : m.base_median));
      const double worse_by = t.lower_is_better ? m.median_difference : -m.median_difference;
      const bool significant = m.p_value < thresholds.significance &&
                               (m.difference_interval.low > 0.0 || m.difference_interval.high < 0.0);
      if (significant && worse_by > m.threshold) {
        m.verdict = Verdict::kWorse;
      } else if (significant && -worse_by > m.threshold) {
        m.verdict = Verdict::kBetter;
      } else {
        m.verdict = Verdict::kNoChange;
      }
      c.metrics.push_back(m);
    }
  }
  return c;
}

std::string ComparisonMarkdown(const Comparison& c, const std::string& base_name,
                               const std::string& candidate_name) {
  std::ostringstream out;
  std::size_t worse = 0, better = 0;
  for (const MetricComparison& m : c.metrics) {
    worse += m.verdict == Verdict::kWorse;
    better += m.verdict == Verdict::kBetter;
  }
  out << "## StateBench comparison: " << (worse ? "REGRESSION" : "no regression") << "\n\n"
      << "base `" << base_name << "` (" << c.base_runs << " runs) vs candidate `"
      << candidate_name << "` (" << c.candidate_runs << " runs): " << c.pairs
      << " pairs; " << worse << " worse, " << better << " better.\n\n"
      << "| estimator | metric | pairs | base median | candidate median | median diff | 95% CI "
         "of diff | p (signed-rank) | threshold | verdict |\n"
      << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : Rows(c)) {
    const bool flag = r.verdict == "worse" || r.verdict == "better";
    out << "| " << r.estimator << " | " << r.metric << " | " << r.pairs << " | " << r.base << " | "
        << r.candidate << " | " << r.difference << " | " << r.interval << " | " << r.p << " | "
        << r.threshold << " | " << (flag ? "**" + r.verdict + "**" : r.verdict) << " |\n";
  }
  if (!c.unpaired.empty()) {
    out << "\n" << c.unpaired.size() << " runs without a partner (left out):\n";
    for (std::size_t i = 0; i < std::min<std::size_t>(c.unpaired.size(), 10); ++i) {
      out << "- " << c.unpaired[i] << "\n";
    }
  }
  return out.str();
}

}  // namespace statebench::reports
